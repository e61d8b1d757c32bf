// `sinkwatch replay` (replay_command.hpp, docs/replay.md).
#include "sinkwatch/ground/replay_command.hpp"

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_report.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

namespace sinkwatch::ground {
namespace {

struct ReplayArgs {
  std::string telemetry;
  std::string scenario = "embedding";
  std::string csv;
  std::string plot;
  bool verbose = false;
  double every_s = 30.0;
  double gravity = 0.0;  // 0: from the log
  bool no_escape = false;
  std::string table;
};

// A bar on stderr, only when a person is watching it.
class Progress {
 public:
  Progress(std::ostream& err, std::size_t rows)
      : err_(err), on_(&err == &std::cerr && isatty(fileno(stderr)) != 0 && rows >= 1000) {}
  void operator()(double fraction) {
    if (!on_) return;
    const int width = 40;
    const int filled = static_cast<int>(fraction * width);
    err_ << "\r  replaying [" << std::string(static_cast<std::size_t>(filled), '#')
         << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << static_cast<int>(fraction * 100.0)
         << " %" << std::flush;
  }
  ~Progress() {
    if (on_) err_ << "\r" << std::string(60, ' ') << "\r" << std::flush;
  }

 private:
  std::ostream& err_;
  bool on_;
};

int run(const ReplayArgs& a, std::ostream& out, std::ostream& err) {
  TelemetryLog log;
  std::string title;
  if (a.telemetry.empty()) {
    const std::string& text = embedded_scenario_text(a.scenario);
    if (text.empty()) {
      err << "sinkwatch replay: this build has no embedded scenario '" << a.scenario
          << "' (data/telemetry/" << a.scenario << ".csv was missing at configure time)\n";
      return 2;
    }
    log = parse_telemetry_text(text, "<embedded " + a.scenario + ".csv>");
    title = "embedded scenario '" + a.scenario + "' (data/telemetry/" + a.scenario + ".csv, compiled in)";
  } else {
    log = read_telemetry_file(a.telemetry);
    title = a.telemetry;
  }
  ReplayConfig config;
  config.gravity_mps2 = a.gravity > 0.0 ? a.gravity : log_gravity(log);
  config.run_escape = !a.no_escape;
  if (!a.table.empty()) {
    load_parameter_table(a.table, config);
    if (a.gravity > 0.0 && config.rover) {
      err << "sinkwatch replay: --gravity is ignored: the table's rover section sets the gravity\n";
    }
  }
  ReplayResult result;
  {
    Progress bar(err, log.rows.size());
    result = run_replay(log, config, [&bar](double f) { bar(f); });
  }
  ReportOptions options;
  options.verbose = a.verbose;
  options.every_s = a.every_s;
  options.title = title;
  print_report(out, log, config, result, options);
  if (!a.csv.empty()) {
    std::ofstream f(a.csv);
    if (!f) {
      err << "sinkwatch replay: cannot write " << a.csv << '\n';
      return 2;
    }
    write_series_csv(f, log, result);
    out << "  csv        " << result.cycles.size() << " cycles written to " << a.csv << '\n';
  }
  if (!a.plot.empty()) {
    const std::string note = draw_plot(log, config, result, a.plot);
    if (note.empty()) {
      out << "  plot       " << a.plot << '\n';
    } else {
      out << "  plot       note: " << note << '\n';
    }
  }
  return 0;
}

CLI::App* add(CLI::App& app, std::shared_ptr<ReplayArgs> args, std::ostream& out, std::ostream& err, int* exit_code) {
  CLI::App* sub = app.add_subcommand(
      "replay",
      "Replay rover telemetry through the exact fixed-point flight code: wheel loads, sinkage, current limits, "
      "the stop decision and the escape. Without a file: the embedded default scenario.");
  sub->add_option("telemetry", args->telemetry, "telemetry CSV (columns: docs/replay.md)");
  sub->add_option("--scenario", args->scenario, "embedded scenario to replay when no file is given")
      ->check(CLI::IsMember({"embedding", "nominal"}));
  sub->add_option("--csv", args->csv, "write the full time series (every cycle, every wheel) to this CSV");
  sub->add_option("--plot", args->plot, "draw currents vs limits, sinkage and decisions to this .png or .svg (gnuplot)");
  sub->add_flag("-v,--verbose", args->verbose, "print every cycle");
  sub->add_option("--every", args->every_s, "seconds between status lines (besides every change)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--gravity", args->gravity, "gravity in m/s^2 (default: the log's gravity_mps2, else the Moon's)")
      ->check(CLI::Range(0.01, 10.0));
  sub->add_option("--table", args->table,
                  "replay with this uploaded flight parameter table (binary, e.g. from sinkwatch calibrate --table)");
  sub->add_flag("--no-escape", args->no_escape, "do not run the escape sequencer after a stop");
  sub->callback([args, &out, &err, exit_code]() {
    int rc = 2;
    try {
      rc = run(*args, out, err);
    } catch (const std::exception& e) {
      err << "sinkwatch replay: " << e.what() << '\n';
      rc = 2;
    }
    if (exit_code) *exit_code = rc;
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
  return sub;
}

}  // namespace

CLI::App* add_replay_command(CLI::App& app) {
  return add(app, std::make_shared<ReplayArgs>(), std::cout, std::cerr, nullptr);
}

int run_replay_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"sinkwatch"};
  int code = 0;
  add(app, std::make_shared<ReplayArgs>(), out, err, &code);
  std::vector<std::string> argv{"replay"};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e, out, err);
    if (dynamic_cast<const CLI::RuntimeError*>(&e) != nullptr) return e.get_exit_code();
    return app.exit(e, out, err);
  }
  return code;
}

}  // namespace sinkwatch::ground
