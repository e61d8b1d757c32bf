// Parameters prepared once per load (prepared_params.hpp) and the corrections
// shared between the step's stages (issue 10): the step on prepared
// parameters must give, cycle by cycle and bit for bit, what the unprepared
// chain gives when every function validates and evaluates C(W) for itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "rover_test_support.hpp"
#include "dividing_oracle.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace {

using flight::PrepareStatus;
using flight::RoverStepStatus;
using rover_test::q;

class PreparedTest : public ::testing::Test {
 protected:
  flight::ParameterTable table = flight::default_parameter_table();
  flight::RoverParams rover = flight::yutu_like_rover_params(flight::kGravityMoon);
};

TEST_F(PreparedTest, PrepareReportsEachRefusalInTheStepsOrder) {
  flight::PreparedParameters p;
  EXPECT_EQ(p.status(), PrepareStatus::invalid_table);
  EXPECT_FALSE(p.table_valid());
  EXPECT_FALSE(p.ready());

  EXPECT_EQ(flight::prepare(table, rover, p), PrepareStatus::ok);
  EXPECT_TRUE(p.ready());
  EXPECT_EQ(p.table().wheel_radius_m, table.wheel_radius_m);
  EXPECT_EQ(p.rover().mass_kg, rover.mass_kg);

  flight::ParameterTable bad_table = table;
  bad_table.correction.count = 0U;
  EXPECT_EQ(flight::prepare(bad_table, rover, p), PrepareStatus::invalid_table);
  EXPECT_FALSE(p.table_valid());

  flight::RoverParams bad_rover = rover;
  bad_rover.mass_kg = flight::MassKg::zero();
  EXPECT_EQ(flight::prepare(table, bad_rover, p), PrepareStatus::invalid_rover_params);
  EXPECT_TRUE(p.table_valid());
  EXPECT_FALSE(p.ready());

  flight::RoverParams other_wheel = rover;
  other_wheel.wheel_radius_m = q<flight::LengthM>(0.16);
  EXPECT_EQ(flight::prepare(table, other_wheel, p), PrepareStatus::radius_mismatch);
  EXPECT_TRUE(p.table_valid());
  EXPECT_FALSE(p.ready());
}

TEST_F(PreparedTest, UnpreparedParametersStopTheRover) {
  const flight::PreparedParameters none;
  flight::RoverStep step;
  flight::RoverTelemetry t{};
  t.time = flight::TimeMs{100U};
  t.valid = true;
  flight::RoverStepOutput out{};
  step.step(t, t.time, none, out);
  EXPECT_EQ(out.status, RoverStepStatus::invalid_table);
  EXPECT_EQ(out.decision, flight::RoverDecision::stop_and_replan);

  // The prepared overloads of the stages refuse them too.
  const flight::WheelLoadResult loads = flight::wheel_loads(none, rover_test::attitude(0.0, 0.0),
                                                            rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  EXPECT_EQ(loads.status, flight::WheelLoadStatus::invalid_params);
  flight::WheelLoadResult good = flight::wheel_loads(test::prepared_rover(rover), rover_test::attitude(0.0, 0.0),
                                                     rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  ASSERT_EQ(good.status, flight::WheelLoadStatus::ok);
  flight::DrawbarInput in{};
  for (flight::Ratio& r : in.dp_max_ratio) {
    r = q<flight::Ratio>(0.5);
  }
  EXPECT_EQ(flight::drawbar_pulls(none, good, in).status, flight::DrawbarStatus::invalid_input);
  good.status = flight::WheelLoadStatus::tip_over;
  EXPECT_EQ(flight::drawbar_pulls(none, good, in).status, flight::DrawbarStatus::invalid_loads);
}

TEST_F(PreparedTest, PreparedParametersAreACopy) {
  flight::PreparedParameters p;
  ASSERT_EQ(flight::prepare(table, rover, p), PrepareStatus::ok);
  const flight::MonitorParams before = p.table().monitor;
  table.monitor.stop_sinkage_m = flight::SinkageM::zero();
  rover.mass_kg = flight::MassKg::zero();
  EXPECT_EQ(p.table().monitor.stop_sinkage_m, before.stop_sinkage_m);
  EXPECT_TRUE(p.ready());
  EXPECT_NE(p.rover().mass_kg, rover.mass_kg);
}

// The statics' constants are the rover's own numbers: every length exactly
// in Q6.25 (Q7.24 into Q6.25 is a left shift for lengths of at most 4 m) and
// within half an LSB in Q10.21 and Q15.16 (one rounding), the weight
// m g rounded once, and its reciprocal within 2^-29 relative. Rovers at the
// validated limits as well as the default.
TEST_F(PreparedTest, PreparedStaticsHoldTheRoverLengthsExactlyAndItsWeight) {
  flight::RoverParams extreme = rover;
  extreme.mass_kg = q<flight::MassKg>(1000.0);
  extreme.gravity_mps2 = q<flight::AccelMps2>(10.0);
  extreme.track_width_m = q<flight::LengthM>(4.0);
  extreme.rocker_front_axle.x_m = q<flight::LengthM>(2.0);
  extreme.bogie_rear_axle.z_m = q<flight::LengthM>(-2.0);
  extreme.com_y_m = flight::LengthM::from_raw(-33554431);  // just inside half the track
  for (const flight::RoverParams& r : {rover, extreme}) {
    flight::PreparedParameters p;
    ASSERT_EQ(flight::prepare(table, r, p), PrepareStatus::ok);
    // Every length within half an LSB of its format: exactly in Q6.25.
    fx::Status st;
    const auto lengths_exact = [&r, &st](const auto& k) {
      // `lsb`: the rounding allowed in a format coarser than Q7.24.
      // Each length is bounded (fx::Bounded): its value is q().
      const auto exact = [](auto bounded, flight::LengthM expected, double lsb = 0.5) {
        const auto v = bounded.q();
        const double allowed = std::ldexp(lsb, -decltype(v)::frac_bits);
        const double error = std::fabs(fx::to_double(v) - fx::to_double(expected.q()));
        EXPECT_LE(error, (decltype(v)::frac_bits >= flight::LengthQ::frac_bits) ? 0.0 : allowed);
      };
      const auto exact_point = [&exact](auto v, flight::SidePointM expected) {
        exact(v.x, expected.x_m);
        exact(v.z, expected.z_m);
      };
      exact_point(k.rocker_front, r.rocker_front_axle);
      exact_point(k.rocker_bogie, r.rocker_bogie_pivot);
      exact_point(k.bogie_middle, r.bogie_middle_axle);
      exact_point(k.bogie_rear, r.bogie_rear_axle);
      exact(k.wheel_radius, r.wheel_radius_m);
      // Half the track: the length rounded, then halved and rounded again.
      constexpr fx::Q1_30 kHalf = fx::constant<fx::Q1_30>(0.5);
      exact(k.half_track, flight::LengthM{fx::mul<flight::LengthQ>(kHalf, r.track_width_m.q(), st)}, 0.75);
      exact(k.com_x, r.com_x_m);
      exact(k.com_y, r.com_y_m);
      exact(k.com_z, r.com_z_m);
    };
    lengths_exact(p.rover_statics().fine);
    lengths_exact(p.rover_statics().mid);
    lengths_exact(p.rover_statics().coarse);
    const flight::StaticsConstants<flight::StaticsQ>& k = p.rover_statics().fine;
    const double weight = fx::to_double(r.mass_kg.q()) * fx::to_double(r.gravity_mps2.q());
    EXPECT_LE(std::fabs(fx::to_double(k.weight_n.q()) - weight), std::ldexp(1.0, -17) + 1e-9);  // half an LSB
    const double inverse = std::ldexp(static_cast<double>(k.inv_weight.mantissa), -k.inv_weight.scale);
    EXPECT_LE(std::fabs((inverse * weight) - 1.0), std::ldexp(1.0, -29));
  }
}

TEST_F(PreparedTest, CurrentLimitOnPreparedDivisorsIsWithinItsBoundOfTheDividingOracle) {
  // Loads below, inside (on and between breakpoints) and above Table 2.
  const flight::CorrectionDivisors cd = flight::make_correction_divisors(table.correction);
  const flight::MotorDivisors md = flight::make_motor_divisors(table.motor);
  for (std::int32_t raw = 1; raw < (250 << 16); raw += 104729) {
    const flight::WheelLoadN w = flight::WheelLoadN::from_raw(raw);
    const flight::CurrentLimitResult a = oracle::current_limit(table, w);
    const flight::CurrentLimitResult b =
        flight::current_limit(flight::corrections_at(table.correction, cd, w), table.motor, md,
                              table.wheel_radius_m, w, table.monitor.allowed_sinkage_m);
    ASSERT_EQ(a.status, b.status) << raw;
    ASSERT_EQ(a.clamp, b.clamp) << raw;
    ASSERT_EQ(a.torque_limit_nm, b.torque_limit_nm) << raw;
    // The motor's reciprocal: within its bound of the three divisions.
    const double diff_a = std::ldexp(static_cast<double>(a.current_limit_a.raw() - b.current_limit_a.raw()), -20);
    ASSERT_LE(std::fabs(diff_a), oracle::current_tolerance_a(table.motor, a.current_limit_a)) << raw;
  }
}

/// Cycle k's telemetry: attitudes, joints and currents that move the wheels
/// through NOMINAL, CAUTION and STOP (wheel 1 and 4 draw rising currents).
flight::RoverTelemetry cycle(std::uint32_t k) {
  flight::RoverTelemetry t{};
  t.time = flight::TimeMs{1000U + (100U * k)};
  t.valid = true;
  const double s = static_cast<double>(k % 17U) / 17.0;
  t.attitude = rover_test::attitude(-0.2 + (0.4 * s), 0.1 - (0.2 * s));
  t.joints = rover_test::joints(0.1 * s, -0.05 * s, 0.2 * (0.5 - s), 0.1 * s);
  t.accel_valid = true;
  t.accel_mps2 = q<flight::AccelMps2>(0.01 * (s - 0.5));
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    const double rising = ((i == 1U) || (i == 4U)) ? 0.02 * static_cast<double>(k % 60U) : 0.0;
    t.current_a[i] = q<flight::CurrentA>(0.2 + (0.03 * static_cast<double>(i)) + rising);
    t.direction[i] = ((k % 11U) == 3U) ? flight::DriveDirection::reverse : flight::DriveDirection::forward;
  }
  return t;
}

void expect_same_wheel(const flight::WheelOutput& a, const flight::WheelOutput& b, std::uint32_t k,
                       std::uint32_t i) {
  EXPECT_EQ(a.state, b.state) << k << " " << i;
  EXPECT_EQ(a.sample_status, b.sample_status) << k << " " << i;
  EXPECT_EQ(a.stop_reason, b.stop_reason) << k << " " << i;
  EXPECT_EQ(a.stop_tripped, b.stop_tripped) << k << " " << i;
  EXPECT_EQ(a.estimate_valid, b.estimate_valid) << k << " " << i;
  EXPECT_EQ(a.torque_nm, b.torque_nm) << k << " " << i;
  EXPECT_EQ(a.sinkage_m, b.sinkage_m) << k << " " << i;
  EXPECT_EQ(a.limit_valid, b.limit_valid) << k << " " << i;
  EXPECT_EQ(a.current_limit_a, b.current_limit_a) << k << " " << i;
  EXPECT_EQ(a.clamp, b.clamp) << k << " " << i;
}

TEST_F(PreparedTest, StepEqualsItsStagesChainedByHand) {
  // The chain below has no sensor health stage: its checks off (this
  // telemetry's attitude and current jumps would be spikes).
  table.health = flight::HealthParams{};
  flight::PreparedParameters p;
  ASSERT_EQ(flight::prepare(table, rover, p), PrepareStatus::ok);
  flight::RoverStep step;
  flight::RoverMonitor reference;  // fed by the chain, evaluating C(W) itself (no WheelInput::corrections)
  std::uint32_t stops = 0U;
  std::uint32_t cautions = 0U;
  for (std::uint32_t k = 0U; k < 240U; ++k) {
    const flight::RoverTelemetry t = cycle(k);
    flight::RoverStepOutput out{};
    step.step(t, t.time, p, out);
    ASSERT_EQ(out.status, RoverStepStatus::ok) << k;

    // Each wheel's torque from its current (the monitor's too), in the loads
    // where the step's health stage passed the current.
    flight::DriveTorques torques{};
    flight::TorqueResult torque[flight::kWheelCount]{};
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      torque[i] = flight::torque_from_current(table.motor, t.current_a[i], t.direction[i]);
      torques.usable[i] = out.health.current_usable[i] && (torque[i].status == flight::EstimateStatus::ok);
      torques.torque_nm[i] = torques.usable[i] ? torque[i].torque_nm : flight::TorqueNm::zero();
    }
    const flight::WheelLoadResult loads = flight::wheel_loads(test::prepared_rover(rover), t.attitude, t.joints, torques);
    ASSERT_EQ(loads.status, flight::WheelLoadStatus::ok) << k;
    EXPECT_EQ(out.torque_fallback_mask, loads.torque_fallback_mask) << k;
    flight::DrawbarInput in{};
    in.accel_mps2 = t.accel_mps2;
    in.pitch_rad = t.attitude.pitch_rad;
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      in.dp_max_ratio[i] = test::corrections_of(table.correction, loads.load_n[i]).dp_max_ratio;
    }
    const flight::DrawbarResult dp = flight::drawbar_pulls(test::prepared_rover(rover), loads, in);
    ASSERT_TRUE(flight::usable(dp.status)) << k;
    flight::WheelInput inputs[flight::kMaxWheels]{};
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      inputs[i] = flight::WheelInput{t.time, t.current_a[i], loads.load_n[i], dp.dp_n[i], t.direction[i], true};
      inputs[i].drive_torque = torque[i];
      ASSERT_EQ(out.load_n[i], loads.load_n[i]) << k;
      ASSERT_EQ(out.drawbar_pull_n[i], dp.dp_n[i]) << k;
    }
    flight::RoverOutput ref{};
    reference.step(inputs, t.time, p, ref);
    EXPECT_EQ(out.decision, ref.decision) << k;
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      expect_same_wheel(out.monitor.wheels[i], ref.wheels[i], k, i);
      stops += out.monitor.wheels[i].stop_tripped ? 1U : 0U;
      cautions += (out.monitor.wheels[i].state == flight::WheelState::caution) ? 1U : 0U;
    }
    for (std::uint8_t i = 0U; i < flight::kMaxWheels; ++i) {
      const flight::WheelMonitor& a = step.monitor().wheel(i);
      const flight::WheelMonitor& b = reference.wheel(i);
      ASSERT_EQ(a.has_event(), b.has_event());
      if (a.has_event()) {
        EXPECT_EQ(a.last_event().peak_sinkage_m, b.last_event().peak_sinkage_m) << k;
        EXPECT_EQ(a.last_event().peak_current_a, b.last_event().peak_current_a) << k;
      }
    }
    if ((k % 60U) == 59U) {
      step.clear_stop();
      reference.clear_stop();
    }
  }
  // The sequence must have exercised the transitions it claims to compare.
  EXPECT_GT(stops, 0U);
  EXPECT_GT(cautions, 0U);
}

TEST_F(PreparedTest, RefusedRoverParametersAreReportedOnlyForFreshSamples) {
  flight::RoverParams bad_rover = rover;
  bad_rover.high_slip = flight::Ratio::zero();
  flight::PreparedParameters p;
  ASSERT_EQ(flight::prepare(table, bad_rover, p), PrepareStatus::invalid_rover_params);
  flight::RoverStep step;
  const flight::RoverTelemetry t = cycle(0U);
  flight::RoverStepOutput out{};
  step.step(t, t.time, p, out);
  EXPECT_EQ(out.status, RoverStepStatus::invalid_rover_params);
  // The same time stamp again is a repeated sample before it is a bad rover.
  step.step(t, t.time, p, out);
  EXPECT_EQ(out.status, RoverStepStatus::telemetry_repeated);
}

/// The drawbar split as it was written before issue 10: every share through
/// fx::div of the loads widened to Q31.32 (drawbar_pull.hpp's formula).
flight::DrawbarPullN share_by_fx_div(const flight::RoverParams& p, const flight::WheelLoadResult& loads,
                                     const flight::DrawbarInput& in, std::uint32_t i, fx::Status& st) {
  using W = flight::WideQ;
  W sum = W::zero();
  for (const flight::WheelLoadN& w : loads.load_n) {
    sum = fx::add(sum, fx::rescale<W>(w.q(), st), st);
  }
  const W sin_pitch = fx::rescale<W>(fx::sin(in.pitch_rad.q(), st), st);
  const W g_along = fx::mul<W>(p.gravity_mps2.q(), sin_pitch, st);
  const W total = fx::mul<W>(p.mass_kg.q(), fx::add(fx::rescale<W>(in.accel_mps2.q(), st), g_along, st), st);
  const W load = fx::rescale<W>(loads.load_n[i].q(), st);
  const W cap = fx::mul<W>(in.dp_max_ratio[i].q(), load, st);
  const W share = fx::mul(total, fx::div(load, sum, st), st);
  return flight::DrawbarPullN{fx::rescale<flight::LoadQ>(fx::clamp(share, fx::neg(cap, st), cap, st), st)};
}

TEST_F(PreparedTest, DrawbarSharesEqualTheQ3132DivisionOfTheLoads) {
  // drawbar_pulls splits by W_i / sum W through a reciprocal of the raw sum:
  // every pull must be the bits of the fx::div form, zero, tiny and large
  // loads included.
  std::mt19937_64 rng(21U);
  std::uint32_t compared = 0U;
  for (int k = 0; k < 20000; ++k) {
    flight::WheelLoadResult loads{};
    loads.status = flight::WheelLoadStatus::ok;
    for (flight::WheelLoadN& w : loads.load_n) {
      const std::uint64_t r = rng();
      w = flight::WheelLoadN::from_raw(((r & 7U) == 0U) ? 0 : static_cast<std::int32_t>(r >> (33U + (r & 15U))));
    }
    flight::DrawbarInput in{};
    in.accel_mps2 = q<flight::AccelMps2>((0.5 * static_cast<double>(k % 7)) - 1.5);
    in.pitch_rad = q<flight::AngleRad>((0.01 * static_cast<double>(k % 50)) - 0.25);
    for (flight::Ratio& r : in.dp_max_ratio) {
      r = q<flight::Ratio>(0.05 + (0.3 * static_cast<double>(rng() % 6U)));
    }
    const flight::DrawbarResult dp = flight::drawbar_pulls(test::prepared_rover(rover), loads, in);
    if (!flight::usable(dp.status)) {
      continue;  // every load zero
    }
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      fx::Status st;
      const flight::DrawbarPullN expected = share_by_fx_div(rover, loads, in, i, st);
      ASSERT_TRUE(st.ok()) << k;
      ASSERT_EQ(dp.dp_n[i], expected) << k << " " << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 100000U);
}

TEST_F(PreparedTest, MonitorWithKnownCorrectionsEqualsTheMonitorEvaluatingThem) {
  flight::WheelMonitor own(0U);
  flight::WheelMonitor shared(0U);
  const flight::PreparedParameters p = test::prepared_of(table);
  for (std::uint32_t k = 0U; k < 120U; ++k) {
    const flight::WheelLoadN w = q<flight::WheelLoadN>(20.0 + (1.7 * static_cast<double>(k)));
    const flight::CurrentA i = q<flight::CurrentA>(0.2 + (0.015 * static_cast<double>(k % 50U)));
    flight::WheelInput in = test::with_drive_torque(
        flight::WheelInput{flight::TimeMs{100U * (k + 1U)}, i, w, q<flight::DrawbarPullN>(-1.0),
                           flight::DriveDirection::forward, true},
        table.motor);
    flight::WheelOutput a{};
    own.step(in, in.time, p, a);
    const flight::CorrectionResult corr = test::corrections_of(table.correction, w);
    in.corrections = &corr;
    flight::WheelOutput b{};
    shared.step(in, in.time, p, b);
    expect_same_wheel(a, b, k, 0U);
  }
}

}  // namespace
}  // namespace sinkwatch
