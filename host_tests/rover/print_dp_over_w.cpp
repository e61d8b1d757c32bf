// Prints (not a test): DP/W against the wheel load at fixed slips, from the
// ground's Wong-Reece simulator (ground/sim), for the soils it ships, under
// lunar gravity. It is the evidence behind splitting the rover's drawbar pull
// in proportion to the wheel loads (docs/rover-loads.md, section 6.2): at a
// given slip DP/W barely depends on the load.
#include <cstdio>

#include "sinkwatch/ground/soil_presets.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

namespace sg = sinkwatch::ground;

int main() {
  const double loads[] = {10.0, 20.0, 30.0, 40.0, 60.0, 80.0};
  for (const char* soil : {"hit-lss1", "lunar-soil"}) {
    sg::SimParameters p = sg::default_parameters(soil);
    p.gravity_m_s2 = 1.62;
    std::printf("soil %s, lunar gravity\n  load [N]   ", soil);
    for (const double w : loads) std::printf(" %7.0f", w);
    std::printf("   spread\n");
    for (const double s : {0.05, 0.1, 0.2, 0.3, 0.5}) {
      std::printf("  s = %.2f  ", s);
      double lo = 1e9;
      double hi = -1e9;
      for (const double w : loads) {
        const sg::Evaluation e = sg::evaluate(p, w, s);
        const double ratio = e.state.drawbar_pull_n / w;
        lo = ratio < lo ? ratio : lo;
        hi = ratio > hi ? ratio : hi;
        std::printf(" %7.3f", ratio);
      }
      std::printf("   %.3f\n", hi - lo);
    }
  }
  return 0;
}
