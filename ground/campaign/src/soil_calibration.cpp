// soil_calibration.cpp: a simulated soil-bin test of a traverse's soil and the
// flight table fitted to it (soil_calibration.hpp; docs/campaign.md).
#include "sinkwatch/ground/soil_calibration.hpp"

#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/sim_dataset.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

#include <algorithm>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sinkwatch::ground {
namespace {

// Soil-bin measurement noise (docs/campaign.md): a sinkage gauge of 0.5 mm,
// torque and pull cells of 2 % plus 0.05 N m and 0.2 N.
NoiseModel soil_bin_noise() {
  NoiseModel n;
  n.sinkage_m = {0.0005, 0.0};
  n.torque_nm = {0.05, 0.02};
  n.drawbar_pull_n = {0.2, 0.02};
  return n;
}

std::vector<double> calibration_loads(const ScenarioSpec& spec) {
  const double mean_load_n = spec.mass_kg * spec.gravity_mps2 / 6.0;
  std::vector<double> loads;
  for (const double f : kCalibrationLoadFactors) loads.push_back(f * mean_load_n);
  return loads;
}

// The soil-bin rows of the soil at `scale`, as the calibration tool reads
// them: through the CSV that `sinkwatch simulate` writes (one path).
SoilBinDataset soil_bin(const ScenarioSpec& spec, double scale, std::uint64_t seed) {
  const std::vector<DatasetRow> rows =
      generate_dataset(scenario_soil(spec, scale), calibration_loads(spec), std::vector<double>(std::begin(kCalibrationSlips), std::end(kCalibrationSlips)), soil_bin_noise(), seed);
  std::stringstream csv;
  write_soil_bin_csv(csv, rows, {"campaign soil bin of " + spec.name});
  return parse_soil_bin_csv(csv, spec.name + " soil bin");
}

// The paper's Table 2 form: C1 = C2 = 1, C3 and DP_max/W per load.
SoilCalibration fit_table(const SoilBinDataset& dataset, const flight::ParameterTable& base, double scale) {
  const FixedCoefficients fixed = parse_fixed_coefficients("c1=1,c2=1");
  const CalibrationFit pooled = fit_sinkage_function(observations_of(dataset), fixed);
  const std::vector<LoadFit> per_load = fit_per_load(dataset, fixed);
  FlightTableRequest request;
  request.rows = correction_entries(dataset, pooled, &per_load);
  request.wheel_radius_m = common_wheel_radius(dataset);
  SoilCalibration out;
  out.table = build_flight_table(base, request).table;
  out.fit.soil_scale = scale;
  const CorrectionEntry& mean = request.rows.at(2);  // kCalibrationLoadFactors[2] == 1.0
  out.fit.c3_at_mean_load = mean.c[2];
  out.fit.dp_max_at_mean_load = mean.dp_max_ratio;
  return out;
}

}  // namespace

const char* calibration_soil_name(CalibrationSoil s) {
  switch (s) {
    case CalibrationSoil::site: return "site";
    case CalibrationSoil::softest: return "softest";
    case CalibrationSoil::none: break;
  }
  return "none";
}

CalibrationSoil calibration_soil_from_name(const std::string& name) {
  for (const CalibrationSoil s : {CalibrationSoil::none, CalibrationSoil::site, CalibrationSoil::softest}) {
    if (name == calibration_soil_name(s)) return s;
  }
  throw std::invalid_argument("--calibrate: '" + name + "' is not none, site or softest");
}

SoilCalibration calibrate_to_soil(const ScenarioSpec& spec, double min_soil_scale, CalibrationSoil soil,
                                  const flight::ParameterTable& base, std::uint64_t seed) {
  static_assert(kCalibrationLoadFactors[2] == 1.0, "fit_table reads the mean load's row at index 2");
  double scale = soil == CalibrationSoil::softest ? min_soil_scale : 1.0;
  // softest: a soil too soft for a soil-bin pull at some load (DP_max <= 0,
  // refused) or one that takes the wheel to its axle gives way to the next
  // firmer soil of the path.
  for (int doubling = 0; soil == CalibrationSoil::softest && scale < 1.0 && doubling < kSoftestScaleDoublings;
       ++doubling) {
    try {
      return fit_table(soil_bin(spec, scale, seed), base, scale);
    } catch (const CalibrationError&) {
    } catch (const SimError&) {
    }
    scale = std::min(1.0, 2.0 * scale);
  }
  try {
    return fit_table(soil_bin(spec, scale, seed), base, scale);
  } catch (const std::runtime_error& e) {
    throw CalibrationError(spec.name + ": no soil-bin calibration of its soil at scale " + std::to_string(scale) +
                           ": " + e.what());
  }
}

}  // namespace sinkwatch::ground
