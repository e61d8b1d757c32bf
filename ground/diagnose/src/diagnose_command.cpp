// diagnose_command.cpp: the `sinkwatch diagnose` subcommand.
#include "sinkwatch/ground/diagnose_command.hpp"

#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

namespace sinkwatch {
namespace ground {

void run_diagnose(const DiagnoseOptions& options, std::ostream& out) {
  if (options.model != "wong-reece" && options.model != "estimator") {
    throw std::invalid_argument("--model must be wong-reece or estimator, not '" + options.model + "'");
  }
  // Every output is checked before the run (docs/output-files.md).
  if (!options.json_path.empty()) {
    (void)check_output_path(options.json_path);
  }
  if (!options.report_dir.empty()) {
    check_report_directory(options.report_dir);
  }
  DiagnosisReadOptions read_options;
  read_options.radius_m = options.radius_m;
  read_options.width_m = options.width_m;
  read_options.load_n = options.load_n;
  const DiagnosisData data = read_diagnosis_data(options.data_path, read_options);
  if (options.detail != nullptr) {
    *options.detail << "sinkwatch diagnose: " << data.rows.size() << " rows from " << data.source << ", model "
                    << options.model << '\n';
  }

  std::unique_ptr<DiagnosisModel> model;
  if (options.model == "estimator") {
    model = std::make_unique<EstimatorModel>();
  } else {
    if (!data.has_loads) {
      throw std::invalid_argument(data.source +
                                  ": the wong-reece model needs the wheel load of every row (a load_N column or --load)");
    }
    SimParameters start = default_parameters(options.soil);
    start.gravity_m_s2 = options.gravity_m_s2;
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
    model = std::make_unique<WongReeceModel>(start, names);
  }
  const DiagnosisResult result = diagnose(*model, data.rows, data.source);

  // Compute everything before writing anything. The JSON goes through a
  // temporary that is renamed only once the summary and the report are out
  // (output_file.hpp); "-" writes it to `out`.
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

void add_diagnose_command(CLI::App& app) {
  auto options = std::make_shared<DiagnoseOptions>();
  auto radius = std::make_shared<double>(0.0);
  auto width = std::make_shared<double>(0.0);
  auto load = std::make_shared<double>(0.0);
  auto verbosity = std::make_shared<Verbosity>();
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Diagnose the sim-to-real gap: where a model misses soil-bin data, which unmodelled effect causes it, "
      "and how far the held-out gap shrinks once that effect is added");
  non_empty_value(sub->add_option("--real", options->data_path,
                                  "soil-bin CSV, '-' for standard input (the calibrate command's formats; "
                                  "wheel_width_m column or --width too)")
                      ->required());
  sub->add_option("--model", options->model, "base model: wong-reece (simulator) or estimator (Eq. 11)")
      ->check(CLI::IsMember({"wong-reece", "estimator"}))
      ->capture_default_str();
  CLI::Option* radius_option = sub->add_option("--radius", *radius, "wheel radius in metres (else wheel_radius_m column)")
                                   ->check(positive_finite_number());
  CLI::Option* width_option = sub->add_option("--width", *width, "wheel width in metres (else wheel_width_m column)")
                                  ->check(positive_finite_number());
  CLI::Option* load_option =
      sub->add_option("--load", *load, "wheel load in newtons of every row, for files without load_N")
          ->check(positive_finite_number());
  // The options of the wong-reece model only; --model estimator refuses them.
  CLI::Option* soil_option = sub->add_option("--soil", options->soil, "wong-reece: soil preset the fit starts from")
                                 ->check(CLI::IsMember(soil_preset_names()))
                                 ->capture_default_str();
  CLI::Option* gravity_option = sub->add_option("--gravity", options->gravity_m_s2, "wong-reece: gravity in m/s^2")
                                    ->check(positive_finite_number())
                                    ->capture_default_str();
  CLI::Option* fit_option = non_empty_list(
      sub->add_option("--fit", options->base_fit,
                      "wong-reece: simulator parameters of the base fit, comma-separated (default "
                      "soil.kphi,soil.n,soil.c_pa,soil.phi_deg,soil.K_m)"));
  non_empty_value(sub->add_option("--json", options->json_path, "write where / ranking / base_fit as JSON to this file"));
  non_empty_value(
      sub->add_option("--report", options->report_dir, "write summary.md and residual plots (gnuplot SVG) to this folder"));
  add_verbosity_flags(*sub, *verbosity);
  sub->callback([options, radius, radius_option, width, width_option, load, load_option, soil_option,
                 gravity_option, fit_option, verbosity]() {
    if (radius_option->count() > 0) {
      options->radius_m = *radius;
    }
    if (width_option->count() > 0) {
      options->width_m = *width;
    }
    if (load_option->count() > 0) {
      options->load_n = *load;
    }
    if (options->model == "estimator") {
      for (const CLI::Option* option : {soil_option, gravity_option, fit_option}) {
        if (option->count() > 0) {
          throw_usage_error(option->get_name() +
                            " applies only to --model wong-reece; --model estimator has no such setting");
        }
      }
    } else if (!options->base_fit.empty()) {
      const SimParameters start = default_parameters(options->soil);
      std::stringstream list(options->base_fit);
      std::string name;
      while (std::getline(list, name, ',')) {
        try {
          (void)get_parameter(start, name);
        } catch (const std::exception& e) {
          throw_usage_error(std::string("--fit: ") + e.what());
        }
      }
    }
    options->detail = verbosity->verbose ? &std::cerr : nullptr;
    run_reporting_errors("diagnose", std::cout, std::cerr,
                         [&options]() { run_diagnose(*options, std::cout); });
  });
}

}  // namespace ground
}  // namespace sinkwatch
