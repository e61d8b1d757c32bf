// The diagnosis pipeline (issue 16): families ranked by their best form, the
// verdict rule (explained / not_explained / ambiguous), the two-condition
// mechanics, small data (one load, not_enough_data with a campaign
// suggestion), the checks on inputs before any work, the settings in the
// report, the progress callback and the parallel candidate stage (identical
// to the serial one). A small linear model with known terms keeps it fast;
// the Wong–Reece two-condition check is test_diagnosis_two_condition.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnose_command.hpp"
#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_data.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/output_file.hpp"

namespace sinkwatch {
namespace ground {
namespace {

namespace fs = std::filesystem;

// y = a + b s (+ k term(row)), one channel: the traction coefficient.
struct Term {
  std::string family;
  std::string form;
  double (*value)(const DiagnosisRow&);
};

double square(const DiagnosisRow& r) { return r.slip * r.slip; }
double cube(const DiagnosisRow& r) { return r.slip * r.slip * r.slip; }
double load_term(const DiagnosisRow& r) { return r.load_n / 50.0 - 1.0; }
// Bilinear in slip and load: invisible to the neighbour-scatter noise
// estimate (third differences), centred in slip (mean slip 0.295), and in no
// candidate.
double interaction(const DiagnosisRow& r) { return (r.slip - 0.295) * (r.load_n / 50.0 - 1.0); }

class LineModel final : public DiagnosisModel {
 public:
  explicit LineModel(std::vector<Term> terms) : terms_(std::move(terms)) {}
  std::string name() const override { return "line"; }
  std::vector<ChannelInfo> channels() const override { return {{"traction_coeff", "DP/W"}}; }
  std::vector<double> measured(const DiagnosisRow& row) const override { return {row.traction_coeff}; }
  std::vector<ParameterSpec> base_parameters(const std::vector<DiagnosisRow>&) const override {
    return {{"a", 0.0, -10.0, 10.0}, {"b", 0.0, -10.0, 10.0}};
  }
  std::vector<Candidate> candidates(const std::vector<DiagnosisRow>&) const override {
    std::vector<Candidate> out;
    for (const Term& t : terms_) {
      Candidate c;
      c.name = t.family + "." + t.form;
      c.family = t.family;
      c.form = t.form;
      c.extra = {{c.name + ".k", 0.1, -10.0, 10.0}};
      c.nominal_size = 1.0;
      out.push_back(c);
    }
    return out;
  }
  bool predict(const Candidate* candidate, const std::vector<double>& p, const DiagnosisRow& row,
               std::vector<double>& out) const override {
    double y = p[0] + p[1] * row.slip;
    if (candidate != nullptr) {
      for (const Term& t : terms_) {
        if (candidate->name == t.family + "." + t.form) {
          y += p[2] * t.value(row);
        }
      }
    }
    out = {y};
    return true;
  }

 private:
  std::vector<Term> terms_;
};

const std::vector<Term> kLibrary = {
    {"curvature", "square", square}, {"curvature", "cube", cube}, {"load", "linear", load_term}};

// Rows y = 0.2 + 0.8 s + extra(row) + noise, at `loads` x `slips` slips from 0.05.
std::vector<DiagnosisRow> line_rows(const std::vector<double>& loads, int slips, double (*extra)(const DiagnosisRow&),
                                    double size, unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 0.005);
  std::vector<DiagnosisRow> rows;
  for (double load : loads) {
    for (int k = 0; k < slips; ++k) {
      DiagnosisRow row = make_row(0.05 + 0.07 * k, load, 0.01, 1.0, 0.0, 0.15, 0.15);
      const double y = 0.2 + 0.8 * row.slip + (extra != nullptr ? size * extra(row) : 0.0) + gauss(rng);
      rows.push_back(make_row(row.slip, load, 0.01 + 0.001 * k, 1.0 + 0.1 * k, y * load, 0.15, 0.15));
    }
  }
  return rows;
}

const std::vector<double> kThreeLoads = {20.0, 50.0, 80.0};

TEST(DiagnosisVerdict, EveryVerdictHasItsOwnName) {
  const std::vector<Verdict> all = {Verdict::no_gap,    Verdict::weak_gap,      Verdict::explained,
                                    Verdict::partly_explained, Verdict::ambiguous, Verdict::not_explained,
                                    Verdict::not_enough_data};
  std::vector<std::string> names;
  for (Verdict v : all) {
    names.emplace_back(verdict_name(v));
  }
  EXPECT_EQ(names.front(), "no_gap");
  EXPECT_EQ(names.back(), "not_enough_data");
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (std::size_t j = i + 1; j < names.size(); ++j) {
      EXPECT_NE(names[i], names[j]);
    }
  }
}

TEST(DiagnosisFamilies, FamilyRankedByItsBestFormWithTheOtherFormsListed) {
  const std::vector<DiagnosisRow> rows = line_rows(kThreeLoads, 8, square, 1.0);
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  ASSERT_EQ(result.families.size(), 2U);
  const RankedFamily& best = result.families.front();
  EXPECT_EQ(best.family, "curvature");
  EXPECT_EQ(best.best_form, "square");
  ASSERT_EQ(best.forms.size(), 2U);
  EXPECT_EQ(best.forms[1].form, "cube");
  EXPECT_EQ(best.forms[0].effect, best.best_effect);
  EXPECT_EQ(best.heldout_rms_after, best.forms[0].heldout_rms_after);
  EXPECT_EQ(result.ranking[best.best_rank].effect, "curvature.square");
  EXPECT_EQ(result.verdict, Verdict::explained) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("curvature (form square)"), std::string::npos) << result.verdict_text;
  const std::string json = to_json(result);
  EXPECT_NE(json.find("\"families\""), std::string::npos);
  EXPECT_NE(json.find("\"best_form\": \"square\""), std::string::npos);
  EXPECT_NE(json.find("\"verdict\": \"explained\""), std::string::npos);
  EXPECT_NE(summary_markdown(result).find("## Which family"), std::string::npos);
}

TEST(DiagnosisFamilies, AGapNoFamilyDescribesIsNotExplainedNotTheNearestNamed) {
  // A slip-load interaction that no candidate has: the verdict must not name one.
  const std::vector<DiagnosisRow> rows = line_rows(kThreeLoads, 8, interaction, 0.2);
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  EXPECT_GT(result.cv_heldout_rms_scaled, 2.0) << "the wiggle must leave a significant gap";
  EXPECT_EQ(result.verdict, Verdict::not_explained) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("no candidate family explains"), std::string::npos) << result.verdict_text;
}

// A curvature the library has, plus a slip-load interaction no candidate has
// at 3 % of the curvature's size: small enough that the curvature leaves a
// held-out residual below 2 sigma, large enough to be more than noise.
double square_and_small_interaction(const DiagnosisRow& r) { return square(r) + 0.03 * interaction(r); }
const std::vector<double> kFiveLoads = {20.0, 35.0, 50.0, 65.0, 80.0};

TEST(DiagnosisVerdict, ResidualBoundIsTheNoisesFQuantileWidenedByTheFitsLeverage) {
  // 5 loads x 12 slips: 24 held-out residuals over the two extreme-load
  // folds, noise from 45 slip-wise third differences. F(24, 45) at 1 %:
  // 2.23 (tables: 2.29 at (24, 40), 2.12 at (24, 60), interpolated in 1/m).
  // The line does not depend on load, so a held-out load's rows repeat the
  // slips of each of the 4 training loads: their leverages sum to 3
  // parameters / 4 loads, 3/48 per held-out row (the noise's relative part
  // weights the rows a little unevenly).
  const DiagnosisResult result = diagnose(LineModel(kLibrary), line_rows(kFiveLoads, 12, square, 1.0), "generated");
  ASSERT_EQ(result.noise.front().dof, 45U);
  EXPECT_NEAR(result.heldout_leverage, 3.0 / 48.0, 0.003);
  EXPECT_NEAR(result.residual_bound * result.residual_bound, 2.23 * (1.0 + result.heldout_leverage), 0.04);
  EXPECT_LE(result.families.front().heldout_rms_after, result.residual_bound);
  EXPECT_EQ(result.verdict, Verdict::explained) << result.verdict_text;
}

TEST(DiagnosisVerdict, AResidualAboveWhatTheNoiseAllowsIsNotExplainedEvenBelowTwoSigma) {
  const std::vector<DiagnosisRow> rows = line_rows(kFiveLoads, 12, square_and_small_interaction, 1.0);
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  const RankedFamily& best = result.families.front();
  EXPECT_EQ(best.family, "curvature");
  // The case the 2 sigma rule called explained: above the bound, below 2 sigma.
  EXPECT_GT(best.heldout_rms_after, result.residual_bound);
  EXPECT_LT(best.heldout_rms_after, result.settings.residual_threshold);
  EXPECT_EQ(result.verdict, Verdict::partly_explained) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("more than the noise allows"), std::string::npos) << result.verdict_text;
}

TEST(DiagnosisFamilies, TwoFamiliesThatFitAlikeAreAmbiguous) {
  // The same term in two families: held-out scores tie; the data cannot tell them apart.
  const std::vector<Term> twins = {{"curvature", "square", square}, {"parabola", "square", square}};
  const std::vector<DiagnosisRow> rows = line_rows(kThreeLoads, 8, square, 1.0);
  const DiagnosisResult result = diagnose(LineModel(twins), rows, "generated");
  EXPECT_EQ(result.verdict, Verdict::ambiguous) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("parabola"), std::string::npos) << result.verdict_text;
}

TEST(DiagnosisTwoCondition, BaseHeldFixedAndCandidatesFitOnlyTheirTerms) {
  const std::vector<DiagnosisRow> base_rows = line_rows(kThreeLoads, 8, nullptr, 0.0, 3);
  const std::vector<DiagnosisRow> rows = line_rows({50.0}, 10, square, 1.0, 5);  // one load, 10 slips
  const LineModel model(kLibrary);
  const DiagnosisResult result = diagnose_against_base(model, {base_rows, "smooth.csv"}, rows, "lugged.csv");
  ASSERT_TRUE(result.two_condition);
  EXPECT_EQ(result.base_rows, base_rows.size());
  ASSERT_EQ(result.base.values.size(), 2U);
  EXPECT_EQ(result.base.values, result.base_condition_fit.values) << "the base parameters are held fixed";
  ASSERT_FALSE(result.ranking.empty());
  const RankedEffect& top = result.ranking.front();
  EXPECT_EQ(top.family, "curvature");
  EXPECT_EQ(std::vector<double>(top.fit.values.begin(), top.fit.values.begin() + 2), result.base.values)
      << "a candidate fits only its own term";
  EXPECT_NEAR(top.fitted.at("curvature.square.k"), 1.0, 0.1);
  ASSERT_EQ(result.references.size(), 1U);
  EXPECT_EQ(result.references.front().effect, "base_refit_on_data");
  EXPECT_EQ(result.verdict, Verdict::explained) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("soil change"), std::string::npos) << result.verdict_text;
  const std::string json = to_json(result);
  EXPECT_NE(json.find("\"base_data\": \"smooth.csv\""), std::string::npos);
  EXPECT_NE(json.find("base_refit_on_data"), std::string::npos);
}

TEST(DiagnosisTwoCondition, ABaseConditionTooSmallToFitIsNotEnoughData) {
  const std::vector<DiagnosisRow> base_rows = line_rows({50.0}, 3, nullptr, 0.0, 3);  // 3 rows, 2 parameters
  const std::vector<DiagnosisRow> rows = line_rows({50.0}, 10, square, 1.0, 5);
  const DiagnosisResult result = diagnose_against_base(LineModel(kLibrary), {base_rows, "tiny.csv"}, rows, "data.csv");
  EXPECT_EQ(result.verdict, Verdict::not_enough_data);
  EXPECT_NE(result.verdict_text.find("base condition (3 rows"), std::string::npos) << result.verdict_text;
  EXPECT_TRUE(result.ranking.empty());
}

TEST(DiagnosisSmallData, OneLoadOfNineRowsIsHeldOutBySlipRange) {
  const std::vector<DiagnosisRow> rows = line_rows({50.0}, 9, square, 1.0);
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  ASSERT_NE(result.verdict, Verdict::not_enough_data) << result.verdict_text;
  EXPECT_EQ(result.folds.size(), 4U);
  EXPECT_NE(result.split_rule.find("by slip"), std::string::npos) << result.split_rule;
  // The held-out rows of the first split include the highest slip.
  EXPECT_NE(std::find(result.heldout.begin(), result.heldout.end(), rows.size() - 1), result.heldout.end());
  EXPECT_EQ(result.families.front().family, "curvature");
  EXPECT_EQ(result.verdict, Verdict::explained) << result.verdict_text;
}

TEST(DiagnosisSmallData, FewerThanEightRowsIsNotEnoughDataWithACampaignSuggestion) {
  const std::vector<DiagnosisRow> rows = line_rows({50.0}, 6, square, 1.0);
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  EXPECT_EQ(result.verdict, Verdict::not_enough_data);
  EXPECT_TRUE(result.ranking.empty());
  EXPECT_NE(result.verdict_text.find("6 rows"), std::string::npos) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("add rows at loads 25 N and 100 N"), std::string::npos) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("slips 0.05"), std::string::npos) << result.verdict_text;
  EXPECT_NE(to_json(result).find("\"verdict\": \"not_enough_data\""), std::string::npos);
  const std::string dir = (fs::temp_directory_path() / ("sinkwatch_h2_small_" + std::to_string(::getpid()))).string();
  EXPECT_NO_THROW((void)write_report(result, dir, ""));
  EXPECT_TRUE(fs::exists(fs::path(dir) / "summary.md"));
  fs::remove_all(dir);
}

TEST(DiagnosisSmallData, TwoLoadsWithTooFewTrainingRowsIsNotEnoughData) {
  std::vector<DiagnosisRow> rows = line_rows({80.0}, 8, square, 1.0);
  const std::vector<DiagnosisRow> low = line_rows({20.0}, 2, square, 1.0);
  rows.insert(rows.end(), low.begin(), low.end());
  const DiagnosisResult result = diagnose(LineModel(kLibrary), rows, "generated");
  EXPECT_EQ(result.verdict, Verdict::not_enough_data) << result.verdict_text;
  EXPECT_NE(result.verdict_text.find("add rows at load 160 N"), std::string::npos) << result.verdict_text;
}

TEST(DiagnosisStages, ParallelCandidatesGiveTheSerialResultAndReportProgress) {
  const std::vector<DiagnosisRow> rows = line_rows(kThreeLoads, 8, square, 1.0);
  const LineModel model(kLibrary);
  DiagnosisSettings serial;
  serial.threads = 1;
  DiagnosisSettings parallel;
  parallel.threads = 3;
  std::vector<std::size_t> done;
  std::size_t total = 0;
  parallel.progress = [&](std::size_t d, std::size_t t) {
    done.push_back(d);
    total = t;
  };
  const DiagnosisResult a = diagnose(model, rows, "generated", serial);
  const DiagnosisResult b = diagnose(model, rows, "generated", parallel);
  ASSERT_EQ(a.ranking.size(), b.ranking.size());
  for (std::size_t k = 0; k < a.ranking.size(); ++k) {
    EXPECT_EQ(a.ranking[k].effect, b.ranking[k].effect);
    EXPECT_EQ(a.ranking[k].heldout_rms_after, b.ranking[k].heldout_rms_after);
    EXPECT_EQ(a.ranking[k].fit.values, b.ranking[k].fit.values);
  }
  EXPECT_EQ(total, a.ranking.size());
  ASSERT_EQ(done.size(), a.ranking.size());
  EXPECT_EQ(done.back(), total);
}

// ---------------------------------------------------------------- the command

std::string temp_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_h2_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

// A dimensional CSV of `n` rows at one load (line 1 is the header).
std::string csv(std::size_t n, const std::string& replace_line = {}, std::size_t at = 0) {
  std::ostringstream os;
  os << "slip,load_N,sinkage_m,torque_Nm,drawbar_pull_N\n";
  for (std::size_t i = 0; i < n; ++i) {
    const double s = 0.05 + 0.07 * static_cast<double>(i);
    if (i + 2 == at) {
      os << replace_line << "\n";
    } else {
      os << s << ",30," << 0.01 + 0.004 * s * s << "," << 0.5 + s << "," << 3.0 * s - 0.2 * s * s << "\n";
    }
  }
  return os.str();
}

DiagnoseOptions command_options(const std::string& data) {
  DiagnoseOptions options;
  options.data_path = data;
  options.radius_m = 0.15;
  options.width_m = 0.15;
  return options;
}

TEST(DiagnoseInputs, GravityIsCheckedBeforeAnyWork) {
  for (double g : {0.0, -9.81, std::nan(""), HUGE_VAL}) {
    DiagnoseOptions options = command_options("/nonexistent/data.csv");
    options.gravity_m_s2 = g;
    std::ostringstream out;
    try {
      run_diagnose(options, out);
      ADD_FAILURE() << "gravity " << g << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--gravity"), std::string::npos) << e.what();
    }
  }
}

TEST(DiagnoseInputs, AnUnwritableOutputIsRefusedBeforeTheDataIsRead) {
  DiagnoseOptions options = command_options("/nonexistent/data.csv");
  options.json_path = "/nonexistent-dir/out.json";
  std::ostringstream out;
  EXPECT_THROW(run_diagnose(options, out), OutputError);
}

// A report folder that cannot be made (its parent is a file) is refused
// before the data is read, like an unwritable JSON path.
TEST(DiagnoseInputs, AReportFolderThatCannotBeMadeIsRefusedBeforeTheDataIsRead) {
  const std::string blocker = temp_file("not_a_folder.txt", "a file where the report's parent folder should be\n");
  DiagnoseOptions options = command_options("/nonexistent/data.csv");
  options.report_dir = blocker + "/report";
  std::ostringstream out;
  EXPECT_THROW(run_diagnose(options, out), OutputError);
}

TEST(DiagnoseInputs, BadGeometryOptionIsAnError) {
  const std::string path = temp_file("geometry.csv", csv(9));
  for (double bad : {-0.15, 0.0, std::nan(""), HUGE_VAL}) {
    DiagnoseOptions radius = command_options(path);
    radius.radius_m = bad;
    DiagnoseOptions width = command_options(path);
    width.width_m = bad;
    std::ostringstream out;
    EXPECT_THROW(run_diagnose(radius, out), DataError) << "radius " << bad;
    EXPECT_THROW(run_diagnose(width, out), DataError) << "width " << bad;
  }
}

struct BadRow {
  std::string name;
  std::string line;       // replaces data line 4 (file line 5)
  std::size_t column;     // expected column of the error (1-based)
};

class DiagnoseBadRow : public ::testing::TestWithParam<BadRow> {};

TEST_P(DiagnoseBadRow, NamesFileLineAndColumn) {
  const BadRow bad = GetParam();
  const std::string path = temp_file(bad.name + ".csv", csv(9, bad.line, 5));
  std::ostringstream out;
  try {
    run_diagnose(command_options(path), out);
    FAIL() << "accepted: " << bad.line;
  } catch (const DataError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_EQ(e.line(), 5U) << e.what();
    EXPECT_EQ(e.column(), bad.column) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Rows, DiagnoseBadRow,
                         ::testing::Values(BadRow{"huge_load", "0.3,1e300,0.01,1,1", 2},
                                           BadRow{"slip_above_one", "1.5,30,0.01,1,1", 1},
                                           BadRow{"zero_load", "0.3,0,0.01,1,1", 2},
                                           BadRow{"negative_sinkage", "0.3,30,-0.002,1,1", 3}),
                         [](const ::testing::TestParamInfo<BadRow>& param_info) { return param_info.param.name; });

TEST(DiagnoseInputs, AChannelWithoutScatterNamesItsColumn) {
  std::ostringstream os;
  os << "# a copied torque column\nslip,load_N,sinkage_m,torque_Nm,drawbar_pull_N\n";
  for (int i = 0; i < 9; ++i) {
    os << 0.05 + 0.07 * i << ",30," << 0.01 + 0.001 * i << ",1.25," << 1.0 + 0.3 * i << "\n";
  }
  const std::string path = temp_file("constant_torque.csv", os.str());
  std::ostringstream out;
  try {
    run_diagnose(command_options(path), out);
    FAIL() << "a constant torque column was accepted";
  } catch (const DataError& e) {
    EXPECT_EQ(e.line(), 3U) << e.what();
    EXPECT_EQ(e.column(), 4U) << e.what();
    EXPECT_EQ(e.column_name(), "torque_Nm");
    EXPECT_NE(std::string(e.what()).find("same value"), std::string::npos) << e.what();
  }
}

TEST(DiagnoseCommandSmallData, FiveRowsWriteTheNotEnoughDataReportWithEverySetting) {
  DiagnoseOptions options = command_options(temp_file("five.csv", csv(5)));
  options.gravity_m_s2 = 1.62;
  options.soil = "hit-lss1";
  options.json_path = temp_file("five.json", "");
  std::ostringstream out;
  ASSERT_NO_THROW(run_diagnose(options, out));
  EXPECT_NE(out.str().find("not_enough_data"), std::string::npos) << out.str();
  std::ifstream in(options.json_path);
  std::stringstream json;
  json << in.rdbuf();
  for (const char* key : {"\"verdict\": \"not_enough_data\"", "\"gravity (m/s^2)\": \"1.62\"",
                          "\"soil preset (start of the fit)\": \"hit-lss1\"", "\"wheel radius (m)\": \"0.15\"",
                          "\"wheel width (m)\": \"0.15\"", "\"gap threshold (x noise)\"",
                          "\"candidate starts (x initial size)\": \"1, 4\"", "add rows at loads 15 N and 60 N",
                          "\"base parameters fitted\": \"soil.kphi,soil.n,soil.c_pa,soil.phi_deg,soil.K_m\"",
                          "\"simulator quadrature tolerance (relative)\""}) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key << "\n" << json.str();
  }
}

TEST(DiagnoseCommandSmallData, OneLoadTenRowFileRunsWithTheEstimator) {
  // Eq. 11 has one channel: 10 rows leave 7 for 3 coefficients and a term.
  DiagnoseOptions options = command_options(temp_file("ten.csv", csv(10)));
  options.model = "estimator";
  options.json_path = temp_file("ten.json", "");
  std::ostringstream out;
  ASSERT_NO_THROW(run_diagnose(options, out));
  std::ifstream in(options.json_path);
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_EQ(json.str().find("not_enough_data"), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("\"cv_folds\": 4"), std::string::npos);
  EXPECT_NE(json.str().find("\"noise\": [{\"channel\": \"traction_coeff\""), std::string::npos);
  // The noise model (floor and relative part) and the fitted parameters are stated.
  for (const char* key : {"\"floor\": ", "\"relative\": ", "\"base_fit\"", "\"split_rule\""}) {
    EXPECT_NE(json.str().find(key), std::string::npos) << key;
  }
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
