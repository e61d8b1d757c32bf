// calibration_report.hpp: the outputs of `sinkwatch calibrate`: a compact
// human-readable report and a JSON document, both from one CalibrationReport.
// The fit itself (Eq. 11 by least squares, Eq. 12/13) is in calibration.hpp.
#ifndef SINKWATCH_GROUND_CALIBRATION_REPORT_HPP
#define SINKWATCH_GROUND_CALIBRATION_REPORT_HPP

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

/// What went into the flight parameter table (--table), read back from the
/// decoded bytes: the numbers the flight code will use.
struct FlightTableSummary {
  struct Row {
    double load_n = 0.0;
    double c1 = 0.0;
    double c2 = 0.0;
    double c3 = 0.0;
    double dp_max_ratio = 0.0;
  };
  std::string path;
  std::size_t bytes = 0;
  std::uint32_t crc = 0;
  std::uint16_t table_version = 0;
  double wheel_radius_m = 0.0;
  bool radius_from_data = false;  // else kept from the base table
  std::string base;               // "flight default" or the base table's path
  std::vector<Row> rows;
};

struct CalibrationReport {
  std::string source;
  SoilBinForm form = SoilBinForm::dimensionless;
  FixedCoefficients fixed;
  CalibrationFit fit;               // all rows pooled
  bool per_load = false;
  std::vector<LoadFit> load_table;  // the C(W) table when per_load
  std::optional<FlightTableSummary> flight_table;
};

/// The default terminal output: coefficients with standard errors and 95 %
/// intervals, correlations, condition number, RMS, LOO RMS, residuals by slip,
/// and the C(W) table when fitted per load.
void print_report(std::ostream& out, const CalibrationReport& report);

/// Everything in the report as one JSON object. Top-level keys include c1,
/// c2, c3, std_err, condition_number, rms, loo_rms; a number that does not
/// exist (a fixed coefficient's standard error, say) is null.
[[nodiscard]] std::string to_json(const CalibrationReport& report);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_CALIBRATION_REPORT_HPP
