// The motion-resistance check (flight/traction.hpp, docs/traction.md): the
// coefficient against its double twin, the median, the trend carried ahead,
// the N-of-M states, the restart when the rover stands, and every sample the
// check refuses.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>

#include "rover_test_support.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/traction.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace {

using namespace sinkwatch::flight;
using sinkwatch::rover_test::d;
using sinkwatch::rover_test::q;

constexpr double kRadiusM = 0.15;
constexpr double kLoadN = 30.0;
constexpr double kPullN = 1.0;
constexpr double kSpeedMps = 0.05;
constexpr std::uint32_t kCycleMs = 200U;  // 1 cm per cycle at kSpeedMps

const ParameterTable& table() {
  static const ParameterTable t = default_parameter_table();
  return t;
}

/// The check's 1/r at kRadiusM, as PreparedParameters holds it.
InverseRadius per_radius() { return inverse_radius(q<LengthM>(kRadiusM)); }

/// Six wheels forward at kLoadN and kPullN, each with the torque that gives
/// `rho` (T = r (rho W + DP)), at `speed` m/s.
TractionInput sample(std::uint32_t time_ms, double rho, double speed = kSpeedMps) {
  TractionInput in{};
  in.time = TimeMs{time_ms};
  in.loads_valid = true;
  in.speed_valid = true;
  in.speed_mps = q<SpeedMps>(speed);
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    in.load_n[i] = q<WheelLoadN>(kLoadN);
    in.drawbar_pull_n[i] = q<DrawbarPullN>(kPullN);
    in.torque_valid[i] = true;
    in.torque_nm[i] = q<TorqueNm>(kRadiusM * (rho * kLoadN + kPullN));
    in.direction[i] = DriveDirection::forward;
  }
  return in;
}

/// A monitor driven through `cycles` samples of `rho_at(k)`; the last output.
class Drive {
 public:
  template <typename F>
  TractionOutput run(std::uint32_t cycles, F rho_at, double speed = kSpeedMps) {
    TractionOutput out{};
    for (std::uint32_t k = 0U; k < cycles; ++k) {
      out = step(sample(time_ms_, rho_at(k), speed));
    }
    return out;
  }
  TractionOutput step(const TractionInput& in) {
    time_ms_ = in.time.ms + kCycleMs;
    last_ = monitor_.step(in, table().traction, table().monitor, per_radius());
    if (last_.stop_tripped) ++trips_;
    return last_;
  }
  [[nodiscard]] std::uint32_t now_ms() const { return time_ms_; }
  [[nodiscard]] int trips() const { return trips_; }
  TractionMonitor& monitor() { return monitor_; }

 private:
  TractionMonitor monitor_;
  TractionOutput last_{};
  std::uint32_t time_ms_{0U};
  int trips_{0};
};

double lsb_ratio() { return std::ldexp(1.0, -24); }

}  // namespace

TEST(Traction, ATableWithoutSection8LeavesTheCheckOff) {
  TractionMonitor m;
  const TractionOutput out = m.step(sample(0U, 2.0), TractionParams{}, table().monitor, per_radius());
  EXPECT_EQ(out.state, TractionState::off);
  EXPECT_EQ(out.sample, TractionSample::check_off);
  EXPECT_FALSE(out.rho_valid);
}

TEST(Traction, TheCoefficientIsTheThrustLessThePullOverTheWeightWithinOneLsb) {
  TractionInput in = sample(0U, 0.3);
  in.torque_nm[2] = q<TorqueNm>(2.3);  // uneven wheels
  in.drawbar_pull_n[4] = q<DrawbarPullN>(-0.7);
  in.load_n[5] = q<WheelLoadN>(41.5);
  std::array<double, kWheelCount> t{};
  std::array<double, kWheelCount> p{};
  std::array<double, kWheelCount> w{};
  for (std::size_t i = 0U; i < kWheelCount; ++i) {
    t[i] = d(in.torque_nm[i]);
    p[i] = d(in.drawbar_pull_n[i]);
    w[i] = d(in.load_n[i]);
  }
  Drive drive;
  const TractionOutput out = drive.step(in);
  ASSERT_TRUE(out.rho_valid);
  EXPECT_EQ(out.sample, TractionSample::filling);  // the median is not full yet
  const double twin = sinkwatch::ground::resistance_coefficient(t, p, w, kRadiusM);
  EXPECT_NEAR(d(out.resistance), twin, lsb_ratio());
}

TEST(Traction, AConstantCoefficientAtTheStopLevelTripsOnceAfterTheMedianFillsAndLatches) {
  Drive drive;
  // Samples 1..4 fill the median; from sample 5 each is STOP evidence; the
  // window trips at trip_n of them.
  TractionOutput out = drive.run(kTractionMedianSamples + table().monitor.trip_n - 2U, [](std::uint32_t) { return 0.40; });
  EXPECT_NE(out.state, TractionState::stop);
  out = drive.run(1U, [](std::uint32_t) { return 0.40; });
  EXPECT_EQ(out.state, TractionState::stop);
  EXPECT_TRUE(out.stop_tripped);
  out = drive.run(20U, [](std::uint32_t) { return 0.1; });
  EXPECT_EQ(out.state, TractionState::stop) << "STOP is latched";
  EXPECT_EQ(drive.trips(), 1);
  drive.monitor().clear_stop();
  EXPECT_EQ(drive.monitor().state(), TractionState::nominal);
}

TEST(Traction, OneSpikeAmongLowSamplesDoesNotTrip) {
  Drive drive;
  const TractionOutput out = drive.run(40U, [](std::uint32_t k) { return (k == 20U) ? 3.0 : 0.2; });
  EXPECT_EQ(out.state, TractionState::nominal);
  EXPECT_EQ(drive.trips(), 0);
}

TEST(Traction, CautionBelowTheStopLevelAndBackToNominalWhenClear) {
  Drive drive;
  TractionOutput out = drive.run(20U, [](std::uint32_t) { return 0.32; });
  EXPECT_EQ(out.state, TractionState::caution);
  out = drive.run(20U, [](std::uint32_t) { return 0.20; });
  EXPECT_EQ(out.state, TractionState::nominal);
  EXPECT_EQ(drive.trips(), 0);
}

TEST(Traction, ARisingCoefficientTripsBeforeItReachesTheStopLevel) {
  // rho rises 0.05 per metre (1 cm per cycle): carried 2 m ahead it reads
  // 0.1 high, so the check stops near rho = 0.28, not at 0.38.
  Drive drive;
  const auto rising = [](std::uint32_t k) { return 0.15 + 0.0005 * static_cast<double>(k); };
  TractionOutput out{};
  std::uint32_t k = 0U;
  for (; (k < 600U) && (drive.trips() == 0); ++k) {
    out = drive.step(sample(drive.now_ms(), rising(k)));
  }
  ASSERT_EQ(drive.trips(), 1) << "never tripped";
  EXPECT_TRUE(out.trend_known);
  EXPECT_LT(d(out.resistance_median), 0.30);
  EXPECT_GE(d(out.resistance_ahead), 0.38);
  // The carried value against the twin, from the same median one span back.
  const double back = rising(k - 1U - 2U - 100U);  // median lag 2 samples, 1 m = 100 cycles back (marks every 12.5 cm)
  const double twin = sinkwatch::ground::resistance_ahead(d(out.resistance_median), back, 1.0, 2.0);
  EXPECT_NEAR(d(out.resistance_ahead), twin, 0.01) << "marks are 12.5 cm apart: the span is 1.0 to 1.125 m";
}

TEST(Traction, TheFirstSpanOfADriveSetsNoBaselineAndStandingRestartsTheHistory) {
  Drive drive;
  TractionOutput out = drive.run(99U, [](std::uint32_t) { return 0.2; });  // 0.99 m: still settling
  EXPECT_FALSE(out.trend_known);
  out = drive.run(250U, [](std::uint32_t) { return 0.2; });
  EXPECT_TRUE(out.trend_known);
  out = drive.run(1U, [](std::uint32_t) { return 0.2; }, 0.0);
  EXPECT_EQ(out.sample, TractionSample::standing);
  EXPECT_FALSE(out.rho_valid);
  out = drive.run(1U, [](std::uint32_t) { return 0.2; });
  EXPECT_EQ(out.sample, TractionSample::filling) << "the median restarts";
  EXPECT_FALSE(out.trend_known) << "the trend restarts";
}

TEST(Traction, AGapLongerThanTwoSecondsIsNotTravelled) {
  Drive drive;
  TractionOutput out = drive.run(90U, [](std::uint32_t) { return 0.2; });
  // Ten samples 3 s apart would be 1.5 m at 5 cm/s: none of it counts.
  for (std::uint32_t k = 0U; k < 10U; ++k) {
    out = drive.step(sample(drive.now_ms() + 2800U, 0.2));
  }
  EXPECT_FALSE(out.trend_known);
}

TEST(Traction, WithoutOdometryThePresentMedianDecides) {
  Drive drive;
  TractionOutput out{};
  for (std::uint32_t k = 0U; k < 200U; ++k) {
    TractionInput in = sample(drive.now_ms(), 0.15 + 0.002 * static_cast<double>(k));
    in.speed_valid = false;
    out = drive.step(in);
  }
  EXPECT_FALSE(out.trend_known);
  EXPECT_EQ(out.resistance_ahead, out.resistance_median);
  EXPECT_EQ(out.state, TractionState::stop);  // 0.15 + 0.4 > 0.38
}

TEST(Traction, FewerThanHalfTheWheelsWithATorqueIsNoEvidence) {
  TractionInput in = sample(0U, 0.5);
  for (std::uint32_t i = 0U; i < 4U; ++i) in.torque_valid[i] = false;
  TractionMonitor m;
  EXPECT_EQ(m.step(in, table().traction, table().monitor, per_radius()).sample,
            TractionSample::too_few_wheels);
  in.torque_valid[3] = true;  // three of six: half
  EXPECT_EQ(m.step(in, table().traction, table().monitor, per_radius()).sample, TractionSample::filling);
}

TEST(Traction, AssumedPullsMissingLoadsAndMixedDirectionsAreNoEvidence) {
  TractionMonitor m;
  const auto step = [&m](const TractionInput& in) {
    return m.step(in, table().traction, table().monitor, per_radius()).sample;
  };
  TractionInput in = sample(0U, 0.5);
  in.pull_assumed = true;
  EXPECT_EQ(step(in), TractionSample::pull_assumed);
  in = sample(200U, 0.5);
  in.loads_valid = false;
  EXPECT_EQ(step(in), TractionSample::no_loads);
  in = sample(400U, 0.5);
  in.direction[1] = DriveDirection::reverse;
  EXPECT_EQ(step(in), TractionSample::mixed_direction);
  for (std::uint32_t k = 0U; k < 30U; ++k) {
    in.time = TimeMs{600U + k * kCycleMs};
    EXPECT_NE(m.step(in, table().traction, table().monitor, per_radius()).state, TractionState::stop);
  }
}

TEST(Traction, ReverseDrivingReadsThePullBackwards) {
  TractionInput fwd = sample(0U, 0.25);
  TractionInput rev = fwd;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    rev.direction[i] = DriveDirection::reverse;
    rev.drawbar_pull_n[i] = q<DrawbarPullN>(-kPullN);  // along body -x
  }
  rev.speed_mps = q<SpeedMps>(-kSpeedMps);
  TractionMonitor a;
  TractionMonitor b;
  const TractionOutput fo = a.step(fwd, table().traction, table().monitor, per_radius());
  const TractionOutput ro = b.step(rev, table().traction, table().monitor, per_radius());
  ASSERT_TRUE(fo.rho_valid && ro.rho_valid);
  EXPECT_EQ(fo.resistance, ro.resistance);
}

TEST(Traction, AnOverflowIsReportedNotANumber) {
  TractionMonitor m;
  TractionInput in = sample(0U, 0.2);
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    in.torque_nm[i] = q<TorqueNm>(1000.0);  // within the products' range: the quotient leaves Q7.24
    in.load_n[i] = WheelLoadN::from_raw(1);
  }
  const TractionOutput out = m.step(in, table().traction, table().monitor, per_radius());
  EXPECT_EQ(out.sample, TractionSample::overflow);
  EXPECT_FALSE(out.rho_valid);
}

// The products stay in 64 bits while |sum T| < 32768 N m (docs/traction.md):
// beyond it the sample is overflow, no number, even where rho itself would be
// small; just below it the coefficient is the twin's.
TEST(Traction, ATorqueSumBeyondTheProductsRangeIsReportedNotANumber) {
  TractionInput in = sample(0U, 0.2);
  std::array<double, kWheelCount> t{};
  std::array<double, kWheelCount> p{};
  std::array<double, kWheelCount> w{};
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    in.torque_nm[i] = TorqueNm::from_raw(static_cast<std::int32_t>((std::int64_t{1} << 31U) / 6));  // sum 2^31 - 2 raw
    in.load_n[i] = q<WheelLoadN>(20000.0);
    in.drawbar_pull_n[i] = q<DrawbarPullN>(kPullN);
    t[i] = d(in.torque_nm[i]);
    p[i] = kPullN;
    w[i] = 20000.0;
  }
  const LengthM radius = q<LengthM>(2.0);
  TractionMonitor below;
  const TractionOutput ok = below.step(in, table().traction, table().monitor, inverse_radius(radius));
  ASSERT_TRUE(ok.rho_valid);
  EXPECT_NEAR(d(ok.resistance), sinkwatch::ground::resistance_coefficient(t, p, w, 2.0), 2.0 * lsb_ratio());
  in.torque_nm[0] = TorqueNm::from_raw(in.torque_nm[0].raw() + 2);  // the sum reaches 2^31 raw
  TractionMonitor beyond;
  const TractionOutput out = beyond.step(in, table().traction, table().monitor, inverse_radius(radius));
  EXPECT_EQ(out.sample, TractionSample::overflow);
  EXPECT_FALSE(out.rho_valid);
}

// A radius outside the validated range has no 1/r: every sample is overflow.
TEST(Traction, ARadiusOutsideTheTablesRangeGivesNoCoefficient) {
  EXPECT_EQ(inverse_radius(LengthM::zero()).per_m_q24, 0U);
  EXPECT_EQ(inverse_radius(q<LengthM>(2.5)).per_m_q24, 0U);
  EXPECT_EQ(inverse_radius(q<LengthM>(0.5)).per_m_q24, 1U << 25U);  // 1/0.5 m = 2 in Q7.24
  TractionMonitor m;
  const TractionOutput out = m.step(sample(0U, 0.2), table().traction, table().monitor, InverseRadius{});
  EXPECT_EQ(out.sample, TractionSample::overflow);
  EXPECT_FALSE(out.rho_valid);
}

// The trend's arithmetic at its edges: a falling median carries nothing, a
// distance that is not positive gives no number, and the carried term is the
// twin's within half an LSB (its only rounding).
TEST(Traction, TheCarriedTermIsTheTwinsAndOnlyARiseIsCarried) {
  Ratio ahead{};
  EXPECT_TRUE(carried_ahead(q<Ratio>(0.20), q<Ratio>(0.25), q<LengthM>(1.0).raw(), q<LengthM>(2.0), ahead));
  EXPECT_EQ(ahead, q<Ratio>(0.20));
  EXPECT_FALSE(carried_ahead(q<Ratio>(0.30), q<Ratio>(0.25), 0, q<LengthM>(2.0), ahead));
  EXPECT_EQ(ahead, q<Ratio>(0.30));
  ASSERT_TRUE(carried_ahead(q<Ratio>(0.30), q<Ratio>(0.25), q<LengthM>(1.1).raw(), q<LengthM>(2.0), ahead));
  const double twin = sinkwatch::ground::resistance_ahead(d(q<Ratio>(0.30)), d(q<Ratio>(0.25)),
                                                          d(q<LengthM>(1.1)), d(q<LengthM>(2.0)));
  EXPECT_NEAR(d(ahead), twin, 0.5 * lsb_ratio());
}

TEST(Traction, ATrendBeyondTheRatioFormatIsReportedNotANumber) {
  // rho from 0 to 120 within the span: carried 2 m ahead it is beyond Q7.24.
  Drive drive;
  TractionOutput out = drive.run(250U, [](std::uint32_t) { return 0.0; });
  ASSERT_TRUE(out.trend_known);
  out = drive.run(10U, [](std::uint32_t) { return 120.0; });
  EXPECT_EQ(out.sample, TractionSample::overflow);
  EXPECT_FALSE(out.rho_valid);
}
