// `sinkwatch campaign`: the Monte Carlo evaluation of the flight code over
// families of simulated traverses (campaign.hpp, docs/campaign.md).
// ground/cli/main.cpp only registers it.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sinkwatch::ground {

/// Adds `campaign` to app. Errors carry the "sinkwatch campaign: " prefix and
/// end with exit code 1 (data or I/O) or 2 (usage), as every subcommand.
/// `command_line` is recorded in summary.md.
CLI::App* add_campaign_command(CLI::App& app, const std::string& command_line = "sinkwatch campaign");

/// Runs `sinkwatch campaign ARGS...` (without the program name and
/// "campaign") and returns the exit code; for tests.
int run_campaign_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace sinkwatch::ground
