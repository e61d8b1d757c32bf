// calibrate_command.cpp: the `sinkwatch calibrate` subcommand.
#include "sinkwatch/ground/calibrate_command.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/calibration_report.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

namespace {

struct PendingFile {
  std::string path;
  std::string contents;
};

// Writes every file through a temporary in its directory (output_file.hpp):
// all are written, fsynced and closed before the first is renamed into place,
// and the report on `out` is checked before that too, so a failure leaves
// every target as it was. "-" writes to `out`.
void write_all(const std::vector<PendingFile>& files, std::ostream& out) {
  OutputFileSet set;
  for (const PendingFile& file : files) {
    set.add(file.path, &out).write(file.contents);
  }
  finish_standard_output(out);
  set.commit();
}

// What the report says about the table --table writes: its size, CRC,
// version, radius and the correction rows as the flight code will read them.
FlightTableSummary summarise_table(const FlightTable& table, const CalibrateOptions& options,
                                   bool radius_from_data) {
  FlightTableSummary summary;
  summary.path = options.table_path;
  summary.bytes = table.bytes.size();
  summary.crc = table.crc;
  summary.table_version = table.table.table_version;
  summary.wheel_radius_m = fx::to_double(table.table.wheel_radius_m.q());
  summary.radius_from_data = radius_from_data;
  summary.base = options.base_table_path.empty() ? "flight default table"
                                                 : "base table " + options.base_table_path;
  for (std::uint8_t i = 0U; i < table.table.correction.count; ++i) {
    const flight::CorrectionRow& row = table.table.correction.rows[i];
    summary.rows.push_back({fx::to_double(row.load_n.q()), fx::to_double(row.c1.q()),
                            fx::to_double(row.c2.q()), fx::to_double(row.c3.q()),
                            fx::to_double(row.dp_max_ratio.q())});
  }
  return summary;
}

// Builds the --table file from the fit (the per-load rows when --per-load)
// on top of the base table, records its summary in `report` and returns its
// bytes, still to be written.
PendingFile flight_table_file(const CalibrateOptions& options, const SoilBinDataset& dataset,
                              CalibrationReport& report) {
  const flight::ParameterTable base = options.base_table_path.empty()
                                          ? flight::default_parameter_table()
                                          : read_flight_table(options.base_table_path);
  FlightTableRequest request;
  request.rows = correction_entries(dataset, report.fit,
                                    options.per_load ? &report.load_table : nullptr);
  request.wheel_radius_m = common_wheel_radius(dataset);
  request.table_version = options.table_version;
  const FlightTable table = build_flight_table(base, request);
  report.flight_table = summarise_table(table, options, request.wheel_radius_m.has_value());
  return {options.table_path, std::string(table.bytes.begin(), table.bytes.end())};
}

// Reads the soil-bin data as the options say (radius, load); -v tells what
// was read.
SoilBinDataset read_dataset(const CalibrateOptions& options) {
  SoilBinReadOptions read_options;
  read_options.wheel_radius_m = options.wheel_radius_m;
  read_options.load_n = options.load_n;
  SoilBinDataset dataset = read_soil_bin_csv(options.data_path, read_options);
  if (options.detail != nullptr) {
    *options.detail << "sinkwatch calibrate: " << dataset.rows.size() << " rows from " << dataset.source
                    << (dataset.has_load ? ", every row with its load" : ", no loads") << '\n';
  }
  return dataset;
}

// The pooled fit, and the C(W) table when --per-load; a fit error names the
// data file.
CalibrationReport fit_dataset(const SoilBinDataset& dataset, const FixedCoefficients& fixed,
                              bool per_load) {
  CalibrationReport report;
  report.source = dataset.source;
  report.form = dataset.form;
  report.fixed = fixed;
  try {
    report.fit = fit_sinkage_function(observations_of(dataset), fixed);
  } catch (const CalibrationError& e) {
    throw CalibrationError(dataset.source + ": " + e.what());
  }
  report.per_load = per_load;
  if (per_load) {
    report.load_table = fit_per_load(dataset, fixed);
  }
  return report;
}

}  // namespace

void run_calibrate(const CalibrateOptions& options, std::ostream& out) {
  // Every output path is checked before any work (docs/output-files.md).
  for (const std::string* path : {&options.table_path, &options.json_path}) {
    if (!path->empty()) {
      (void)check_output_path(*path);
    }
  }
  const FixedCoefficients fixed = parse_fixed_coefficients(options.fix);
  const SoilBinDataset dataset = read_dataset(options);
  CalibrationReport report = fit_dataset(dataset, fixed, options.per_load);

  std::vector<PendingFile> files;
  if (!options.table_path.empty()) {
    files.push_back(flight_table_file(options, dataset, report));
  }
  if (!options.json_path.empty()) {
    files.push_back({options.json_path, to_json(report)});
  }
  print_report(out, report);
  write_all(files, out);
}

namespace {

// The values of the options that are optional in CalibrateOptions: CLI11
// writes into these, the callback copies those given.
struct OptionalValues {
  double radius_m = 0.0;
  double load_n = 0.0;
  std::uint16_t table_version = 0U;
  CLI::Option* radius_option = nullptr;
  CLI::Option* load_option = nullptr;
  CLI::Option* version_option = nullptr;
};

// The input options: the data file and what it may lack (radius, load).
void add_input_options(CLI::App& sub, CalibrateOptions& options, OptionalValues& values) {
  non_empty_value(sub.add_option("data", options.data_path,
                                 "soil-bin CSV ('-': standard input): slip, load_N, torque_Nm, "
                                 "sinkage_m, drawbar_pull_N (+ wheel_radius_m or --radius), or slip, "
                                 "sinkage_ratio, drive_coeff, traction_coeff (+ optional load_N)")
                      ->required());
  values.radius_option =
      sub.add_option("--radius", values.radius_m, "wheel radius in metres, for dimensional data "
                                                  "without a wheel_radius_m column")
          ->check(positive_finite_number());
  values.load_option =
      sub.add_option("--load", values.load_n,
                     "wheel load in newtons of every row, for data without a load_N column")
          ->check(positive_finite_number());
}

// The fit and output options: --per-load, --fix, --json and the flight table.
void add_output_options(CLI::App& sub, CalibrateOptions& options, OptionalValues& values) {
  sub.add_flag("--per-load", options.per_load,
               "also fit each load separately and print the C(W) table (needs load_N)");
  non_empty_list(sub.add_option("--fix", options.fix,
                                "hold coefficients fixed, e.g. c1=1,c2=1 (the paper's Table 2 form)"));
  non_empty_value(sub.add_option("--json", options.json_path, "write every result as JSON to this file"));
  CLI::Option* table_option = non_empty_value(
      sub.add_option("--table", options.table_path,
                     "write the binary flight parameter table (with its CRC) holding the fitted "
                     "C(W) rows; needs the load (load_N or --load)"));
  non_empty_value(sub.add_option("--base-table", options.base_table_path,
                                 "take the other sections of --table from this table file (default: the "
                                 "flight module's default table)"))
      ->needs(table_option);
  values.version_option =
      sub.add_option("--table-version", values.table_version,
                     "table version written into --table (default: the base table's)")
          ->transform(non_negative_integer())
          ->needs(table_option);
}

// Copies the optional values given on the command line into `options`.
void take_optional_values(const OptionalValues& values, CalibrateOptions& options) {
  if (values.version_option->count() > 0) {
    options.table_version = values.table_version;
  }
  if (values.radius_option->count() > 0) {
    options.wheel_radius_m = values.radius_m;
  }
  if (values.load_option->count() > 0) {
    options.load_n = values.load_n;
  }
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto options = std::make_shared<CalibrateOptions>();
  auto values = std::make_shared<OptionalValues>();
  auto verbosity = std::make_shared<Verbosity>();
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "Fit C1, C2, C3 of DP/W = C1*T/(rW) - C2*z/r - C3 (Eq. 11) to soil-bin data by least squares");
  add_input_options(*sub, *options, *values);
  add_output_options(*sub, *options, *values);
  add_verbosity_flags(*sub, *verbosity);
  sub->callback([options, values, verbosity]() {
    take_optional_values(*values, *options);
    try {
      (void)parse_fixed_coefficients(options->fix);
    } catch (const std::exception& e) {
      throw_usage_error(e.what());  // names --fix
    }
    options->detail = verbosity->verbose ? &std::cerr : nullptr;
    run_reporting_errors("calibrate", std::cout, std::cerr,
                         [&options]() { run_calibrate(*options, std::cout); });
  });
}

}  // namespace ground
}  // namespace sinkwatch
