// diagnose_command.cpp: the `sinkwatch diagnose` subcommand.
#include "sinkwatch/ground/diagnose_command.hpp"

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

namespace sinkwatch {
namespace ground {

namespace {

// A progress bar on stderr when it is a terminal: "\r[#####     ] 5/14".
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream* out) : out_(out) {}
  void operator()(std::size_t done, std::size_t total) const {
    constexpr std::size_t kWidth = 30;
    const std::size_t filled = total > 0 ? kWidth * done / total : kWidth;
    *out_ << "\rsinkwatch diagnose: [" << std::string(filled, '#') << std::string(kWidth - filled, ' ') << "] " << done
          << "/" << total << " candidate fits" << (done == total ? "\n" : "") << std::flush;
  }

 private:
  std::ostream* out_;
};

DiagnosisData read_data(const std::string& path, const DiagnoseOptions& options) {
  DiagnosisReadOptions read_options;
  read_options.radius_m = options.radius_m;
  read_options.width_m = options.width_m;
  read_options.load_n = options.load_n;
  return read_diagnosis_data(path, read_options);
}

std::unique_ptr<DiagnosisModel> make_model(const DiagnoseOptions& options, const DiagnosisData& data) {
  if (options.model == "estimator") {
    return std::make_unique<EstimatorModel>();
  }
  if (!data.has_loads) {
    throw std::invalid_argument(data.source +
                                ": the wong-reece model needs the wheel load of every row (a load_N column or --load)");
  }
  SimParameters start = default_parameters(options.soil);
  start.gravity_m_s2 = options.gravity_m_s2;
  start.quadrature_rel_tol = options.quadrature_rel_tol;
  std::vector<std::string> names = WongReeceModel::default_base_parameters();
  if (!options.base_fit.empty()) {
    names.clear();
    std::stringstream list(options.base_fit);
    std::string name;
    while (std::getline(list, name, ',')) {
      (void)get_parameter(start, name);  // throws naming an unknown parameter
      names.push_back(name);
    }
  }
  return std::make_unique<WongReeceModel>(start, names);
}

// The settings of the run, the caller's part stated in the report.
DiagnosisSettings run_settings(const DiagnoseOptions& options) {
  DiagnosisSettings settings;
  std::ostringstream gravity;
  gravity << options.gravity_m_s2;
  std::ostringstream tolerance;
  tolerance << options.quadrature_rel_tol;
  settings.inputs.push_back({"model", options.model});
  if (options.model == "wong-reece") {
    settings.inputs.push_back({"gravity (m/s^2)", gravity.str()});
    settings.inputs.push_back({"soil preset (start of the fit)", options.soil});
    settings.inputs.push_back(
        {"base parameters fitted", options.base_fit.empty() ? "soil.kphi,soil.n,soil.c_pa,soil.phi_deg,soil.K_m"
                                                            : options.base_fit});
    settings.inputs.push_back({"simulator quadrature tolerance (relative)", tolerance.str()});
  }
  if (options.load_n) {
    std::ostringstream load;
    load << *options.load_n;
    settings.inputs.push_back({"load of every row (N, --load)", load.str()});
  }
  if (options.progress != nullptr) {
    settings.progress = ProgressBar(options.progress);
  }
  return settings;
}

// Every input number and output path is checked before any work
// (docs/input-files.md, docs/output-files.md).
void check_before_work(const DiagnoseOptions& options) {
  if (options.model != "wong-reece" && options.model != "estimator") {
    throw std::invalid_argument("--model must be wong-reece or estimator, not '" + options.model + "'");
  }
  if (!std::isfinite(options.gravity_m_s2) || options.gravity_m_s2 <= 0.0) {
    throw std::invalid_argument("--gravity must be a positive finite number in m/s^2");
  }
  if (!(options.quadrature_rel_tol >= 1e-15 && options.quadrature_rel_tol <= 1e-3)) {
    throw std::invalid_argument("the quadrature tolerance must be in [1e-15, 1e-3]");
  }
  if (!options.json_path.empty()) {
    (void)check_output_path(options.json_path);
  }
  if (!options.report_dir.empty()) {
    check_report_directory(options.report_dir);
  }
}

// Computes nothing: writes the result. The JSON goes through a temporary that
// is renamed only once the summary and the report are out (output_file.hpp);
// "-" writes it to `out`.
void write_outputs(const DiagnosisResult& result, const DiagnoseOptions& options, std::ostream& out) {
  std::optional<OutputFile> json;
  if (!options.json_path.empty()) {
    json.emplace(options.json_path, &out);
    json->write(to_json(result));
    json->close();
  }
  out << summary_markdown(result);
  finish_standard_output(out);
  if (!options.report_dir.empty()) {
    for (const std::string& note : write_report(result, options.report_dir, find_gnuplot())) {
      out << "\nreport: " << note << '\n';
    }
  }
  finish_standard_output(out);
  if (json) {
    json->commit();
  }
}

}  // namespace

void run_diagnose(const DiagnoseOptions& options, std::ostream& out) {
  check_before_work(options);
  const DiagnosisData data = read_data(options.data_path, options);
  std::optional<DiagnosisData> base;
  if (!options.base_path.empty()) {
    base = read_data(options.base_path, options);
  }
  if (options.detail != nullptr) {
    *options.detail << "sinkwatch diagnose: " << data.rows.size() << " rows from " << data.source << ", model "
                    << options.model << (base ? ", base condition " + base->source : std::string()) << '\n';
  }
  const std::unique_ptr<DiagnosisModel> model = make_model(options, data);
  if (base && options.model == "wong-reece" && !base->has_loads) {
    throw std::invalid_argument(base->source +
                                ": the wong-reece model needs the wheel load of every row (a load_N column or --load)");
  }
  const DiagnosisSettings settings = run_settings(options);
  const DiagnosisResult result = base ? diagnose_against_base(*model, {base->rows, base->source}, data.rows,
                                                              data.source, settings)
                                      : diagnose(*model, data.rows, data.source, settings);
  write_outputs(result, options, out);
}

namespace {

// What the parse fills in, shared by the option groups and the callback.
struct DiagnoseCli {
  DiagnoseOptions options;
  double radius = 0.0;
  double width = 0.0;
  double load = 0.0;
  Verbosity verbosity;
  CLI::Option* radius_option = nullptr;
  CLI::Option* width_option = nullptr;
  CLI::Option* load_option = nullptr;
  CLI::Option* soil_option = nullptr;
  CLI::Option* gravity_option = nullptr;
  CLI::Option* fit_option = nullptr;
};

void add_data_options(CLI::App& sub, DiagnoseCli& cli) {
  non_empty_value(sub.add_option("--real", cli.options.data_path,
                                 "soil-bin CSV, '-' for standard input (the calibrate command's formats; "
                                 "wheel_width_m column or --width too)")
                      ->required());
  non_empty_value(sub.add_option(
      "--base", cli.options.base_path,
      "two-condition diagnosis: soil-bin CSV of the base condition (a smooth wheel, a reference simulant); the base "
      "model is fitted on all its rows and held fixed on --real, and candidates fit only their own terms"));
  cli.radius_option = sub.add_option("--radius", cli.radius, "wheel radius in metres (else wheel_radius_m column)")
                          ->check(positive_finite_number("m"));
  cli.width_option = sub.add_option("--width", cli.width, "wheel width in metres (else wheel_width_m column)")
                         ->check(positive_finite_number("m"));
  cli.load_option = sub.add_option("--load", cli.load, "wheel load in newtons of every row, for files without load_N")
                        ->check(positive_finite_number("N"));
  non_empty_value(sub.add_option("--json", cli.options.json_path, "write where / ranking / base_fit as JSON to this file"));
  non_empty_value(
      sub.add_option("--report", cli.options.report_dir, "write summary.md and residual plots (gnuplot SVG) to this folder"));
}

void add_model_options(CLI::App& sub, DiagnoseCli& cli) {
  sub.add_option("--model", cli.options.model, "base model: wong-reece (simulator) or estimator (Eq. 11)")
      ->check(CLI::IsMember({"wong-reece", "estimator"}))
      ->capture_default_str();
  // The options of the wong-reece model only; --model estimator refuses them.
  cli.soil_option = sub.add_option("--soil", cli.options.soil, "wong-reece: soil preset the fit starts from")
                        ->check(CLI::IsMember(soil_preset_names()))
                        ->capture_default_str();
  cli.gravity_option = sub.add_option("--gravity", cli.options.gravity_m_s2, "wong-reece: gravity in m/s^2")
                           ->check(positive_finite_number("m/s^2"))
                           ->capture_default_str();
  cli.fit_option = non_empty_list(
      sub.add_option("--fit", cli.options.base_fit,
                     "wong-reece: simulator parameters of the base fit, comma-separated (default "
                     "soil.kphi,soil.n,soil.c_pa,soil.phi_deg,soil.K_m)"));
}

// After the parse: the optional numbers, the model's own options, the outputs
// of -v and of the progress bar; usage errors exit with code 2.
void apply_parsed(DiagnoseCli& cli) {
  DiagnoseOptions& options = cli.options;
  if (cli.radius_option->count() > 0) {
    options.radius_m = cli.radius;
  }
  if (cli.width_option->count() > 0) {
    options.width_m = cli.width;
  }
  if (cli.load_option->count() > 0) {
    options.load_n = cli.load;
  }
  if (options.model == "estimator") {
    for (const CLI::Option* option : {cli.soil_option, cli.gravity_option, cli.fit_option}) {
      if (option->count() > 0) {
        throw_usage_error(option->get_name() + " applies only to --model wong-reece; --model estimator has no such setting");
      }
    }
  } else if (!options.base_fit.empty()) {
    const SimParameters start = default_parameters(options.soil);
    std::stringstream list(options.base_fit);
    std::string name;
    while (std::getline(list, name, ',')) {
      try {
        (void)get_parameter(start, name);
      } catch (const std::exception& e) {
        throw_usage_error(std::string("--fit: ") + e.what());
      }
    }
  }
  options.detail = cli.verbosity.verbose ? &std::cerr : nullptr;
  // A progress bar only where someone watches: a terminal, and not -q.
  options.progress = cli.verbosity.inform() && isatty(STDERR_FILENO) != 0 ? &std::cerr : nullptr;
}

}  // namespace

void add_diagnose_command(CLI::App& app) {
  auto cli = std::make_shared<DiagnoseCli>();
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Diagnose the sim-to-real gap: where a model misses soil-bin data, which unmodelled effect causes it, "
      "and how far the held-out gap shrinks once that effect is added");
  add_data_options(*sub, *cli);
  add_model_options(*sub, *cli);
  add_verbosity_flags(*sub, cli->verbosity);
  sub->callback([cli]() {
    apply_parsed(*cli);
    run_reporting_errors("diagnose", std::cout, std::cerr, [&cli]() { run_diagnose(cli->options, std::cout); });
  });
}

}  // namespace ground
}  // namespace sinkwatch
