// `sinkwatch simulate`: soil-bin style CSV from the reference simulator.
// The subcommand lives here; ground/cli/main.cpp only registers it.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sinkwatch::ground {

// Adds the `simulate` subcommand to app. `command_line` is recorded in the
// CSV comments (use join_command_line(argc, argv)). Output goes to --out or
// to `out`; errors are printed to `err` with the "sinkwatch simulate: " prefix
// and end the program with exit code 1 through CLI::RuntimeError; bad flags
// raise CLI::ValidationError, exit code 2 (cli_conventions.hpp).
CLI::App* add_simulate_command(CLI::App& app, std::string command_line, std::ostream& out,
                                  std::ostream& err);
CLI::App* add_simulate_command(CLI::App& app, std::string command_line);

// argv joined with spaces; arguments with spaces or quotes are single-quoted.
std::string join_command_line(int argc, const char* const* argv);

// Runs `sinkwatch simulate ARGS...` (args exclude the program name and the
// word "simulate") and returns the exit code. For tests and scripting.
int run_simulate(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace sinkwatch::ground
