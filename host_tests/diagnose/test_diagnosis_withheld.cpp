// The withheld-effect check (issue 8): for each effect of the simulator's
// catalogue, generate soil-bin data with that effect on (at the size
// switch_on gives) plus realistic measurement noise, diagnose it with the base
// model that lacks every effect, and require that
//   - the withheld effect's family ranks first among the families (each
//     scored by its best form; the library has every form of every effect), and
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
#include "withheld_campaign.hpp"

namespace sinkwatch {
namespace ground {
namespace {

using withheld::campaign_rows;
using withheld::FamilyReading;
using withheld::read_family;
using withheld::true_heldout_rms;

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
  double bound = 0.0;  // the held-out RMS the noise allows the best family
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
  const std::vector<DiagnosisRow> rows = campaign_rows(truth);

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
  out.bound = result.residual_bound;
  // The family's rank among the families, each scored by its best form.
  const FamilyReading family = read_family(result, effect);
  out.top = family.top;
  out.rank = family.rank;
  out.after = family.after;
  out.shrink = family.shrink;
  out.fitted_name = family.best_effect + ": " + family.fitted_name;
  out.fitted = family.fitted;
  out.truth = get_parameter(truth, primary_parameter_name(effect));

  // True model on the same held-out rows (pooled over the same folds as the
  // ranking) and noise scale.
  const Candidate candidate = model.candidate_for(effect);
  std::vector<double> true_params = get_parameters(truth, WongReeceModel::default_base_parameters());
  for (const ParameterSpec& extra : candidate.extra) {
    true_params.push_back(get_parameter(truth, extra.name));
  }
  out.true_after = true_heldout_rms(model, &candidate, true_params, rows, result);
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
          "after (true model) | noise allows | shrink reported % | true shrink % | verdict | time s |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Outcome& o : outcomes()) {
      os << "| " << o.effect << " | " << o.rank << " | " << o.top << " | " << o.fitted_name << " = " << o.fitted
         << " | " << o.truth << " | " << o.before << " | " << o.after << " | " << o.true_after << " | " << o.bound << " | " << o.shrink
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
