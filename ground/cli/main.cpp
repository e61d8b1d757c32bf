// sinkwatch: the ground command line. Each subcommand lives with its tool;
// this file only assembles them. The exit codes, the error prefix and the
// handling of CLI11's own errors are shared (cli_conventions.hpp,
// docs/conventions.md).
#include <CLI/CLI.hpp>

#include "sinkwatch/ground/calibrate_command.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/diagnose_command.hpp"
#include "sinkwatch/ground/replay_command.hpp"
#include "sinkwatch/ground/rover_table_command.hpp"
#include "sinkwatch/ground/simulate_command.hpp"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  CLI::App app{"sinkwatch: wheel-sinkage estimation and embedding prevention for planetary rovers",
               "sinkwatch"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sinkwatch 0.1.0");
  sinkwatch::ground::add_calibrate_command(app);
  sinkwatch::ground::add_campaign_command(app, sinkwatch::ground::join_command_line(argc, argv));
  sinkwatch::ground::add_diagnose_command(app);
  sinkwatch::ground::add_replay_command(app);
  sinkwatch::ground::add_rover_table_command(app);
  sinkwatch::ground::add_simulate_command(app, sinkwatch::ground::join_command_line(argc, argv));
  sinkwatch::ground::add_table_info_command(app);
  const std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
  return sinkwatch::ground::run_command_line(app, args, std::cout, std::cerr);
}
