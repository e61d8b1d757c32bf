// test_cov_monitor_prepared.cpp: the monitor given prepared parameters that
// hold no valid table (prepared_params.hpp: a default PreparedParameters, or
// prepare() on a table validate() refuses). There are no thresholds then, so
// a wheel must fail safe (STOP on its first sample) and the rover must ask to
// stop and re-plan, whatever the telemetry says.
#include <gtest/gtest.h>

#include "prepared_support.hpp"
#include "quantity_support.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace {

using namespace sinkwatch::flight;
using sinkwatch::test::q;

// A sample the default table would call nominal: 1 A at 98.1 N, z about 1 cm.
WheelInput good_sample(std::uint32_t t_ms) {
  const double torque = (1.0 - 0.1) * 0.025 * 0.6 * 400.0;
  const double dp = 98.1 * ((torque / 98.1 - 0.01) / 0.15 - 0.13);
  const WheelInput in{TimeMs{t_ms}, q<CurrentA>(1.0), q<WheelLoadN>(98.1), q<DrawbarPullN>(dp),
                      DriveDirection::forward, true};
  return sinkwatch::test::with_drive_torque(in, default_parameter_table().motor);
}

PreparedParameters prepared_from_bad_table() {
  ParameterTable bad = default_parameter_table();
  bad.monitor.window_m = 0U;
  PreparedParameters p{};
  EXPECT_EQ(prepare(bad, yutu_like_rover_params(kGravityMoon), p), PrepareStatus::invalid_table);
  return p;
}

TEST(MonitorWithoutATable, WheelStopsOnItsFirstSampleAndCountsItUnusable) {
  const PreparedParameters none = prepared_from_bad_table();
  ASSERT_FALSE(none.table_valid());
  WheelMonitor wheel{0U};
  WheelOutput o{};
  wheel.step(good_sample(1000U), TimeMs{1000U}, none, o);
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_FALSE(o.estimate_valid);
  EXPECT_FALSE(o.limit_valid);
  EXPECT_NE(o.sample_status, SampleStatus::ok);
  // The same sample with a valid table is nominal: the table made the difference.
  PreparedParameters good{};
  ASSERT_EQ(prepare(default_parameter_table(), yutu_like_rover_params(kGravityMoon), good), PrepareStatus::ok);
  WheelMonitor control{0U};
  WheelOutput c{};
  control.step(good_sample(1000U), TimeMs{1000U}, good, c);
  EXPECT_EQ(c.state, WheelState::nominal);
  EXPECT_TRUE(c.estimate_valid);
}

TEST(MonitorWithoutATable, RoverAsksToStopAndReplan) {
  RoverMonitor rover;
  WheelInput inputs[kMaxWheels]{};
  for (std::uint32_t i = 0U; i < kMaxWheels; ++i) {
    inputs[i] = good_sample(1000U);
  }
  // The output is written whole: a record left over from a good cycle
  // (continue, a wheel in STOP) does not survive into the blind one.
  RoverOutput none{};
  none.wheels_in_stop = 3U;
  none.wheels[0].state = WheelState::stop;
  rover.step(inputs, TimeMs{1000U}, PreparedParameters{}, none);
  EXPECT_EQ(none.decision, RoverDecision::stop_and_replan);
  EXPECT_EQ(none.wheels_in_stop, 0U);
  EXPECT_EQ(none.wheels[0].state, WheelState::nominal);
  RoverOutput bad{};
  rover.step(inputs, TimeMs{1000U}, prepared_from_bad_table(), bad);
  EXPECT_EQ(bad.decision, RoverDecision::stop_and_replan);
  PreparedParameters good{};
  ASSERT_EQ(prepare(default_parameter_table(), yutu_like_rover_params(kGravityMoon), good), PrepareStatus::ok);
  RoverMonitor control;
  RoverOutput controlled{};
  controlled.decision = RoverDecision::stop_and_replan;
  control.step(inputs, TimeMs{1000U}, good, controlled);
  EXPECT_EQ(controlled.decision, RoverDecision::continue_drive);
}

}  // namespace
