// Fixed-point drawbar pulls against the double reference (docs/rover-loads.md,
// section 7.3): any stable load set, acceleration, slope, slip and DP_max/W
// in the accepted ranges. The reference gets the fixed-point loads exactly,
// so the comparison isolates this function's arithmetic.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdint>

#include "prepared_support.hpp"
#include "rover_test_support.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace {

using rover_test::d;

/// Uniform over [lo, hi]: inRange scales its range with the test size, which
/// would crowd the first tests at the lower limit (every angle at -limit).
std::int32_t uniform_in(std::int32_t lo, std::int32_t hi) {
  return *rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int32_t>(lo, hi + 1));
}

template <typename Quantity>
Quantity raw_within(Quantity lo, Quantity hi) {
  return Quantity::from_raw(uniform_in(lo.raw(), hi.raw()));
}

RC_GTEST_PROP(RoverDrawbarPullProp, FixedPointWithinBoundOfReference, ()) {
  const flight::AccelMps2 gravities[3] = {flight::kGravityMoon, flight::kGravityMars, flight::kGravityEarth};
  const flight::RoverParams p = flight::yutu_like_rover_params(gravities[uniform_in(0, 2)]);
  const flight::AngleRad pitch_limit = rover_test::q<flight::AngleRad>(0.6);
  const flight::AngleRad pitch = raw_within(flight::AngleRad{flight::AngleQ::from_raw(-pitch_limit.raw())}, pitch_limit);
  const flight::AngleRad roll = raw_within(flight::AngleRad{flight::AngleQ::from_raw(-pitch_limit.raw())}, pitch_limit);
  const flight::JointAnglesRad joints = rover_test::joints(0.1, -0.1, 0.0, 0.2);
  const flight::WheelLoadResult loads = flight::wheel_loads(test::prepared_rover(p), flight::RoverAttitude{pitch, roll}, joints, flight::kNoDriveTorques);
  RC_PRE(loads.status == flight::WheelLoadStatus::ok);

  flight::DrawbarInput in{};
  in.accel_mps2 = raw_within(flight::AccelMps2{flight::AccelQ::from_raw(-flight::kMaxAbsAccel.raw())}, flight::kMaxAbsAccel);
  if (*rc::gen::arbitrary<bool>()) {
    // Most of the time a rover-like acceleration, so the cap is not always hit.
    in.accel_mps2 = flight::AccelMps2::from_raw(in.accel_mps2.raw() / 100);
  }
  in.pitch_rad = pitch;
  in.slip_known = *rc::gen::arbitrary<bool>();
  in.slip = raw_within(rover_test::q<flight::Ratio>(-1.0), rover_test::q<flight::Ratio>(1.0));
  ground::DrawbarParams gp;
  gp.high_slip = d(p.high_slip);
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    in.dp_max_ratio[i] = raw_within(flight::Ratio::from_raw(1), flight::kMaxDpMaxRatio);
    gp.dp_max_over_w[i] = d(in.dp_max_ratio[i]);
  }
  const flight::DrawbarResult r = flight::drawbar_pulls(test::prepared_rover(p), loads, in);

  ground::WheelLoads gl;
  gl.status = ground::LoadStatus::ok;
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) gl.load_n[i] = d(loads.load_n[i]);
  const ground::DrawbarPulls ref = ground::drawbar_pulls(
      rover_test::to_ground(p), gl, ground::DrawbarInput{d(in.accel_mps2), d(in.pitch_rad), in.slip_known, d(in.slip)},
      gp);
  RC_ASSERT(ref.status != ground::DrawbarStatus::invalid_input);
  RC_ASSERT(flight::usable(r.status));
  const double mg = d(p.mass_kg) * d(p.gravity_mps2);
  const double bound = rover_test::drawbar_bound_n(mg, ref.total_n);
  RC_ASSERT(std::fabs(d(r.total_n) - ref.total_n) <= bound);
  RC_ASSERT((r.status == flight::DrawbarStatus::saturated) == (ref.status == ground::DrawbarStatus::saturated));
  RC_CLASSIFY(r.status == flight::DrawbarStatus::capped, "capped");
  RC_CLASSIFY(r.status == flight::DrawbarStatus::saturated, "saturated");
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    RC_ASSERT(std::fabs(d(r.dp_n[i]) - ref.dp_n[i]) <= bound);
  }
}

}  // namespace
}  // namespace sinkwatch
