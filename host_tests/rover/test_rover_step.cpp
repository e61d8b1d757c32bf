// The per-cycle step (docs/rover-loads.md, section 8): a nominal cycle end to
// end, against the chain of flight functions called one by one; acceleration
// from the speed difference (its bits, and none from a repeated time stamp);
// slip and high slip; a wheel carrying exactly 0 N; every telemetry failure
// and its fail-safe; tip-over stopping the rover at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <cmath>
#include <cstdint>

#include "rover_test_support.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/traction.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace {

using flight::RoverStepStatus;
using rover_test::d;
using rover_test::q;

flight::RoverTelemetry telemetry(std::uint32_t time_ms) {
  flight::RoverTelemetry t{};
  t.time = flight::TimeMs{time_ms};
  t.valid = true;
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    t.current_a[i] = q<flight::CurrentA>(0.35);
    t.direction[i] = flight::DriveDirection::forward;
  }
  t.attitude = rover_test::attitude(0.0, 0.0);
  t.joints = rover_test::joints(0, 0, 0, 0);
  t.accel_valid = true;
  t.accel_mps2 = flight::AccelMps2::zero();
  t.speed_valid = false;
  t.rim_speed_valid = false;
  return t;
}

/// A cycle with a ground speed and no measured acceleration: the step
/// differences the speed.
flight::RoverTelemetry speed_sample(std::uint32_t time_ms, double speed_mps) {
  flight::RoverTelemetry t = telemetry(time_ms);
  t.accel_valid = false;
  t.speed_valid = true;
  t.speed_mps = q<flight::SpeedMps>(speed_mps);
  return t;
}

class RoverStepTest : public ::testing::Test {
 protected:
  flight::ParameterTable table = flight::default_parameter_table();
  flight::RoverParams rover = flight::yutu_like_rover_params(flight::kGravityMoon);
  flight::RoverStep step;
};

TEST_F(RoverStepTest, NominalCycleGivesEveryNumberAndMatchesTheChain) {
  flight::RoverTelemetry t = telemetry(1000U);
  t.attitude = rover_test::attitude(0.12, -0.05);
  t.joints = rover_test::joints(0.08, -0.08, 0.1, -0.02);
  t.accel_mps2 = q<flight::AccelMps2>(0.01);
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{1010U}, test::prepared_of(table, rover), out);
  ASSERT_EQ(out.status, RoverStepStatus::ok);
  ASSERT_TRUE(out.loads_valid);
  ASSERT_TRUE(out.drawbar_valid);
  EXPECT_EQ(out.decision, flight::RoverDecision::continue_drive);

  // The same chain, one function at a time: every current is healthy, so
  // every wheel's torque enters the statics.
  flight::DriveTorques torques{};
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    torques.torque_nm[i] = flight::torque_from_current(table.motor, t.current_a[i], t.direction[i]).torque_nm;
    torques.usable[i] = true;
  }
  const flight::WheelLoadResult loads = flight::wheel_loads(test::prepared_rover(rover), t.attitude, t.joints, torques);
  ASSERT_EQ(loads.status, flight::WheelLoadStatus::ok);
  EXPECT_EQ(out.torque_fallback_mask, 0U);
  EXPECT_FALSE(out.torque_overload);
  flight::DrawbarInput in{};
  in.accel_mps2 = t.accel_mps2;
  in.pitch_rad = t.attitude.pitch_rad;
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    in.dp_max_ratio[i] = test::corrections_of(table.correction, loads.load_n[i]).dp_max_ratio;
  }
  const flight::DrawbarResult dp = flight::drawbar_pulls(test::prepared_rover(rover), loads, in);
  ASSERT_TRUE(flight::usable(dp.status));
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    EXPECT_EQ(out.load_n[i], loads.load_n[i]);
    EXPECT_EQ(out.drawbar_pull_n[i], dp.dp_n[i]);
    const flight::WheelOutput& w = out.monitor.wheels[i];
    EXPECT_EQ(w.sample_status, flight::SampleStatus::ok) << i;
    ASSERT_TRUE(w.estimate_valid) << i;
    ASSERT_TRUE(w.limit_valid) << i;
    EXPECT_EQ(w.state, flight::WheelState::nominal) << i;
    const flight::TorqueResult torque =
        flight::torque_from_current(table.motor, t.current_a[i], flight::DriveDirection::forward);
    const flight::CorrectionResult corr = test::corrections_of(table.correction, loads.load_n[i]);
    const flight::SinkageResult z = flight::sinkage_from_pull(corr.coefficients, table.wheel_radius_m,
                                                              loads.load_n[i], torque.torque_nm, dp.dp_n[i]);
    EXPECT_EQ(w.torque_nm, torque.torque_nm) << i;
    EXPECT_EQ(w.sinkage_m, z.sinkage_m) << i;
    // The same 0.35 A on every wheel while climbing 0.12 rad: the estimates
    // stay small either way.
    EXPECT_LT(std::fabs(d(w.sinkage_m)), 0.03) << i;
  }
}

TEST_F(RoverStepTest, ACurrentBeyondTheSensorRangeGivesNoTorqueToTheLoads) {
  flight::RoverTelemetry t = telemetry(3000U);
  t.current_a[4] = q<flight::CurrentA>(d(table.motor.current_abs_max_a) + 0.5);
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{3000U}, test::prepared_of(table, rover), out);
  ASSERT_TRUE(out.loads_valid);
  EXPECT_EQ(out.torque_fallback_mask, 1U << 4U);
  EXPECT_FALSE(out.torque_overload);
}

TEST_F(RoverStepTest, AccelerationFromTheSpeedDifference) {
  flight::RoverTelemetry t = speed_sample(2000U, 0.05);
  flight::RoverStepOutput first{};
  step.step(t, flight::TimeMs{2000U}, test::prepared_of(table, rover), first);
  EXPECT_EQ(first.status, RoverStepStatus::no_acceleration);
  EXPECT_TRUE(first.loads_valid);  // the loads exist, the pulls do not
  EXPECT_FALSE(first.drawbar_valid);
  EXPECT_EQ(first.monitor.wheels[0].sample_status, flight::SampleStatus::flagged_invalid);

  t.time = flight::TimeMs{2100U};
  t.speed_mps = q<flight::SpeedMps>(0.06);
  flight::RoverStepOutput second{};
  step.step(t, flight::TimeMs{2100U}, test::prepared_of(table, rover), second);
  ASSERT_EQ(second.status, RoverStepStatus::ok);
  ASSERT_TRUE(second.accel_valid);
  EXPECT_NEAR(d(second.accel_mps2), 0.1, 1e-6);
  double sum = 0.0;
  for (const flight::DrawbarPullN p : second.drawbar_pull_n) sum += d(p);
  EXPECT_NEAR(sum, d(rover.mass_kg) * 0.1, 1e-3);  // flat ground: m a
}

/// (v - v_prev) / dt in Q7.24 as the step defines it: in Q31.32 (2^-32 m/s^2)
/// round(dv 2^8 1000 / dt), then rounded into Q7.24; both roundings half
/// away from zero, written out in integers.
std::int32_t accel_raw_in_q31_32_then_q7_24(std::int32_t speed_raw, std::int32_t previous_raw, std::uint32_t dt_ms) {
  const std::int64_t dv = static_cast<std::int64_t>(speed_raw) - previous_raw;
  const std::uint64_t n = static_cast<std::uint64_t>((dv < 0) ? -dv : dv) * 256000U;
  const std::uint64_t q32 = (n / dt_ms) + ((2U * (n % dt_ms) >= dt_ms) ? 1U : 0U);
  const auto q24 = static_cast<std::int64_t>((q32 + 128U) >> 8U);
  return static_cast<std::int32_t>((dv < 0) ? -q24 : q24);
}

TEST_F(RoverStepTest, DifferencedAccelerationHasTheBitsOfTheQ31_32Quotient) {
  // Speeds and intervals whose quotients are not exact, both signs; each
  // cycle's acceleration is this speed less the last one over the interval.
  std::mt19937 rng(0x15A);
  flight::RoverTelemetry t = speed_sample(2000U, 0.05);
  flight::RoverStepOutput out{};
  step.step(t, t.time, test::prepared_of(table, rover), out);
  for (int i = 0; i < 40; ++i) {
    const std::int32_t previous_raw = t.speed_mps.raw();
    const std::uint32_t dt_ms = 7U + (rng() % 193U);
    t.time = flight::TimeMs{t.time.ms + dt_ms};
    t.speed_mps = q<flight::SpeedMps>(0.05 + 0.01 * static_cast<double>(static_cast<int>(rng() % 2001U) - 1000) / 1000.0);
    step.step(t, t.time, test::prepared_of(table, rover), out);
    ASSERT_TRUE(out.accel_valid) << i;
    EXPECT_EQ(out.accel_mps2.raw(), accel_raw_in_q31_32_then_q7_24(t.speed_mps.raw(), previous_raw, dt_ms)) << i;
  }
}

TEST_F(RoverStepTest, SpeedWithTheTimeStampOfTheLastSpeedGivesNoAcceleration) {
  // A speed sample that reuses the last speed's time stamp (the cycle in
  // between carried no speed): no differenced acceleration, so the cycle
  // reports no_acceleration instead of dividing by zero.
  flight::RoverTelemetry a = telemetry(1000U);  // speed and a measured acceleration
  a.speed_valid = true;
  a.speed_mps = q<flight::SpeedMps>(0.05);
  flight::RoverStepOutput out{};
  step.step(a, flight::TimeMs{1000U}, test::prepared_of(table, rover), out);
  ASSERT_EQ(out.status, RoverStepStatus::ok);
  const flight::RoverTelemetry b = telemetry(1100U);  // no speed, a measured acceleration
  step.step(b, flight::TimeMs{1100U}, test::prepared_of(table, rover), out);
  ASSERT_EQ(out.status, RoverStepStatus::ok);
  const flight::RoverTelemetry c = speed_sample(1000U, 0.07);  // the speed sample's time again, not the last cycle's
  step.step(c, flight::TimeMs{1150U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::no_acceleration);
  EXPECT_FALSE(out.accel_valid);
  // The control: the speed of c was still remembered (at 1000 ms), so 200 ms
  // later the difference exists: (0.09 - 0.07) / 0.2 s = 0.1 m/s^2.
  const flight::RoverTelemetry e = speed_sample(1200U, 0.09);
  flight::RoverStepOutput later{};
  step.step(e, flight::TimeMs{1200U}, test::prepared_of(table, rover), later);
  ASSERT_TRUE(later.accel_valid);
  EXPECT_NEAR(d(later.accel_mps2), 0.1, 1e-6);
}

/// The largest roll (raw Q3.28) at which no wheel needs a negative load, by
/// bisection between level ground and a roll that tips the rover over.
flight::AngleRad last_roll_before_tip_over(const flight::RoverParams& p) {
  std::int32_t ok_raw = 0;
  std::int32_t tip_raw = q<flight::AngleRad>(0.99).raw();
  const flight::JointAnglesRad level_joints{};
  const auto status_at = [&](std::int32_t roll_raw) {
    const flight::RoverAttitude at{flight::AngleRad::zero(), flight::AngleRad::from_raw(roll_raw)};
    return flight::wheel_loads(test::prepared_rover(p), at, level_joints, flight::kNoDriveTorques).status;
  };
  EXPECT_EQ(status_at(tip_raw), flight::WheelLoadStatus::tip_over);
  while (tip_raw - ok_raw > 1) {
    const std::int32_t mid = ok_raw + ((tip_raw - ok_raw) / 2);
    if (status_at(mid) == flight::WheelLoadStatus::ok) {
      ok_raw = mid;
    } else {
      tip_raw = mid;
    }
  }
  return flight::AngleRad::from_raw(ok_raw);
}

TEST_F(RoverStepTest, WheelCarryingExactlyZeroNewtonsFailsTheDrawbarStage) {
  // The last attitude before tip-over: a wheel carries exactly 0 N (raw 0),
  // for which the corrections have no row (Eq. 11 divides by W), so the
  // drawbar stage fails instead of producing pulls.
  rover.com_z_m = q<flight::LengthM>(0.60);  // a high centre of mass tips within the attitude limit
  ASSERT_EQ(flight::validate_rover_params(rover), flight::RoverParamStatus::ok);
  const flight::AngleRad roll = last_roll_before_tip_over(rover);
  const flight::WheelLoadResult loads =
      flight::wheel_loads(test::prepared_rover(rover), flight::RoverAttitude{flight::AngleRad::zero(), roll}, flight::JointAnglesRad{},
                          flight::kNoDriveTorques);
  ASSERT_EQ(loads.status, flight::WheelLoadStatus::ok);
  std::int32_t lowest = loads.load_n[0].raw();
  for (const flight::WheelLoadN& l : loads.load_n) {
    lowest = (l.raw() < lowest) ? l.raw() : lowest;
  }
  // At the last roll before tip-over the lifting wheel's support is below
  // half an LSB of the load format: its load is exactly zero.
  ASSERT_EQ(lowest, 0) << "roll " << d(roll);
  flight::RoverTelemetry t = telemetry(1000U);
  t.attitude.roll_rad = roll;
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{1000U}, test::prepared_of(table, rover), out);
  EXPECT_TRUE(out.loads_valid);
  EXPECT_EQ(out.status, RoverStepStatus::drawbar_failed);
  EXPECT_EQ(out.drawbar_status, flight::DrawbarStatus::invalid_input);
  EXPECT_FALSE(out.drawbar_valid);
}

TEST_F(RoverStepTest, SlipFromGroundAndRimSpeedAndHighSlipSaturates) {
  flight::RoverTelemetry t = telemetry(3000U);
  t.speed_valid = true;
  t.speed_mps = q<flight::SpeedMps>(0.04);
  t.rim_speed_valid = true;
  t.rim_speed_mps = q<flight::SpeedMps>(0.05);
  flight::RoverStepOutput low{};
  step.step(t, flight::TimeMs{3000U}, test::prepared_of(table, rover), low);
  ASSERT_EQ(low.status, RoverStepStatus::ok);
  ASSERT_TRUE(low.slip_known);
  EXPECT_NEAR(d(low.slip), 0.2, 1e-6);
  EXPECT_EQ(low.drawbar_status, flight::DrawbarStatus::ok);

  t.time = flight::TimeMs{3100U};
  t.speed_mps = q<flight::SpeedMps>(0.01);  // slip 0.8 >= high_slip 0.6
  flight::RoverStepOutput high{};
  step.step(t, flight::TimeMs{3100U}, test::prepared_of(table, rover), high);
  ASSERT_EQ(high.status, RoverStepStatus::ok);
  EXPECT_NEAR(d(high.slip), 0.8, 1e-6);
  EXPECT_EQ(high.drawbar_status, flight::DrawbarStatus::saturated);
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    EXPECT_NEAR(d(high.drawbar_pull_n[i]), 0.5 * d(high.load_n[i]), 1e-4);  // DP_max/W = 0.5
  }

  t.time = flight::TimeMs{3200U};
  t.speed_mps = q<flight::SpeedMps>(-0.05);  // moving against the wheels: limited to 1
  flight::RoverStepOutput against{};
  step.step(t, flight::TimeMs{3200U}, test::prepared_of(table, rover), against);
  EXPECT_EQ(d(against.slip), 1.0);
  t.time = flight::TimeMs{3300U};
  t.rim_speed_mps = q<flight::SpeedMps>(0.0005);  // below 1 mm/s: slip undefined
  flight::RoverStepOutput idle{};
  step.step(t, flight::TimeMs{3300U}, test::prepared_of(table, rover), idle);
  EXPECT_FALSE(idle.slip_known);
}

TEST_F(RoverStepTest, FlaggedStaleAndRepeatedTelemetryAreRefusedAndCounted) {
  flight::RoverTelemetry t = telemetry(5000U);
  t.valid = false;
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{5000U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::telemetry_invalid);
  EXPECT_FALSE(out.loads_valid);
  EXPECT_EQ(out.monitor.wheels[0].sample_status, flight::SampleStatus::flagged_invalid);

  t.valid = true;
  step.step(t, flight::TimeMs{5000U + table.monitor.stale_timeout_ms + 1U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::telemetry_stale);
  EXPECT_EQ(out.monitor.wheels[3].sample_status, flight::SampleStatus::stale);
  EXPECT_FALSE(out.loads_valid);

  // From the future: stale as well (the wrapping age is huge).
  step.step(t, flight::TimeMs{4000U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::telemetry_stale);

  step.step(t, flight::TimeMs{5010U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::ok);
  step.step(t, flight::TimeMs{5020U}, test::prepared_of(table, rover), out);  // same stamp again
  EXPECT_EQ(out.status, RoverStepStatus::telemetry_repeated);
  EXPECT_NE(out.monitor.wheels[0].sample_status, flight::SampleStatus::ok);
  EXPECT_FALSE(out.monitor.wheels[0].estimate_valid);

  const flight::WheelCounters& c = step.monitor().wheel(0U).counters();
  EXPECT_EQ(c.by_status[static_cast<std::size_t>(flight::SampleStatus::stale)], 2U);
  EXPECT_GE(c.by_status[static_cast<std::size_t>(flight::SampleStatus::flagged_invalid)], 1U);
}

TEST_F(RoverStepTest, MotionOutOfRangeIsRefused) {
  flight::RoverTelemetry t = telemetry(6000U);
  t.accel_mps2 = q<flight::AccelMps2>(12.0);
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{6000U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::motion_out_of_range);
  t.time = flight::TimeMs{6100U};
  t.accel_mps2 = flight::AccelMps2::zero();
  t.speed_valid = true;
  t.speed_mps = q<flight::SpeedMps>(6.0);
  step.step(t, flight::TimeMs{6100U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::motion_out_of_range);
  t.time = flight::TimeMs{6200U};
  t.speed_valid = false;
  t.rim_speed_valid = true;
  t.rim_speed_mps = q<flight::SpeedMps>(-5.5);
  step.step(t, flight::TimeMs{6200U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::motion_out_of_range);
}

TEST_F(RoverStepTest, TipOverStopsTheRoverInTheSameCycle) {
  flight::RoverTelemetry t = telemetry(7000U);
  t.attitude = rover_test::attitude(0.0, 0.75);  // beyond the 39.3 deg roll limit
  flight::RoverStepOutput out{};
  step.step(t, flight::TimeMs{7000U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::tip_over);
  EXPECT_EQ(out.load_status, flight::WheelLoadStatus::tip_over);
  EXPECT_EQ(out.decision, flight::RoverDecision::stop_and_replan);
  EXPECT_LT(out.lifting_wheel, 3U);  // a left wheel lifts
  EXPECT_FALSE(out.loads_valid);
  EXPECT_FALSE(out.drawbar_valid);
  for (const flight::WheelLoadN w : out.load_n) EXPECT_EQ(w.raw(), 0);
}

TEST_F(RoverStepTest, PersistentlyUnusableTelemetryStopsTheRover) {
  flight::RoverTelemetry t = telemetry(8000U);
  t.attitude = rover_test::attitude(1.02, 0.0);  // beyond the attitude limit: no loads
  flight::RoverStepOutput out{};
  for (std::uint32_t k = 0U; k < table.monitor.invalid_to_stop; ++k) {
    t.time = flight::TimeMs{8000U + 100U * k};
    step.step(t, t.time, test::prepared_of(table, rover), out);
    EXPECT_EQ(out.status, RoverStepStatus::loads_failed);
    EXPECT_EQ(out.load_status, flight::WheelLoadStatus::attitude_out_of_range);
    if (k + 1U < table.monitor.invalid_to_stop) {
      EXPECT_EQ(out.decision, flight::RoverDecision::continue_drive) << k;
    }
  }
  EXPECT_EQ(out.decision, flight::RoverDecision::stop_and_replan);
  EXPECT_EQ(out.monitor.wheels[0].state, flight::WheelState::stop);
  EXPECT_EQ(out.monitor.wheels[0].stop_reason, flight::StopReason::telemetry);
}

TEST_F(RoverStepTest, BadParametersFailSafe) {
  flight::ParameterTable bad_table = table;
  bad_table.wheel_radius_m = flight::LengthM::zero();
  flight::RoverStepOutput no_table{};
  step.step(telemetry(9000U), flight::TimeMs{9000U}, test::prepared_of(bad_table, rover), no_table);
  EXPECT_EQ(no_table.status, RoverStepStatus::invalid_table);
  EXPECT_EQ(no_table.decision, flight::RoverDecision::stop_and_replan);

  flight::RoverParams bad_rover = rover;
  bad_rover.gravity_mps2 = flight::AccelMps2::zero();
  flight::RoverStepOutput out{};
  step.step(telemetry(9100U), flight::TimeMs{9100U}, test::prepared_of(table, bad_rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::invalid_rover_params);
  EXPECT_FALSE(out.loads_valid);
  EXPECT_EQ(out.monitor.wheels[5].sample_status, flight::SampleStatus::flagged_invalid);

  flight::RoverParams other_wheel = rover;
  other_wheel.wheel_radius_m = q<flight::LengthM>(0.16);
  ASSERT_EQ(flight::validate_rover_params(other_wheel), flight::RoverParamStatus::ok);
  flight::RoverStepOutput mismatch{};
  step.step(telemetry(9200U), flight::TimeMs{9200U}, test::prepared_of(table, other_wheel), mismatch);
  EXPECT_EQ(mismatch.status, RoverStepStatus::radius_mismatch);
  EXPECT_FALSE(mismatch.loads_valid);
  EXPECT_EQ(mismatch.monitor.wheels[0].sample_status, flight::SampleStatus::flagged_invalid);
}

TEST_F(RoverStepTest, HighCurrentTripsStopThroughTheMonitor) {
  // A current far above the limit on wheel 2, every cycle: STOP after trip_n.
  flight::RoverStepOutput out{};
  for (std::uint32_t k = 0U; k < table.monitor.trip_n; ++k) {
    flight::RoverTelemetry t = telemetry(10000U + 100U * k);
    t.current_a[2] = q<flight::CurrentA>(5.0);
    step.step(t, t.time, test::prepared_of(table, rover), out);
    ASSERT_EQ(out.status, RoverStepStatus::ok);
  }
  EXPECT_EQ(out.monitor.wheels[2].state, flight::WheelState::stop);
  EXPECT_EQ(out.monitor.wheels[0].state, flight::WheelState::nominal);
  // 5 A is far beyond traction: its torque would lift the middle wheel, so
  // the loads are taken without torques, flagged, and the step goes on.
  EXPECT_TRUE(out.torque_overload);
  EXPECT_EQ(out.torque_fallback_mask, 0x3FU);
  EXPECT_EQ(out.decision, flight::RoverDecision::stop_and_replan);
  step.clear_stop();
  flight::RoverStepOutput after{};
  step.step(telemetry(11000U), flight::TimeMs{11000U}, test::prepared_of(table, rover), after);
  EXPECT_EQ(after.monitor.wheels[2].state, flight::WheelState::nominal);
}

// Stage 6 sees this cycle's loads, pulls and the wheel monitors' torques:
// the step's traction output is that of a TractionMonitor fed, cycle by
// cycle, the input built from the step's own output (a torque only where the
// cycle has loads and the wheel's estimate is valid, among the first
// wheel_count), whatever the cycles (usable with uneven currents, a wheel
// beyond the sensor's range, flagged invalid between them, round 14: the
// arrays are written only with loads). Round 16 sums the step's arrays in
// place over every wheel: the runs with fewer monitored wheels (the
// monitor's defaults beyond them), in reverse and with mixed directions
// show the sums are the twin's.
void expect_traction_as_twin(const flight::ParameterTable& table, const flight::RoverParams& rover,
                             std::uint32_t reverse_every) {
  const flight::PreparedParameters prepared = test::prepared_of(table, rover);
  ASSERT_TRUE(prepared.table_valid());
  flight::RoverStep step;
  flight::TractionMonitor twin;
  std::mt19937_64 rng(1414U);
  flight::RoverStepOutput out{};
  int with_rho = 0;
  for (std::uint32_t k = 0U; k < 120U; ++k) {
    flight::RoverTelemetry t = speed_sample(20000U + 100U * k, 0.05);
    t.accel_valid = true;
    t.valid = (k % 9U) != 4U;
    for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
      t.current_a[i] = q<flight::CurrentA>(0.2 + 0.05 * static_cast<double>(rng() % 8U));
    }
    if ((k % 5U) == 2U) {
      t.current_a[rng() % flight::kWheelCount] = q<flight::CurrentA>(50.0);  // beyond the sensor's range
    }
    if ((reverse_every > 0U) && ((k % reverse_every) == 0U)) {
      // One wheel, or on every other such cycle all of them, driving back.
      const bool all = ((k / reverse_every) % 2U) == 0U;
      for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
        if (all || (i == (rng() % flight::kWheelCount))) {
          t.direction[i] = flight::DriveDirection::reverse;
          t.current_a[i] = flight::CurrentA::from_raw(-t.current_a[i].raw());
        }
      }
    }
    step.step(t, t.time, prepared, out);
    flight::TractionInput in{};
    in.time = t.time;
    in.loads_valid = out.status == RoverStepStatus::ok;
    in.pull_assumed = out.drawbar_status == flight::DrawbarStatus::saturated;
    in.speed_valid = t.speed_valid;
    in.speed_mps = t.speed_mps;
    for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
      in.load_n[i] = out.load_n[i];
      in.drawbar_pull_n[i] = out.drawbar_pull_n[i];
      in.torque_valid[i] = in.loads_valid && out.monitor.wheels[i].estimate_valid;
      in.torque_nm[i] = out.monitor.wheels[i].torque_nm;
      in.direction[i] = t.direction[i];
    }
    flight::TractionOutput expected{};
    twin.step(in, table.traction, table.monitor, prepared.traction_inverse_radius(), expected);
    ASSERT_EQ(out.traction.sample, expected.sample) << k;
    ASSERT_EQ(out.traction.state, expected.state) << k;
    ASSERT_EQ(out.traction.stop_tripped, expected.stop_tripped) << k;
    ASSERT_EQ(out.traction.rho_valid, expected.rho_valid) << k;
    ASSERT_EQ(out.traction.resistance.raw(), expected.resistance.raw()) << k;
    ASSERT_EQ(out.traction.resistance_median.raw(), expected.resistance_median.raw()) << k;
    ASSERT_EQ(out.traction.trend_known, expected.trend_known) << k;
    ASSERT_EQ(out.traction.resistance_ahead.raw(), expected.resistance_ahead.raw()) << k;
    with_rho += expected.rho_valid ? 1 : 0;
  }
  EXPECT_GT(with_rho, 40);
}

TEST_F(RoverStepTest, TractionCheckSeesTheCyclesLoadsPullsAndTorques) {
  expect_traction_as_twin(table, rover, 0U);
}

TEST_F(RoverStepTest, TractionCheckSumsOnlyTheMonitoredWheelsInEitherDirection) {
  flight::ParameterTable four = table;
  four.monitor.wheel_count = 4U;
  four.monitor.rover_stop_k = (four.monitor.rover_stop_k > 4U) ? std::uint8_t{4U} : four.monitor.rover_stop_k;
  four.health.max_blind_wheels =
      (four.health.max_blind_wheels >= 4U) ? std::uint8_t{3U} : four.health.max_blind_wheels;
  expect_traction_as_twin(four, rover, 7U);
  expect_traction_as_twin(table, rover, 3U);
}

/// Every field the step reports, a against b (the monitor's wheel records
/// field by field are MonitorTest.OverwritesEveryFieldOfAReusedOutputRecord's).
void expect_same_output(const flight::RoverStepOutput& a, const flight::RoverStepOutput& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.load_status, b.load_status);
  EXPECT_EQ(a.drawbar_status, b.drawbar_status);
  EXPECT_EQ(a.loads_valid, b.loads_valid);
  EXPECT_EQ(a.drawbar_valid, b.drawbar_valid);
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    EXPECT_EQ(a.load_n[i], b.load_n[i]);
    EXPECT_EQ(a.drawbar_pull_n[i], b.drawbar_pull_n[i]);
    EXPECT_EQ(a.health.current_usable[i], b.health.current_usable[i]);
    EXPECT_EQ(a.monitor.wheels[i].state, b.monitor.wheels[i].state);
    EXPECT_EQ(a.monitor.wheels[i].sample_status, b.monitor.wheels[i].sample_status);
    EXPECT_EQ(a.monitor.wheels[i].estimate_valid, b.monitor.wheels[i].estimate_valid);
    EXPECT_EQ(a.monitor.wheels[i].sinkage_m, b.monitor.wheels[i].sinkage_m);
  }
  EXPECT_EQ(a.accel_valid, b.accel_valid);
  EXPECT_EQ(a.accel_mps2, b.accel_mps2);
  EXPECT_EQ(a.slip_known, b.slip_known);
  EXPECT_EQ(a.slip, b.slip);
  EXPECT_EQ(a.lifting_wheel, b.lifting_wheel);
  EXPECT_EQ(a.torque_fallback_mask, b.torque_fallback_mask);
  EXPECT_EQ(a.torque_overload, b.torque_overload);
  for (std::size_t c = 0; c < flight::kSensorChannelCount; ++c) {
    EXPECT_EQ(a.health.channel[c], b.health.channel[c]);
  }
  EXPECT_EQ(a.health.attitude_usable, b.health.attitude_usable);
  EXPECT_EQ(a.health.attitude_bridged, b.health.attitude_bridged);
  EXPECT_EQ(a.health.attitude.roll_rad, b.health.attitude.roll_rad);
  EXPECT_EQ(a.health.joints_usable, b.health.joints_usable);
  EXPECT_EQ(a.health.joints.bogie_rad[1], b.health.joints.bogie_rad[1]);
  EXPECT_EQ(a.monitor.decision, b.monitor.decision);
  EXPECT_EQ(a.monitor.wheels_in_stop, b.monitor.wheels_in_stop);
  EXPECT_EQ(a.monitor.wheels_blind, b.monitor.wheels_blind);
  EXPECT_EQ(a.traction.state, b.traction.state);
  EXPECT_EQ(a.traction.sample, b.traction.sample);
  EXPECT_EQ(a.traction.rho_valid, b.traction.rho_valid);
  EXPECT_EQ(a.traction.resistance, b.traction.resistance);
  EXPECT_EQ(a.decision, b.decision);
}

/// A record with every field away from what any cycle below writes.
flight::RoverStepOutput stale_output() {
  flight::RoverStepOutput o{};
  o.status = RoverStepStatus::drawbar_failed;
  o.load_status = flight::WheelLoadStatus::ok;
  o.drawbar_status = flight::DrawbarStatus::ok;
  o.loads_valid = true;
  o.drawbar_valid = true;
  for (std::size_t i = 0; i < flight::kWheelCount; ++i) {
    o.load_n[i] = q<flight::WheelLoadN>(123.0);
    o.drawbar_pull_n[i] = q<flight::DrawbarPullN>(-7.0);
    o.health.current_usable[i] = true;
    o.monitor.wheels[i].state = flight::WheelState::stop;
    o.monitor.wheels[i].estimate_valid = true;
    o.monitor.wheels[i].sinkage_m = q<flight::SinkageM>(0.07);
  }
  o.accel_valid = true;
  o.accel_mps2 = q<flight::AccelMps2>(0.3);
  o.slip_known = true;
  o.slip = q<flight::Ratio>(0.4);
  o.lifting_wheel = 2U;
  o.torque_fallback_mask = 0x15U;
  o.torque_overload = true;
  for (std::size_t c = 0; c < flight::kSensorChannelCount; ++c) {
    o.health.channel[c] = flight::SensorHealth::recovering;
  }
  o.health.attitude_usable = true;
  o.health.attitude_bridged = true;
  o.health.attitude = rover_test::attitude(0.2, 0.3);
  o.health.joints_usable = true;
  o.health.joints = rover_test::joints(0.1, 0.1, 0.1, 0.1);
  o.monitor.decision = flight::RoverDecision::stop_and_replan;
  o.monitor.wheels_in_stop = 6U;
  o.monitor.wheels_blind = 3U;
  o.traction.state = flight::TractionState::stop;
  o.traction.rho_valid = true;
  o.traction.resistance = q<flight::Ratio>(0.9);
  o.decision = flight::RoverDecision::stop_and_replan;
  return o;
}

TEST_F(RoverStepTest, OverwritesEveryFieldOfAReusedOutputRecord) {
  // Two steps fed the same cycles: one writes into a fresh record each
  // cycle, the other into a record left over with every field set. They
  // differ if the step leaves a field of the record as it was.
  flight::RoverStep twin;
  flight::ParameterTable bad_table = table;
  bad_table.wheel_radius_m = flight::LengthM::zero();
  const auto pair = [&](flight::RoverStep& a, flight::RoverStep& b, const flight::RoverTelemetry& t,
                        const flight::ParameterTable& tab) {
    flight::RoverStepOutput fresh{};
    a.step(t, t.time, test::prepared_of(tab, rover), fresh);
    flight::RoverStepOutput reused = stale_output();
    b.step(t, t.time, test::prepared_of(tab, rover), reused);
    expect_same_output(fresh, reused);
    return fresh.status;
  };
  const auto both = [&](const flight::RoverTelemetry& t, const flight::ParameterTable& tab) {
    return pair(step, twin, t, tab);
  };
  // Tip-over on a first sample (later, the health monitor would bridge the
  // jump in roll).
  flight::RoverStep tipping;
  flight::RoverStep tipping_twin;
  flight::RoverTelemetry t = telemetry(1000U);
  t.attitude = rover_test::attitude(0.0, 0.75);
  EXPECT_EQ(pair(tipping, tipping_twin, t, table), RoverStepStatus::tip_over);
  t = telemetry(1000U);
  t.speed_valid = true;
  t.speed_mps = q<flight::SpeedMps>(0.05);
  t.rim_speed_valid = true;
  t.rim_speed_mps = q<flight::SpeedMps>(0.06);
  EXPECT_EQ(both(t, table), RoverStepStatus::ok);
  EXPECT_EQ(both(telemetry(1200U), bad_table), RoverStepStatus::invalid_table);
  t = telemetry(1300U);
  t.valid = false;
  EXPECT_EQ(both(t, table), RoverStepStatus::telemetry_invalid);
  t = telemetry(1400U);
  t.accel_valid = false;
  EXPECT_EQ(both(t, table), RoverStepStatus::no_acceleration);
}

/// The slip as the step took it before round 15: the Q31.32 chain of
/// fx::div, fx::sub, fx::clamp and fx::rescale, with its status.
flight::Ratio slip_by_the_chain(std::int32_t speed_raw, std::int32_t rim_raw, bool& ok) {
  using W = flight::WideQ;
  constexpr W kOne{fx::constant<W>(1.0)};
  constexpr W kMinusOne{fx::constant<W>(-1.0)};
  fx::Status st;
  const W ratio = fx::div<W>(flight::SpeedQ::from_raw(speed_raw), flight::SpeedQ::from_raw(rim_raw), st);
  const W slip = fx::clamp(fx::sub(kOne, ratio, st), kMinusOne, kOne, st);
  const flight::Ratio out{fx::rescale<flight::RatioQ>(slip, st)};
  ok = st.ok();
  return out;
}

// detail::slip_in_range (one 64 / 32-bit quotient) against the chain it
// replaced, over the step's range (|v|, |v_rim| <= 5 m/s, |v_rim| above
// 1 mm/s): random speeds of every size, both signs, ratios next to 0, 1
// and 2 (where the clamp and the sign of s change), v = 0, and rounding
// ties of the quotient and of the rescale searched around them.
TEST(RoverSlip, SlipInRangeIsTheQ31_32ChainBitForBit) {
  const std::int32_t max_raw = flight::kMaxAbsSpeed.raw();
  const std::int32_t min_rim_raw = flight::kMinRimSpeedForSlip.raw() + 1;
  std::mt19937_64 rng(1515U);
  const auto magnitude = [&rng](std::int32_t lo, std::int32_t hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1U;
    switch (rng() % 4U) {
      case 0U: return lo + static_cast<std::int32_t>(rng() % 4U);
      case 1U: return hi - static_cast<std::int32_t>(rng() % 4U);
      case 2U: return lo + static_cast<std::int32_t>(rng() % std::min<std::uint64_t>(span, 1U << (rng() % 28U)));
      default: return lo + static_cast<std::int32_t>(rng() % span);
    }
  };
  int cases = 0;
  int interior = 0;
  for (int k = 0; k < 2000000; ++k) {
    const std::int32_t rim_mag = magnitude(min_rim_raw, max_raw);
    std::int64_t speed_mag = 0;
    switch (rng() % 6U) {
      case 0U: speed_mag = magnitude(0, max_raw); break;
      case 1U: speed_mag = 0; break;
      // Next to a ratio of 1 or 2 (s next to 0 or -1), and next to a ratio
      // whose Q7.24 rounding of s is a tie: s 2^24 = n + 1/2.
      case 2U: speed_mag = rim_mag + static_cast<std::int64_t>(rng() % 7U) - 3; break;
      case 3U: speed_mag = 2 * static_cast<std::int64_t>(rim_mag) + static_cast<std::int64_t>(rng() % 7U) - 3; break;
      default: {
        const double s = (static_cast<double>(rng() % (1U << 25U)) + 0.5) / static_cast<double>(1U << 24U) - 1.0;
        speed_mag = static_cast<std::int64_t>(std::llround((1.0 - s) * rim_mag)) + static_cast<std::int64_t>(rng() % 3U) - 1;
        break;
      }
    }
    speed_mag = std::clamp<std::int64_t>(speed_mag, 0, max_raw);
    const std::int32_t speed = ((rng() % 2U) == 0U) ? static_cast<std::int32_t>(speed_mag) : -static_cast<std::int32_t>(speed_mag);
    const std::int32_t rim = ((rng() % 2U) == 0U) ? rim_mag : -rim_mag;
    bool ok = false;
    const flight::Ratio expected = slip_by_the_chain(speed, rim, ok);
    ASSERT_TRUE(ok) << speed << " " << rim;
    const flight::Ratio got =
        flight::detail::slip_in_range(flight::SpeedMps::from_raw(speed), flight::SpeedMps::from_raw(rim));
    ASSERT_EQ(got.raw(), expected.raw()) << speed << " " << rim;
    ++cases;
    interior += (std::abs(expected.raw()) < (1 << 24)) ? 1 : 0;
  }
  EXPECT_EQ(cases, 2000000);
  EXPECT_GT(interior, 500000);
}

}  // namespace
}  // namespace sinkwatch
