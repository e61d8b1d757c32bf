// `sinkwatch campaign` (campaign_command.hpp, docs/campaign.md).
#include "sinkwatch/ground/campaign_command.hpp"

#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_report.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/level_choice.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/replay.hpp"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

struct CampaignArgs {
  std::size_t traverses = 8;
  std::uint64_t seed = 14;
  std::vector<std::string> families;
  std::vector<std::string> held_out;
  std::string table;
  unsigned jobs = 0;
  std::string out_dir;
  std::vector<double> levels_mm;
  std::vector<double> traction_levels;
  std::vector<std::string> faults;
  std::string loss_policy;
  std::string flight_mass = "true";
  std::string calibrate = "none";
  double path_length_m = 16.0;
  bool choose_levels = false;
  double max_false_stop = 0.0;
  std::string table_out;  // default: DIR/chosen.tbl
  Verbosity verbosity;
  std::string command_line = "sinkwatch campaign";
};

std::vector<CampaignFamily> families_of(const std::vector<std::string>& names) {
  std::vector<CampaignFamily> out;
  for (const std::string& n : names) {
    if (n == "none") continue;
    try {
      out.push_back(family_from_name(n));
    } catch (const std::invalid_argument& e) {
      throw_usage_error(e.what());
    }
  }
  return out;
}

// --faults: class names, or "all" for every class.
std::vector<FaultClass> fault_classes_of(const std::vector<std::string>& names) {
  std::vector<FaultClass> out;
  for (const std::string& n : names) {
    try {
      const std::vector<FaultClass> add = n == "all" ? all_fault_classes() : std::vector<FaultClass>{fault_class_from_name(n)};
      for (const FaultClass c : add) {
        if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
      }
    } catch (const std::invalid_argument& e) {
      throw_usage_error(std::string("--faults: ") + e.what());
    }
  }
  return out;
}

// The sweeps' and the choice's levels (--levels, --traction-levels,
// --choose-levels), each checked against the table before any work.
void set_levels(const CampaignArgs& a, CampaignOptions& o) {
  if (!a.levels_mm.empty()) o.sweep_stop_mm = a.levels_mm;
  if (!a.traction_levels.empty()) o.sweep_traction_stop = a.traction_levels;
  if (a.choose_levels) {
    o.choice_grid = choice_grid(o.table, a.levels_mm.empty() ? choice_grid_mm(o.table) : a.levels_mm,
                                o.sweep_traction_stop);
  }
  if (a.choose_levels && std::all_of(o.families.begin(), o.families.end(), [&](CampaignFamily f) {
        return std::find(o.held_out.begin(), o.held_out.end(), f) != o.held_out.end();
      })) {
    throw_usage_error("--choose-levels: every family of --families is --held-out; the choice needs tuning families");
  }
  // Each sinkage level and each coefficient checked alone, so that the
  // message names the option at fault; the choice's grid is their pairs.
  try {
    for (const double level : o.sweep_stop_mm) (void)table_at_stop_level(o.table, level / 1000.0);
    for (const LevelPair& point : o.choice_grid) (void)table_at_stop_level(o.table, point.stop_mm / 1000.0);
  } catch (const std::invalid_argument& e) {
    throw_usage_error(std::string("--levels: ") + e.what());
  }
  if (!a.traction_levels.empty() && !flight::traction_check_on(o.table.traction)) {
    throw_usage_error("--traction-levels: the table has no section 8 (the motion-resistance check is off)");
  }
  try {
    if (flight::traction_check_on(o.table.traction)) {
      for (const double c : o.sweep_traction_stop) (void)table_at_traction_level(o.table, c);
    }
  } catch (const std::invalid_argument& e) {
    throw_usage_error(std::string("--traction-levels: ") + e.what());
  }
  try {
    for (const LevelPair& point : o.choice_grid) (void)table_at_levels(o.table, point);
  } catch (const std::invalid_argument& e) {
    throw_usage_error(std::string("--levels with --traction-levels: ") + e.what());
  }
}

CampaignOptions options_of(const CampaignArgs& a) {
  CampaignOptions o;
  if (a.traverses == 0) throw_usage_error("--traverses must be at least 1");
  o.traverses_per_family = a.traverses;
  o.seed = a.seed;
  if (!a.families.empty()) o.families = families_of(a.families);
  if (o.families.empty()) throw_usage_error("--families names no family");
  if (!a.held_out.empty()) o.held_out = families_of(a.held_out);
  o.faults = fault_classes_of(a.faults);
  o.threads = a.jobs;
  o.path_length_m = a.path_length_m;
  if (!a.table.empty()) {
    ReplayConfig config;
    load_parameter_table(a.table, config);
    o.table = config.table;
    o.table_source = a.table;
    o.rover = config.rover;
  }
  o.flight_mass = flight_mass_from_name(a.flight_mass);
  o.calibration = calibration_soil_from_name(a.calibrate);
  if (o.calibration != CalibrationSoil::none) {
    o.table_source += ", calibrated to each traverse's " + std::string(calibration_soil_name(o.calibration)) + " soil";
  }
  if (!a.loss_policy.empty()) {
    try {
      set_loss_policy(a.loss_policy, o.table, o.table_source);
    } catch (const std::invalid_argument& e) {
      throw_usage_error(e.what());
    }
  }
  set_levels(a, o);
  return o;
}

// A progress bar on stderr when it is a terminal.
std::function<void(std::size_t, std::size_t)> progress_bar(std::ostream& err, bool show) {
  if (!show || isatty(STDERR_FILENO) == 0) return {};
  return [&err](std::size_t done, std::size_t total) {
    const std::size_t width = 40;
    const std::size_t filled = total ? width * done / total : width;
    err << "\r  [" << std::string(filled, '#') << std::string(width - filled, '.') << "] " << done << "/" << total
        << (done == total ? "\n" : "") << std::flush;
  };
}

// --choose-levels: the choice on the tuning families and the chosen table,
// loaded back by the flight code (a table it refuses ends the run, exit 1).
ChoiceFiles choice_files(const CampaignResult& result, double max_false_stop, const std::string& table_path) {
  const LevelChoice choice = choose_levels(result, max_false_stop);
  ChoiceFiles files;
  try {
    EncodedTable table = encode_chosen_table(result, choice);
    files.markdown = level_choice_markdown(result, choice, table_path, table.crc);
    files.json = level_choice_json(result, choice, table_path, table.crc);
    files.table_bytes = std::move(table.bytes);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("--choose-levels: the chosen levels give a table the flight code refuses: ") +
                             e.what() + "; nothing written");
  }
  return files;
}

std::string table_out_path(const CampaignArgs& a) {
  if (a.table_out == "-") throw_usage_error("--table-out: '-' is not allowed (the summary goes to standard output)");
  return a.table_out.empty() ? (std::filesystem::path(a.out_dir) / "chosen.tbl").string() : a.table_out;
}

int run(const CampaignArgs& a, std::ostream& out, std::ostream& err) {
  CampaignOptions options = options_of(a);
  const std::optional<std::string> table_out =
      a.choose_levels ? std::optional<std::string>(table_out_path(a)) : std::nullopt;
  // Every output is checked before the campaign runs (docs/output-files.md).
  CampaignReport report(a.out_dir, find_campaign_gnuplot(), !options.faults.empty(), table_out);
  options.progress = progress_bar(err, a.verbosity.inform());
  if (a.verbosity.verbose) {
    err << "sinkwatch campaign: " << options.families.size() * options.traverses_per_family << " traverses\n";
  }
  const CampaignResult result = run_campaign(options);
  std::optional<ChoiceFiles> choice;
  if (table_out) choice = choice_files(result, a.max_false_stop, *table_out);
  const std::vector<std::string> written = report.write(result, a.command_line, choice ? &*choice : nullptr);
  const bool plots = std::any_of(written.begin(), written.end(), [](const std::string& path) {
    return std::filesystem::path(path).filename() == "lead_by_family.svg";
  });
  out << campaign_summary(result, a.command_line, plots) << (choice ? choice->markdown : std::string());
  for (const std::string& path : written) out << "  wrote " << path << '\n';
  finish_standard_output(out);
  return 0;
}

void add_choice_options(CLI::App* sub, CampaignArgs& a) {
  CLI::Option* choose = sub->add_flag(
      "--choose-levels", a.choose_levels,
      "choose the caution and stop levels on the tuning families for --max-false-stop and write the flight table "
      "(docs/campaign.md, 'Choosing the levels'); with section 8 in the table, its stop coefficient is chosen with "
      "them (the --traction-levels, or off); the sinkage grid is 20 mm to the wheel radius in 2.5 mm steps "
      "unless --levels is given");
  CLI::Option* target = sub->add_option("--max-false-stop", a.max_false_stop,
                                        "target false-stop rate over traverses that never embed, in (0, 1)")
                            ->check(positive_finite_number())
                            ->check(CLI::Validator(
                                [](const std::string& text) {
                                  return std::stod(text) < 1.0 ? std::string() : std::string("must be below 1");
                                },
                                "in (0, 1)"));
  CLI::Option* table_out = non_empty_value(sub->add_option(
      "--table-out", a.table_out, "where --choose-levels writes the chosen flight table (default: OUT/chosen.tbl)"));
  CLI::Option* calibrate = sub->add_option(
      "--calibrate", a.calibrate,
      "each traverse's table calibrated to its soil by a simulated soil-bin test (docs/campaign.md, 'A table "
      "calibrated to the soil'): site (the soil at scale 1), softest (the path's softest soil that still gives a "
      "soil-bin pull), or none");
  calibrate->check(CLI::IsMember({"none", "site", "softest"}))->capture_default_str();
  // One table per traverse: there is no one calibrated table to choose levels for.
  choose->excludes(calibrate);
  choose->needs(target);
  target->needs(choose);
  table_out->needs(choose);
}

void add_options(CLI::App* sub, CampaignArgs& a) {
  sub->add_option("--traverses", a.traverses, "traverses per family")->transform(non_negative_integer())->capture_default_str();
  sub->add_option("--seed", a.seed, "campaign seed: the same seed gives the same files")->transform(non_negative_integer())->capture_default_str();
  non_empty_list(sub->add_option("--families", a.families,
                                 "families to run (default: all): gradual abrupt stepwise one-side slope roll bumps "
                                 "drawn-soil effects")->delimiter(','));
  non_empty_list(sub->add_option("--held-out", a.held_out,
                                 "families kept out of any tuning and reported apart (default: one-side,drawn-soil; "
                                 "'none' for none)")->delimiter(','));
  non_empty_value(sub->add_option("--table", a.table, "flight parameter table (binary; default: the built-in default table)"));
  sub->add_option("-j,--jobs", a.jobs, "threads (default: all cores)")->transform(non_negative_integer());
  non_empty_value(sub->add_option("--out", a.out_dir, "report folder: summary.md, traverses.csv, traverses.json, plots"))
      ->required();
  non_empty_list(sub->add_option("--levels", a.levels_mm, "stop levels of the sweep [mm] (default 25,30,...,70)")
                     ->delimiter(',')
                     ->check(positive_finite_number("mm")));
  non_empty_list(sub->add_option("--traction-levels", a.traction_levels,
                                 "section 8's stop coefficients for its sweep and for --choose-levels "
                                 "(default 0.30,0.34,...,0.50)")
                     ->delimiter(',')
                     ->check(positive_finite_number()));
  sub->add_option("--path-length", a.path_length_m, "length of every traverse [m]")
      ->check(positive_finite_number("m"))
      ->check(CLI::Range(4.0, 200.0))
      ->capture_default_str();
  non_empty_list(sub->add_option("--faults", a.faults,
                                 "sensor-fault classes, one of each injected per traverse (docs/fault-injection.md): "
                                 "stuck-current zero-current dropout-current dropout-side dropout-imu dropout-joints "
                                 "spike-current bias-pitch noise-imu freeze-joints stall-current freewheel-current "
                                 "repeat-clock jump-clock, or all")
                     ->delimiter(','));
  sub->add_option("--loss-policy", a.loss_policy,
                  "what a lasting loss of sensor evidence leads to (the table's section 7, docs/fault-tolerance.md)")
      ->check(CLI::IsMember({"stop", "continue-degraded"}));
  sub->add_option("--flight-mass", a.flight_mass,
                  "the mass the flight code is given: true (each traverse's drawn mass, as an operator who sets it "
                  "has it) or default (the table's section 6, else the Yutu-like 140 kg)")
      ->check(CLI::IsMember({"true", "default"}))
      ->capture_default_str();
  add_choice_options(sub, a);
  add_verbosity_flags(*sub, a.verbosity);
}

CLI::App* add(CLI::App& app, std::shared_ptr<CampaignArgs> args, std::ostream& out, std::ostream& err) {
  CLI::App* sub = app.add_subcommand(
      "campaign",
      "Monte Carlo evaluation of the flight code in the loop over families of simulated traverses: embedding "
      "point, first CAUTION and STOP, lead, outcome, and the ideal sinkage sensor's lead (docs/campaign.md).");
  add_options(sub, *args);
  sub->callback([args, &out, &err]() {
    int rc = exit_status(ExitCode::data_error);
    run_reporting_errors("campaign", out, err, [&]() { rc = run(*args, out, err); });
    if (rc != exit_status(ExitCode::ok)) throw CLI::RuntimeError(rc);
  });
  return sub;
}

}  // namespace

CLI::App* add_campaign_command(CLI::App& app, const std::string& command_line) {
  const std::shared_ptr<CampaignArgs> a = std::make_shared<CampaignArgs>();
  a->command_line = command_line;
  return add(app, a, std::cout, std::cerr);
}

int run_campaign_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"sinkwatch", "sinkwatch"};
  const std::shared_ptr<CampaignArgs> a = std::make_shared<CampaignArgs>();
  for (const std::string& s : args) a->command_line += " " + s;
  add(app, a, out, err);
  std::vector<std::string> argv{"campaign"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command_line(app, argv, out, err);
}

}  // namespace sinkwatch::ground
