// The per-cycle step on arbitrary raw telemetry (any bits in every field, any
// time stamps): it must never produce a number from an invalid input, and
// whatever it returns must be consistent. Run under the sanitizer build, this
// is also the undefined-behaviour check of the whole chain.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdint>

#include "rover_test_support.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_step.hpp"

namespace sinkwatch {
namespace {

using rover_test::d;

std::int32_t any_raw() { return *rc::gen::arbitrary<std::int32_t>(); }

/// Mostly plausible values (so that the chain runs through), sometimes any bits.
template <typename Quantity>
Quantity plausible(double limit) {
  if (*rc::gen::weightedElement<bool>({{1, true}, {4, false}})) {
    return Quantity::from_raw(any_raw());
  }
  const std::int32_t lim = rover_test::q<Quantity>(limit).raw();
  return Quantity::from_raw(*rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int32_t>(-lim, lim + 1)));
}

RC_GTEST_PROP(RoverStepProp, NeverANumberFromInvalidInputAndAlwaysConsistent, ()) {
  const flight::ParameterTable table = flight::default_parameter_table();
  const flight::RoverParams rover = flight::yutu_like_rover_params(flight::kGravityMoon);
  flight::RoverStep step;
  const int cycles = *rc::gen::inRange(1, 12);
  std::uint32_t now = *rc::gen::arbitrary<std::uint32_t>();
  for (int c = 0; c < cycles; ++c) {
    flight::RoverTelemetry t{};
    now += *rc::gen::inRange<std::uint32_t>(0U, 300U);
    // Usually a fresh stamp, sometimes any stamp (stale, future, repeated).
    t.time = flight::TimeMs{*rc::gen::weightedElement<bool>({{4, true}, {1, false}})
                                ? now - *rc::gen::inRange<std::uint32_t>(0U, 50U)
                                : *rc::gen::arbitrary<std::uint32_t>()};
    t.valid = *rc::gen::weightedElement<bool>({{9, true}, {1, false}});
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      t.current_a[i] = plausible<flight::CurrentA>(3.0);
      t.direction[i] = *rc::gen::weightedElement<flight::DriveDirection>(
          {{8, flight::DriveDirection::forward}, {1, flight::DriveDirection::reverse},
           {1, static_cast<flight::DriveDirection>(7U)}});
    }
    t.attitude.pitch_rad = plausible<flight::AngleRad>(0.8);
    t.attitude.roll_rad = plausible<flight::AngleRad>(0.8);
    for (std::uint32_t s = 0U; s < flight::kSideCount; ++s) {
      t.joints.rocker_rad[s] = plausible<flight::AngleRad>(0.4);
      t.joints.bogie_rad[s] = plausible<flight::AngleRad>(0.55);
    }
    t.accel_valid = *rc::gen::arbitrary<bool>();
    t.accel_mps2 = plausible<flight::AccelMps2>(0.5);
    t.speed_valid = *rc::gen::arbitrary<bool>();
    t.speed_mps = plausible<flight::SpeedMps>(0.2);
    t.rim_speed_valid = *rc::gen::arbitrary<bool>();
    t.rim_speed_mps = plausible<flight::SpeedMps>(0.2);

    flight::RoverStepOutput out{};
    step.step(t, flight::TimeMs{now}, test::prepared_of(table, rover), out);

    const bool ok = out.status == flight::RoverStepStatus::ok;
    RC_CLASSIFY(ok, "full chain");
    RC_CLASSIFY(out.status == flight::RoverStepStatus::tip_over, "tip-over");
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      // No estimate without the whole chain behind it.
      if (!ok) {
        RC_ASSERT(!out.monitor.wheels[i].estimate_valid);
        RC_ASSERT(!out.monitor.wheels[i].limit_valid);
        RC_ASSERT(out.monitor.wheels[i].sample_status != flight::SampleStatus::ok);
      }
    }
    if (!t.valid || (static_cast<std::uint32_t>(now - t.time.ms) > table.monitor.stale_timeout_ms)) {
      RC_ASSERT(!out.loads_valid);
      RC_ASSERT(!out.drawbar_valid);
    }
    if (out.status == flight::RoverStepStatus::tip_over) {
      RC_ASSERT(out.decision == flight::RoverDecision::stop_and_replan);
      RC_ASSERT(out.lifting_wheel < flight::kWheelCount);
    }
    if (ok) {
      RC_ASSERT(out.loads_valid && out.drawbar_valid && out.accel_valid);
    }
    // The loads rest on the health stage's attitude: this sample's, or the
    // last good one while a spike or a fault is bridged.
    if (out.loads_valid && !out.health.attitude_bridged) {
      RC_ASSERT(out.health.attitude.pitch_rad == t.attitude.pitch_rad);
      RC_ASSERT(out.health.attitude.roll_rad == t.attitude.roll_rad);
    }
    // A wheel whose current channel is unusable has no estimate.
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      if (ok && !out.health.current_usable[i]) {
        // sensor_fault, or a reason the monitor checks first (a bad direction)
        RC_ASSERT(out.monitor.wheels[i].sample_status != flight::SampleStatus::ok);
        RC_ASSERT(!out.monitor.wheels[i].estimate_valid);
      }
    }
    if (out.loads_valid) {
      // A wheel's torque enters the loads only from a current the health
      // stage passed (docs/rover-loads.md 12.3); an overload takes none (12.4).
      double torque_abs_sum_nm = 0.0;
      for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
        const bool fell_back = ((out.torque_fallback_mask >> i) & 1U) != 0U;
        RC_ASSERT(fell_back || out.health.current_usable[i]);
        if (!fell_back) {
          const flight::TorqueResult torque = flight::torque_from_current(table.motor, t.current_a[i], t.direction[i]);
          RC_ASSERT(torque.status == flight::EstimateStatus::ok);
          torque_abs_sum_nm += std::fabs(d(torque.torque_nm));
        }
      }
      RC_ASSERT(!out.torque_overload || (out.torque_fallback_mask == 0x3FU));
      RC_CLASSIFY(out.torque_fallback_mask == 0U, "every torque in the loads");
      // The couples are internal: the loads still sum to the weight's normal part.
      const flight::RoverAttitude& a = out.health.attitude;
      const double mg = d(rover.mass_kg) * d(rover.gravity_mps2);
      const double normal = mg * std::cos(d(a.pitch_rad)) * std::cos(d(a.roll_rad));
      double sum = 0.0;
      for (const flight::WheelLoadN w : out.load_n) {
        RC_ASSERT(w.raw() >= 0);
        sum += d(w);
      }
      RC_ASSERT(std::fabs(sum - normal) <=
                6.0 * rover_test::load_bound_with_torques_n(mg, torque_abs_sum_nm) + 1e-6 * mg);
    }
    if (out.drawbar_valid) {
      // The default table's DP_max/W is 0.5 at every load: the cap holds.
      for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
        RC_ASSERT(std::fabs(d(out.drawbar_pull_n[i])) <= 0.5 * d(out.load_n[i]) + 1e-4);
      }
    }
    if (out.slip_known) {
      RC_ASSERT(std::fabs(d(out.slip)) <= 1.0);
    }
  }
}

}  // namespace
}  // namespace sinkwatch
