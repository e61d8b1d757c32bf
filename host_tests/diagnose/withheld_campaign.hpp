// The soil-bin campaign and bookkeeping shared by the withheld-effect checks
// (test_diagnosis_withheld.cpp: each effect in the library's own form;
// test_diagnosis_crossform.cpp: effects in forms the library is denied, and a
// form it does not have): 36 rows, the noise model, the seed, and the
// family-level reading of a diagnosis (rank of a family, its best form's
// shrink and fitted size, the generating model's own held-out RMS).
#ifndef SINKWATCH_HOST_TESTS_WITHHELD_CAMPAIGN_HPP
#define SINKWATCH_HOST_TESTS_WITHHELD_CAMPAIGN_HPP

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/sim_dataset.hpp"

// The reduced set of the sanitizer build (Debug, several times slower): the
// CMake definition, or the sanitizer itself as the compiler reports it.
#if !defined(SINKWATCH_DIAGNOSIS_QUICK)
#if defined(__SANITIZE_ADDRESS__)
#define SINKWATCH_DIAGNOSIS_QUICK 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define SINKWATCH_DIAGNOSIS_QUICK 1
#endif
#endif
#endif

namespace sinkwatch {
namespace ground {
namespace withheld {

// A comma list from the environment, or the fallback.
inline std::vector<double> list_from_env(const char* name, std::vector<double> fallback) {
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

// 6 loads over the 12:1 range a wheel of this size carries (2 to 24 kg on
// Earth) x 6 slips (docs/findings-diagnosis.md says why);
// SINKWATCH_DIAGNOSIS_MASSES and SINKWATCH_DIAGNOSIS_SLIPS try another design.
inline std::vector<double> test_loads() {
  std::vector<double> loads;
  for (double kg : list_from_env("SINKWATCH_DIAGNOSIS_MASSES", {2.0, 4.0, 7.0, 11.0, 16.0, 24.0})) {
    loads.push_back(kg * 9.81);
  }
  return loads;
}
inline std::vector<double> test_slips() {
  return list_from_env("SINKWATCH_DIAGNOSIS_SLIPS", {0.05, 0.15, 0.3, 0.45, 0.6, 0.75});
}

// Soil-bin noise: sinkage gauge 0.2 mm plus 1 %, torque sensor 0.005 N m
// plus 1 %, drawbar-pull load cell 0.2 N plus 2 %.
inline NoiseModel test_noise() {
  NoiseModel noise;
  noise.sinkage_m = {2e-4, 0.01};
  noise.torque_nm = {0.005, 0.01};
  noise.drawbar_pull_n = {0.2, 0.02};
  return noise;
}

// SINKWATCH_DIAGNOSIS_SEED picks another noise draw (docs/findings-diagnosis.md).
inline unsigned noise_seed() {
  const char* text = std::getenv("SINKWATCH_DIAGNOSIS_SEED");
  return text != nullptr ? static_cast<unsigned>(std::strtoul(text, nullptr, 10)) : 20261121U;
}

// The campaign's rows, generated with `truth` and the noise above.
inline std::vector<DiagnosisRow> campaign_rows(const SimParameters& truth) {
  std::vector<DiagnosisRow> rows;
  for (const DatasetRow& g : generate_dataset(truth, test_loads(), test_slips(), test_noise(), noise_seed())) {
    rows.push_back(make_row(g.slip, g.load_n, g.sinkage_m, g.torque_nm, g.drawbar_pull_n, g.wheel_radius_m,
                            g.wheel_width_m));
  }
  return rows;
}

// How a diagnosis ranked one effect family.
struct FamilyReading {
  std::size_t rank = 0;     // 1 = first among the families; 0 = not ranked
  std::string top;          // the first family
  std::string best_effect;  // the family's best candidate ("grouser.lug_face")
  std::string best_form;
  double after = 0.0;       // its held-out RMS (noise units, pooled)
  double shrink = 0.0;
  std::string fitted_name;  // the best form's primary parameter and fitted value
  double fitted = std::nan("");
};

inline FamilyReading read_family(const DiagnosisResult& result, Effect family) {
  FamilyReading out;
  const std::string name(effect_name(family));
  out.top = result.families.empty() ? std::string() : result.families.front().family;
  for (std::size_t k = 0; k < result.families.size(); ++k) {
    const RankedFamily& f = result.families[k];
    if (f.family != name) {
      continue;
    }
    out.rank = k + 1;
    out.best_effect = f.best_effect;
    out.best_form = f.best_form.empty() ? effect_forms(family).front() : f.best_form;
    out.after = f.heldout_rms_after;
    out.shrink = f.shrink_pct;
    out.fitted_name = primary_parameter_name(family, out.best_form);
    const RankedEffect& best = result.ranking.at(f.best_rank);
    const auto it = best.fitted.find(out.fitted_name);
    out.fitted = it != best.fitted.end() ? it->second : std::nan("");
  }
  return out;
}

// The generating model itself (true soil, true effect, no fit) on the same
// held-out rows of the same folds and the same per-row noise as the ranking.
// `candidate` null: the model's base (e.g. a model started from the truth).
inline double true_heldout_rms(const WongReeceModel& model, const Candidate* candidate,
                               const std::vector<double>& true_params, const std::vector<DiagnosisRow>& rows,
                               const DiagnosisResult& result) {
  std::vector<FitResult> fits;
  for (const DataSplit& fold : result.folds) {
    fits.push_back(evaluate_model(model, candidate, true_params, rows, fold, result.noise));
  }
  return pooled_heldout(model, rows, fits, result.folds, result.noise).scaled;
}

}  // namespace withheld
}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_WITHHELD_CAMPAIGN_HPP
