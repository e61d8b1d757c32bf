// The withheld-effect check (issue 8): for each effect of the simulator's
// catalogue, generate soil-bin data with that effect on (at the size
// switch_on gives) plus realistic measurement noise, diagnose it with the base
// model that lacks every effect, and require that
//   - the withheld effect ranks first, and
//   - the reported shrink is within 10 percentage points of the true shrink.
// True shrink: 100 (before - true_after) / before, where before is the base
// model's held-out RMS (noise units, pooled over the cross-validation folds,
// as reported) and true_after is the held-out RMS of the generating model
// itself (true soil, true effect size) on the same held-out rows of the same
// folds and the same noise scale: the best any fit of that model could do.
//
// The results table (docs/findings-diagnosis.md) is printed on stdout and,
// when SINKWATCH_DIAGNOSIS_TABLE names a file, written there.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/sim_dataset.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

namespace sinkwatch {
namespace ground {
namespace {

// A soil-bin campaign of 36 rows: 6 loads over the 12:1 range a wheel of this
// size carries (2 to 24 kg on Earth) x 6 slips (docs/findings-diagnosis.md
// says why this design and not the paper's 3-15 kg).
// SINKWATCH_DIAGNOSIS_MASSES and SINKWATCH_DIAGNOSIS_SLIPS (comma lists) try
// another design.
std::vector<double> list_from_env(const char* name, std::vector<double> fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr) {
    return fallback;
  }
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    values.push_back(std::stod(item));
  }
  return values;
}
std::vector<double> test_loads() {
  std::vector<double> loads;
  for (double kg : list_from_env("SINKWATCH_DIAGNOSIS_MASSES", {2.0, 4.0, 7.0, 11.0, 16.0, 24.0})) {
    loads.push_back(kg * 9.81);
  }
  return loads;
}
std::vector<double> test_slips() {
  return list_from_env("SINKWATCH_DIAGNOSIS_SLIPS", {0.05, 0.15, 0.3, 0.45, 0.6, 0.75});
}

// Soil-bin noise: sinkage gauge 0.2 mm plus 1 %, torque sensor 0.005 N m
// plus 1 %, drawbar-pull load cell 0.2 N plus 2 %.
NoiseModel test_noise() {
  NoiseModel noise;
  noise.sinkage_m = {2e-4, 0.01};
  noise.torque_nm = {0.005, 0.01};
  noise.drawbar_pull_n = {0.2, 0.02};
  return noise;
}

// The noise seed of the check; SINKWATCH_DIAGNOSIS_SEED picks another one to
// see how the results vary with the noise draw (docs/findings-diagnosis.md).
unsigned noise_seed() {
  const char* text = std::getenv("SINKWATCH_DIAGNOSIS_SEED");
  return text != nullptr ? static_cast<unsigned>(std::strtoul(text, nullptr, 10)) : 20261121U;
}

// The effect at the size the check uses: the simulator's documented default
// (docs/simulator.md), except for three effects whose defaults are too small
// for this campaign's noise: 2 cm grousers (default 1 cm), a 4 degree
// friction-angle drop per e-fold of contact stress (default 1.5), 0.3 N m of
// gearbox drag (default 0.1). At the defaults the check passes for the
// seed below but not over noise draws: docs/findings-diagnosis.md has both.
void switch_on(SimParameters& p, Effect effect) {
  p.effects.set_enabled(effect, true);
  if (effect == Effect::grouser) {
    set_parameter(p, "grouser.height_m", 0.02);
  } else if (effect == Effect::load_dependence) {
    set_parameter(p, "load_dependence.dphi_deg", 4.0);
  } else if (effect == Effect::drive_friction) {
    set_parameter(p, "drive_friction.t0_nm", 0.3);
  }
}

// Every effect of the catalogue. An effect the check did not resolve would
// be listed in unresolved_effects() and run as a DISABLED_ case
// (`--gtest_also_run_disabled_tests`); none is now (findings-diagnosis.md).
// The sanitizer build (Debug, several times slower) checks one effect.
std::vector<Effect> resolved_effects() {
#if defined(SINKWATCH_DIAGNOSIS_QUICK)
  return {Effect::slip_sinkage};
#else
  return {Effect::slip_sinkage, Effect::stress_peak_shift, Effect::rear_contact, Effect::grouser,
          Effect::bulldozing, Effect::load_dependence, Effect::drive_friction};
#endif
}
std::vector<Effect> unresolved_effects() { return {}; }

struct Outcome {
  std::string effect;
  std::size_t rank = 0;
  std::string top;
  std::string fitted_name;
  double fitted = 0.0;
  double truth = 0.0;
  double before = 0.0;
  double after = 0.0;
  double shrink = 0.0;
  double true_after = 0.0;
  double true_shrink = 0.0;
  std::string verdict;
  double seconds = 0.0;
};

std::vector<Outcome>& outcomes() {
  static std::vector<Outcome> all;
  return all;
}

class WithheldEffect : public ::testing::TestWithParam<Effect> {};

TEST_P(WithheldEffect, RanksFirstWithTheTrueShrink) {
  const auto t0 = std::chrono::steady_clock::now();
  const Effect effect = GetParam();
  SimParameters truth = default_parameters("hit-lss1");
  switch_on(truth, effect);
  const std::vector<DatasetRow> generated =
      generate_dataset(truth, test_loads(), test_slips(), test_noise(), noise_seed());
  std::vector<DiagnosisRow> rows;
  for (const DatasetRow& g : generated) {
    rows.push_back(make_row(g.slip, g.load_n, g.sinkage_m, g.torque_nm, g.drawbar_pull_n, g.wheel_radius_m,
                            g.wheel_width_m));
  }

  // The fit starts from the preset with every effect off.
  const WongReeceModel model(default_parameters("hit-lss1"));
  DiagnosisSettings settings;
  // SINKWATCH_DIAGNOSIS_EVERY_LOAD: leave every load out in turn instead of
  // the two extreme ones (docs/diagnosis.md), for comparison.
  settings.every_load_fold = std::getenv("SINKWATCH_DIAGNOSIS_EVERY_LOAD") != nullptr;
  const DiagnosisResult result = diagnose(model, rows, "generated", settings);

  Outcome out;
  out.effect = std::string(effect_name(effect));
  out.verdict = verdict_name(result.verdict);
  out.before = result.cv_heldout_rms_scaled;
  out.top = result.ranking.front().effect;
  for (std::size_t k = 0; k < result.ranking.size(); ++k) {
    if (result.ranking[k].effect == out.effect) {
      const RankedEffect& found = result.ranking[k];
      out.rank = k + 1;
      out.after = found.heldout_rms_after;
      out.shrink = found.shrink_pct;
      out.fitted_name = primary_parameter_name(effect);
      const auto it = found.fitted.find(out.fitted_name);
      out.fitted = it != found.fitted.end() ? it->second : std::nan("");
    }
  }
  out.truth = get_parameter(truth, primary_parameter_name(effect));

  // True model on the same held-out rows (pooled over the same folds as the
  // ranking) and noise scale.
  const Candidate candidate = model.candidate_for(effect);
  std::vector<double> true_params = get_parameters(truth, WongReeceModel::default_base_parameters());
  for (const ParameterSpec& extra : candidate.extra) {
    true_params.push_back(get_parameter(truth, extra.name));
  }
  std::vector<FitResult> true_fits;
  for (const DataSplit& fold : result.folds) {
    true_fits.push_back(evaluate_model(model, &candidate, true_params, rows, fold, result.noise));
  }
  out.true_after = pooled_heldout(model, rows, true_fits, result.folds, result.noise).scaled;
  out.true_shrink = 100.0 * (out.before - out.true_after) / out.before;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  outcomes().push_back(out);

  EXPECT_NE(result.verdict, Verdict::no_gap) << "the withheld effect left no significant held-out gap";
  EXPECT_EQ(out.rank, 1U) << "top-ranked: " << out.top;
  EXPECT_NEAR(out.shrink, out.true_shrink, 10.0) << "reported shrink vs true shrink (percentage points)";
}

std::string case_name(const ::testing::TestParamInfo<Effect>& param_info) {
  return std::string(effect_name(param_info.param));
}

INSTANTIATE_TEST_SUITE_P(Catalogue, WithheldEffect, ::testing::ValuesIn(resolved_effects()), case_name);
INSTANTIATE_TEST_SUITE_P(DISABLED_Unresolved, WithheldEffect, ::testing::ValuesIn(unresolved_effects()), case_name);

// Prints the table once every parameterised case has run.
class TablePrinter : public ::testing::Environment {
 public:
  void TearDown() override {
    if (outcomes().empty()) {
      return;
    }
    std::ostringstream os;
    os << std::setprecision(3);
    os << "| effect | rank found | top-ranked | fitted size | true size | held-out before | after (fit) | "
          "after (true model) | shrink reported % | true shrink % | verdict | time s |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Outcome& o : outcomes()) {
      os << "| " << o.effect << " | " << o.rank << " | " << o.top << " | " << o.fitted_name << " = " << o.fitted
         << " | " << o.truth << " | " << o.before << " | " << o.after << " | " << o.true_after << " | " << o.shrink
         << " | " << o.true_shrink << " | " << o.verdict << " | " << o.seconds << " |\n";
    }
    std::printf("\n%s\n", os.str().c_str());
    if (const char* path = std::getenv("SINKWATCH_DIAGNOSIS_TABLE")) {
      std::ofstream(path) << os.str();
    }
  }
};

const ::testing::Environment* const kPrinter = ::testing::AddGlobalTestEnvironment(new TablePrinter);

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
