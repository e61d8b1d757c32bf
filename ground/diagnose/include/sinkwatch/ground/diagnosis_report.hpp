// diagnosis_report.hpp: the diagnosis as text (terminal and summary.md), as
// JSON (--json: keys where, ranking, base_fit) and as gnuplot plots of the
// residuals against slip and load before and after the top effect (--report).
// gnuplot runs as an external process on a generated script; without it the
// report directory still gets the data, the scripts and the summary, with a note.
#ifndef SINKWATCH_GROUND_DIAGNOSIS_REPORT_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_REPORT_HPP

#include <iosfwd>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"

namespace sinkwatch {
namespace ground {

[[nodiscard]] std::string to_json(const DiagnosisResult& result);

/// Human-readable summary (Markdown).
[[nodiscard]] std::string summary_markdown(const DiagnosisResult& result);

/// The y-range every residual panel shares: symmetric about zero, covering
/// every finite noise-scaled residual of the base fit and of the top effect
/// (the values of residuals.dat), at least +-1.
struct ResidualRange {
  double low;
  double high;
};
[[nodiscard]] ResidualRange residual_plot_range(const DiagnosisResult& result);

/// The text of residuals.gp: residual / noise against slip and against load,
/// base fit and base + top effect side by side per channel, every panel on
/// residual_plot_range(); drawn from residuals.dat in the same folder.
[[nodiscard]] std::string residuals_plot_script(const DiagnosisResult& result);

/// Checks, before any work, that the report can be written to `dir`
/// (docs/output-files.md): `dir` is a writable directory, or its parent is,
/// and none of the report's files there is anything but a regular file.
/// Throws OutputError naming the path.
void check_report_directory(const std::string& dir);

/// Writes summary.md, residuals.dat, residuals.gp and, when gnuplot runs,
/// the SVG plots into `dir` (created if missing; its parent must exist).
/// Every file goes through a temporary and is renamed into place only when
/// all are complete (gnuplot's exit status and both plots checked), so an
/// error (an exception naming the path) leaves no half-written report.
/// Returns notes on what was and was not produced. `gnuplot` is the program
/// to run ("" disables plots: the data, script and summary are still written).
std::vector<std::string> write_report(const DiagnosisResult& result, const std::string& dir,
                                      const std::string& gnuplot);

/// The gnuplot program to use: $SINKWATCH_GNUPLOT if set, else "gnuplot";
/// empty when it cannot be run.
[[nodiscard]] std::string find_gnuplot();

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_REPORT_HPP
