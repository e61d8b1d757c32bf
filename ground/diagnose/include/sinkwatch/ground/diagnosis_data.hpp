// diagnosis_data.hpp: the rows the sim-to-real diagnosis works on, how they
// are split into training and held-out rows, and how the measurement noise of
// each channel is estimated without any model.
//
// The rows come from the soil-bin CSV reader (soil_bin_csv.hpp) and carry both
// the dimensional measurements (z, T, DP at load W and slip s) and the
// dimensionless quantities of the paper's Eq. 10/11 (z/r, T/(rW), DP/W).
// The wheel geometry comes from --radius/--width or from the wheel_radius_m /
// wheel_width_m columns; a file with neither is an error.
//
// Host only, double precision. Input errors throw DataError (file, line, column).
#ifndef SINKWATCH_GROUND_DIAGNOSIS_DATA_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_DATA_HPP

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

/// One soil-bin run, with every quantity the diagnosis models need.
struct DiagnosisRow {
  std::size_t line = 0;  // line in the source file (0 for generated rows)
  double slip = 0.0;
  double load_n = 0.0;   // W; from --load when the file has no load column
  bool load_measured = false;
  double radius_m = 0.0;
  double width_m = 0.0;
  double sinkage_m = 0.0;       // z
  double torque_nm = 0.0;       // T
  double drawbar_pull_n = 0.0;  // DP
  double sinkage_ratio = 0.0;   // z/r
  double drive_coeff = 0.0;     // T/(rW)
  double traction_coeff = 0.0;  // DP/W
};

struct DiagnosisData {
  std::string source;
  std::vector<DiagnosisRow> rows;
  bool has_loads = false;        // every row has a load (measured or --load)
  bool loads_measured = false;   // loads come from the file
  bool dimensional = false;      // the file had the dimensional columns
};

struct DiagnosisReadOptions {
  std::optional<double> radius_m;  // --radius
  std::optional<double> width_m;   // --width
  std::optional<double> load_n;    // --load, for files without a load_N column
};

/// Reads a soil-bin CSV. The wheel radius and width must come from exactly one
/// source each (option or column); a file with neither is a DataError.
[[nodiscard]] DiagnosisData read_diagnosis_data(const std::string& path,
                                                const DiagnosisReadOptions& options);

/// Builds the derived quantities of a row from its dimensional ones.
[[nodiscard]] DiagnosisRow make_row(double slip, double load_n, double sinkage_m, double torque_nm,
                                    double drawbar_pull_n, double radius_m, double width_m);

/// The training / held-out split and the rule that made it, in words.
struct DataSplit {
  std::vector<std::size_t> train;    // indices into the rows
  std::vector<std::size_t> heldout;
  std::string rule;
};

/// The split rule (docs/diagnosis.md, "Split"):
///  - two or more distinct loads: every row at the highest load is held out
///    (the model must carry over to a load it was not fitted at);
///  - one load: sort by slip and hold out every 4th row counting from the
///    highest slip (indices n-1, n-5, ...), so the held-out rows span the slip
///    range and include its high-slip end.
/// Needs at least 8 rows. Throws std::invalid_argument otherwise.
[[nodiscard]] DataSplit split_rows(const std::vector<DiagnosisRow>& rows);

/// The cross-validation folds the ranking is scored on (docs/diagnosis.md,
/// "Split"); the first fold is split_rows(rows), so the WHERE breakdown and
/// the shown fits use the same split as before.
///  - three or more loads: the highest load held out, then the lowest; with
///    `every_load`, then every other load too (leave one load out); a fold
///    with fewer than 4 training rows is skipped;
///  - two loads: the split_rows split only (holding out the lower load would
///    leave a single training load, on which load terms are not identifiable);
///  - one load: four folds, fold j holding out every 4th row of the
///    slip-sorted rows counting down from the (j+1)-th highest slip.
[[nodiscard]] std::vector<DataSplit> cross_validation_folds(const std::vector<DiagnosisRow>& rows,
                                                           bool every_load = false);

/// Distinct loads, ascending (loads within 1e-9 relative are one load).
[[nodiscard]] std::vector<double> distinct_loads(const std::vector<DiagnosisRow>& rows);

/// Model-free noise estimate of one channel from neighbour scatter.
///  - Replicates (rows with the same load and slip) give the pooled
///    within-group standard deviation when there are at least 3 degrees of
///    freedom.
///  - Otherwise, within each load, rows sorted by slip: the 3rd divided
///    difference of four consecutive points is zero for any quadratic trend,
///    so d = sum w_j y_j with w_j = 1 / prod_{m != j} (x_j - x_m) has
///    E[d^2] = sigma^2 sum w_j^2 plus only the cubic part of the trend;
///    sigma^2 = mean of d^2 / sum w_j^2. Needs at least 3 such differences.
/// `method` is "replicates", "neighbour_scatter" or "none" (not enough rows).
/// With at least 6 differences, sigma(y) = hypot(floor, relative |y|) is
/// fitted to them (sensors with a floor and a relative error: load cells,
/// torque transducers); `sigma` is then that model's RMS over the rows.
/// Replicates give floor = sigma, relative = 0.
struct NoiseEstimate {
  double sigma = 0.0;
  double floor = 0.0;
  double relative = 0.0;
  std::string method;
  std::size_t dof = 0;
};

[[nodiscard]] NoiseEstimate estimate_noise(const std::vector<DiagnosisRow>& rows,
                                           const std::vector<double>& values);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_DATA_HPP
