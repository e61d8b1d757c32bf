// `sinkwatch rover-table` (write a table's rover section: the rover's mass,
// gravity, centre of mass and geometry) and `sinkwatch table-info` (a table
// file's every section in human units); docs/rover-table.md.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sinkwatch::ground {

void add_rover_table_command(CLI::App& app);
void add_table_info_command(CLI::App& app);

/// Runs `sinkwatch rover-table <args>` / `sinkwatch table-info <args>`
/// in-process; returns the exit status (tests).
int run_rover_table_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int run_table_info_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace sinkwatch::ground
