// calibration_report.hpp: the outputs of `sinkwatch calibrate`: a compact
// human-readable report and a JSON document, both from one CalibrationReport.
// The fit itself (Eq. 11 by least squares, Eq. 12/13) is in calibration.hpp.
#ifndef SINKWATCH_GROUND_CALIBRATION_REPORT_HPP
#define SINKWATCH_GROUND_CALIBRATION_REPORT_HPP

#include <iosfwd>
#include <string>
#include <vector>

#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

struct CalibrationReport {
  std::string source;
  SoilBinForm form = SoilBinForm::dimensionless;
  FixedCoefficients fixed;
  CalibrationFit fit;               // all rows pooled
  bool per_load = false;
  std::vector<LoadFit> load_table;  // the C(W) table when per_load
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
