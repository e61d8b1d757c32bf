// Unit tests of the diagnosis: split rule, model-free noise estimate, input
// errors, the Eq. 11 model with withheld terms, the Table 1 run and the
// report outputs.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_data.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/diagnose_command.hpp"

namespace sinkwatch {
namespace ground {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_diag_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path) << text;
  return path;
}

DiagnosisRow row_at(double slip, double load) {
  return make_row(slip, load, 0.01, 1.0, 5.0, 0.15, 0.15);
}

TEST(DiagnosisSplit, SeveralLoadsHoldOutTheHighestLoad) {
  std::vector<DiagnosisRow> rows;
  for (double load : {30.0, 60.0, 90.0}) {
    for (double s : {0.1, 0.2, 0.3, 0.4}) {
      rows.push_back(row_at(s, load));
    }
  }
  const DataSplit split = split_rows(rows);
  ASSERT_EQ(split.heldout.size(), 4U);
  EXPECT_EQ(split.train.size(), 8U);
  for (std::size_t i : split.heldout) {
    EXPECT_DOUBLE_EQ(rows[i].load_n, 90.0);
  }
  EXPECT_NE(split.rule.find("highest load"), std::string::npos);
}

TEST(DiagnosisSplit, OneLoadHoldsOutEveryFourthSlipFromTheTop) {
  std::vector<DiagnosisRow> rows;
  for (int k = 15; k >= 0; --k) {  // unsorted on purpose
    rows.push_back(row_at(0.04 * k + 0.06, 29.43));
  }
  const DataSplit split = split_rows(rows);
  ASSERT_EQ(split.heldout.size(), 4U);
  std::vector<double> held;
  for (std::size_t i : split.heldout) {
    held.push_back(rows[i].slip);
  }
  std::sort(held.begin(), held.end());
  EXPECT_NEAR(held[0], 0.18, 1e-12);
  EXPECT_NEAR(held[3], 0.66, 1e-12);  // the highest slip is held out
}

TEST(DiagnosisSplit, CrossValidationFolds) {
  std::vector<DiagnosisRow> rows;
  for (double load : {60.0, 30.0, 120.0, 90.0}) {  // unsorted on purpose
    for (double s : {0.1, 0.2, 0.3}) {
      rows.push_back(row_at(s, load));
    }
  }
  auto held_load = [&](const DataSplit& fold) {
    std::vector<double> loads;
    for (std::size_t i : fold.heldout) {
      loads.push_back(rows[i].load_n);
    }
    std::sort(loads.begin(), loads.end());
    loads.erase(std::unique(loads.begin(), loads.end()), loads.end());
    return loads;
  };
  // The two extreme loads, the highest first (the split_rows split).
  const std::vector<DataSplit> extremes = cross_validation_folds(rows);
  ASSERT_EQ(extremes.size(), 2U);
  EXPECT_EQ(held_load(extremes[0]), std::vector<double>{120.0});
  EXPECT_EQ(held_load(extremes[1]), std::vector<double>{30.0});
  EXPECT_EQ(extremes[1].train.size(), 9U);
  // Every load once.
  const std::vector<DataSplit> every = cross_validation_folds(rows, true);
  ASSERT_EQ(every.size(), 4U);
  std::vector<double> all;
  for (const DataSplit& fold : every) {
    ASSERT_EQ(held_load(fold).size(), 1U);
    all.push_back(held_load(fold).front());
  }
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all, (std::vector<double>{30.0, 60.0, 90.0, 120.0}));

  // Two loads: the one split. One load: four folds, every row held out once.
  std::vector<DiagnosisRow> two;
  for (double load : {30.0, 60.0}) {
    for (double s : {0.1, 0.2, 0.3, 0.4}) {
      two.push_back(row_at(s, load));
    }
  }
  EXPECT_EQ(cross_validation_folds(two).size(), 1U);
  std::vector<DiagnosisRow> one;
  for (int k = 0; k < 14; ++k) {
    one.push_back(row_at(0.05 * k, 29.43));
  }
  const std::vector<DataSplit> slip_folds = cross_validation_folds(one);
  ASSERT_EQ(slip_folds.size(), 4U);
  std::vector<int> times_held(one.size(), 0);
  for (const DataSplit& fold : slip_folds) {
    EXPECT_EQ(fold.train.size() + fold.heldout.size(), one.size());
    for (std::size_t i : fold.heldout) {
      ++times_held[i];
    }
  }
  EXPECT_EQ(std::count(times_held.begin(), times_held.end(), 1), 14);
}

TEST(DiagnosisSplit, TooFewRowsIsAnError) {
  std::vector<DiagnosisRow> rows(7, row_at(0.1, 30.0));
  EXPECT_THROW((void)split_rows(rows), std::invalid_argument);
}

TEST(DiagnosisNoise, NeighbourScatterRecoversSigmaUnderACurvedTrend) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0.0, 0.02);
  std::vector<DiagnosisRow> rows;
  std::vector<double> values;
  for (double load : {30.0, 60.0, 90.0, 120.0}) {
    for (int k = 0; k < 12; ++k) {
      const double s = 0.05 + 0.05 * k;
      rows.push_back(row_at(s, load));
      values.push_back(0.5 * (1.0 - std::exp(-s / 0.15)) + 0.3 * s * s + gauss(rng));
    }
  }
  const NoiseEstimate e = estimate_noise(rows, values);
  EXPECT_EQ(e.method, "neighbour_scatter");
  EXPECT_NEAR(e.sigma, 0.02, 0.005);
}

// A coarse 6 x 6 grid whose slip trend rises steeply at low slip (as the
// shear curve does): the slip-wise differences would see the trend, the
// load-wise ones (forces proportional to load^1.2) hardly do.
TEST(DiagnosisNoise, LoadWiseScatterOnACoarseSlipGrid) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 0.05);
  std::vector<DiagnosisRow> rows;
  std::vector<double> values;
  for (double load : {20.0, 40.0, 70.0, 110.0, 160.0, 240.0}) {
    for (double s : {0.05, 0.15, 0.3, 0.45, 0.6, 0.75}) {
      rows.push_back(row_at(s, load));
      values.push_back(0.05 * std::pow(load, 1.2) * (1.0 - std::exp(-s / 0.08)) + gauss(rng));
    }
  }
  const NoiseEstimate e = estimate_noise(rows, values);
  EXPECT_EQ(e.method, "neighbour_scatter_load");
  EXPECT_EQ(e.dof, 18U);
  EXPECT_NEAR(e.sigma, 0.05, 0.0125);
}

TEST(DiagnosisNoise, ReplicatesArePreferred) {
  std::vector<DiagnosisRow> rows;
  std::vector<double> values;
  for (double s : {0.1, 0.2, 0.3, 0.4}) {
    rows.push_back(row_at(s, 30.0));
    values.push_back(s + 0.01);
    rows.push_back(row_at(s, 30.0));
    values.push_back(s - 0.01);
  }
  const NoiseEstimate e = estimate_noise(rows, values);
  EXPECT_EQ(e.method, "replicates");
  EXPECT_NEAR(e.sigma, std::sqrt(4 * 2 * 0.0001 / 4.0), 1e-12);
}

TEST(DiagnosisData, MissingGeometryIsAClearError) {
  const std::string path = write_file("nogeom.csv",
                                      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N\n"
                                      "0.1,30,1.0,0.01,5\n0.2,30,1.2,0.011,6\n");
  try {
    (void)read_diagnosis_data(path, {});
    FAIL() << "no error";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos) << e.what();
  }
  DiagnosisReadOptions radius_only;
  radius_only.radius_m = 0.15;
  try {
    (void)read_diagnosis_data(path, radius_only);
    FAIL() << "no error";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("width"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 2U);
  }
}

TEST(DiagnosisData, WidthColumnIsReadAndABadValueNamesLineAndColumn) {
  const std::string good = write_file("width.csv",
                                      "# comment\nslip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
                                      "0.1,30,1.0,0.01,5,0.15,0.12\n");
  const DiagnosisData data = read_diagnosis_data(good, {});
  ASSERT_EQ(data.rows.size(), 1U);
  EXPECT_DOUBLE_EQ(data.rows[0].width_m, 0.12);
  EXPECT_NEAR(data.rows[0].drive_coeff, 1.0 / (0.15 * 30), 1e-12);
  const std::string bad = write_file("badwidth.csv",
                                     "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
                                     "0.1,30,1.0,0.01,5,0.15,wide\n");
  try {
    (void)read_diagnosis_data(bad, {});
    FAIL() << "no error";
  } catch (const DataError& e) {
    EXPECT_EQ(e.line(), 2U);
    EXPECT_EQ(e.column(), 7U);
  }
}

// The diagnosis reads its file in one pass through the soil-bin reader (it
// used to scan the file a second time for the width), so "-" works.
TEST(DiagnosisData, DashReadsStandardInputWidthColumnIncluded) {
  std::istringstream text(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
      "0.1,30,1.0,0.01,5,0.15,0.12\n0.2,30,1.2,0.011,6,0.15,0.12\n");
  std::streambuf* const old = std::cin.rdbuf(text.rdbuf());
  try {
    const DiagnosisData data = read_diagnosis_data("-", {});
    std::cin.rdbuf(old);
    EXPECT_EQ(data.source, "<stdin>");
    ASSERT_EQ(data.rows.size(), 2U);
    EXPECT_DOUBLE_EQ(data.rows[1].width_m, 0.12);
  } catch (const std::exception& e) {
    std::cin.rdbuf(old);
    FAIL() << e.what();
  }
  std::cin.clear();
}

TEST(DiagnosisData, WidthGivenTwiceNamesTheHeaderLineAndColumn) {
  const std::string path = write_file("width_twice.csv",
                                      "# comment\nslip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
                                      "0.1,30,1.0,0.01,5,0.15,0.12\n");
  DiagnosisReadOptions width;
  width.width_m = 0.12;
  try {
    (void)read_diagnosis_data(path, width);
    FAIL() << "no error";
  } catch (const DataError& e) {
    EXPECT_EQ(e.line(), 2U);
    EXPECT_EQ(e.column(), 7U);
    EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
  }
}

TEST(DiagnosisData, WidthOutOfItsPhysicalRangeIsRefused) {
  const std::string path = write_file("width_mm.csv",
                                      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
                                      "0.1,30,1.0,0.01,5,0.15,120\n");
  try {
    (void)read_diagnosis_data(path, {});
    FAIL() << "no error";
  } catch (const DataError& e) {
    EXPECT_EQ(e.line(), 2U);
    EXPECT_EQ(e.column(), 7U);
    EXPECT_NE(std::string(e.what()).find("120 is outside the physical range (0, 5] m"), std::string::npos)
        << e.what();
  }
}

// Eq. 11 data with one extra term switched on, at three loads; the estimator
// model without it must rank that term first.
struct TermCase {
  std::string term;
  double size;
};

class EstimatorWithheldTerm : public ::testing::TestWithParam<TermCase> {};

TEST_P(EstimatorWithheldTerm, RanksFirst) {
  const TermCase tc = GetParam();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss(0.0, 0.005);
  std::vector<DiagnosisRow> rows;
  for (double load : {20.0, 50.0, 80.0, 110.0}) {
    for (int k = 0; k < 8; ++k) {
      const double s = 0.05 + 0.08 * k;
      const double zr = 0.03 + 0.25 * s * (0.5 + load / 110.0);
      const double tw = 0.9 * (1.0 - std::exp(-s / 0.2)) + 0.4 * zr;
      double dpw = tw - zr - 0.13;
      if (tc.term == "entry_angle_geometry") {
        dpw -= tc.size * std::acos(1.0 - zr);
      } else if (tc.term == "load_offset") {
        dpw -= tc.size * (load / 65.0 - 1.0);
      } else if (tc.term == "slip_shear") {
        dpw -= tc.size * std::exp(-s / 0.08);
      } else if (tc.term == "bulldozing_z2") {
        dpw -= tc.size * zr * zr;
      }
      dpw += gauss(rng);
      rows.push_back(make_row(s, load, zr * 0.15, tw * 0.15 * load, dpw * load, 0.15, 0.15));
    }
  }
  const EstimatorModel model;
  const DiagnosisResult result = diagnose(model, rows, "generated");
  EXPECT_NE(result.verdict, Verdict::no_gap);
  EXPECT_EQ(result.ranking.front().effect, tc.term) << result.verdict_text;
  EXPECT_GT(result.ranking.front().shrink_pct, 50.0);
}

INSTANTIATE_TEST_SUITE_P(Terms, EstimatorWithheldTerm,
                         ::testing::Values(TermCase{"entry_angle_geometry", 1.0}, TermCase{"load_offset", 0.05},
                                           TermCase{"slip_shear", 0.3}, TermCase{"bulldozing_z2", 3.0}),
                         [](const ::testing::TestParamInfo<TermCase>& param_info) { return param_info.param.term; });

TEST(DiagnosisEstimator, NoTermIsNotExplained) {
  // Pure Eq. 11 plus noise: no significant gap, and the verdict says so.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> gauss(0.0, 0.01);
  std::vector<DiagnosisRow> rows;
  for (double load : {20.0, 50.0, 80.0}) {
    for (int k = 0; k < 8; ++k) {
      const double s = 0.05 + 0.08 * k;
      const double zr = 0.03 + 0.2 * s;
      const double tw = 0.9 * (1.0 - std::exp(-s / 0.2)) + 0.4 * zr;
      const double dpw = tw - zr - 0.13 + gauss(rng);
      rows.push_back(make_row(s, load, zr * 0.15, tw * 0.15 * load, dpw * load, 0.15, 0.15));
    }
  }
  const DiagnosisResult result = diagnose(EstimatorModel{}, rows, "generated");
  EXPECT_TRUE(result.verdict == Verdict::no_gap || result.verdict == Verdict::weak_gap || result.verdict == Verdict::not_explained)
      << result.verdict_text;
}

TEST(DiagnosisTable1, EstimatorRunReproducesTheFullFitAndQuantisationIsNegligible) {
  DiagnosisReadOptions options;
  options.radius_m = 0.15;
  options.width_m = 0.15;
  options.load_n = 3 * 9.81;
  const DiagnosisData data = read_diagnosis_data(std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv", options);
  ASSERT_EQ(data.rows.size(), 16U);
  const DiagnosisResult result = diagnose(EstimatorModel{}, data.rows, data.source);
  EXPECT_EQ(result.train.size(), 12U);
  EXPECT_EQ(result.heldout.size(), 4U);
  EXPECT_TRUE(result.base.converged);
  // The base fit is a weighted least-squares fit of Eq. 11 (each row by its
  // noise, hypot(floor, relative DP/W)): its weighted residuals are
  // orthogonal to the columns of A (the normal equations hold).
  const ChannelNoiseEstimate& noise = result.noise.front();
  double dot[3] = {0.0, 0.0, 0.0};
  for (std::size_t i : result.train) {
    const double sigma =
        std::max(std::hypot(noise.floor, noise.relative * data.rows[i].traction_coeff), 0.05 * noise.sigma);
    const double r = result.base.residuals[i][0] / (sigma * sigma);
    dot[0] += r * data.rows[i].drive_coeff;
    dot[1] += r * data.rows[i].sinkage_ratio;
    dot[2] += r;
  }
  for (double d : dot) {
    EXPECT_NEAR(d, 0.0, 1e-3);  // residual / sigma^2 is O(100) per row here
  }
  ASSERT_FALSE(result.where.components.empty());
  const GapComponent& q = result.where.components.front();
  EXPECT_EQ(q.name, "fixed_point_quantisation");
  ASSERT_TRUE(std::isfinite(q.rms)) << q.note;
  EXPECT_GT(q.rms, 0.0);
  EXPECT_LT(q.over_noise, 1e-3);
  EXPECT_EQ(result.ranking.size(), 4U);
  EXPECT_FALSE(result.ranking.back().identifiable);  // load_offset at one load
}

TEST(DiagnosisReport, JsonKeysAndReportWithoutGnuplot) {
  DiagnosisReadOptions options;
  options.radius_m = 0.15;
  options.width_m = 0.15;
  const DiagnosisData data = read_diagnosis_data(std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv", options);
  const DiagnosisResult result = diagnose(EstimatorModel{}, data.rows, data.source);
  const std::string json = to_json(result);
  for (const char* key : {"\"where\"", "\"ranking\"", "\"base_fit\"", "\"heldout_rms_before\"", "\"heldout_rms_after\"",
                          "\"shrink_pct\"", "\"effect\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  const std::string dir = temp_path("report_nognuplot");
  const std::vector<std::string> notes = write_report(result, dir, "");
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.front().find("gnuplot not found"), std::string::npos);
  EXPECT_TRUE(fs::exists(fs::path(dir) / "summary.md"));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "residuals.gp"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "residuals_vs_slip.svg"));
}


TEST(DiagnoseCommand, WritesJsonAndRejectsBadInput) {
  DiagnoseOptions options;
  options.data_path = std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv";
  options.model = "estimator";
  options.radius_m = 0.15;
  options.width_m = 0.15;
  options.json_path = temp_path("t1.json");
  std::ostringstream out;
  run_diagnose(options, out);
  EXPECT_NE(out.str().find("verdict"), std::string::npos);
  std::ifstream json(options.json_path);
  std::stringstream text;
  text << json.rdbuf();
  EXPECT_NE(text.str().find("\"ranking\""), std::string::npos);

  // Table 1 has no loads: the simulator model cannot run on it.
  DiagnoseOptions sim = options;
  sim.model = "wong-reece";
  sim.json_path.clear();
  try {
    run_diagnose(sim, out);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("load"), std::string::npos) << e.what();
  }
  DiagnoseOptions bad = options;
  bad.model = "neural-net";
  EXPECT_THROW(run_diagnose(bad, out), std::invalid_argument);
  DiagnoseOptions no_geometry = options;
  no_geometry.radius_m.reset();
  EXPECT_THROW(run_diagnose(no_geometry, out), DataError);
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
