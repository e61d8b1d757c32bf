// Dataset generation: grid order, noise statistics, seed reproducibility,
// CSV layout and the spec parsers.
#include "sinkwatch/ground/sim_dataset.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace sg = sinkwatch::ground;

namespace {
std::string to_csv(const std::vector<sg::DatasetRow>& rows) {
  std::ostringstream out;
  sg::write_soil_bin_csv(out, rows, {"test"});
  return out.str();
}
sg::NoiseModel some_noise() {
  sg::NoiseModel n;
  sg::apply_noise_spec("sinkage=0.0005,torque=3%,drawbar_pull=0.5", n);
  return n;
}
}  // namespace

TEST(SimDataset, GridIsLoadMajorAndCleanWithoutNoise) {
  const sg::SimParameters p = sg::default_parameters("hit-lss1");
  const auto rows = sg::generate_dataset(p, {30.0, 60.0}, {0.1, 0.4, 0.7}, sg::NoiseModel{}, 7);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].load_n, 30.0);
  EXPECT_EQ(rows[2].slip, 0.7);
  EXPECT_EQ(rows[3].load_n, 60.0);
  for (const auto& r : rows) {
    EXPECT_EQ(r.sinkage_m, r.clean.sinkage_m);
    EXPECT_EQ(r.torque_nm, r.clean.torque_nm);
    EXPECT_EQ(r.drawbar_pull_n, r.clean.drawbar_pull_n);
    EXPECT_EQ(r.wheel_radius_m, 0.15);
    const sg::WheelSoilState direct = sg::evaluate_or_throw(p, r.load_n, r.slip);
    EXPECT_EQ(direct.torque_nm, r.torque_nm);
  }
}

TEST(SimDataset, SameSeedSameBytesOtherSeedOtherNumbers) {
  sg::SimParameters p = sg::default_parameters("dry-sand");
  sg::apply_effect_spec("bulldozing:scale=0.5", p);
  const auto a = sg::generate_dataset(p, {20.0, 80.0}, {0.1, 0.5}, some_noise(), 42);
  const auto b = sg::generate_dataset(p, {20.0, 80.0}, {0.1, 0.5}, some_noise(), 42);
  const auto c = sg::generate_dataset(p, {20.0, 80.0}, {0.1, 0.5}, some_noise(), 43);
  EXPECT_EQ(to_csv(a), to_csv(b));
  EXPECT_NE(to_csv(a), to_csv(c));
}

// The noise has the stated size: standardized residuals have mean ~ 0 and
// standard deviation ~ 1 (210 draws per channel; bounds at ~5 standard errors).
TEST(SimDataset, NoiseHasTheStatedStandardDeviation) {
  const sg::SimParameters p = sg::default_parameters("hit-lss1");
  const sg::NoiseModel noise = some_noise();
  const auto rows = sg::generate_dataset(p, {30.0, 60.0, 90.0, 120.0, 150.0, 180.0, 200.0},
                                         sg::parse_number_list("0.05:0.025:0.775"), noise, 3);
  ASSERT_EQ(rows.size(), 7u * 30u);
  double sum[3] = {0, 0, 0};
  double sq[3] = {0, 0, 0};
  for (const auto& r : rows) {
    const double e[3] = {(r.sinkage_m - r.clean.sinkage_m) / noise.sinkage_m.sigma(r.clean.sinkage_m),
                         (r.torque_nm - r.clean.torque_nm) / noise.torque_nm.sigma(r.clean.torque_nm),
                         (r.drawbar_pull_n - r.clean.drawbar_pull_n) / noise.drawbar_pull_n.sigma(r.clean.drawbar_pull_n)};
    for (int i = 0; i < 3; ++i) {
      sum[i] += e[i];
      sq[i] += e[i] * e[i];
    }
  }
  const double n = static_cast<double>(rows.size());
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sum[i] / n, 0.0, 5.0 / std::sqrt(n)) << "channel " << i;
    EXPECT_NEAR(std::sqrt(sq[i] / n), 1.0, 5.0 / std::sqrt(2.0 * n)) << "channel " << i;
  }
  EXPECT_NEAR(noise.torque_nm.sigma(2.0), 0.06, 1e-15);
  EXPECT_NEAR(noise.sinkage_m.sigma(0.02), 0.0005, 1e-15);
}

TEST(SimDataset, CsvHasCommentsThenTheCalibrationColumns) {
  const sg::SimParameters p = sg::default_parameters("lunar-soil");
  const auto rows = sg::generate_dataset(p, {10.0}, {0.2}, sg::NoiseModel{}, 1);
  std::ostringstream out;
  sg::write_soil_bin_csv(out, rows, {"one", "two"});
  std::istringstream in(out.str());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "# one");
  std::getline(in, line);
  EXPECT_EQ(line, "# two");
  std::getline(in, line);
  EXPECT_EQ(line, "slip,load_N,sinkage_m,torque_Nm,drawbar_pull_N,wheel_radius_m,wheel_width_m");
  std::getline(in, line);
  EXPECT_EQ(line.rfind("0.2,10,", 0), 0u) << line;
  EXPECT_FALSE(std::getline(in, line));
}

TEST(SimDataset, FailingRowNamesLoadAndSlip) {
  const sg::SimParameters p = sg::default_parameters("lunar-soil");
  try {
    sg::generate_dataset(p, {10.0, 1e6}, {0.2}, sg::NoiseModel{}, 1);
    FAIL() << "expected SimError";
  } catch (const sg::SimError& e) {
    EXPECT_EQ(e.status, sg::SimStatus::no_solution);
    EXPECT_NE(std::string(e.what()).find("load 1e+06 N"), std::string::npos) << e.what();
  }
}

TEST(SimDatasetParsers, NumberListsAndRanges) {
  EXPECT_EQ(sg::parse_number_list("3, 7,10"), (std::vector<double>{3, 7, 10}));
  const auto r = sg::parse_number_list("0:0.05:0.7");
  ASSERT_EQ(r.size(), 15u);
  EXPECT_DOUBLE_EQ(r.back(), 0.7);
  EXPECT_DOUBLE_EQ(r[3], 0.15);
  EXPECT_EQ(sg::parse_number_list("0.1:0.2:0.1").size(), 1u);
  EXPECT_THROW(sg::parse_number_list(""), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("1,,2"), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("1,x"), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("0:0:1"), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("1:0.1:0"), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("0:1"), std::invalid_argument);
  EXPECT_THROW(sg::parse_number_list("nan"), std::invalid_argument);
}

TEST(SimDatasetParsers, EffectSpecs) {
  sg::SimParameters p = sg::default_parameters();
  sg::apply_effect_spec("grouser:height_m=0.02, lambda=0.5", p);
  EXPECT_TRUE(p.effects.grouser.enabled);
  EXPECT_EQ(p.effects.grouser.height_m, 0.02);
  EXPECT_EQ(p.effects.grouser.lambda, 0.5);
  sg::apply_effect_spec("drive_friction", p);
  EXPECT_TRUE(p.effects.drive_friction.enabled);
  EXPECT_EQ(p.effects.drive_friction.t0_nm, 0.1);
  EXPECT_EQ(sg::describe_effects(p), "grouser(height_m=0.02,lambda=0.5) drive_friction(t0_nm=0.1,k_w_m=0.001)");
  EXPECT_THROW(sg::apply_effect_spec("mud", p), std::invalid_argument);
  EXPECT_THROW(sg::apply_effect_spec("grouser:depth=3", p), std::invalid_argument);
  EXPECT_THROW(sg::apply_effect_spec("grouser:height_m", p), std::invalid_argument);
  EXPECT_THROW(sg::apply_effect_spec("grouser:height_m=abc", p), std::invalid_argument);
  EXPECT_EQ(sg::describe_effects(sg::default_parameters()), "none");
}

TEST(SimDatasetParsers, NoiseSpecsAndParameterAssignments) {
  sg::NoiseModel n;
  sg::apply_noise_spec("torque=2%", n);
  sg::apply_noise_spec("torque=0.01", n);
  EXPECT_DOUBLE_EQ(n.torque_nm.relative, 0.02);
  EXPECT_DOUBLE_EQ(n.torque_nm.absolute, 0.01);
  EXPECT_TRUE(n.any());
  EXPECT_FALSE(sg::NoiseModel{}.any());
  EXPECT_THROW(sg::apply_noise_spec("current=1", n), std::invalid_argument);
  EXPECT_THROW(sg::apply_noise_spec("torque=-1", n), std::invalid_argument);
  EXPECT_THROW(sg::apply_noise_spec("torque", n), std::invalid_argument);
  sg::SimParameters p = sg::default_parameters();
  sg::apply_parameter_assignment("soil.kphi=2e6", p);
  EXPECT_EQ(p.soil.kphi, 2e6);
  EXPECT_THROW(sg::apply_parameter_assignment("soil.kphee=2e6", p), std::invalid_argument);
  EXPECT_THROW(sg::apply_parameter_assignment("soil.kphi", p), std::invalid_argument);
}
