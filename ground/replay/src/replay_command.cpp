// `sinkwatch replay` (replay_command.hpp, docs/replay.md).
#include "sinkwatch/ground/replay_command.hpp"

#include "sinkwatch/ground/cli_conventions.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_limits.hpp"

#include "sinkwatch/ground/fault_injection.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_report.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

namespace sinkwatch::ground {
namespace {

struct ReplayArgs {
  std::string telemetry;
  std::string scenario = "embedding";
  std::string csv;
  std::string plot;
  Verbosity verbosity;  // -q: no progress bar or notes; -v: every cycle
  double every_s = 30.0;
  double gravity = 0.0;  // 0: from the log
  double mass_kg = 0.0;  // --mass-kg; 0: the log's mass_kg, else the table's, else the default
  bool no_escape = false;
  std::string table;
  std::string loss_policy;
  std::string inject;             // fault specs (fault_injection.hpp); empty: none
  std::uint64_t inject_seed = 18;  // the noise of noise and freewheel faults
};

// A bar on stderr, only when a person is watching it.
class Progress {
 public:
  Progress(std::ostream& err, std::size_t rows, bool allowed)
      : err_(err), on_(allowed && &err == &std::cerr && isatty(fileno(stderr)) != 0 && rows >= 1000) {}
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

// The log to replay and the report's title for it.
struct LoadedLog {
  TelemetryLog log;
  std::string title;
};

// The telemetry file, or the embedded scenario when no file is given;
// nothing (the error printed on `err`) when this build lacks the scenario.
std::optional<LoadedLog> load_log(const ReplayArgs& a, std::ostream& err) {
  if (!a.telemetry.empty()) {
    LoadedLog loaded{read_telemetry_file(a.telemetry), ""};
    loaded.title = loaded.log.source;  // "<stdin>" for "-"
    return loaded;
  }
  const std::string& text = embedded_scenario_text(a.scenario);
  if (text.empty()) {
    err << error_prefix("replay") << "this build has no embedded scenario '" << a.scenario
        << "' (data/telemetry/" << a.scenario << ".csv was missing at configure time)\n";
    return std::nullopt;
  }
  return LoadedLog{parse_telemetry_text(text, "<embedded " + a.scenario + ".csv>"),
                   "embedded scenario '" + a.scenario + "' (data/telemetry/" + a.scenario +
                       ".csv, compiled in)"};
}

// Gravity (--gravity, else the log's), the escape switch and the uploaded
// table, whose rover section overrides --gravity (with a note).
ReplayConfig replay_config(const ReplayArgs& a, const TelemetryLog& log, std::ostream& err) {
  ReplayConfig config;
  config.gravity_mps2 = a.gravity > 0.0 ? a.gravity : log_gravity(log);
  config.run_escape = !a.no_escape;
  if (!a.table.empty()) {
    load_parameter_table(a.table, config);
    if (a.gravity > 0.0 && config.rover && a.verbosity.inform()) {
      err << error_prefix("replay") << "note: --gravity is ignored: the table's rover section sets the gravity\n";
    }
  }
  resolve_rover_mass(log, a.mass_kg > 0.0 ? std::optional<double>(a.mass_kg) : std::nullopt, config);
  if (config.mass_source == MassSource::log_header && config.rover && a.verbosity.inform() &&
      fx::to_double(config.rover->mass_kg.q()) != *config.mass_kg) {
    err << error_prefix("replay") << "note: the log's mass_kg (" << *config.mass_kg
        << " kg) replaces the table's section-6 mass (" << fx::to_double(config.rover->mass_kg.q())
        << " kg); --mass-kg sets another\n";
  }
  if (!a.loss_policy.empty()) {
    try {
      set_loss_policy(a.loss_policy, config.table, config.table_source);
    } catch (const std::invalid_argument& e) {
      throw_usage_error(e.what());
    }
  }
  return config;
}

// --inject: the faults applied to the log before the replay (validated when
// the command line was parsed); a fault whose window misses the log is a note.
void inject_faults(const ReplayArgs& a, TelemetryLog& log, std::ostream& err) {
  if (a.inject.empty()) return;
  const std::vector<AppliedFault> applied = apply_faults(log, parse_faults(a.inject), a.inject_seed);
  for (const AppliedFault& f : applied) {
    if (f.rows == 0 && a.verbosity.inform()) {
      err << error_prefix("replay") << "note: fault '" << f.spec.text()
          << "' changes no row: its window lies outside the log\n";
    }
  }
}

// CLI11's check for --inject: the message of the first spec that cannot be read.
CLI::Validator fault_specs() {
  return CLI::Validator(
      [](const std::string& value) {
        try {
          (void)parse_faults(value);
        } catch (const FaultSpecError& e) {
          return std::string(e.what());
        }
        return std::string();
      },
      "KIND:TARGET@START[+DURATION][=VALUE],...", "fault specs");
}

// The CSV goes through a temporary (output_file.hpp), renamed once the plot
// is drawn too, so an error leaves neither half-written; "-" writes it to
// `out`. Each output written gets a line in the report.
void write_outputs(const ReplayArgs& a, const TelemetryLog& log, const ReplayConfig& config,
                   const ReplayResult& result, std::ostream& out) {
  std::optional<OutputFile> csv;
  if (!a.csv.empty()) {
    csv.emplace(a.csv, &out);
    write_series_csv(csv->stream(), log, result);
    csv->close();
  }
  std::string plot_note;
  if (!a.plot.empty()) {
    plot_note = draw_plot(log, config, result, a.plot);
  }
  if (csv) {
    csv->commit();
    out << "  csv        " << result.cycles.size() << " cycles written to " << a.csv << '\n';
  }
  if (!a.plot.empty()) {
    if (plot_note.empty()) {
      out << "  plot       " << a.plot << '\n';
    } else {
      out << "  plot       note: " << plot_note << '\n';
    }
  }
}

int run(const ReplayArgs& a, std::ostream& out, std::ostream& err) {
  // Every output is checked before the replay (docs/output-files.md).
  if (!a.csv.empty()) (void)check_output_path(a.csv);
  if (!a.plot.empty()) check_plot_path(a.plot);
  std::optional<LoadedLog> loaded = load_log(a, err);
  if (!loaded) {
    return exit_status(ExitCode::data_error);
  }
  TelemetryLog& log = loaded->log;
  inject_faults(a, log, err);
  const ReplayConfig config = replay_config(a, log, err);
  ReplayResult result;
  {
    Progress bar(err, log.rows.size(), a.verbosity.inform());
    result = run_replay(log, config, [&bar](double f) { bar(f); });
  }
  ReportOptions options;
  options.verbose = a.verbosity.verbose;
  options.every_s = a.every_s;
  options.title = loaded->title;
  print_report(out, log, config, result, options);
  write_outputs(a, log, config, result, out);
  finish_standard_output(out);
  return 0;
}

CLI::App* add(CLI::App& app, std::shared_ptr<ReplayArgs> args, std::ostream& out, std::ostream& err) {
  CLI::App* sub = app.add_subcommand(
      "replay",
      "Replay rover telemetry through the exact fixed-point flight code: wheel loads, sinkage, current limits, "
      "the stop decision and the escape. Without a file: the embedded default scenario.");
  CLI::Option* telemetry = non_empty_value(
      sub->add_option("telemetry", args->telemetry, "telemetry CSV, '-' for standard input (columns: docs/replay.md)"));
  CLI::Option* scenario = sub->add_option("--scenario", args->scenario, "embedded scenario to replay when no file is given")
                              ->check(CLI::IsMember({"embedding", "nominal"}))
                              ->capture_default_str();
  telemetry->excludes(scenario);
  non_empty_value(sub->add_option("--csv", args->csv, "write the full time series (every cycle, every wheel) to this CSV"));
  non_empty_value(
      sub->add_option("--plot", args->plot, "draw currents vs limits, sinkage and decisions to this .png or .svg (gnuplot)"));
  sub->add_option("--every", args->every_s, "seconds between status lines (besides every change)")
      ->check(positive_finite_number())
      ->capture_default_str();
  sub->add_option("--gravity", args->gravity, "gravity in m/s^2 (default: the log's gravity_mps2, else the Moon's)")
      ->check(finite_number())
      ->check(CLI::Range(0.01, 10.0));
  sub->add_option("--mass-kg", args->mass_kg,
                  "the rover's mass in kg (default: the log's mass_kg, else the table's section 6, else 140)")
      ->check(positive_finite_number("kg"))
      ->check(CLI::Range(0.0, flight::limits::kMaxMassKg));
  non_empty_value(sub->add_option(
      "--table", args->table,
      "replay with this uploaded flight parameter table (binary, e.g. from sinkwatch calibrate --table)"));
  sub->add_flag("--no-escape", args->no_escape, "do not run the escape sequencer after a stop");
  sub->add_option("--loss-policy", args->loss_policy,
                  "what a lasting loss of sensor evidence leads to (the table's section 7, docs/fault-tolerance.md)")
      ->check(CLI::IsMember({"stop", "continue-degraded"}));
  CLI::Option* inject =
      sub->add_option("--inject", args->inject,
                      "inject sensor faults before the replay, e.g. stuck:LM_current@120s+30s,dropout:imu@200s+5s "
                      "(docs/fault-injection.md)")
          ->check(fault_specs());
  sub->add_option("--inject-seed", args->inject_seed, "seed of the injected noise (noise, freewheel)")
      ->transform(non_negative_integer())
      ->capture_default_str()
      ->needs(inject);
  add_verbosity_flags(*sub, args->verbosity);  // -v: print every cycle
  sub->callback([args, &out, &err]() {
    int rc = exit_status(ExitCode::data_error);
    run_reporting_errors("replay", out, err, [&]() { rc = run(*args, out, err); });
    if (rc != exit_status(ExitCode::ok)) throw CLI::RuntimeError(rc);
  });
  return sub;
}

}  // namespace

CLI::App* add_replay_command(CLI::App& app) {
  return add(app, std::make_shared<ReplayArgs>(), std::cout, std::cerr);
}

int run_replay_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"sinkwatch", "sinkwatch"};
  add(app, std::make_shared<ReplayArgs>(), out, err);
  std::vector<std::string> argv{"replay"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command_line(app, argv, out, err);
}

}  // namespace sinkwatch::ground
