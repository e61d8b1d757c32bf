// `sinkwatch simulate` (CLI11). Resolves the flags into SimParameters, a grid
// and a noise model, then writes the dataset as CSV.
#include "sinkwatch/ground/simulate_command.hpp"

#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/sim_dataset.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace sinkwatch::ground {
namespace {

struct SimulateOptions {
  std::string soil = "hit-lss1";
  std::vector<std::string> sets;
  std::string body = "earth";
  double gravity = 0.0;
  double radius = 0.15;
  double width = 0.15;
  std::string loads;
  std::string masses;
  std::string slips = "0:0.05:0.7";
  std::vector<std::string> effects;
  std::vector<std::string> noise;
  std::uint64_t seed = 1;
  std::string out_path;
  bool list = false;
  Verbosity verbosity;
};

void print_catalogue(std::ostream& out) {
  out << "soils:\n";
  for (const SoilPreset& p : soil_presets()) {
    out << "  " << p.soil.name << "  (" << p.source << ")\n";
  }
  out << "bodies:\n";
  for (const Body& b : bodies()) out << "  " << b.name << "  g = " << b.gravity_m_s2 << " m/s^2\n";
  const SimParameters defaults = default_parameters();
  out << "effects (--effect NAME[:form=FORM,param=value,...]), one line per form (the first is the default), "
         "defaults in brackets:\n";
  for (Effect e : kAllEffects) {
    for (const std::string& form : effect_forms(e)) {
      out << "  " << effect_name(e) << ':';
      if (effect_forms(e).size() > 1) out << " form=" << form;
      for (const std::string& name : effect_parameter_names(e, form)) {
        out << ' ' << name.substr(name.find('.') + 1) << '[' << get_parameter(defaults, name) << ']';
      }
      out << '\n';
    }
  }
  out << "parameters (--set NAME=VALUE):\n";
  for (const ParameterInfo& info : parameter_catalogue()) {
    out << "  " << info.name << " [" << info.unit << "]  " << info.description << '\n';
  }
}

// Everything the options describe, parsed and checked before any work.
struct SimulateSetup {
  SimParameters params;
  std::vector<double> loads;
  std::vector<double> slips;
  NoiseModel noise;
  std::string gravity_text;
};

std::vector<double> checked_slips(const std::string& text) {
  std::vector<double> slips = parse_number_list(text);
  for (double s : slips) {
    if (!(s >= 0.0 && s <= 1.0)) {
      throw std::invalid_argument("--slips: slip " + std::to_string(s) + " is outside [0, 1]");
    }
  }
  return slips;
}

std::vector<double> checked_loads(const SimulateOptions& o, double gravity_m_s2) {
  std::vector<double> loads;
  if (!o.loads.empty()) {
    loads = parse_number_list(o.loads);
  } else {
    for (double m : parse_number_list(o.masses.empty() ? "3,7,10,15,20" : o.masses)) {
      loads.push_back(m * gravity_m_s2);
    }
  }
  for (double w : loads) {
    if (!(w > 0.0)) throw std::invalid_argument("loads and masses must be > 0");
  }
  return loads;
}

SimulateSetup parse_setup(const SimulateOptions& o) {
  SimulateSetup setup;
  try {
    SimParameters& params = setup.params;
    params = default_parameters(o.soil);
    params.wheel.radius_m = o.radius;
    params.wheel.width_m = o.width;
    if (o.gravity > 0.0) {
      params.gravity_m_s2 = o.gravity;
      setup.gravity_text = "custom";
    } else {
      params.gravity_m_s2 = body_gravity(o.body);
      setup.gravity_text = o.body;
    }
    for (const std::string& s : o.sets) apply_parameter_assignment(s, params);
    for (const std::string& e : o.effects) apply_effect_spec(e, params);
    for (const std::string& n : o.noise) apply_noise_spec(n, setup.noise);
    setup.slips = checked_slips(o.slips);
    setup.loads = checked_loads(o, params.gravity_m_s2);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(e.what());
  }
  return setup;
}

void run(const SimulateOptions& o, const std::string& command_line, std::ostream& out, std::ostream& err) {
  if (o.list) {
    print_catalogue(out);
    finish_standard_output(out);
    return;
  }
  // The output is checked before the work (docs/output-files.md).
  if (!o.out_path.empty()) (void)check_output_path(o.out_path);
  const SimulateSetup setup = parse_setup(o);
  std::vector<DatasetRow> rows;
  try {
    rows = generate_dataset(setup.params, setup.loads, setup.slips, setup.noise, o.seed);
  } catch (const SimError& e) {
    err << error_prefix("simulate") << e.what() << '\n';
    throw CLI::RuntimeError(exit_status(ExitCode::data_error));
  }
  if (o.verbosity.verbose) {
    err << error_prefix("simulate") << rows.size() << " rows: " << setup.loads.size() << " loads x "
        << setup.slips.size() << " slips, seed " << o.seed << '\n';
  }
  const std::vector<std::string> comments = {
      "sinkwatch simulate: reference wheel-soil simulator (Wong-Reece rigid wheel, Bekker + Janosi-Hanamoto; "
      "docs/simulator.md)",
      "command: " + command_line,
      describe_soil(setup.params) + " (" + setup.gravity_text + ")",
      "effects: " + describe_effects(setup.params),
      "noise: " + describe_noise(setup.noise),
      "seed: " + std::to_string(o.seed),
  };
  // --out through a temporary renamed into place, or standard output ("-" or
  // no --out), every write checked (output_file.hpp); an error throws
  // OutputError naming the path.
  OutputFile file(o.out_path.empty() ? std::string("-") : o.out_path, &out);
  write_soil_bin_csv(file.stream(), rows, comments);
  file.commit();
}

// The catalogue takes no settings: refuse them rather than ignore them.
void refuse_settings_with_list(const CLI::App& sub) {
  for (const CLI::Option* option : sub.get_options()) {
    const std::string& name = option->get_name();
    if (option->count() > 0 && name != "--list" && name != "--quiet" && name != "--verbose") {
      throw_usage_error("--list excludes " + name);
    }
  }
}

}  // namespace

CLI::App* add_simulate_command(CLI::App& app, std::string command_line, std::ostream& out, std::ostream& err) {
  auto opts = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate", "Reference wheel-soil simulator: soil-bin style CSV over a grid of loads x slips");
  sub->add_option("--soil", opts->soil, "Soil preset (see --list)")->capture_default_str();
  non_empty_value(
      sub->add_option("--set", opts->sets, "Override a model parameter, NAME=VALUE (repeatable; see --list)"));
  auto* body = sub->add_option("--body", opts->body, "earth, moon or mars (sets gravity)")->capture_default_str();
  auto* gravity = sub->add_option("--gravity", opts->gravity, "Gravity in m/s^2 (instead of --body)")
                      ->check(positive_finite_number("m/s^2"));
  body->excludes(gravity);
  sub->add_option("--radius", opts->radius, "Wheel radius, m")->check(positive_finite_number("m"))->capture_default_str();
  sub->add_option("--width", opts->width, "Wheel width, m")->check(positive_finite_number("m"))->capture_default_str();
  auto* loads = non_empty_list(
      sub->add_option("--loads", opts->loads, "Wheel loads in N: list a,b,c or range start:step:stop"));
  auto* masses = non_empty_list(sub->add_option(
      "--masses", opts->masses, "Masses in kg on the body (W = m g), list or range [default 3,7,10,15,20]"));
  loads->excludes(masses);
  non_empty_list(
      sub->add_option("--slips", opts->slips, "Slip ratios in [0, 1]: list or start:step:stop")->capture_default_str());
  non_empty_value(
      sub->add_option("--effect", opts->effects, "Switch an effect on: NAME[:param=value,...] (repeatable)"));
  non_empty_value(sub->add_option("--noise", opts->noise,
                                  "Measurement noise: CHANNEL=VALUE[%],... with channels sinkage (m), torque (N m), "
                                  "drawbar_pull (N); '%' makes it relative (repeatable)"));
  sub->add_option("--seed", opts->seed, "Noise seed")->transform(non_negative_integer())->capture_default_str();
  non_empty_value(sub->add_option("--out", opts->out_path, "Output CSV file, '-' for stdout [default: stdout]"));
  sub->add_flag("--list", opts->list, "List soils, bodies, effects and parameters, then exit");
  add_verbosity_flags(*sub, opts->verbosity);
  std::ostream* out_ptr = &out;
  std::ostream* err_ptr = &err;
  sub->callback([sub, opts, command_line, out_ptr, err_ptr]() {
    if (opts->list) refuse_settings_with_list(*sub);
    run_reporting_errors("simulate", *out_ptr, *err_ptr, [&]() { run(*opts, command_line, *out_ptr, *err_ptr); });
  });
  return sub;
}

CLI::App* add_simulate_command(CLI::App& app, std::string command_line) {
  return add_simulate_command(app, std::move(command_line), std::cout, std::cerr);
}

std::string join_command_line(int argc, const char* const* argv) {
  std::string joined;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (i == 0) {
      // Record the program by its name only, so the file does not depend on the build path.
      const std::size_t slash = a.find_last_of('/');
      if (slash != std::string::npos) a = a.substr(slash + 1);
    }
    const bool quote = a.empty() || a.find_first_of(" \t'\"\\$") != std::string::npos;
    if (quote) {
      std::string q = "'";
      for (char c : a) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      a = q + "'";
    }
    joined += (i ? " " : "") + a;
  }
  return joined;
}

int run_simulate(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"sinkwatch", "sinkwatch"};
  app.require_subcommand(1);
  std::vector<const char*> argv = {"sinkwatch", "simulate"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  add_simulate_command(app, join_command_line(static_cast<int>(argv.size()), argv.data()), out, err);
  std::vector<std::string> words{"simulate"};
  words.insert(words.end(), args.begin(), args.end());
  return run_command_line(app, words, out, err);
}

}  // namespace sinkwatch::ground
