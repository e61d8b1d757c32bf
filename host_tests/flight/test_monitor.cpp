// The monitor: every state transition, every sample status, the rover
// decision and the event record.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "quantity_support.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
namespace ref = sinkwatch::ground::reference;

using sinkwatch::test::d;
using sinkwatch::test::q;

// Default table at W = 98.1 N (10 kg: C = 1, 1, 0.13; DP_max/W = 0.5):
// I_max = 2.3808 A, caution current 2.1427 A, clear below 2.0237 A;
// sinkage caution 0.030 m, stop 0.045 m, clear below 0.025 m.
constexpr double kW = 98.1;

class MonitorTest : public ::testing::Test {
 protected:
  ParameterTable table = default_parameter_table();
  ref::Parameters p = ref::from_flight(default_parameter_table());
  WheelMonitor wheel{2U};
  std::uint32_t t_ms = 1000U;

  /// A fresh sample with current I (in the direction of motion) whose
  /// drawbar pull puts the Eq. 11 estimate at z.
  WheelInput sample(double current, double z, DriveDirection dir = DriveDirection::forward) {
    const double signed_i = dir == DriveDirection::forward ? current : -current;
    const double torque = ref::torque_nm(p.motor, signed_i, dir);
    const ref::Coefficients c = ref::corrections_at(p.correction, kW).coefficients;
    const double dp = kW * ((c.c1 * torque / kW - c.c2 * z) / p.wheel_radius_m - c.c3);
    t_ms += 100U;
    return WheelInput{TimeMs{t_ms}, q<CurrentA>(signed_i), q<WheelLoadN>(kW), q<DrawbarPullN>(dp), dir, true};
  }
  WheelOutput feed(const WheelInput& in) {
    WheelOutput out{};
    wheel.step(test::with_drive_torque(in, table.motor), TimeMs{t_ms}, test::prepared_of(table), out);
    return out;
  }
  WheelOutput nominal() { return feed(sample(1.0, 0.01)); }
  WheelOutput sink_caution() { return feed(sample(1.0, 0.035)); }
  WheelOutput sink_stop() { return feed(sample(1.0, 0.05)); }
  WheelOutput current_caution() { return feed(sample(2.2, 0.01)); }
  WheelOutput current_stop() { return feed(sample(2.5, 0.01)); }
  WheelOutput band() { return feed(sample(1.0, 0.027)); }  // inside the sinkage hysteresis
  WheelOutput invalid() {
    WheelInput in = sample(1.0, 0.01);
    in.valid = false;
    return feed(in);
  }
};

TEST_F(MonitorTest, NominalSampleGivesEstimateAndLimit) {
  const WheelOutput o = nominal();
  EXPECT_EQ(o.state, WheelState::nominal);
  EXPECT_EQ(o.sample_status, SampleStatus::ok);
  ASSERT_TRUE(o.estimate_valid);
  EXPECT_NEAR(d(o.sinkage_m), 0.01, 1e-5);
  ASSERT_TRUE(o.limit_valid);
  EXPECT_NEAR(d(o.current_limit_a), 2.380825, 1e-5);
  EXPECT_EQ(o.clamp, LoadClamp::none);
  EXPECT_FALSE(o.stop_tripped);
}

TEST_F(MonitorTest, OneOrTwoNoisySamplesDoNotTrip) {
  sink_caution();
  nominal();
  EXPECT_EQ(current_caution().state, WheelState::nominal);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(nominal().state, WheelState::nominal);
  EXPECT_EQ(sink_stop().state, WheelState::nominal);
  EXPECT_EQ(sink_stop().state, WheelState::nominal);
  EXPECT_EQ(sink_stop().state, WheelState::stop);  // the third: straight from NOMINAL
}

TEST_F(MonitorTest, NominalToCautionOnNOfMSinkage) {
  sink_caution();
  nominal();
  sink_caution();
  nominal();
  EXPECT_EQ(sink_caution().state, WheelState::caution);
}

TEST_F(MonitorTest, NominalToCautionOnNOfMCurrent) {
  current_caution();
  current_caution();
  EXPECT_EQ(current_caution().state, WheelState::caution);
}

TEST_F(MonitorTest, CautionToNominalNeedsClearNCleanSamples) {
  for (int i = 0; i < 3; ++i) sink_caution();
  ASSERT_EQ(wheel.state(), WheelState::caution);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(nominal().state, WheelState::caution);
  EXPECT_EQ(nominal().state, WheelState::nominal);
}

TEST_F(MonitorTest, HysteresisBandNeitherTripsNorClears) {
  for (int i = 0; i < 10; ++i) EXPECT_EQ(band().state, WheelState::nominal);
  for (int i = 0; i < 3; ++i) sink_caution();
  ASSERT_EQ(wheel.state(), WheelState::caution);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(band().state, WheelState::caution);
  // Current in its band (0.85..0.9 of I_max) does not clear either.
  for (int i = 0; i < 20; ++i) EXPECT_EQ(feed(sample(2.08, 0.01)).state, WheelState::caution);
}

TEST_F(MonitorTest, NominalToStopOnSinkageWithEvent) {
  sink_stop();
  sink_stop();
  const WheelOutput o = sink_stop();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_TRUE(o.stop_tripped);
  EXPECT_EQ(o.stop_reason, StopReason::sinkage);
  ASSERT_TRUE(wheel.has_event());
  const EventRecord& e = wheel.last_event();
  EXPECT_EQ(e.wheel, 2U);
  EXPECT_EQ(e.time.ms, t_ms);
  EXPECT_EQ(e.reason, StopReason::sinkage);
  EXPECT_TRUE(e.max_estimate_valid);
  EXPECT_NEAR(d(e.max_estimated_sinkage_m), 0.05, 1e-5);
}

TEST_F(MonitorTest, CautionToStopOnCurrentRecordsPeakAndSection7Sinkage) {
  for (int i = 0; i < 3; ++i) current_caution();
  ASSERT_EQ(wheel.state(), WheelState::caution);
  current_stop();
  feed(sample(2.9, 0.01));  // the peak
  const WheelOutput o = current_stop();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::current);
  const EventRecord& e = wheel.last_event();
  EXPECT_EQ(e.reason, StopReason::current);
  EXPECT_NEAR(d(e.peak_current_a), 2.9, 1e-6);
  EXPECT_NEAR(d(e.load_at_peak_n), kW, 1e-4);
  ASSERT_TRUE(e.peak_sinkage_valid);
  // Section 7: Eq. 11 at the peak current's torque with DP = DP_max.
  const ref::Corrections c = ref::corrections_at(p.correction, kW);
  const double expected = ref::sinkage_m(c.coefficients, p.wheel_radius_m, kW,
                                         ref::torque_nm(p.motor, 2.9, DriveDirection::forward), c.dp_max_ratio * kW);
  EXPECT_NEAR(d(e.peak_sinkage_m), expected, 1e-5);
  EXPECT_GT(d(e.peak_sinkage_m), 0.045);  // above z_max: the current was above I_max
}

TEST_F(MonitorTest, NominalToStopOnCurrentDirectly) {
  current_stop();
  current_stop();
  const WheelOutput o = current_stop();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::current);
  EXPECT_TRUE(o.stop_tripped);
}

TEST_F(MonitorTest, CautionToStopOnSinkage) {
  for (int i = 0; i < 3; ++i) current_caution();
  ASSERT_EQ(wheel.state(), WheelState::caution);
  sink_stop();
  sink_stop();
  const WheelOutput o = sink_stop();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::sinkage);
  EXPECT_EQ(wheel.last_event().reason, StopReason::sinkage);
  // The peak current of the episode is the caution-level current.
  EXPECT_NEAR(d(wheel.last_event().peak_current_a), 2.2, 1e-6);
}

TEST_F(MonitorTest, NominalToStopOnLostTelemetryDirectly) {
  table.monitor.trip_n = 8U;  // caution needs 8 samples, telemetry loss only 2
  table.monitor.invalid_to_stop = 2U;
  ASSERT_EQ(validate(table), RejectReason::ok);
  EXPECT_EQ(invalid().state, WheelState::nominal);
  const WheelOutput o = invalid();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::telemetry);
  EXPECT_FALSE(wheel.last_event().peak_sinkage_valid);
}

TEST_F(MonitorTest, StopIsLatchedUntilCleared) {
  for (int i = 0; i < 3; ++i) current_stop();
  ASSERT_EQ(wheel.state(), WheelState::stop);
  for (int i = 0; i < 20; ++i) {
    const WheelOutput o = nominal();
    EXPECT_EQ(o.state, WheelState::stop);
    EXPECT_FALSE(o.stop_tripped);
  }
  wheel.clear_stop();
  EXPECT_EQ(wheel.state(), WheelState::nominal);
  EXPECT_EQ(nominal().state, WheelState::nominal);
  EXPECT_EQ(nominal().stop_reason, StopReason::none);
}

TEST_F(MonitorTest, ReverseDrivingUsesTheCurrentInTheDirectionOfMotion) {
  for (int i = 0; i < 3; ++i) feed(sample(2.5, 0.01, DriveDirection::reverse));
  EXPECT_EQ(wheel.state(), WheelState::stop);
  EXPECT_EQ(wheel.last_event().reason, StopReason::current);
  EXPECT_NEAR(d(wheel.last_event().peak_current_a), 2.5, 1e-6);
}

// Corrections handed in whose limit leaves its format while the sinkage
// fits (W = 2,000 N, C1 = 0.25, C3 = 1, the default motor's gain 6 N m/A):
// DP_max/W = 10 gives T_max = W L / C1 = 13,200 N m, within Q15.16, but
// I_max = 2,200 A, beyond Q11.20; DP_max/W = 100 gives T_max = 121,200 N m,
// beyond Q15.16. Either way the sample is unusable: no estimate and no
// limit, not the sinkage alone, and the same corrections with DP_max/W = 0.5
// give both.
TEST_F(MonitorTest, LimitBeyondItsFormatMakesTheSampleUnusableThoughTheSinkageFits) {
  CorrectionResult corr{};
  corr.coefficients.c1 = q<Ratio>(0.25);
  corr.coefficients.c2 = q<Ratio>(1.0);
  corr.coefficients.c3 = q<Ratio>(1.0);
  auto with_ratio = [&](double dp_max_ratio) {
    corr.dp_max_ratio = q<Ratio>(dp_max_ratio);
    t_ms += 100U;
    WheelInput in{TimeMs{t_ms}, q<CurrentA>(1.0), q<WheelLoadN>(2000.0), q<DrawbarPullN>(0.0),
                  DriveDirection::forward, true};
    in.corrections = &corr;
    return feed(in);
  };
  const WheelOutput usable = with_ratio(0.5);
  ASSERT_EQ(usable.sample_status, SampleStatus::ok);
  ASSERT_TRUE(usable.estimate_valid);
  ASSERT_TRUE(usable.limit_valid);
  EXPECT_NE(usable.sinkage_m, SinkageM::zero());
  for (const double ratio : {10.0, 100.0}) {
    const WheelOutput o = with_ratio(ratio);
    EXPECT_EQ(o.sample_status, SampleStatus::estimate_failed) << ratio;
    EXPECT_FALSE(o.estimate_valid) << ratio;
    EXPECT_FALSE(o.limit_valid) << ratio;
    EXPECT_EQ(o.sinkage_m, SinkageM::zero()) << ratio;
    EXPECT_EQ(o.torque_nm, TorqueNm::zero()) << ratio;
    EXPECT_EQ(o.current_limit_a, CurrentA::zero()) << ratio;
  }
}

TEST_F(MonitorTest, InvalidTelemetryIsCountedNeverEstimatedAndFailsSafe) {
  WheelOutput o = invalid();
  EXPECT_EQ(o.sample_status, SampleStatus::flagged_invalid);
  EXPECT_FALSE(o.estimate_valid);
  EXPECT_FALSE(o.limit_valid);
  EXPECT_EQ(o.sinkage_m, SinkageM::zero());
  invalid();
  EXPECT_EQ(invalid().state, WheelState::caution);  // blind counts as caution evidence
  for (int i = 0; i < 6; ++i) EXPECT_EQ(invalid().state, WheelState::caution);
  o = invalid();  // the 10th in a row
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_EQ(o.stop_reason, StopReason::telemetry);
  EXPECT_TRUE(o.stop_tripped);
  EXPECT_FALSE(wheel.last_event().peak_sinkage_valid);
  EXPECT_EQ(wheel.counters().by_status[static_cast<int>(SampleStatus::flagged_invalid)], 10U);
  EXPECT_EQ(wheel.counters().samples, 10U);
}

TEST_F(MonitorTest, AGoodSampleResetsTheUnusableRun) {
  for (int i = 0; i < 9; ++i) invalid();
  nominal();
  for (int i = 0; i < 9; ++i) EXPECT_NE(invalid().state, WheelState::stop);
}

TEST_F(MonitorTest, BlindWheelCannotClearCaution) {
  for (int i = 0; i < 3; ++i) sink_caution();
  // Every other sample unusable: 4 clear of the last 8, never the 6 needed.
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(invalid().state, WheelState::caution);
    EXPECT_EQ(nominal().state, WheelState::caution);
  }
}

TEST_F(MonitorTest, EverySampleStatus) {
  nominal();
  WheelInput in = sample(1.0, 0.01);
  in.time = TimeMs{t_ms - 600U};  // older than 500 ms
  EXPECT_EQ(feed(in).sample_status, SampleStatus::stale);
  in = sample(1.0, 0.01);
  in.time = TimeMs{t_ms + 50U};  // from the future
  EXPECT_EQ(feed(in).sample_status, SampleStatus::stale);
  in = sample(1.0, 0.01);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::ok);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::repeated_time);
  in = sample(1.0, 0.01);
  in.direction = static_cast<DriveDirection>(3);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::direction_invalid);
  in = sample(1.0, 0.01);
  in.current_a = q<CurrentA>(10.5);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::current_out_of_range);
  in = sample(1.0, 0.01);
  in.current_a = CurrentA::from_raw(INT32_MIN);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::current_out_of_range);
  in = sample(1.0, 0.01);
  in.load_n = q<WheelLoadN>(0.5);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::load_out_of_range);
  in = sample(1.0, 0.01);
  in.load_n = q<WheelLoadN>(2500.0);
  EXPECT_EQ(feed(in).sample_status, SampleStatus::load_out_of_range);
  in = sample(1.0, 0.01);
  in.load_n = q<WheelLoadN>(1.0);
  in.drawbar_pull_n = q<DrawbarPullN>(-30000.0);  // z = T/W + r 30000: beyond Q7.24
  const WheelOutput o = feed(in);
  EXPECT_EQ(o.sample_status, SampleStatus::estimate_failed);
  EXPECT_FALSE(o.estimate_valid);
  in = sample(1.0, 0.01);
  in.sensor_fault = true;
  EXPECT_EQ(feed(in).sample_status, SampleStatus::sensor_fault);
  const WheelCounters& c = wheel.counters();
  for (int s = 0; s < kSampleStatusCount; ++s) {
    if (s == static_cast<int>(SampleStatus::flagged_invalid)) continue;
    EXPECT_GE(c.by_status[s], 1U) << "status " << s;
  }
}

// The sensor range is |I| > I_abs_max as fx::abs defines it (INT32_MIN has
// no magnitude: out of range); the monitor tests it as one unsigned
// comparison (monitor.cpp, beyond_magnitude). Every current within a few raw
// units of -I_max, 0 and I_max, the format's ends, and random currents, on
// tables whose I_max spans the range validate() accepts, must be classified
// as that definition says.
TEST_F(MonitorTest, CurrentRangeIsTheMagnitudeTestAtEveryEdge) {
  std::vector<std::int32_t> maxima{table.motor.current_abs_max_a.raw(), q<CurrentA>(2.0).raw(),
                                   q<CurrentA>(8.0).raw(), q<CurrentA>(50.0).raw(), q<CurrentA>(2047.0).raw()};
  std::uint64_t s = 0x9E3779B97F4A7C15ULL;
  int tables = 0;
  for (int k = 0; k < 3; ++k) {
    s ^= s << 13U;
    s ^= s >> 7U;
    s ^= s << 17U;
    maxima.push_back(table.motor.no_load_current_a.raw() + 1 +
                     static_cast<std::int32_t>(s % static_cast<std::uint64_t>(q<CurrentA>(49.0).raw())));
  }
  for (const std::int32_t max_raw : maxima) {
    table.motor.current_abs_max_a = CurrentA::from_raw(max_raw);
    if (!test::prepared_of(table).table_valid()) {
      continue;  // a range validate() refuses: the monitor never classifies on it
    }
    ++tables;
    std::vector<std::int64_t> currents{INT32_MIN, INT32_MIN + 1, INT32_MAX, INT32_MAX - 1};
    for (const std::int64_t centre : {-static_cast<std::int64_t>(max_raw), std::int64_t{0},
                                      static_cast<std::int64_t>(max_raw)}) {
      for (std::int64_t d = -3; d <= 3; ++d) {
        currents.push_back(centre + d);
      }
    }
    for (int k = 0; k < 200; ++k) {
      s ^= s << 13U;
      s ^= s >> 7U;
      s ^= s << 17U;
      currents.push_back(static_cast<std::int32_t>(static_cast<std::uint32_t>(s)));
    }
    for (const std::int64_t raw : currents) {
      WheelInput in = sample(1.0, 0.01);
      in.current_a = CurrentA::from_raw(static_cast<std::int32_t>(raw));
      fx::Status st;
      const CurrentQ magnitude = fx::abs(in.current_a.q(), st);
      const bool beyond = !st.ok() || (magnitude > table.motor.current_abs_max_a.q());
      const SampleStatus status = feed(in).sample_status;
      EXPECT_EQ(status == SampleStatus::current_out_of_range, beyond) << max_raw << " " << raw;
    }
  }
  EXPECT_GE(tables, 3);
}

// step() writes its result into the caller's record field by field (no
// whole-struct reset, which cost the Cortex-M0 a memcpy per wheel): a record
// left over from another cycle must not leak into this one, for a usable
// sample, an unusable one and one whose estimate fails.
TEST_F(MonitorTest, OverwritesEveryFieldOfAReusedOutputRecord) {
  WheelOutput stale{};
  stale.state = WheelState::stop;
  stale.sample_status = SampleStatus::sensor_fault;
  stale.stop_reason = StopReason::traction;
  stale.stop_tripped = true;
  stale.estimate_valid = true;
  stale.torque_nm = q<TorqueNm>(12.5);
  stale.sinkage_m = q<SinkageM>(0.07);
  stale.limit_valid = true;
  stale.current_limit_a = q<CurrentA>(3.5);
  stale.clamp = LoadClamp::above_last;
  const auto same = [](const WheelOutput& a, const WheelOutput& b) {
    EXPECT_EQ(a.state, b.state);
    EXPECT_EQ(a.sample_status, b.sample_status);
    EXPECT_EQ(a.stop_reason, b.stop_reason);
    EXPECT_EQ(a.stop_tripped, b.stop_tripped);
    EXPECT_EQ(a.estimate_valid, b.estimate_valid);
    EXPECT_EQ(a.torque_nm, b.torque_nm);
    EXPECT_EQ(a.sinkage_m, b.sinkage_m);
    EXPECT_EQ(a.limit_valid, b.limit_valid);
    EXPECT_EQ(a.current_limit_a, b.current_limit_a);
    EXPECT_EQ(a.clamp, b.clamp);
  };
  WheelMonitor twin{2U};
  const auto both = [&](const WheelInput& in) {
    WheelOutput fresh{};
    wheel.step(in, TimeMs{t_ms}, test::prepared_of(table), fresh);
    WheelOutput reused = stale;
    twin.step(in, TimeMs{t_ms}, test::prepared_of(table), reused);
    same(fresh, reused);
    return fresh;
  };
  EXPECT_TRUE(both(test::with_drive_torque(sample(1.0, 0.01), table.motor)).estimate_valid);
  WheelInput invalid = sample(1.0, 0.01);
  invalid.valid = false;
  EXPECT_EQ(both(invalid).sample_status, SampleStatus::flagged_invalid);
  // No drive torque: usable, but the estimate fails.
  EXPECT_EQ(both(sample(1.0, 0.01)).sample_status, SampleStatus::estimate_failed);
}

// The monitor takes the caller's torque (WheelInput::drive_torque) and does
// not compute one: a usable sample without it has no estimate, and a torque
// that differs from the current's changes the estimate.
TEST_F(MonitorTest, UsesTheCallersDriveTorqueAndFailsWithoutOne) {
  nominal();
  const WheelInput in = sample(1.0, 0.01);
  WheelOutput without{};
  wheel.step(in, TimeMs{t_ms}, test::prepared_of(table), without);
  EXPECT_EQ(without.sample_status, SampleStatus::estimate_failed);
  EXPECT_FALSE(without.estimate_valid);
  WheelInput given = sample(1.0, 0.01);
  const WheelOutput own = feed(given);
  ASSERT_TRUE(own.estimate_valid);
  given = sample(1.0, 0.01);
  given.drive_torque = TorqueResult{q<TorqueNm>(ref::torque_nm(p.motor, 1.5, DriveDirection::forward)),
                                    EstimateStatus::ok};
  WheelOutput larger{};
  wheel.step(given, TimeMs{t_ms}, test::prepared_of(table), larger);
  ASSERT_TRUE(larger.estimate_valid);
  EXPECT_EQ(larger.torque_nm, given.drive_torque.torque_nm);
  EXPECT_GT(larger.sinkage_m, own.sinkage_m);
}

TEST_F(MonitorTest, LoadOutsideTable2IsEstimatedWithTheClampReported) {
  WheelInput in = sample(1.0, 0.01);
  in.load_n = q<WheelLoadN>(300.0);
  const WheelOutput o = feed(in);
  EXPECT_EQ(o.sample_status, SampleStatus::ok);
  EXPECT_EQ(o.clamp, LoadClamp::above_last);
}

TEST(RoverMonitor, AnyWheelStopsTheRoverWhenKIsOne) {
  ParameterTable table = default_parameter_table();
  const ref::Parameters p = ref::from_flight(table);
  RoverMonitor rover;
  std::uint32_t t = 1000U;
  auto inputs = [&](int stopping_wheels) {
    t += 100U;
    std::array<WheelInput, kMaxWheels> a{};
    for (int i = 0; i < kMaxWheels; ++i) {
      const double z = i < stopping_wheels ? 0.05 : 0.01;
      const double torque = ref::torque_nm(p.motor, 1.0, DriveDirection::forward);
      const double dp = kW * ((torque / kW - z) / p.wheel_radius_m - 0.13);
      a[static_cast<std::size_t>(i)] =
          WheelInput{TimeMs{t}, q<CurrentA>(1.0), q<WheelLoadN>(kW), q<DrawbarPullN>(dp), DriveDirection::forward, true};
    }
    return a;
  };
  auto step = [&](int n) {
    const auto a = inputs(n);
    WheelInput raw[kMaxWheels];
    std::copy(a.begin(), a.end(), raw);
    test::set_drive_torques(raw, table.motor);
    RoverOutput out{};
    rover.step(raw, TimeMs{t}, test::prepared_of(table), out);
    return out;
  };
  for (int i = 0; i < 5; ++i) EXPECT_EQ(step(0).decision, RoverDecision::continue_drive);
  step(1);
  step(1);
  RoverOutput o = step(1);
  EXPECT_EQ(o.decision, RoverDecision::stop_and_replan);
  EXPECT_EQ(o.wheels_in_stop, 1U);
  EXPECT_EQ(o.wheels[0].state, WheelState::stop);
  EXPECT_EQ(rover.wheel(0).last_event().wheel, 0U);

  // k = 2: one wheel in STOP is not enough.
  rover.clear_stop();
  table.monitor.rover_stop_k = 2U;
  for (int i = 0; i < 3; ++i) o = step(1);
  EXPECT_EQ(o.wheels_in_stop, 1U);
  EXPECT_EQ(o.decision, RoverDecision::continue_drive);
  for (int i = 0; i < 3; ++i) o = step(2);
  EXPECT_EQ(o.wheels_in_stop, 2U);
  EXPECT_EQ(o.decision, RoverDecision::stop_and_replan);

  // Fewer monitored wheels: the others are ignored.
  rover.clear_stop();
  table.monitor.wheel_count = 4U;
  table.monitor.rover_stop_k = 1U;
  const auto a = inputs(0);
  WheelInput raw[kMaxWheels];
  std::copy(a.begin(), a.end(), raw);
  test::set_drive_torques(raw, table.motor);
  raw[5].valid = false;
  const std::uint32_t wheel5_samples = rover.wheel(5).counters().samples;
  for (int i = 0; i < 12; ++i) {
    t += 100U;
    for (WheelInput& w : raw) w.time = TimeMs{t};
    rover.step(raw, TimeMs{t}, test::prepared_of(table), o);
  }
  EXPECT_EQ(o.decision, RoverDecision::continue_drive);
  EXPECT_EQ(rover.wheel(5).counters().samples, wheel5_samples);
  EXPECT_EQ(o.wheels_in_caution, 0U);
}

}  // namespace

// At or above the high-slip level the step hands the monitor DP = DP_max
// assumed, not measured (WheelInput::drawbar_assumed): Eq. 11 then gives the
// smallest sinkage the current allows, often below zero. Such samples must
// never clear a wheel, and a run of them is a wheel making no headway: STOP,
// named as slip (docs/scenarios.md finding 3: without this, a stuck rover's
// wheels went back to NOMINAL).
TEST_F(MonitorTest, AssumedDrawbarAtHighSlipIsSlipStopEvidence) {
  const auto slipping = [this] {
    WheelInput in = sample(1.0, -0.02);  // an estimate below zero, as at DP_max
    in.drawbar_assumed = true;
    return feed(in);
  };
  EXPECT_EQ(slipping().state, WheelState::nominal);
  EXPECT_EQ(slipping().state, WheelState::nominal);
  const WheelOutput o = slipping();
  EXPECT_EQ(o.state, WheelState::stop);
  EXPECT_TRUE(o.stop_tripped);
  EXPECT_EQ(o.stop_reason, StopReason::slip);
  EXPECT_TRUE(o.estimate_valid) << "the number is still reported";
  EXPECT_LT(d(o.sinkage_m), 0.0);
  ASSERT_TRUE(wheel.has_event());
  EXPECT_EQ(wheel.last_event().reason, StopReason::slip);
}

TEST_F(MonitorTest, AssumedDrawbarNeverClearsACautionWheel) {
  for (int i = 0; i < 3; ++i) sink_caution();
  ASSERT_EQ(wheel.state(), WheelState::caution);
  // The same numbers that clear the wheel when measured ...
  WheelInput in = sample(1.0, 0.01);
  in.drawbar_assumed = true;
  const WheelOutput o = feed(in);
  // ... are stop evidence when assumed: one sample is not enough to stop.
  EXPECT_EQ(o.state, WheelState::caution);
  for (int i = 0; i < 2; ++i) {
    WheelInput more = sample(1.0, 0.01);
    more.drawbar_assumed = true;
    feed(more);
  }
  EXPECT_EQ(wheel.state(), WheelState::stop);
  EXPECT_EQ(wheel.last_event().reason, StopReason::slip);
}

TEST_F(MonitorTest, CurrentOrSinkageStopKeepsItsReasonAtHighSlip) {
  // Stop evidence of its own wins the name: the current is at its limit.
  for (int i = 0; i < 3; ++i) {
    WheelInput in = sample(2.5, 0.01);
    in.drawbar_assumed = true;
    feed(in);
  }
  EXPECT_EQ(wheel.state(), WheelState::stop);
  EXPECT_EQ(wheel.last_event().reason, StopReason::current);
}

// RoverStep hands the monitor its samples as views of the cycle's arrays
// (WheelSamples), read in place; the monitor must give exactly what the six
// WheelInput records they stand for give: every output field, state, event
// record and counter, over long random runs that reach every sample status,
// CAUTION, STOP (each reason), clear_stop and both loss policies.
namespace {

/// A small deterministic generator (xorshift64*): the same run every time.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    s_ ^= s_ >> 12U;
    s_ ^= s_ << 25U;
    s_ ^= s_ >> 27U;
    return s_ * 0x2545F4914F6CDD1DULL;
  }
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }
  double uniform(double lo, double hi) {
    return lo + ((hi - lo) * static_cast<double>(next() >> 11U) / 9007199254740992.0);
  }
  bool one_in(std::uint32_t n) { return below(n) == 0U; }

 private:
  std::uint64_t s_;
};

void expect_same_wheel(const WheelOutput& a, const WheelOutput& b, int cycle, int wheel) {
  SCOPED_TRACE(testing::Message() << "cycle " << cycle << " wheel " << wheel);
  EXPECT_EQ(a.state, b.state);
  EXPECT_EQ(a.sample_status, b.sample_status);
  EXPECT_EQ(a.stop_reason, b.stop_reason);
  EXPECT_EQ(a.stop_tripped, b.stop_tripped);
  EXPECT_EQ(a.estimate_valid, b.estimate_valid);
  EXPECT_EQ(a.torque_nm.raw(), b.torque_nm.raw());
  EXPECT_EQ(a.sinkage_m.raw(), b.sinkage_m.raw());
  EXPECT_EQ(a.limit_valid, b.limit_valid);
  EXPECT_EQ(a.current_limit_a.raw(), b.current_limit_a.raw());
  EXPECT_EQ(a.clamp, b.clamp);
}

void expect_same_monitor(const WheelMonitor& a, const WheelMonitor& b) {
  EXPECT_EQ(a.state(), b.state());
  EXPECT_EQ(a.has_event(), b.has_event());
  const EventRecord& ea = a.last_event();
  const EventRecord& eb = b.last_event();
  EXPECT_EQ(ea.wheel, eb.wheel);
  EXPECT_EQ(ea.time.ms, eb.time.ms);
  EXPECT_EQ(ea.reason, eb.reason);
  EXPECT_EQ(ea.peak_current_a.raw(), eb.peak_current_a.raw());
  EXPECT_EQ(ea.load_at_peak_n.raw(), eb.load_at_peak_n.raw());
  EXPECT_EQ(ea.peak_sinkage_valid, eb.peak_sinkage_valid);
  EXPECT_EQ(ea.peak_sinkage_m.raw(), eb.peak_sinkage_m.raw());
  EXPECT_EQ(ea.max_estimate_valid, eb.max_estimate_valid);
  EXPECT_EQ(ea.max_estimated_sinkage_m.raw(), eb.max_estimated_sinkage_m.raw());
  EXPECT_EQ(a.counters().samples, b.counters().samples);
  for (std::uint8_t s = 0U; s < kSampleStatusCount; ++s) {
    EXPECT_EQ(a.counters().by_status[s], b.counters().by_status[s]);
  }
}

/// One cycle's arrays, as RoverStep holds them.
struct CycleArrays {
  CurrentA current_a[kMaxWheels];
  DriveDirection direction[kMaxWheels]{};
  WheelLoadN load_n[kMaxWheels];
  DrawbarPullN drawbar_pull_n[kMaxWheels];
  bool current_usable[kMaxWheels]{};
  CorrectionResult corrections[kMaxWheels]{};
  TorqueResult drive_torque[kMaxWheels]{};
};

/// What a run reached: the comparison means something only where it did.
struct Reached {
  bool status[kSampleStatusCount]{};
  bool caution{false};
  bool reason[6]{};  ///< index: StopReason
  bool degraded{false};
};

Reached run_samples_against_inputs(const ParameterTable& table, std::uint64_t seed, int cycles) {
  Reached reached{};
  const PreparedParameters prepared = test::prepared_of(table);
  const ref::Parameters p = ref::from_flight(default_parameter_table());
  RoverMonitor by_inputs;
  RoverMonitor by_samples;
  Rng rng(seed);
  std::uint32_t t_ms = 1000U;
  // Wheels drift between calm and embedding, so that the windows trip.
  double level[kMaxWheels] = {0.01, 0.01, 0.01, 0.01, 0.01, 0.01};
  int outage = 0;
  for (int cycle = 0; cycle < cycles; ++cycle) {
    // The clock: usually fresh, sometimes repeated, stale or from the future.
    const std::uint32_t kind = rng.below(40U);
    if (kind != 0U) {
      t_ms += 100U;
    }
    TimeMs now{t_ms};
    if (kind == 1U) {
      now = TimeMs{t_ms + 5000U};  // stale
    } else if (kind == 2U) {
      now = TimeMs{t_ms - 50U};  // from the future
    } else if (kind == 3U) {
      now = TimeMs{t_ms + table.monitor.stale_timeout_ms};  // the oldest fresh age
    } else if (kind == 4U) {
      now = TimeMs{t_ms + table.monitor.stale_timeout_ms + 1U};  // the youngest stale age
    }
    CycleArrays a{};
    WheelSamples s{};
    s.time = TimeMs{t_ms};
    // Outages long enough for invalid_to_stop, else a lost sample now and then.
    s.valid = (outage == 0) && !rng.one_in(25U);
    outage = (outage > 0) ? (outage - 1) : 0;
    s.drawbar_assumed = rng.one_in(15U);
    const bool with_corrections = !rng.one_in(10U);
    for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
      level[i] = std::clamp(level[i] + rng.uniform(-0.006, 0.0065), -0.01, 0.07);
      const double w = rng.one_in(30U) ? rng.uniform(-5.0, 400.0) : rng.uniform(60.0, 140.0);
      const double current = rng.one_in(30U) ? rng.uniform(-40.0, 40.0) : rng.uniform(0.2, 2.7);
      const DriveDirection dir = rng.one_in(50U)   ? static_cast<DriveDirection>(2U + rng.below(3U))
                                 : rng.one_in(4U) ? DriveDirection::reverse
                                                   : DriveDirection::forward;
      const double signed_i = (dir == DriveDirection::reverse) ? -current : current;
      // The reference's torque for the pull only, from a current it accepts.
      const double torque = ref::torque_nm(p.motor, std::clamp(signed_i, -2.9, 2.9), DriveDirection::forward);
      const ref::Coefficients c = ref::corrections_at(p.correction, std::max(w, 1.0)).coefficients;
      const double z = level[i] + rng.uniform(-0.004, 0.004);
      const double dp = w * ((c.c1 * torque / std::max(w, 1.0) - c.c2 * z) / p.wheel_radius_m - c.c3);
      a.current_a[i] = rng.one_in(200U) ? CurrentA(CurrentQ::from_raw(INT32_MIN)) : q<CurrentA>(signed_i);
      a.direction[i] = dir;
      a.load_n[i] = q<WheelLoadN>(w);
      a.drawbar_pull_n[i] = rng.one_in(200U) ? DrawbarPullN(LoadQ::from_raw(INT32_MAX)) : q<DrawbarPullN>(dp);
      a.current_usable[i] = !rng.one_in(20U);
      a.corrections[i] = corrections_at(table.correction, prepared.correction_divisors(), a.load_n[i]);
      if (rng.one_in(100U)) {
        a.corrections[i].status = EstimateStatus::invalid_load;
      }
      a.drive_torque[i] = torque_from_current(table.motor, a.current_a[i], dir);
      if (rng.one_in(100U)) {
        a.drive_torque[i] = TorqueResult{TorqueNm::zero(), EstimateStatus::invalid_current};
      }
    }
    s.current_a = &a.current_a;
    s.direction = &a.direction;
    s.load_n = &a.load_n;
    s.drawbar_pull_n = &a.drawbar_pull_n;
    s.current_usable = &a.current_usable;
    s.corrections = with_corrections ? &a.corrections : nullptr;
    s.drive_torque = &a.drive_torque;

    WheelInput inputs[kMaxWheels];
    for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
      inputs[i] = WheelInput{s.time, a.current_a[i], a.load_n[i], a.drawbar_pull_n[i], a.direction[i], s.valid};
      inputs[i].drawbar_assumed = s.drawbar_assumed;
      inputs[i].sensor_fault = !a.current_usable[i];
      inputs[i].corrections = with_corrections ? &a.corrections[i] : nullptr;
      inputs[i].drive_torque = a.drive_torque[i];
    }
    RoverOutput out_inputs{};
    RoverOutput out_samples{};
    by_inputs.step(inputs, now, prepared, out_inputs);
    by_samples.step(s, now, prepared, out_samples);
    EXPECT_EQ(out_inputs.decision, out_samples.decision) << "cycle " << cycle;
    EXPECT_EQ(out_inputs.wheels_in_stop, out_samples.wheels_in_stop);
    EXPECT_EQ(out_inputs.wheels_in_caution, out_samples.wheels_in_caution);
    EXPECT_EQ(out_inputs.wheels_blind, out_samples.wheels_blind);
    EXPECT_EQ(out_inputs.degraded, out_samples.degraded);
    // The tallies (kept as the bytes of one word in step_all) against the
    // wheels' own outputs, counted one by one.
    int in_stop = 0;
    int in_caution = 0;
    int blind = 0;
    for (std::uint8_t i = 0U; i < table.monitor.wheel_count; ++i) {
      in_stop += (out_samples.wheels[i].state == WheelState::stop) ? 1 : 0;
      in_caution += (out_samples.wheels[i].state == WheelState::caution) ? 1 : 0;
      blind += (out_samples.wheels[i].sample_status == SampleStatus::sensor_fault) ? 1 : 0;
    }
    EXPECT_EQ(static_cast<int>(out_samples.wheels_in_stop), in_stop) << "cycle " << cycle;
    EXPECT_EQ(static_cast<int>(out_samples.wheels_in_caution), in_caution) << "cycle " << cycle;
    EXPECT_EQ(static_cast<int>(out_samples.wheels_blind), blind) << "cycle " << cycle;
    for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
      expect_same_wheel(out_inputs.wheels[i], out_samples.wheels[i], cycle, i);
      expect_same_monitor(by_inputs.wheel(i), by_samples.wheel(i));
    }
    if (testing::Test::HasFailure()) {
      return reached;
    }
    reached.degraded = reached.degraded || out_samples.degraded;
    for (const WheelOutput& w : out_samples.wheels) {
      reached.status[static_cast<std::uint8_t>(w.sample_status)] = true;
      reached.caution = reached.caution || (w.state == WheelState::caution);
      reached.reason[static_cast<std::uint8_t>(w.stop_reason)] = true;
    }
    if (rng.one_in(60U)) {
      by_inputs.clear_stop();
      by_samples.clear_stop();
      for (double& l : level) {
        l = 0.01;
      }
      outage = rng.one_in(3U) ? 12 : 0;
    }
  }
  return reached;
}

void expect_reached_all(const Reached& r, bool degraded) {
  for (std::uint8_t st = 0U; st < kSampleStatusCount; ++st) {
    EXPECT_TRUE(r.status[st]) << "sample status " << static_cast<int>(st) << " never reached";
  }
  EXPECT_TRUE(r.caution);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::current)]);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::sinkage)]);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::slip)]);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::telemetry)]);
  EXPECT_EQ(r.degraded, degraded);
}

TEST(RoverMonitorSamples, InPlaceSamplesGiveTheInputsResultBitForBit) {
  expect_reached_all(run_samples_against_inputs(default_parameter_table(), 0x5EEDU, 20000), false);
}

TEST(RoverMonitorSamples, SameUnderContinueDegradedAndFewerWheels) {
  ParameterTable table = default_parameter_table();
  table.health.policy = LossPolicy::continue_degraded;
  table.health.max_blind_wheels = 2U;
  table.monitor.wheel_count = 4U;
  table.monitor.rover_stop_k = 2U;
  expect_reached_all(run_samples_against_inputs(table, 0xB1D5U, 20000), true);
}

// The WheelSamples path skips the transitions of a NOMINAL wheel whose
// stop and caution windows are empty (monitor.cpp, transition): it relies
// on the smallest counts validate() accepts (trip_n and invalid_to_stop of
// 1). At those counts, and a one-sample window, it must still give the
// WheelInput path's result, which tests every window.
TEST(RoverMonitorSamples, SameAtTheSmallestCountsAValidatedTableHolds) {
  ParameterTable table = default_parameter_table();
  table.monitor.window_m = 1U;
  table.monitor.trip_n = 1U;
  table.monitor.clear_n = 1U;
  table.monitor.invalid_to_stop = 1U;
  ASSERT_TRUE(test::prepared_of(table).table_valid());
  const Reached r = run_samples_against_inputs(table, 0xC0DEU, 20000);
  EXPECT_TRUE(r.caution);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::telemetry)]);
  EXPECT_TRUE(r.reason[static_cast<std::uint8_t>(StopReason::sinkage)]);
}

// A wheel in CAUTION whose caution window has emptied (samples in the
// hysteresis band, neither caution nor clear, for longer than the window)
// still leaves CAUTION on clear_n clear samples on the WheelSamples path:
// its shortcut is a NOMINAL wheel's only.
TEST(RoverMonitorSamples, CautionWithAnEmptyCautionWindowStillClears) {
  const ParameterTable table = default_parameter_table();
  const PreparedParameters prepared = test::prepared_of(table);
  const ref::Parameters p = ref::from_flight(table);
  RoverMonitor by_inputs;
  RoverMonitor by_samples;
  std::uint32_t t_ms = 1000U;
  auto cycle = [&](double z) {
    const double torque = ref::torque_nm(p.motor, 1.0, DriveDirection::forward);
    const ref::Coefficients c = ref::corrections_at(p.correction, kW).coefficients;
    const double dp = kW * ((c.c1 * torque / kW - c.c2 * z) / p.wheel_radius_m - c.c3);
    t_ms += 100U;
    CycleArrays a{};
    WheelInput inputs[kMaxWheels];
    for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
      const WheelInput in{TimeMs{t_ms},      q<CurrentA>(1.0),        q<WheelLoadN>(kW),
                          q<DrawbarPullN>(dp), DriveDirection::forward, true};
      inputs[i] = test::with_drive_torque(in, table.motor);
      a.current_a[i] = inputs[i].current_a;
      a.direction[i] = inputs[i].direction;
      a.load_n[i] = inputs[i].load_n;
      a.drawbar_pull_n[i] = inputs[i].drawbar_pull_n;
      a.current_usable[i] = true;
      a.drive_torque[i] = inputs[i].drive_torque;
    }
    WheelSamples s{};
    s.time = TimeMs{t_ms};
    s.valid = true;
    s.current_a = &a.current_a;
    s.direction = &a.direction;
    s.load_n = &a.load_n;
    s.drawbar_pull_n = &a.drawbar_pull_n;
    s.current_usable = &a.current_usable;
    s.corrections = nullptr;
    s.drive_torque = &a.drive_torque;
    RoverOutput out_inputs{};
    RoverOutput out_samples{};
    by_inputs.step(inputs, TimeMs{t_ms}, prepared, out_inputs);
    by_samples.step(s, TimeMs{t_ms}, prepared, out_samples);
    for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
      expect_same_wheel(out_inputs.wheels[i], out_samples.wheels[i], static_cast<int>(t_ms), i);
      expect_same_monitor(by_inputs.wheel(i), by_samples.wheel(i));
    }
    return out_samples.wheels[0].state;
  };
  for (int k = 0; k < 3; ++k) cycle(0.035);  // caution sinkage
  ASSERT_EQ(cycle(0.027), WheelState::caution);  // the band, from here on
  for (int k = 0; k < 20; ++k) ASSERT_EQ(cycle(0.027), WheelState::caution);
  WheelState state = WheelState::caution;
  for (int k = 0; (k < 16) && (state == WheelState::caution); ++k) state = cycle(0.01);
  EXPECT_EQ(state, WheelState::nominal);
}

TEST(RoverMonitorSamples, WithoutAValidTableBothStop) {
  ParameterTable table = default_parameter_table();
  table.monitor.window_m = 0U;  // validate() refuses it
  const PreparedParameters prepared = test::prepared_of(table);
  ASSERT_FALSE(prepared.table_valid());
  RoverMonitor by_samples;
  RoverOutput out{};
  out.wheels_in_stop = 3U;
  WheelSamples s{};
  by_samples.step(s, TimeMs{100U}, prepared, out);
  EXPECT_EQ(out.decision, RoverDecision::stop_and_replan);
  EXPECT_EQ(out.wheels_in_stop, 0U);
  EXPECT_EQ(by_samples.wheel(0).counters().samples, 0U);
}

}  // namespace

// Each usable sample's evidence (monitor.hpp: STOP d*I >= I_max or z >= stop;
// CAUTION that, or d*I >= f*I_max or z >= caution; clear d*I < (f-h)*I_max
// and z < caution - hysteresis), seen through the states of fresh wheels fed
// the same sample again and again, against the definition computed here from
// the wheel's own I_max and z, over random corrections that also give
// negative limits (where the products' order turns round) and currents at
// the thresholds to the raw unit.
namespace {

/// fx::mul's rounding of f * L for Q7.24 f: ties away from zero.
std::int32_t fraction_times(std::int32_t f, std::int32_t limit_raw) {
  const std::int64_t p = static_cast<std::int64_t>(f) * limit_raw;
  const std::int64_t m = (p < 0) ? -p : p;
  const std::int64_t r = (m + (std::int64_t{1} << 23)) >> 24;
  return static_cast<std::int32_t>((p < 0) ? -r : r);
}

struct SampleEvidence {
  bool caution;
  bool stop;
  bool clear;
  bool current_stop;
};

/// The states a wheel goes through on `n` samples of the same evidence,
/// from NOMINAL (or from CAUTION entered by hold_in_caution()).
std::vector<WheelState> expected_states(const SampleEvidence& e, const MonitorParams& mp, bool from_caution, int n) {
  std::vector<WheelState> states;
  WheelState state = from_caution ? WheelState::caution : WheelState::nominal;
  std::uint32_t caution_h = 0U;
  std::uint32_t stop_h = 0U;
  std::uint32_t clear_h = 0U;
  const std::uint32_t mask = (1U << mp.window_m) - 1U;
  auto count = [&](std::uint32_t h) { return static_cast<unsigned>(__builtin_popcount(h & mask)); };
  for (int k = 0; k < n; ++k) {
    caution_h = ((caution_h << 1U) | (e.caution ? 1U : 0U)) & 0xFFFFU;
    stop_h = ((stop_h << 1U) | (e.stop ? 1U : 0U)) & 0xFFFFU;
    clear_h = ((clear_h << 1U) | (e.clear ? 1U : 0U)) & 0xFFFFU;
    if (state != WheelState::stop) {
      if (count(stop_h) >= mp.trip_n) {
        state = WheelState::stop;
      } else if ((state == WheelState::nominal) && (count(caution_h) >= mp.trip_n)) {
        state = WheelState::caution;
        clear_h = 0U;
      } else if ((state == WheelState::caution) && (count(clear_h) >= mp.clear_n)) {
        state = WheelState::nominal;
        caution_h = 0U;
      }
    }
    states.push_back(state);
  }
  return states;
}

TEST(MonitorEvidence, EverySampleTakesTheEvidenceOfItsDefinition) {
  const ParameterTable table = default_parameter_table();
  const PreparedParameters prepared = test::prepared_of(table);
  const MonitorParams& mp = table.monitor;
  const std::int32_t f = mp.current_caution_fraction.raw();
  const std::int32_t f_less_h = f - mp.current_hysteresis_fraction.raw();
  const std::int32_t clear_z = mp.caution_sinkage_m.raw() - mp.sinkage_hysteresis_m.raw();
  Rng rng(0xE71DU);
  int negative_limit_clear = 0;
  int positive_limit_clear = 0;
  int cautions = 0;
  int stops = 0;
  constexpr int kFeeds = 12;
  for (int trial = 0; trial < 6000; ++trial) {
    CorrectionResult corr{};
    corr.coefficients.c1 = q<Ratio>(rng.uniform(0.3, 3.5));
    corr.coefficients.c2 = q<Ratio>(rng.uniform(0.3, 3.5));
    corr.coefficients.c3 = q<Ratio>(rng.uniform(-1.0, 1.0));
    corr.dp_max_ratio = q<Ratio>(rng.uniform(-3.0, 1.5));
    const WheelLoadN load = q<WheelLoadN>(rng.uniform(20.0, 300.0));
    const DrawbarPullN pull = q<DrawbarPullN>(rng.uniform(-150.0, 150.0));
    std::uint32_t t_ms = 1000U;
    auto input_with = [&](CurrentA directed) {
      t_ms += 100U;
      WheelInput in{TimeMs{t_ms}, directed, load, pull, DriveDirection::forward, true};
      in.corrections = &corr;
      return test::with_drive_torque(in, table.motor);
    };
    // The limit does not depend on the current: a first sample gives it.
    WheelMonitor probe{0U};
    WheelOutput first{};
    const WheelInput probe_in = input_with(q<CurrentA>(1.0));
    probe.step(probe_in, probe_in.time, prepared, first);
    if (!first.limit_valid) {
      continue;
    }
    const std::int32_t limit = first.current_limit_a.raw();
    // A current at a threshold (to the raw unit), or anywhere in the range.
    const std::int32_t thresholds[3] = {limit, fraction_times(f, limit), fraction_times(f_less_h, limit)};
    std::int64_t d = thresholds[rng.below(3U)] + static_cast<std::int32_t>(rng.below(3U)) - 1;
    if (rng.one_in(3U)) {
      d = q<CurrentA>(rng.uniform(-9.0, 9.0)).raw();
    }
    d = std::clamp<std::int64_t>(d, -q<CurrentA>(9.5).raw(), q<CurrentA>(9.5).raw());
    const CurrentA directed(CurrentQ::from_raw(static_cast<std::int32_t>(d)));
    for (int from_caution = 0; from_caution < 2; ++from_caution) {
      WheelMonitor wheel{0U};
      if (from_caution == 1) {
        wheel.hold_in_caution();
      }
      std::vector<WheelState> seen;
      WheelOutput o{};
      for (int k = 0; k < kFeeds; ++k) {
        const WheelInput in = input_with(directed);
        wheel.step(in, in.time, prepared, o);
        seen.push_back(o.state);
      }
      if (o.sample_status != SampleStatus::ok) {
        continue;  // no number: no evidence of this kind
      }
      ASSERT_EQ(o.current_limit_a.raw(), limit);
      const std::int32_t z = o.sinkage_m.raw();
      SampleEvidence e{};
      e.current_stop = d >= limit;
      e.stop = e.current_stop || (z >= mp.stop_sinkage_m.raw());
      e.caution = e.stop || (d >= fraction_times(f, limit)) || (z >= mp.caution_sinkage_m.raw());
      e.clear = (d < fraction_times(f_less_h, limit)) && (z < clear_z);
      ASSERT_EQ(seen, expected_states(e, mp, from_caution == 1, kFeeds))
          << "trial " << trial << " limit " << limit << " d " << d << " z " << z;
      if (e.clear) {
        ++((limit < 0) ? negative_limit_clear : positive_limit_clear);
      }
      cautions += (e.caution && !e.stop) ? 1 : 0;
      stops += e.stop ? 1 : 0;
      if (e.stop) {
        EXPECT_EQ(wheel.last_event().reason, e.current_stop ? StopReason::current : StopReason::sinkage);
      }
    }
  }
  // The run reaches each side, negative limits with clear samples included.
  EXPECT_GT(negative_limit_clear, 50);
  EXPECT_GT(positive_limit_clear, 50);
  EXPECT_GT(cautions, 50);
  EXPECT_GT(stops, 50);
}

}  // namespace
