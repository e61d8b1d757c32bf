// test_cov_rover_step.cpp: two edges of the per-cycle step (rover_step.hpp)
// the scenario tests do not reach:
//  * a speed sample that reuses the time stamp of the last speed (the
//    cycle in between carried no speed): no differenced acceleration, so
//    the cycle reports no_acceleration instead of dividing by zero;
//  * a wheel that carries exactly 0 N (raw 0), the last attitude before
//    tip-over: the corrections have no row for it (Eq. 11 divides by W), so
//    the drawbar stage fails instead of producing pulls.
#include <gtest/gtest.h>

#include <cstdint>

#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "../flight/quantity_support.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

using sinkwatch::test::q;

RoverTelemetry level(std::uint32_t time_ms) {
  RoverTelemetry t{};
  t.time = TimeMs{time_ms};
  t.valid = true;
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    t.current_a[i] = q<CurrentA>(0.35);
    t.direction[i] = DriveDirection::forward;
  }
  return t;
}

TEST(RoverStepMotion, SpeedWithTheTimeStampOfTheLastSpeedGivesNoAcceleration) {
  const ParameterTable table = default_parameter_table();
  const RoverParams rover = yutu_like_rover_params(kGravityMoon);
  RoverStep step;
  RoverTelemetry a = level(1000U);
  a.speed_valid = true;
  a.speed_mps = q<SpeedMps>(0.05);
  a.accel_valid = true;  // this one measured
  RoverStepOutput out{};
  step.step(a, TimeMs{1000U}, test::prepared_of(table, rover), out);
  ASSERT_EQ(out.status, RoverStepStatus::ok);
  RoverTelemetry b = level(1100U);  // no speed, measured acceleration
  b.accel_valid = true;
  step.step(b, TimeMs{1100U}, test::prepared_of(table, rover), out);
  ASSERT_EQ(out.status, RoverStepStatus::ok);
  RoverTelemetry c = level(1000U);  // the speed sample's time again, not the last cycle's
  c.speed_valid = true;
  c.speed_mps = q<SpeedMps>(0.07);
  step.step(c, TimeMs{1150U}, test::prepared_of(table, rover), out);
  EXPECT_EQ(out.status, RoverStepStatus::no_acceleration);
  EXPECT_FALSE(out.accel_valid);
  // The control: the speed of c was still remembered (at 1000 ms), so 200 ms
  // later the difference exists: (0.09 - 0.07) / 0.2 s = 0.1 m/s^2.
  RoverTelemetry e = level(1200U);
  e.speed_valid = true;
  e.speed_mps = q<SpeedMps>(0.09);
  RoverStepOutput later{};
  step.step(e, TimeMs{1200U}, test::prepared_of(table, rover), later);
  ASSERT_TRUE(later.accel_valid);
  EXPECT_NEAR(fx::to_double(later.accel_mps2.q()), 0.1, 1e-6);
}

// The largest roll (raw Q3.28) at which no wheel needs a negative load, by
// bisection between level ground and a roll that tips the rover over.
AngleRad last_roll_before_tip_over(const RoverParams& p) {
  std::int32_t ok_raw = 0;
  std::int32_t tip_raw = q<AngleRad>(0.99).raw();
  const JointAnglesRad joints{};
  EXPECT_EQ(wheel_loads(p, RoverAttitude{AngleRad::zero(), AngleRad::from_raw(tip_raw)}, joints, kNoDriveTorques).status,
            WheelLoadStatus::tip_over);
  while (tip_raw - ok_raw > 1) {
    const std::int32_t mid = ok_raw + ((tip_raw - ok_raw) / 2);
    const WheelLoadStatus s = wheel_loads(p, RoverAttitude{AngleRad::zero(), AngleRad::from_raw(mid)}, joints, kNoDriveTorques).status;
    if (s == WheelLoadStatus::ok) {
      ok_raw = mid;
    } else {
      tip_raw = mid;
    }
  }
  return AngleRad::from_raw(ok_raw);
}

TEST(RoverStepDrawbar, WheelCarryingExactlyZeroNewtonsFailsTheDrawbarStage) {
  const ParameterTable table = default_parameter_table();
  RoverParams rover = yutu_like_rover_params(kGravityMoon);
  rover.com_z_m = q<LengthM>(0.60);  // a high centre of mass tips within the attitude limit
  ASSERT_EQ(validate_rover_params(rover), RoverParamStatus::ok);
  const AngleRad roll = last_roll_before_tip_over(rover);
  const WheelLoadResult loads = wheel_loads(rover, RoverAttitude{AngleRad::zero(), roll}, JointAnglesRad{}, kNoDriveTorques);
  ASSERT_EQ(loads.status, WheelLoadStatus::ok);
  std::int32_t lowest = loads.load_n[0].raw();
  for (const WheelLoadN& l : loads.load_n) {
    lowest = (l.raw() < lowest) ? l.raw() : lowest;
  }
  // At the last roll before tip-over the lifting wheel's support is below
  // half an LSB of the load format: its load is exactly zero.
  ASSERT_EQ(lowest, 0) << "roll " << fx::to_double(roll.q());

  RoverStep step;
  RoverTelemetry t = level(1000U);
  t.accel_valid = true;
  t.attitude.roll_rad = roll;
  RoverStepOutput out{};
  step.step(t, TimeMs{1000U}, test::prepared_of(table, rover), out);
  EXPECT_TRUE(out.loads_valid);
  EXPECT_EQ(out.status, RoverStepStatus::drawbar_failed);
  EXPECT_EQ(out.drawbar_status, DrawbarStatus::invalid_input);
  EXPECT_FALSE(out.drawbar_valid);
}

}  // namespace
