// diagnose_command.hpp: the `sinkwatch diagnose --real DATA.csv` subcommand
// (issue 8): reads soil-bin data, runs the diagnosis (diagnosis.hpp) with the
// Wong–Reece simulator or Eq. 11 as the model, prints the result and writes
// --json and --report outputs. With --base DATA, a two-condition diagnosis.
#ifndef SINKWATCH_GROUND_DIAGNOSE_COMMAND_HPP
#define SINKWATCH_GROUND_DIAGNOSE_COMMAND_HPP

#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace sinkwatch {
namespace ground {

/// The simulator's relative quadrature tolerance during the diagnosis fits
/// (docs/diagnosis.md, "Speed"; the simulator's own default is 1e-9).
inline constexpr double kDiagnosisQuadratureRelTol = 1e-9;

struct DiagnoseOptions {
  std::string data_path;                 // --real
  std::string base_path;                 // --base: the base condition (two-condition diagnosis), or empty
  std::string model = "wong-reece";      // --model wong-reece|estimator
  std::optional<double> radius_m;        // --radius
  std::optional<double> width_m;         // --width
  std::optional<double> load_n;          // --load (files without load_N)
  std::string soil = "hit-lss1";         // --soil: starting point of the Wong–Reece fit
  double gravity_m_s2 = 9.81;            // --gravity
  std::string base_fit;                  // --fit: simulator parameters of the base fit (comma list)
  std::string json_path;                 // --json
  std::string report_dir;                // --report
  // The simulator's quadrature tolerance during the fits (wong-reece).
  double quadrature_rel_tol = kDiagnosisQuadratureRelTol;
  std::ostream* detail = nullptr;        // -v/--verbose: extra detail (stderr), else none
  std::ostream* progress = nullptr;      // progress bar (stderr on a terminal, not under -q), else none
};

/// Runs the diagnosis; throws on bad input (the CLI prints the message).
void run_diagnose(const DiagnoseOptions& options, std::ostream& out);

/// Registers the `diagnose` subcommand. Errors are printed on stderr with the
/// "sinkwatch diagnose: " prefix and end the program with exit code 1 (data or
/// I/O) or 2 (usage), as every subcommand (cli_conventions.hpp).
void add_diagnose_command(CLI::App& app);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSE_COMMAND_HPP
