// test_cov_monitor.cpp: monitor behaviour the main monitor tests do not
// reach: an unusable run longer than the run counter's range, corrections
// handed in by the caller (valid and failed), a DP_max that does not fit the
// load format when the event's Section 7 sinkage is computed, and tables the
// validator would refuse (rover_stop_k = 0, a window longer than the 16-bit
// history, a clear threshold that saturates), where the monitor must still
// fail safe.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "quantity_support.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace {

using namespace sinkwatch::flight;
namespace test = sinkwatch::test;
using sinkwatch::test::d;
using sinkwatch::test::q;

constexpr double kW = 98.1;  // 10 kg: the default table gives C = 1, 1, 0.13 here

// Wheel torque of the default motor (gear 400, efficiency 0.6, Kt 0.025 N m/A,
// I0 0.1 A) driving forward at `current_a`.
double torque_nm(double current_a) { return (current_a - 0.1) * 0.025 * 0.6 * 400.0; }

class MonitorCov : public ::testing::Test {
 protected:
  ParameterTable table = default_parameter_table();
  WheelMonitor wheel{1U};
  std::uint32_t t_ms = 1000U;

  // A sample at load `load_n` whose drawbar pull puts the Eq. 11 estimate (with
  // C = 1, 1, 0.13 and r = 0.15 m) at `z`.
  WheelInput sample(double current_a, double z, double load_n = kW) {
    const double dp = load_n * ((torque_nm(current_a) / load_n - z) / 0.15 - 0.13);
    t_ms += 100U;
    return WheelInput{TimeMs{t_ms}, q<CurrentA>(current_a), q<WheelLoadN>(load_n), q<DrawbarPullN>(dp),
                      DriveDirection::forward, true};
  }
  WheelOutput feed(const WheelInput& in) {
    WheelOutput out{};
    wheel.step(test::with_drive_torque(in, table.motor), TimeMs{t_ms}, test::prepared_of(table), out);
    return out;
  }
  WheelOutput invalid() {
    WheelInput in = sample(1.0, 0.01);
    in.valid = false;
    return feed(in);
  }
};

TEST_F(MonitorCov, UnusableRunLongerThan255SamplesStaysInStopAndIsCountedInFull) {
  WheelOutput o{};
  for (int i = 0; i < 300; ++i) {
    o = invalid();
  }
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::telemetry);
  EXPECT_FALSE(o.stop_tripped);  // tripped once, at the 10th
  EXPECT_EQ(wheel.counters().by_status[static_cast<int>(SampleStatus::flagged_invalid)], 300U);
  EXPECT_EQ(wheel.counters().samples, 300U);
  // After the ground's acknowledgement the run starts again from zero: nine
  // more unusable samples are not enough to stop.
  wheel.clear_stop();
  for (int i = 0; i < 9; ++i) {
    EXPECT_NE(invalid().state, WheelState::stop);
  }
  EXPECT_EQ(invalid().state, WheelState::stop);
}

TEST_F(MonitorCov, CorrectionsHandedInAreUsedInsteadOfTheTable) {
  // C3 = 0.20 instead of the table's 0.13 at this load: Eq. 11 gives a
  // sinkage lower by r * 0.07 = 10.5 mm for the same torque and pull.
  CorrectionResult corr = test::corrections_of(table.correction, q<WheelLoadN>(kW));
  ASSERT_EQ(corr.status, EstimateStatus::ok);
  const WheelOutput from_table = feed(sample(1.0, 0.02));
  corr.coefficients.c3 = q<Ratio>(0.20);
  WheelInput in = sample(1.0, 0.02);
  in.corrections = &corr;
  const WheelOutput handed_in = feed(in);
  ASSERT_TRUE(from_table.estimate_valid);
  ASSERT_TRUE(handed_in.estimate_valid);
  EXPECT_NEAR(d(from_table.sinkage_m), 0.02, 1e-5);
  EXPECT_NEAR(d(handed_in.sinkage_m), 0.02 - 0.15 * 0.07, 1e-5);
}

TEST_F(MonitorCov, FailedCorrectionsHandedInMakeTheSampleUnusable) {
  CorrectionResult corr = test::corrections_of(table.correction, q<WheelLoadN>(kW));
  corr.status = EstimateStatus::invalid_coefficient;
  WheelInput in = sample(1.0, 0.01);
  in.corrections = &corr;
  const WheelOutput o = feed(in);
  EXPECT_EQ(o.sample_status, SampleStatus::estimate_failed);
  EXPECT_FALSE(o.estimate_valid);
  EXPECT_FALSE(o.limit_valid);
  EXPECT_EQ(wheel.counters().by_status[static_cast<int>(SampleStatus::estimate_failed)], 1U);
}

// A valid table whose last breakpoint has DP_max/W = 2 and whose load
// envelope reaches 30 kN: at 20 kN the event's DP_max is 40 kN, beyond the
// load format, so the Section 7 sinkage of the event is marked invalid
// instead of being computed from a saturated number.
TEST_F(MonitorCov, EventSinkageIsMarkedInvalidWhenDpMaxDoesNotFitTheLoadFormat) {
  table.correction.rows[4].dp_max_ratio = q<Ratio>(2.0);
  table.monitor.load_max_n = q<WheelLoadN>(30000.0);
  ASSERT_EQ(validate(table), RejectReason::ok);
  const auto run_to_stop = [&](double load_n) {
    wheel = WheelMonitor{1U};
    const WheelOutput first = feed(sample(1.0, 0.0, load_n));
    EXPECT_EQ(first.sample_status, SampleStatus::ok) << load_n;
    for (int i = 0; i < 10; ++i) {
      invalid();
    }
    EXPECT_EQ(wheel.state(), WheelState::stop);
    EXPECT_TRUE(wheel.has_event());
    return wheel.last_event();
  };
  const EventRecord fits = run_to_stop(10000.0);  // DP_max 20 kN
  EXPECT_EQ(fits.reason, StopReason::telemetry);
  EXPECT_NEAR(d(fits.load_at_peak_n), 10000.0, 1e-3);
  EXPECT_TRUE(fits.peak_sinkage_valid);
  const EventRecord too_big = run_to_stop(20000.0);  // DP_max 40 kN
  EXPECT_NEAR(d(too_big.load_at_peak_n), 20000.0, 1e-3);
  EXPECT_FALSE(too_big.peak_sinkage_valid);
  EXPECT_EQ(too_big.peak_sinkage_m, SinkageM::zero());
}

// A wheel carrying 1 N (the bottom of the default load envelope) at 10 A with
// a gear ratio of 1000: the samples' own estimates fit (their drawbar pull
// balances the torque), and the current trips STOP. The event's Section 7
// sinkage, with DP = DP_max = 0.5 N instead, is T/W - r (C3 + 0.5) = 148 m:
// beyond Q7.24 (128 m), so the event says it has no number.
TEST_F(MonitorCov, EventSinkageBeyondItsFormatIsMarkedInvalid) {
  table.motor.gear_ratio = q<GearRatio>(1000.0);
  ASSERT_EQ(validate(table), RejectReason::ok);
  const double torque = (10.0 - 0.1) * 0.025 * 0.6 * 1000.0;  // 148.5 N m
  const double load = 1.0;
  const double dp = load * ((torque / load - 0.01) / 0.15 - 0.20);  // C3 = 0.20 below the first breakpoint
  WheelOutput o{};
  for (int i = 0; i < 3; ++i) {
    t_ms += 100U;
    o = feed(WheelInput{TimeMs{t_ms}, q<CurrentA>(10.0), q<WheelLoadN>(load), q<DrawbarPullN>(dp),
                        DriveDirection::forward, true});
    ASSERT_TRUE(o.estimate_valid) << i;
    EXPECT_NEAR(d(o.sinkage_m), 0.01, 1e-4);
  }
  ASSERT_EQ(o.state, WheelState::stop);
  ASSERT_TRUE(wheel.has_event());
  const EventRecord& e = wheel.last_event();
  EXPECT_EQ(e.reason, StopReason::current);
  EXPECT_NEAR(d(e.peak_current_a), 10.0, 1e-5);
  EXPECT_FALSE(e.peak_sinkage_valid);
  EXPECT_EQ(e.peak_sinkage_m, SinkageM::zero());
}

}  // namespace
