// calibrate_command.hpp: the `sinkwatch calibrate DATA.csv` subcommand. Reads
// soil-bin data (soil_bin_csv.hpp), fits Eq. 11 by least squares
// (calibration.hpp, the paper's Eq. 12/13) and writes the report, optionally
// the per-load C(W) table (--per-load), the JSON (--json) and the binary
// flight parameter table (--table, flight_table.hpp).
#ifndef SINKWATCH_GROUND_CALIBRATE_COMMAND_HPP
#define SINKWATCH_GROUND_CALIBRATE_COMMAND_HPP

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace sinkwatch {
namespace ground {

struct CalibrateOptions {
  std::string data_path;
  std::optional<double> wheel_radius_m;  // --radius
  std::optional<double> load_n;          // --load, for data without load_N
  bool per_load = false;                 // --per-load
  std::string fix;                       // --fix c1=1,c2=1
  std::string json_path;                 // --json FILE, empty: none
  std::string table_path;                // --table FILE: binary flight parameter table
  std::string base_table_path;           // --base-table FILE, empty: the flight default
  std::optional<std::uint16_t> table_version;  // --table-version
  std::ostream* detail = nullptr;              // -v/--verbose: extra detail (stderr), else none
};

/// Runs a calibration: prints the report on `out` and writes the requested
/// files. Every input is read and every result computed before the first file
/// is written, and files are written through a temporary and renamed, so an
/// error (thrown as an exception) leaves nothing behind.
void run_calibrate(const CalibrateOptions& options, std::ostream& out);

/// Registers the `calibrate` subcommand. Errors are printed on stderr with the
/// "sinkwatch calibrate: " prefix and end the program with exit code 1 (data or
/// I/O) or 2 (usage), as every subcommand (cli_conventions.hpp).
void add_calibrate_command(CLI::App& app);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_CALIBRATE_COMMAND_HPP
