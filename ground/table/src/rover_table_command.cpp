// `sinkwatch rover-table` and `sinkwatch table-info` (rover_table_command.hpp,
// docs/rover-table.md).
#include "sinkwatch/ground/rover_table_command.hpp"

#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/rover_table.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace sinkwatch::ground {
namespace {

struct RoverTableArgs {
  std::string out_path;
  std::string base_table;
  std::vector<double> values = std::vector<double>(rover_fields().size(), 0.0);
  std::vector<CLI::Option*> options;  // one per rover field, to see which were given
  Verbosity verbosity;
};

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08x", static_cast<unsigned>(v));
  return buf;
}

int run_rover_table(const RoverTableArgs& a, std::ostream& out, std::ostream& err) {
  (void)check_output_path(a.out_path);  // before any work (docs/output-files.md)
  const LoadedTable base = a.base_table.empty() ? default_table() : read_table_file(a.base_table);
  std::vector<std::pair<std::string, double>> settings;
  std::string given;
  for (std::size_t i = 0; i < a.options.size(); ++i) {
    if (a.options[i]->count() == 0) continue;
    settings.emplace_back(rover_fields()[i].name, a.values[i]);
    given += std::string(given.empty() ? "" : ", ") + rover_fields()[i].name;
  }
  RoverTable written;
  try {
    written = build_rover_table(base, settings);
  } catch (const RoverTableError& e) {
    throw_usage_error(e.what());
  }
  OutputFile file(a.out_path, &out);
  file.write(std::string(written.bytes.begin(), written.bytes.end()));
  file.commit();
  // The summary goes to stderr when the table itself went to standard output.
  std::ostream& report = is_standard_output(a.out_path) ? err : out;
  if (!a.verbosity.inform() && &report == &err) return 0;
  report << "sinkwatch rover-table: wrote " << a.out_path << ": " << written.bytes.size() << " bytes, CRC-32 "
         << hex(written.crc) << ", table version " << written.table.table_version
         << ", accepted by the flight loader (flight::load)\n"
         << "  sections 1-5 and 7 from " << base.source << "; section 6 (rover) from "
         << (base.rover ? "its section 6" : "the Yutu-like default with its wheel radius")
         << (given.empty() ? std::string() : ", with " + given + " as given") << ":\n"
         << describe_rover(written.rover);
  return 0;
}

CLI::App* add_rover_table(CLI::App& app, std::shared_ptr<RoverTableArgs> a, std::ostream& out, std::ostream& err) {
  CLI::App* sub = app.add_subcommand(
      "rover-table",
      "Write a flight parameter table whose rover section (section 6) holds the rover's mass, gravity, centre of mass "
      "and suspension geometry; every other section from --base-table (docs/rover-table.md).");
  non_empty_value(sub->add_option("--out", a->out_path, "the table file to write (binary, with its CRC)"))->required();
  non_empty_value(sub->add_option("--base-table", a->base_table,
                                  "table whose sections are kept and whose rover section (if any) is the starting "
                                  "point (default: the built-in default table and the Yutu-like rover)"));
  for (std::size_t i = 0; i < rover_fields().size(); ++i) {
    const RoverField& f = rover_fields()[i];
    const std::string unit = *f.unit ? std::string(" [") + f.unit + "]" : std::string();
    a->options.push_back(
        sub->add_option(std::string("--") + f.name, a->values[i], std::string(f.help) + unit)->check(finite_number()));
  }
  add_verbosity_flags(*sub, a->verbosity);
  sub->callback([a, &out, &err]() {
    int rc = exit_status(ExitCode::data_error);
    run_reporting_errors("rover-table", out, err, [&]() { rc = run_rover_table(*a, out, err); });
    if (rc != exit_status(ExitCode::ok)) throw CLI::RuntimeError(rc);
  });
  return sub;
}

struct TableInfoArgs {
  std::string path;
  Verbosity verbosity;  // the convention of every subcommand; the listing has no optional detail
};

CLI::App* add_table_info(CLI::App& app, std::shared_ptr<TableInfoArgs> a, std::ostream& out, std::ostream& err) {
  CLI::App* sub = app.add_subcommand(
      "table-info", "Show every section of a flight parameter table file in human units (docs/rover-table.md).");
  non_empty_value(sub->add_option("table", a->path, "the table file (binary)"))->required();
  add_verbosity_flags(*sub, a->verbosity);
  sub->callback([a, &out, &err]() {
    run_reporting_errors("table-info", out, err, [&]() {
      out << describe_table(read_table_file(a->path));
      finish_standard_output(out);
    });
  });
  return sub;
}

int run_in_process(const char* name, const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"sinkwatch", "sinkwatch"};
  if (std::string(name) == "rover-table") {
    add_rover_table(app, std::make_shared<RoverTableArgs>(), out, err);
  } else {
    add_table_info(app, std::make_shared<TableInfoArgs>(), out, err);
  }
  std::vector<std::string> argv{name};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command_line(app, argv, out, err);
}

}  // namespace

void add_rover_table_command(CLI::App& app) { add_rover_table(app, std::make_shared<RoverTableArgs>(), std::cout, std::cerr); }

void add_table_info_command(CLI::App& app) { add_table_info(app, std::make_shared<TableInfoArgs>(), std::cout, std::cerr); }

int run_rover_table_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  return run_in_process("rover-table", args, out, err);
}

int run_table_info_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  return run_in_process("table-info", args, out, err);
}

}  // namespace sinkwatch::ground
