// The table calibrated to a traverse's soil (soil_calibration.hpp, the
// campaign's --calibrate; issue 14): the fit recovers what the simulator's
// soil gives, `softest` moves to a firmer soil only where the soft one gives
// no soil-bin pull, the base table's other sections are kept, the draws are
// deterministic, and the command reports the calibration.
#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/soil_calibration.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using namespace sinkwatch::ground;
namespace fl = sinkwatch::flight;
namespace fx = sinkwatch::fx;

// The C3 of Eq. 11 with C1 = C2 = 1 that the clean simulator gives at one
// load, T/(rW) - DP/W - z/r, averaged over the soil bin's slips (the
// least-squares C3 of noise-free rows).
double clean_c3(const SimParameters& soil, double load_n) {
  double sum = 0.0;
  for (const double s : kCalibrationSlips) {
    const WheelSoilState w = evaluate_or_throw(soil, load_n, s);
    const double r = soil.wheel.radius_m;
    sum += w.torque_nm / (r * load_n) - w.drawbar_pull_n / load_n - w.sinkage_m / r;
  }
  return sum / static_cast<double>(std::size(kCalibrationSlips));
}

TEST(SoilCalibration, SiteFitRecoversTheSimulatedSoilsC3AndPull) {
  const TraverseDraw draw = draw_traverse(CampaignFamily::gradual, 16, 2);
  const SoilCalibration c = calibrate_to_soil(draw.spec, draw.min_soil_scale, CalibrationSoil::site,
                                              fl::default_parameter_table(), 99);
  EXPECT_EQ(c.fit.soil_scale, 1.0);
  const double mean_load_n = draw.spec.mass_kg * draw.spec.gravity_mps2 / 6.0;
  const SimParameters soil = scenario_soil(draw.spec, 1.0);
  // Noise of 2 % on torque and pull over 12 rows: C3 within 0.01 of the clean value.
  EXPECT_NEAR(c.fit.c3_at_mean_load, clean_c3(soil, mean_load_n), 0.01);
  double best_pull = -1.0;
  for (const double s : kCalibrationSlips) {
    best_pull = std::max(best_pull, evaluate_or_throw(soil, mean_load_n, s).drawbar_pull_n / mean_load_n);
  }
  EXPECT_NEAR(c.fit.dp_max_at_mean_load, best_pull, 0.03);
  // The table holds one row per soil-bin load, in the flight code's formats.
  ASSERT_EQ(c.table.correction.count, std::size(kCalibrationLoadFactors));
  EXPECT_NEAR(fx::to_double(c.table.correction.rows[2].load_n.q()), mean_load_n, 1e-3);
  EXPECT_NEAR(fx::to_double(c.table.correction.rows[2].c3.q()), c.fit.c3_at_mean_load, 1e-6);
  EXPECT_EQ(fx::to_double(c.table.correction.rows[2].c1.q()), 1.0);
}

TEST(SoilCalibration, KeepsTheBaseTablesOtherSections) {
  const TraverseDraw draw = draw_traverse(CampaignFamily::abrupt, 16, 1);
  const fl::ParameterTable base = fl::default_parameter_table();
  const fl::ParameterTable t =
      calibrate_to_soil(draw.spec, draw.min_soil_scale, CalibrationSoil::site, base, 5).table;
  EXPECT_EQ(t.monitor.stop_sinkage_m.q().raw(), base.monitor.stop_sinkage_m.q().raw());
  EXPECT_EQ(t.monitor.caution_sinkage_m.q().raw(), base.monitor.caution_sinkage_m.q().raw());
  EXPECT_EQ(t.traction.stop_coefficient.q().raw(), base.traction.stop_coefficient.q().raw());
  EXPECT_EQ(t.motor.kt_nm_per_a.q().raw(), base.motor.kt_nm_per_a.q().raw());
  EXPECT_EQ(fl::validate(t), fl::RejectReason::ok);
}

TEST(SoilCalibration, SoftestTakesTheSoftSoilWhereItGivesAPullAndAFirmerOneWhereNot) {
  TraverseDraw draw = draw_traverse(CampaignFamily::gradual, 16, 0);
  // A soft soil that still carries the wheels with a pull: taken as it is.
  const SoilCalibration soft = calibrate_to_soil(draw.spec, 0.3, CalibrationSoil::softest,
                                                 fl::default_parameter_table(), 5);
  EXPECT_EQ(soft.fit.soil_scale, 0.3);
  // Far too soft for any soil-bin pull: the first doubling of the scale that gives one.
  const SoilCalibration firmer = calibrate_to_soil(draw.spec, 0.001, CalibrationSoil::softest,
                                                   fl::default_parameter_table(), 5);
  EXPECT_GT(firmer.fit.soil_scale, 0.001);
  EXPECT_LE(firmer.fit.soil_scale, 1.0);
  EXPECT_GT(firmer.fit.dp_max_at_mean_load, 0.0);
  const double log2_steps = std::log2(firmer.fit.soil_scale / 0.001);
  EXPECT_NEAR(log2_steps, std::round(log2_steps), 1e-9);
  // The softer the soil, the smaller its soil-bin pull.
  EXPECT_LT(soft.fit.dp_max_at_mean_load,
            calibrate_to_soil(draw.spec, 1.0, CalibrationSoil::site, fl::default_parameter_table(), 5).fit.dp_max_at_mean_load);
}

TEST(SoilCalibration, ASoilWithoutAnySoilBinPullIsRefusedAndTheTraverseKeepsTheGivenTable) {
  // effects-0 of seed 16 has bulldozing on: no slip gives a positive pull
  // even at scale 1 (docs/scenarios.md finding 9), so DP_max cannot be fitted.
  const TraverseDraw draw = draw_traverse(CampaignFamily::effects, 16, 0, 4.0);
  ASSERT_NE(draw.effects.find("bulldozing"), std::string::npos) << draw.effects;
  for (const CalibrationSoil soil : {CalibrationSoil::site, CalibrationSoil::softest}) {
    EXPECT_THROW((void)calibrate_to_soil(draw.spec, draw.min_soil_scale, soil, fl::default_parameter_table(), 1),
                 CalibrationError);
  }
  CampaignOptions options;
  options.calibration = CalibrationSoil::site;
  options.sweep_stop_mm.clear();
  options.sweep_traction_stop.clear();
  const TraverseResult r = evaluate_traverse(draw, options);
  EXPECT_FALSE(r.calibration.has_value());
  options.calibration = CalibrationSoil::none;
  EXPECT_EQ(evaluate_traverse(draw, options).flight.stop_time_s, r.flight.stop_time_s);  // the given table's verdict
}

TEST(SoilCalibration, IsAPureFunctionOfItsSeed) {
  const TraverseDraw draw = draw_traverse(CampaignFamily::drawn_soil, 16, 4);
  const auto c3 = [&](std::uint64_t seed) {
    return calibrate_to_soil(draw.spec, draw.min_soil_scale, CalibrationSoil::softest, fl::default_parameter_table(),
                             seed)
        .table.correction.rows[2]
        .c3.q()
        .raw();
  };
  EXPECT_EQ(c3(3), c3(3));
  EXPECT_NE(c3(3), c3(4));  // the soil bin's noise follows the seed
}

TEST(SoilCalibration, NamesParseAndUnknownOnesAreRefused) {
  for (const CalibrationSoil s : {CalibrationSoil::none, CalibrationSoil::site, CalibrationSoil::softest}) {
    EXPECT_EQ(calibration_soil_from_name(calibration_soil_name(s)), s);
  }
  EXPECT_THROW(calibration_soil_from_name("firm"), std::invalid_argument);
}

std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("sinkwatch_soil_cal_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(SoilCalibrationCommand, CalibrateWritesTheFitPerTraverseAndTheSummaryTable) {
  const std::filesystem::path dir = fresh_dir("cmd");
  std::ostringstream out, err;
  const int rc = run_campaign_command({"--traverses", "1", "--families", "gradual,abrupt", "--seed", "16",
                                       "--calibrate", "site", "--out", dir.string(), "-j", "1", "-q"},
                                      out, err);
  ASSERT_EQ(rc, 0) << err.str();
  EXPECT_NE(out.str().find("calibrated to each traverse's site soil"), std::string::npos);
  EXPECT_NE(out.str().find("| embedding |"), std::string::npos);
  std::ifstream csv(dir / "traverses.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_NE(header.find("calibration_soil_scale,calibration_c3,calibration_dp_max"), std::string::npos);
  EXPECT_NE(row.find(",1.0000,"), std::string::npos) << row;  // the site soil is scale 1
  std::filesystem::remove_all(dir);
}

TEST(SoilCalibrationCommand, CalibrateWithChooseLevelsOrAnUnknownSoilIsAUsageError) {
  const std::filesystem::path dir = fresh_dir("usage");
  std::ostringstream out, err;
  EXPECT_EQ(run_campaign_command({"--calibrate", "site", "--choose-levels", "--max-false-stop", "0.1", "--out",
                                  dir.string()},
                                 out, err),
            exit_status(ExitCode::usage_error));
  EXPECT_EQ(run_campaign_command({"--calibrate", "firm", "--out", dir.string()}, out, err),
            exit_status(ExitCode::usage_error));
  EXPECT_FALSE(std::filesystem::exists(dir / "traverses.csv"));
}

}  // namespace
