// Benchmark (prints numbers; not a test): seconds per Wong–Reece diagnosis
// of the withheld-effect check's design (issue 16, docs/diagnosis.md "Speed"):
// 36 rows, 6 loads 2-24 kg x 6 slips 0.05-0.75, the check's noise and seed,
// one effect switched on, the base lacking every effect.
//
//   bench_diagnosis [EFFECT] [--threads N] [--tol QUADRATURE_REL_TOL]
//                   [--ftol FUNCTION_TOLERANCE] [--ptol PARAMETER_TOLERANCE]
//                   [--repeat K] [--fits]
//
// EFFECT (default grouser) is a name of the simulator's catalogue. Prints one
// line per run: seconds (wall and CPU of all threads), candidates, threads, tolerance, the top family and
// form, its shrink and the verdict, so that a faster setting can be checked
// for the same answer.
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_models.hpp"
#include "sinkwatch/ground/sim_dataset.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

namespace sg = sinkwatch::ground;

namespace {

struct Options {
  std::string effect = "grouser";
  std::size_t threads = 0;
  double tol = sg::kDefaultQuadratureRelTol;
  double ftol = sg::DiagnosisSettings{}.function_tolerance;
  double ptol = sg::DiagnosisSettings{}.parameter_tolerance;
  int repeat = 1;
  bool fits = false;  // --fits: each candidate's first-split fit (iterations, solver message) and predictions
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--threads" && has_value) {
      o.threads = std::strtoul(argv[++i], nullptr, 10);
    } else if (arg == "--tol" && has_value) {
      o.tol = std::strtod(argv[++i], nullptr);
    } else if (arg == "--ftol" && has_value) {
      o.ftol = std::strtod(argv[++i], nullptr);
    } else if (arg == "--ptol" && has_value) {
      o.ptol = std::strtod(argv[++i], nullptr);
    } else if (arg == "--fits") {
      o.fits = true;
    } else if (arg == "--repeat" && has_value) {
      o.repeat = std::atoi(argv[++i]);
    } else {
      o.effect = arg;
    }
  }
  return o;
}

// Forwards to a model and counts its predictions: the work of a diagnosis,
// independent of the machine's load (every prediction is one simulator
// evaluation, the whole cost: docs/diagnosis.md, "Speed").
class CountingModel final : public sg::DiagnosisModel {
 public:
  explicit CountingModel(const sg::DiagnosisModel& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  std::vector<sg::ChannelInfo> channels() const override { return inner_.channels(); }
  std::vector<double> measured(const sg::DiagnosisRow& row) const override { return inner_.measured(row); }
  std::vector<sg::ParameterSpec> base_parameters(const std::vector<sg::DiagnosisRow>& train) const override {
    return inner_.base_parameters(train);
  }
  std::vector<sg::Candidate> candidates(const std::vector<sg::DiagnosisRow>& train) const override {
    return inner_.candidates(train);
  }
  bool predict(const sg::Candidate* candidate, const std::vector<double>& params, const sg::DiagnosisRow& row,
               std::vector<double>& out) const override {
    tally(candidate);
    return inner_.predict(candidate, params, row, out);
  }
  bool predict_warm(const sg::Candidate* candidate, const std::vector<double>& params, const sg::DiagnosisRow& row,
                    std::vector<double>& out, std::vector<double>& warm) const override {
    tally(candidate);
    return inner_.predict_warm(candidate, params, row, out, warm);
  }
  std::size_t count() const { return count_.load(); }
  // Predictions per candidate ("base" for none), counted when per_candidate is set.
  std::map<std::string, std::size_t> by_candidate() const {
    const std::lock_guard<std::mutex> lock(lock_);
    return by_candidate_;
  }
  bool per_candidate = false;

 private:
  void tally(const sg::Candidate* candidate) const {
    ++count_;
    if (per_candidate) {
      const std::lock_guard<std::mutex> lock(lock_);
      ++by_candidate_[candidate != nullptr ? candidate->name : "base"];
    }
  }
  const sg::DiagnosisModel& inner_;
  mutable std::atomic<std::size_t> count_{0};
  mutable std::mutex lock_;
  mutable std::map<std::string, std::size_t> by_candidate_;
};

// The withheld-effect check's campaign (test_diagnosis_withheld.cpp).
std::vector<sg::DiagnosisRow> campaign(const std::string& effect) {
  sg::SimParameters truth = sg::default_parameters("hit-lss1");
  const sg::Effect e = sg::effect_from_name(effect);
  truth.effects.set_enabled(e, true);
  // The sizes of the withheld check (test_diagnosis_withheld.cpp, switch_on).
  if (e == sg::Effect::grouser) {
    sg::set_parameter(truth, "grouser.height_m", 0.02);
  } else if (e == sg::Effect::load_dependence) {
    sg::set_parameter(truth, "load_dependence.dphi_deg", 4.0);
  } else if (e == sg::Effect::drive_friction) {
    sg::set_parameter(truth, "drive_friction.t0_nm", 0.3);
  }
  std::vector<double> loads;
  for (double kg : {2.0, 4.0, 7.0, 11.0, 16.0, 24.0}) {
    loads.push_back(kg * 9.81);
  }
  sg::NoiseModel noise;
  noise.sinkage_m = {2e-4, 0.01};
  noise.torque_nm = {0.005, 0.01};
  noise.drawbar_pull_n = {0.2, 0.02};
  std::vector<sg::DiagnosisRow> rows;
  for (const sg::DatasetRow& g :
       sg::generate_dataset(truth, loads, {0.05, 0.15, 0.3, 0.45, 0.6, 0.75}, noise, 20261121U)) {
    rows.push_back(sg::make_row(g.slip, g.load_n, g.sinkage_m, g.torque_nm, g.drawbar_pull_n, g.wheel_radius_m,
                                g.wheel_width_m));
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const std::vector<sg::DiagnosisRow> rows = campaign(o.effect);
  sg::SimParameters start = sg::default_parameters("hit-lss1");
  start.quadrature_rel_tol = o.tol;
  const sg::WongReeceModel simulator(start);
  CountingModel model(simulator);
  model.per_candidate = o.fits;
  sg::DiagnosisSettings settings;
  settings.threads = o.threads;
  settings.function_tolerance = o.ftol;
  settings.parameter_tolerance = o.ptol;
  for (int k = 0; k < o.repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const std::size_t predictions0 = model.count();
    const sg::DiagnosisResult r = sg::diagnose(model, rows, "bench", settings);
    const std::size_t predictions = model.count() - predictions0;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    const sg::RankedFamily* top = r.families.empty() ? nullptr : &r.families.front();
    std::printf("%.2f s (cpu %.2f s, %zu predictions)  effect %s  %zu candidates  threads %zu  tol %g  ftol %g  top %s/%s  after %.4f  shrink %.2f %%  %s\n",
                seconds, cpu_seconds, predictions, o.effect.c_str(), r.ranking.size(), o.threads, o.tol, o.ftol,
                top != nullptr ? top->family.c_str() : "-", top != nullptr ? top->best_form.c_str() : "-",
                top != nullptr ? top->heldout_rms_after : 0.0, top != nullptr ? top->shrink_pct : 0.0,
                sg::verdict_name(r.verdict));
    if (o.fits) {
      const std::map<std::string, std::size_t> counts = model.by_candidate();
      const auto count_of = [&](const std::string& name) {
        const auto it = counts.find(name);
        return it != counts.end() ? it->second : std::size_t{0};
      };
      std::printf("  base: %d iterations, %zu predictions, %s\n", r.base.iterations, count_of("base"),
                  r.base.solver_message.c_str());
      for (const sg::RankedEffect& e : r.ranking) {
        std::printf("  %-32s after %.4f  %d iterations, %zu predictions, %s\n", e.effect.c_str(), e.heldout_rms_after,
                    e.fit.iterations, count_of(e.effect), e.fit.solver_message.c_str());
      }
    }
  }
  return 0;
}
