// diagnose_command.cpp: the `sinkwatch diagnose` subcommand.
#include "sinkwatch/ground/diagnose_command.hpp"

#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

namespace sinkwatch {
namespace ground {

void run_diagnose(const DiagnoseOptions& options, std::ostream& out) {
  if (options.model != "wong-reece" && options.model != "estimator") {
    throw std::invalid_argument("--model must be wong-reece or estimator, not '" + options.model + "'");
  }
  DiagnosisReadOptions read_options;
  read_options.radius_m = options.radius_m;
  read_options.width_m = options.width_m;
  read_options.load_n = options.load_n;
  const DiagnosisData data = read_diagnosis_data(options.data_path, read_options);

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

  // Compute everything before writing anything.
  const std::string json = options.json_path.empty() ? std::string() : to_json(result);
  out << summary_markdown(result);
  if (!options.json_path.empty()) {
    std::ofstream f(options.json_path);
    f << json;
    f.close();
    if (!f) {
      throw std::runtime_error(options.json_path + ": cannot write the file");
    }
  }
  if (!options.report_dir.empty()) {
    for (const std::string& note : write_report(result, options.report_dir, find_gnuplot())) {
      out << "\nreport: " << note << '\n';
    }
  }
}

void add_diagnose_command(CLI::App& app) {
  auto options = std::make_shared<DiagnoseOptions>();
  auto radius = std::make_shared<double>(0.0);
  auto width = std::make_shared<double>(0.0);
  auto load = std::make_shared<double>(0.0);
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Diagnose the sim-to-real gap: where a model misses soil-bin data, which unmodelled effect causes it, "
      "and how far the held-out gap shrinks once that effect is added");
  sub->add_option("--real", options->data_path,
                  "soil-bin CSV (the calibrate command's formats; wheel_width_m column or --width too)")
      ->required();
  sub->add_option("--model", options->model, "base model: wong-reece (simulator) or estimator (Eq. 11)")
      ->check(CLI::IsMember({"wong-reece", "estimator"}));
  CLI::Option* radius_option = sub->add_option("--radius", *radius, "wheel radius in metres (else wheel_radius_m column)");
  CLI::Option* width_option = sub->add_option("--width", *width, "wheel width in metres (else wheel_width_m column)");
  CLI::Option* load_option =
      sub->add_option("--load", *load, "wheel load in newtons of every row, for files without load_N");
  sub->add_option("--soil", options->soil, "soil preset the wong-reece fit starts from (default hit-lss1)");
  sub->add_option("--gravity", options->gravity_m_s2, "gravity in m/s^2 for the wong-reece model (default 9.81)");
  sub->add_option("--fit", options->base_fit,
                  "wong-reece: simulator parameters of the base fit, comma-separated (default "
                  "soil.kphi,soil.n,soil.c_pa,soil.phi_deg,soil.K_m)");
  sub->add_option("--json", options->json_path, "write where / ranking / base_fit as JSON to this file");
  sub->add_option("--report", options->report_dir, "write summary.md and residual plots (gnuplot SVG) to this folder");
  sub->callback([options, radius, radius_option, width, width_option, load, load_option]() {
    if (radius_option->count() > 0) {
      options->radius_m = *radius;
    }
    if (width_option->count() > 0) {
      options->width_m = *width;
    }
    if (load_option->count() > 0) {
      options->load_n = *load;
    }
    try {
      run_diagnose(*options, std::cout);
    } catch (const std::exception& e) {
      std::cout.flush();
      std::cerr << "sinkwatch diagnose: error: " << e.what() << '\n';
      throw CLI::RuntimeError(1);
    }
  });
}

}  // namespace ground
}  // namespace sinkwatch
