// diagnose_command.hpp: the `sinkwatch diagnose --real DATA.csv` subcommand
// (issue 8): reads soil-bin data, runs the diagnosis (diagnosis.hpp) with the
// Wong–Reece simulator or Eq. 11 as the model, prints the result and writes
// --json and --report outputs.
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

struct DiagnoseOptions {
  std::string data_path;                 // --real
  std::string model = "wong-reece";      // --model wong-reece|estimator
  std::optional<double> radius_m;        // --radius
  std::optional<double> width_m;         // --width
  std::optional<double> load_n;          // --load (files without load_N)
  std::string soil = "hit-lss1";         // --soil: starting point of the Wong–Reece fit
  double gravity_m_s2 = 9.81;            // --gravity
  std::string base_fit;                  // --fit: simulator parameters of the base fit (comma list)
  std::string json_path;                 // --json
  std::string report_dir;                // --report
  std::ostream* detail = nullptr;        // -v/--verbose: extra detail (stderr), else none
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
