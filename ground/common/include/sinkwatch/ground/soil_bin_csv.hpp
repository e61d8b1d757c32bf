// soil_bin_csv.hpp: reads soil-bin test data (one row per steady-state run of
// a single wheel) from CSV into the dimensionless quantities of the paper's
// sinkage estimation function, Eq. 10/11:
//
//     sinkage ratio   z/r        drive coefficient     T/(rW)
//     traction coeff  DP/W       slip                  s = 1 - v/(r w)
//
// Two input forms are accepted, recognised by their header:
//   dimensional:   slip, load_N, torque_Nm, sinkage_m, drawbar_pull_N, and the
//                  wheel radius from a wheel_radius_m column or the caller;
//   dimensionless: slip, sinkage_ratio, drive_coeff, traction_coeff (the
//                  paper's Table 1), load_N optional (a column, or one
//                  load for every row from the caller).
// When every dimensional column is present the dimensional form is used (the
// raw measurements are the primary data). The other known columns are
// wheel_radius_m, wheel_width_m (read for the diagnosis) and paper_eq10_fit
// (Table 1's own fitted value, checked and not used). A column the reader does
// not know is an error naming it, unless its name starts with "note" (free
// text, ignored): docs/input-files.md. Every number must lie in its column's
// physical range (the table there); "-" reads standard input; a leading UTF-8
// byte-order mark is skipped; a directory or a binary file is refused.
//
// Host only (ground tools). Every malformed input throws DataError naming the
// file, the line and, where one is at fault, the column.
#ifndef SINKWATCH_GROUND_SOIL_BIN_CSV_HPP
#define SINKWATCH_GROUND_SOIL_BIN_CSV_HPP

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sinkwatch {
namespace ground {

/// An input error located in a file. line and column are 1-based; 0 means
/// "not tied to a line" / "not tied to a column".
class DataError : public std::runtime_error {
 public:
  DataError(std::string source, std::size_t line, std::size_t column, std::string column_name,
            const std::string& detail);

  [[nodiscard]] const std::string& source() const noexcept { return source_; }
  [[nodiscard]] std::size_t line() const noexcept { return line_; }
  [[nodiscard]] std::size_t column() const noexcept { return column_; }
  [[nodiscard]] const std::string& column_name() const noexcept { return column_name_; }
  [[nodiscard]] const std::string& detail() const noexcept { return detail_; }

 private:
  std::string source_;
  std::size_t line_;
  std::size_t column_;
  std::string column_name_;
  std::string detail_;
};

enum class SoilBinForm { dimensional, dimensionless };

[[nodiscard]] const char* to_string(SoilBinForm form) noexcept;

/// One soil-bin run. The dimensionless quantities are always filled; the
/// dimensional ones only when the input had them.
struct SoilBinRow {
  std::size_t line = 0;  // where the row came from, for messages
  double slip = 0.0;
  double sinkage_ratio = 0.0;   // z/r
  double drive_coeff = 0.0;     // T/(rW)
  double traction_coeff = 0.0;  // DP/W
  std::optional<double> load_n;
  std::optional<double> torque_nm;
  std::optional<double> sinkage_m;
  std::optional<double> drawbar_pull_n;
  std::optional<double> wheel_radius_m;
  std::optional<double> wheel_width_m;  // the wheel_width_m column, or the caller's
};

struct SoilBinDataset {
  std::string source;  // file name as given, for messages
  SoilBinForm form = SoilBinForm::dimensionless;
  bool has_load = false;  // every row has load_n
  std::vector<SoilBinRow> rows;
};

struct SoilBinReadOptions {
  /// Wheel radius for dimensional input without a wheel_radius_m column.
  /// Giving both is an error: two sources for one number hide mistakes.
  std::optional<double> wheel_radius_m;
  /// Wheel load of every row, for dimensionless input without a load_N
  /// column (Table 1 is all 3 kg). With a load_N column it is an error.
  std::optional<double> load_n;
  /// Wheel width of every row, for input without a wheel_width_m column
  /// (the diagnosis's --width). With a wheel_width_m column it is an error.
  std::optional<double> wheel_width_m;
};

/// Parses CSV text. `source` names the input in messages.
[[nodiscard]] SoilBinDataset parse_soil_bin_csv(std::istream& in, const std::string& source,
                                                const SoilBinReadOptions& options = {});

/// Opens and parses a file ("-": standard input, named "<stdin>" in
/// messages); a missing or unreadable file or a directory is a DataError too.
[[nodiscard]] SoilBinDataset read_soil_bin_csv(const std::string& path,
                                               const SoilBinReadOptions& options = {});

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_SOIL_BIN_CSV_HPP
