// Fixed-point wheel loads against the double reference over the envelope:
// every attitude up to the attitude limit (beyond the tip-over limits), every
// joint angle the geometry allows, Moon, Mars and Earth gravity, and centres
// of mass moved around the default. docs/rover-loads.md, section 7.2, gives
// the bound asserted here (section 7.4 for the Q6.25 statics) and the rule
// for the stability decision.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "prepared_support.hpp"
#include "rover_test_support.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
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

flight::AngleRad angle_within(flight::AngleRad limit) {
  return flight::AngleRad::from_raw(uniform_in(-limit.raw(), limit.raw()));
}

/// The statuses the step refuses alike (loads_failed): a collapsed lever,
/// or an intermediate beyond every format of section 7.4.
bool refused(flight::WheelLoadStatus s) {
  return (s == flight::WheelLoadStatus::degenerate) || (s == flight::WheelLoadStatus::overflow);
}

flight::RoverParams envelope_params() {
  const flight::AccelMps2 gravities[3] = {flight::kGravityMoon, flight::kGravityMars, flight::kGravityEarth};
  flight::RoverParams p = flight::yutu_like_rover_params(gravities[uniform_in(0, 2)]);
  // The centre of mass anywhere within +-5 cm of the default, in any LSB.
  const std::int32_t five_cm = rover_test::q<flight::LengthM>(0.05).raw();
  p.com_x_m = flight::LengthM::from_raw(uniform_in(-five_cm, five_cm));
  p.com_y_m = flight::LengthM::from_raw(uniform_in(-five_cm, five_cm));
  p.com_z_m = flight::LengthM::from_raw(p.com_z_m.raw() + uniform_in(-five_cm, five_cm));
  return p;
}

RC_GTEST_PROP(RoverWheelLoadProp, FixedPointWithinBoundOfReference, ()) {
  const flight::RoverParams p = envelope_params();
  RC_ASSERT(flight::validate_rover_params(p) == flight::RoverParamStatus::ok);
  const flight::RoverAttitude att{angle_within(p.attitude_limit_rad), angle_within(p.attitude_limit_rad)};
  flight::JointAnglesRad j{};
  for (std::uint32_t s = 0U; s < flight::kSideCount; ++s) {
    j.rocker_rad[s] = angle_within(p.rocker_limit_rad);
    j.bogie_rad[s] = angle_within(p.bogie_limit_rad);
  }
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, j, flight::kNoDriveTorques);
  const ground::WheelLoads ref =
      ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(att), rover_test::to_ground(j), ground::k_no_drive_torques);
  const double mg = d(p.mass_kg) * d(p.gravity_mps2);
  const double bound = rover_test::load_bound_n(mg);

  RC_ASSERT(r.status != flight::WheelLoadStatus::invalid_params);
  // Both guard the same levers at 1 mm; they could disagree only for a lever
  // within the rounding of the guard, which the envelope does not reach. An
  // overflow is only allowed where the twin's lateral span collapsed
  // (section 7.4: every format overflowed before the span was formed).
  RC_ASSERT((ref.status == ground::LoadStatus::degenerate) == refused(r.status));
  RC_CLASSIFY(r.status == flight::WheelLoadStatus::degenerate, "degenerate lever");
  RC_CLASSIFY(r.status == flight::WheelLoadStatus::overflow, "overflow at a collapsed lateral span");
  if (refused(r.status)) {
    return;
  }
  RC_ASSERT(ref.status == ground::LoadStatus::ok || ref.status == ground::LoadStatus::tip_over);
  if (ref.min_load_n > bound) {
    RC_ASSERT(r.status == flight::WheelLoadStatus::ok);
  } else if (ref.min_load_n < -bound) {
    RC_ASSERT(r.status == flight::WheelLoadStatus::tip_over);
    for (const flight::WheelLoadN w : r.load_n) RC_ASSERT(w.raw() == 0);
  }
  RC_CLASSIFY(r.status == flight::WheelLoadStatus::ok, "stable");
  RC_CLASSIFY(r.status == flight::WheelLoadStatus::tip_over, "beyond the stability limit");
  if (r.status == flight::WheelLoadStatus::ok) {
    for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
      RC_ASSERT(r.load_n[i].raw() >= 0);
      RC_ASSERT(std::fabs(d(r.load_n[i]) - ref.load_n[i]) <= bound);
    }
    RC_ASSERT(std::fabs(d(r.weight_normal_n) - ref.weight_normal_n) <= bound);
  }
}

/// Torques for the six wheels: each usable with probability 5/6, up to a
/// third of the rover's weight times the wheel radius (beyond any traction:
/// the overload fallback is exercised too), in any LSB.
flight::DriveTorques envelope_torques(const flight::RoverParams& p) {
  const double weight_n = d(p.mass_kg) * d(p.gravity_mps2);
  const std::int32_t max_raw = rover_test::q<flight::TorqueNm>(weight_n * d(p.wheel_radius_m) / 3.0).raw();
  flight::DriveTorques t{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    t.usable[i] = uniform_in(0, 5) != 0;
    t.torque_nm[i] = flight::TorqueNm::from_raw(t.usable[i] ? uniform_in(-max_raw, max_raw) : 0);
  }
  return t;
}

ground::DriveTorques to_ground(const flight::DriveTorques& t) {
  ground::DriveTorques g{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    g.usable[i] = t.usable[i];
    g.torque_nm[i] = d(t.torque_nm[i]);
  }
  return g;
}

// With drive torques: the bound of section 12.5, the fallback mask, and the
// two stability decisions (the torques' overload, then the weight's) outside
// their bands.
RC_GTEST_PROP(RoverWheelLoadProp, WithTorquesWithinBoundOfReference, ()) {
  const flight::RoverParams p = envelope_params();
  const flight::RoverAttitude att{angle_within(p.attitude_limit_rad), angle_within(p.attitude_limit_rad)};
  flight::JointAnglesRad j{};
  for (std::uint32_t s = 0U; s < flight::kSideCount; ++s) {
    j.rocker_rad[s] = angle_within(p.rocker_limit_rad);
    j.bogie_rad[s] = angle_within(p.bogie_limit_rad);
  }
  const flight::DriveTorques torques = envelope_torques(p);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, j, torques);
  const ground::WheelLoads ref = ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(att),
                                                     rover_test::to_ground(j), to_ground(torques));
  double torque_sum = 0.0;
  std::uint32_t mask = 0U;
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    torque_sum += std::fabs(d(torques.torque_nm[i]));
    mask |= torques.usable[i] ? 0U : (1U << i);
  }
  const double bound = rover_test::load_bound_with_torques_n(d(p.mass_kg) * d(p.gravity_mps2), torque_sum);
  RC_ASSERT((ref.status == ground::LoadStatus::degenerate) == refused(r.status));
  if (refused(r.status)) {
    return;
  }
  // The torques' decision: fall back exactly when they would lift a wheel.
  const bool torques_clear = ref.torque_min_load_n > bound;
  const bool torques_lift = ref.torque_min_load_n < -bound;
  if (torques_clear) {
    RC_ASSERT(!r.torque_overload);
    RC_ASSERT(r.torque_fallback_mask == mask);
  } else if (torques_lift && (mask != 0x3FU)) {
    RC_ASSERT(r.torque_fallback_mask == 0x3FU);
  }
  RC_CLASSIFY(r.torque_overload, "torque overload");
  if ((r.status == flight::WheelLoadStatus::ok) && (r.torque_overload == ref.torque_overload) &&
      (ref.status == ground::LoadStatus::ok)) {
    for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
      RC_ASSERT(r.load_n[i].raw() >= 0);
      RC_ASSERT(std::fabs(d(r.load_n[i]) - ref.load_n[i]) <= bound);
    }
  }
  RC_CLASSIFY(r.status == flight::WheelLoadStatus::ok && !r.torque_overload, "stable with torques");
}

// Near the stability limit: attitudes drawn close to the pure-pitch and
// pure-roll limits, where the smallest load crosses zero.
RC_GTEST_PROP(RoverWheelLoadProp, StabilityDecisionAgreesOutsideTheBand, ()) {
  const flight::RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  const bool pitch_axis = *rc::gen::arbitrary<bool>();
  const double limit = pitch_axis ? std::atan(0.25 / 0.30) : std::atan(0.45 / 0.55);
  const double offset = uniform_in(-100000, 100000) * 1e-7;  // +-0.01 rad
  const double sign = *rc::gen::arbitrary<bool>() ? 1.0 : -1.0;
  const double angle = sign * (limit + offset);
  const flight::RoverAttitude att =
      pitch_axis ? rover_test::attitude(angle, 0.0) : rover_test::attitude(0.0, angle);
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, zero, flight::kNoDriveTorques);
  const ground::WheelLoads ref =
      ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(att), rover_test::to_ground(zero), ground::k_no_drive_torques);
  const double bound = rover_test::load_bound_n(d(p.mass_kg) * d(p.gravity_mps2));
  if (ref.min_load_n > bound) {
    RC_ASSERT(r.status == flight::WheelLoadStatus::ok);
  } else if (ref.min_load_n < -bound) {
    RC_ASSERT(r.status == flight::WheelLoadStatus::tip_over);
  } else {
    RC_ASSERT(r.status == flight::WheelLoadStatus::ok || r.status == flight::WheelLoadStatus::tip_over);
  }
}

}  // namespace
}  // namespace sinkwatch
