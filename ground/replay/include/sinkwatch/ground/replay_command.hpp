// `sinkwatch replay [TELEMETRY.csv]`: the subcommand. ground/cli/main.cpp
// only registers it.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sinkwatch::ground {

/// The shipped scenarios compiled into the binary ("embedding", "nominal");
/// empty when the build had no data/telemetry/<name>.csv.
const std::string& embedded_scenario_text(const std::string& name);

/// Adds `replay` to app. Errors are printed with the "sinkwatch replay: "
/// prefix and end the program with exit code 1 (data or I/O) or 2 (usage), as
/// every subcommand (cli_conventions.hpp).
CLI::App* add_replay_command(CLI::App& app);

/// Runs `sinkwatch replay ARGS...` (without the program name and "replay")
/// and returns the exit code; for tests and scripting.
int run_replay_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace sinkwatch::ground
