// Benchmark (prints numbers; not a test): cost of one simulator evaluation and
// of a fit-sized workload (issue 8: a few dozen rows x hundreds of evaluations).
#include "sinkwatch/ground/soil_presets.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <chrono>
#include <cstdio>

namespace sg = sinkwatch::ground;

int main() {
  struct Case {
    const char* name;
    sg::SimParameters params;
  };
  sg::SimParameters all = sg::default_parameters("hit-lss1");
  for (sg::Effect e : sg::kAllEffects) all.effects.set_enabled(e, true);
  const Case cases[] = {{"base model (hit-lss1)", sg::default_parameters("hit-lss1")},
                        {"all seven effects on", all}};
  for (const Case& c : cases) {
    // 5 loads x 15 slips = 75 rows, 40 passes = 3000 evaluations.
    int evaluations = 0;
    double checksum = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int pass = 0; pass < 40; ++pass) {
      for (double m : {3.0, 7.0, 10.0, 15.0, 20.0}) {
        for (int i = 0; i < 15; ++i) {
          checksum += sg::evaluate(c.params, m * 9.81, 0.05 * i).state.drawbar_pull_n;
          ++evaluations;
        }
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-24s %6d evaluations, %.3f ms each; 40 rows x 500 evaluations ~ %.1f s (checksum %.6g)\n",
                c.name, evaluations, 1e3 * seconds / evaluations, 40 * 500 * seconds / evaluations, checksum);
  }
  return 0;
}
