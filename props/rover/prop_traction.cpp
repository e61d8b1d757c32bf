// The motion-resistance coefficient (flight/traction.hpp) against its double
// twin (ground/rover_loads.hpp) over the whole input envelope: any loads in
// the default table's [load_min, load_max], torques to +-200 N m, pulls to
// +-500 N, radii 0.05..1 m. Bound (docs/traction.md, "Error"): the thrust
// sum T / r rounds once in Q31.32, the quotient once into Q7.24:
//   |rho_fixed - rho_ref| <= 2^-25 + 2^-33 / sum W.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "rover_test_support.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/traction.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace {

using rover_test::d;
using rover_test::q;

std::int32_t uniform_in(std::int32_t lo, std::int32_t hi) {
  return *rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int32_t>(lo, hi + 1));
}

template <typename Quantity>
Quantity raw_within(double lo, double hi) {
  return Quantity::from_raw(uniform_in(q<Quantity>(lo).raw(), q<Quantity>(hi).raw()));
}

RC_GTEST_PROP(TractionProp, CoefficientWithinBoundOfTheTwin, ()) {
  const flight::ParameterTable table = flight::default_parameter_table();
  const bool reverse = *rc::gen::arbitrary<bool>();
  flight::TractionInput in{};
  in.loads_valid = true;
  std::array<double, flight::kWheelCount> t{};
  std::array<double, flight::kWheelCount> p{};
  std::array<double, flight::kWheelCount> w{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    in.load_n[i] = raw_within<flight::WheelLoadN>(d(table.monitor.load_min_n), d(table.monitor.load_max_n));
    in.torque_nm[i] = raw_within<flight::TorqueNm>(-200.0, 200.0);
    in.drawbar_pull_n[i] = raw_within<flight::DrawbarPullN>(-500.0, 500.0);
    in.torque_valid[i] = true;
    in.direction[i] = reverse ? flight::DriveDirection::reverse : flight::DriveDirection::forward;
    t[i] = d(in.torque_nm[i]);
    p[i] = reverse ? -d(in.drawbar_pull_n[i]) : d(in.drawbar_pull_n[i]);
    w[i] = d(in.load_n[i]);
  }
  const flight::LengthM radius = raw_within<flight::LengthM>(0.05, 1.0);
  const double twin = ground::resistance_coefficient(t, p, w, d(radius));
  flight::TractionMonitor m;
  const flight::TractionOutput out = m.step(in, table.traction, table.monitor, radius);
  if (std::fabs(twin) >= 127.0) {
    RC_ASSERT(!out.rho_valid || std::fabs(d(out.resistance)) >= 127.0);  // saturated or reported
    return;
  }
  RC_ASSERT(out.rho_valid);
  double load = 0.0;
  for (const double x : w) load += x;
  const double bound = std::ldexp(1.0, -25) + std::ldexp(1.0, -33) / load + 1e-12 * std::fabs(twin);
  RC_ASSERT(std::fabs(d(out.resistance) - twin) <= bound);
}

}  // namespace
}  // namespace sinkwatch
