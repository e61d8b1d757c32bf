// The motion-resistance check (flight/traction.hpp, docs/traction.md): the
// coefficient against its double twin, the median, the trend carried ahead,
// the N-of-M states, the restart when the rover stands, and every sample the
// check refuses.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <random>

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

/// One cycle of `m` into a fresh record (TractionMonitor::step writes into
/// the caller's).
TractionOutput stepped(TractionMonitor& m, const TractionInput& in, const TractionParams& params,
                       const MonitorParams& monitor, InverseRadius per_r) {
  TractionOutput out{};
  m.step(in, params, monitor, per_r, out);
  return out;
}

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
    last_ = stepped(monitor_, in, table().traction, table().monitor, per_radius());
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
  const TractionOutput out = stepped(m, sample(0U, 2.0), TractionParams{}, table().monitor, per_radius());
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
  EXPECT_EQ(stepped(m, in, table().traction, table().monitor, per_radius()).sample,
            TractionSample::too_few_wheels);
  in.torque_valid[3] = true;  // three of six: half
  EXPECT_EQ(stepped(m, in, table().traction, table().monitor, per_radius()).sample, TractionSample::filling);
}

TEST(Traction, AssumedPullsMissingLoadsAndMixedDirectionsAreNoEvidence) {
  TractionMonitor m;
  const auto step = [&m](const TractionInput& in) {
    return stepped(m, in, table().traction, table().monitor, per_radius()).sample;
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
    EXPECT_NE(stepped(m, in, table().traction, table().monitor, per_radius()).state, TractionState::stop);
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
  const TractionOutput fo = stepped(a, fwd, table().traction, table().monitor, per_radius());
  const TractionOutput ro = stepped(b, rev, table().traction, table().monitor, per_radius());
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
  const TractionOutput out = stepped(m, in, table().traction, table().monitor, per_radius());
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
  const TractionOutput ok = stepped(below, in, table().traction, table().monitor, inverse_radius(radius));
  ASSERT_TRUE(ok.rho_valid);
  EXPECT_NEAR(d(ok.resistance), sinkwatch::ground::resistance_coefficient(t, p, w, 2.0), 2.0 * lsb_ratio());
  in.torque_nm[0] = TorqueNm::from_raw(in.torque_nm[0].raw() + 2);  // the sum reaches 2^31 raw
  TractionMonitor beyond;
  const TractionOutput out = stepped(beyond, in, table().traction, table().monitor, inverse_radius(radius));
  EXPECT_EQ(out.sample, TractionSample::overflow);
  EXPECT_FALSE(out.rho_valid);
}

// A radius outside the validated range has no 1/r: every sample is overflow.
TEST(Traction, ARadiusOutsideTheTablesRangeGivesNoCoefficient) {
  EXPECT_EQ(inverse_radius(LengthM::zero()).per_m_q24, 0U);
  EXPECT_EQ(inverse_radius(q<LengthM>(2.5)).per_m_q24, 0U);
  EXPECT_EQ(inverse_radius(q<LengthM>(0.5)).per_m_q24, 1U << 25U);  // 1/0.5 m = 2 in Q7.24
  TractionMonitor m;
  const TractionOutput out = stepped(m, sample(0U, 0.2), table().traction, table().monitor, InverseRadius{});
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

// ---------------------------------------------------------------------------
// Round 12 of issue 15 cut the check's per-cycle work and kept its bits: the
// quotient and the cycle's distance without a 64-bit library division, the
// median kept sorted instead of sorted for, the wheel sums in registers, the
// output written in place, no count of an empty N-of-M history. The tests
// below hold the new forms to the old ones, bit for bit.

namespace {

/// round(n / d), half up, as the check divided before round 12.
std::uint64_t plain_rounded_quotient(std::uint64_t n, std::uint64_t d) {
  std::uint64_t quotient = n / d;
  const std::uint64_t remainder = n - (quotient * d);
  if (remainder >= (d - remainder)) {
    ++quotient;
  }
  return quotient;
}

/// Divisors and dividends at the edges of the normalised division: powers of
/// two and their neighbours, the ends of 32 and 64 bits, and the dividends
/// whose quotient sits at 2^32 or whose remainder is exactly half the divisor.
std::uint64_t edge_divisor(std::mt19937_64& rng) {
  const std::uint32_t k = static_cast<std::uint32_t>(rng() % 34U);  // 2^0 .. 2^33
  const std::uint64_t p = std::uint64_t{1} << k;
  switch (rng() % 4U) {
    case 0U:
      return p;
    case 1U:
      return p + 1U;
    case 2U:
      return (p > 1U) ? (p - 1U) : 1U;
    default:
      return (rng() % p) + 1U;
  }
}

std::uint64_t edge_dividend(std::mt19937_64& rng, std::uint64_t d) {
  const std::uint64_t q = rng() >> (rng() % 64U);
  switch (rng() % 6U) {
    case 0U:
      return (q * d) + (d / 2U);  // a tie when d is even (q d may wrap: any n is fine)
    case 1U:
      return (q * d) + ((d - 1U) / 2U);
    case 2U:
      return (std::uint64_t{1} << 32U) * d - (rng() % 3U);  // the quotient at 2^32 (wraps for large d)
    case 3U:
      return std::uint64_t{1} << 63U;
    case 4U:
      return rng() >> (rng() % 64U);
    default:
      return (q * d) + (rng() % d);
  }
}

}  // namespace

TEST(TractionRound12, TheNormalisedQuotientIsThePlainRoundedQuotient) {
  std::mt19937_64 rng(20261215U);
  for (std::uint32_t k = 0U; k < 600000U; ++k) {
    const std::uint64_t d = edge_divisor(rng);
    const std::uint64_t n = edge_dividend(rng, d);
    ASSERT_EQ(detail::rounded_quotient(n, d), plain_rounded_quotient(n, d)) << n << " / " << d;
  }
  // Every divisor width with the largest dividend of a 32-bit quotient, and
  // the first of a 33-bit one (the library's path).
  for (std::uint32_t bits = 1U; bits <= 32U; ++bits) {
    for (const std::uint64_t d : {std::uint64_t{1} << (bits - 1U), (std::uint64_t{1} << bits) - 1U}) {
      const std::uint64_t top = ((std::uint64_t{1} << 32U) * d) - 1U;
      ASSERT_EQ(detail::rounded_quotient(top, d), plain_rounded_quotient(top, d)) << d;
      ASSERT_EQ(detail::rounded_quotient(top + 1U, d), plain_rounded_quotient(top + 1U, d)) << d;
      ASSERT_EQ(detail::rounded_quotient(0U, d), 0U) << d;
    }
  }
  ASSERT_EQ(detail::rounded_quotient(~std::uint64_t{0}, 1U), ~std::uint64_t{0});
  ASSERT_EQ(detail::rounded_quotient(~std::uint64_t{0}, ~std::uint64_t{0}), 1U);
}

// Round 15 of issue 15: on a core that divides words (the Cortex-M4) a
// one-word divisor with a quotient below 2^32 takes the normalised
// two-digit division (detail::rounded_quotient_one_word) in the check's own
// code instead of the library's 64-bit division. Its edges: every shift s
// (the divisor's width), the quotient's ends (0, rho's Q7.24 limit 2^31,
// the largest below 2^32), remainders at half the divisor (ties), and the
// first dividend and divisor outside the form, which one_word_quotient
// must refuse.
TEST(TractionRound15, TheOneWordDivisionIsThePlainRoundedQuotientAtItsEdges) {
  std::mt19937_64 rng(20261128U);
  constexpr std::uint64_t kWord = std::uint64_t{1} << 32U;
  std::uint64_t taken = 0U;
  for (std::uint32_t bits = 1U; bits <= 33U; ++bits) {
    const std::uint64_t low_end = std::uint64_t{1} << (bits - 1U);
    const std::uint64_t high_end = (std::uint64_t{1} << bits) - 1U;
    for (std::uint32_t k = 0U; k < 4000U; ++k) {
      const std::uint64_t d =
          (k == 0U) ? low_end : ((k == 1U) ? high_end : (low_end + (rng() % (high_end - low_end + 1U))));
      const std::uint64_t quotients[] = {0U, 1U, (std::uint64_t{1} << 31U) - 1U, std::uint64_t{1} << 31U,
                                         kWord - 1U, kWord, rng() % kWord, rng() >> 40U};
      const std::uint64_t any = rng() >> (rng() % 64U);
      for (const std::uint64_t quotient : quotients) {
        for (const std::uint64_t part : {std::uint64_t{0}, d / 2U, (d - 1U) / 2U, (d + 1U) / 2U, d - 1U, rng() % d, any}) {
          const std::uint64_t n = (quotient * d) + part;  // wraps for the largest: any n is fine
          const bool one_word = (d < kWord) && ((n / d) < kWord);
          ASSERT_EQ(detail::one_word_quotient(n, d), one_word) << n << " / " << d;
          if (one_word) {
            ASSERT_EQ(detail::rounded_quotient_one_word(n, d), plain_rounded_quotient(n, d)) << n << " / " << d;
            ++taken;
          }
        }
      }
    }
  }
  EXPECT_GT(taken, 500000U);
}

TEST(TractionRound12, TheCyclesDistanceIsThePlainRoundedThousandth) {
  // Every gap the check integrates (0..2000 ms) at the ends of the speed's
  // range, around multiples of 1000, and at random speeds.
  std::mt19937 rng(7U);
  std::array<std::uint32_t, 500> speeds{};
  const std::uint32_t ends[] = {0U, 1U, 499U, 500U, 999U, 1000U, 1001U, 0x7FFFFFFFU, 0x80000000U, 2147483000U,
                                2147482999U, 2147483647U - 647U};
  std::size_t n = 0U;
  for (const std::uint32_t e : ends) {
    speeds[n++] = e;
  }
  while (n < speeds.size()) {
    const std::uint32_t v = static_cast<std::uint32_t>(rng()) & 0x7FFFFFFFU;
    speeds[n] = ((n % 3U) == 0U) ? ((v / 1000U) * 1000U + 999U) : v;
    ++n;
  }
  for (const std::uint32_t speed : speeds) {
    for (std::uint32_t dt = 0U; dt <= 2000U; ++dt) {
      const std::uint64_t plain = ((static_cast<std::uint64_t>(speed) * dt) + 500U) / 1000U;
      ASSERT_EQ(detail::travelled_q24(speed, dt), plain) << speed << " m/s raw, " << dt << " ms";
    }
  }
}

/// The check as it was before round 12 (traction.cpp at c2cb290), kept as
/// the oracle of the differential test below; its internal helpers
/// (median.hpp, n_of_m.hpp) copied with it.
namespace before {

std::uint8_t count_bits(std::uint16_t bits, std::uint8_t window) {
  const std::uint32_t width = (window < kMaxWindow) ? window : kMaxWindow;
  const std::uint32_t mask = (1U << width) - 1U;
  std::uint32_t v = static_cast<std::uint32_t>(bits) & mask;
  v = v - ((v >> 1U) & 0x5555U);
  v = (v & 0x3333U) + ((v >> 2U) & 0x3333U);
  v = (v + (v >> 4U)) & 0x0F0FU;
  v = (v + (v >> 8U)) & 0x1FU;
  return static_cast<std::uint8_t>(v);
}

std::uint16_t shift_in(std::uint16_t history, bool bit) {
  return static_cast<std::uint16_t>((static_cast<std::uint32_t>(history) << 1U) | (bit ? 1U : 0U));
}

template <typename T, std::uint8_t N>
T median_of(const T (&values)[N], std::uint8_t count) {
  T sorted[N]{};
  for (std::uint8_t i = 0U; (i < count) && (i < N); ++i) {
    const T v = values[i];
    std::uint8_t j = i;
    while ((j > 0U) && (v < sorted[j - 1U])) {
      sorted[j] = sorted[j - 1U];
      --j;
    }
    sorted[j] = v;
  }
  const std::uint8_t used = (count < N) ? count : N;
  const std::uint8_t middle = (used > 0U) ? static_cast<std::uint8_t>((used - 1U) / 2U) : 0U;
  return sorted[middle];
}

constexpr std::uint64_t kMsPerSecond = 1000U;
constexpr std::uint64_t kMaxTorqueSumQ16 = (std::uint64_t{1U} << 31U) - 1U;
constexpr std::int64_t kQ16ToQ40 = static_cast<std::int64_t>(std::uint64_t{1U} << 24U);
constexpr std::uint32_t kMaxGapMs = 2000U;
constexpr std::int32_t kMarksPerSpan = 8;

struct WheelSums {
  std::int64_t torque_q16{0};
  std::int64_t pull_q16{0};
  std::int64_t load_q16{0};
  std::uint8_t wheels{0U};
  bool mixed{false};
};

WheelSums sum_wheels(const TractionInput& in, std::uint8_t wheels) {
  WheelSums s{};
  bool have_direction = false;
  DriveDirection direction = DriveDirection::forward;
  for (std::uint8_t i = 0U; (i < wheels) && (i < kWheelCount); ++i) {
    if (in.torque_valid[i]) {
      if (have_direction && (in.direction[i] != direction)) {
        s.mixed = true;
      }
      have_direction = true;
      direction = in.direction[i];
      const std::int64_t pull = in.drawbar_pull_n[i].raw();
      s.pull_q16 += (direction == DriveDirection::reverse) ? -pull : pull;
      s.torque_q16 += in.torque_nm[i].raw();
      s.load_q16 += in.load_n[i].raw();
      ++s.wheels;
    }
  }
  return s;
}

Ratio rounded_ratio(std::int64_t n, std::uint64_t d, sinkwatch::fx::Status& st) {
  const bool negative = n < 0;
  const std::uint64_t magnitude = sinkwatch::fx::detail::magnitude(n);
  std::uint64_t quotient = magnitude / d;
  const std::uint64_t remainder = magnitude - (quotient * d);
  if (remainder >= (d - remainder)) {
    ++quotient;
  }
  return Ratio::from_raw(sinkwatch::fx::detail::from_sign_magnitude<RatioQ::storage_type>(
      negative && (quotient != 0U), quotient, st));
}

class TractionMonitor {
 public:
  TractionOutput step(const TractionInput& input, const TractionParams& params, const MonitorParams& monitor,
                      InverseRadius per_radius) {
    TractionOutput out{};
    if (!traction_check_on(params)) {
      out.state = TractionState::off;
      out.sample = TractionSample::check_off;
      return out;
    }
    Ratio rho{};
    out.sample = resistance_of(input, monitor.wheel_count, per_radius, rho);
    if (out.sample == TractionSample::ok) {
      out.sample = evaluate(input, params, rho, out);
    }
    bool caution = false;
    bool stop = false;
    bool clear = false;
    if (out.sample == TractionSample::ok) {
      sinkwatch::fx::Status st;
      stop = out.resistance_ahead >= params.stop_coefficient;
      caution = out.resistance_ahead >= params.caution_coefficient;
      clear = out.resistance_ahead.q() < sinkwatch::fx::sub(params.caution_coefficient.q(), params.hysteresis.q(), st);
    }
    caution_history_ = shift_in(caution_history_, caution);
    stop_history_ = shift_in(stop_history_, stop);
    clear_history_ = shift_in(clear_history_, clear);
    transition(monitor, out);
    out.state = state_;
    return out;
  }

  void clear_stop() { *this = TractionMonitor(); }
  [[nodiscard]] TractionState state() const { return state_; }

 private:
  static TractionSample resistance_of(const TractionInput& in, std::uint8_t wheels, InverseRadius per_radius,
                                      Ratio& rho) {
    if (!in.loads_valid) {
      return TractionSample::no_loads;
    }
    if (in.pull_assumed) {
      return TractionSample::pull_assumed;
    }
    const WheelSums s = sum_wheels(in, wheels);
    if ((static_cast<std::uint32_t>(s.wheels) * 2U) < static_cast<std::uint32_t>(wheels)) {
      return TractionSample::too_few_wheels;
    }
    if (s.mixed) {
      return TractionSample::mixed_direction;
    }
    const std::uint64_t torque = sinkwatch::fx::detail::magnitude(s.torque_q16);
    if ((per_radius.per_m_q24 == 0U) || (torque > kMaxTorqueSumQ16) || (s.load_q16 <= 0)) {
      return TractionSample::overflow;
    }
    const std::uint64_t thrust = static_cast<std::uint64_t>(torque) * per_radius.per_m_q24;
    const std::int64_t signed_thrust =
        (s.torque_q16 < 0) ? -static_cast<std::int64_t>(thrust) : static_cast<std::int64_t>(thrust);
    const std::int64_t resistance = signed_thrust - (s.pull_q16 * kQ16ToQ40);
    sinkwatch::fx::Status st;
    rho = rounded_ratio(resistance, static_cast<std::uint64_t>(s.load_q16), st);
    return st.ok() ? TractionSample::ok : TractionSample::overflow;
  }

  Ratio push_median(Ratio rho) {
    recent_[recent_next_] = rho;
    recent_next_ = static_cast<std::uint8_t>(((recent_next_ + 1U) < kTractionMedianSamples) ? (recent_next_ + 1U) : 0U);
    if (recent_count_ < kTractionMedianSamples) {
      ++recent_count_;
    }
    return median_of(recent_, recent_count_);
  }

  TractionSample evaluate(const TractionInput& input, const TractionParams& params, Ratio rho, TractionOutput& out) {
    sinkwatch::fx::Status st;
    const bool standing =
        input.speed_valid && (sinkwatch::fx::abs(input.speed_mps.q(), st) < kTractionStandingSpeed.q());
    if (standing || !st.ok()) {
      recent_count_ = 0U;
      recent_next_ = 0U;
      mark_count_ = 0U;
      since_mark_m_ = LengthM::zero();
      settled_ = false;
      have_time_ = true;
      last_time_ = input.time;
      return TractionSample::standing;
    }
    const Ratio rho_med = push_median(rho);
    advance(input, rho_med, params);
    Ratio ahead{};
    bool overflow = false;
    out.trend_known = ahead_of(rho_med, params, ahead, overflow);
    if (overflow) {
      out.trend_known = false;
      return TractionSample::overflow;
    }
    out.rho_valid = true;
    out.resistance = rho;
    out.resistance_median = rho_med;
    out.resistance_ahead = ahead;
    return (recent_count_ < kTractionMedianSamples) ? TractionSample::filling : TractionSample::ok;
  }

  void advance(const TractionInput& in, Ratio rho_med, const TractionParams& params) {
    const std::uint32_t dt_ms = have_time_ ? elapsed_ms(last_time_, in.time) : 0U;
    have_time_ = true;
    last_time_ = in.time;
    if (!in.speed_valid || (dt_ms > kMaxGapMs)) {
      return;
    }
    const std::uint64_t speed = sinkwatch::fx::detail::magnitude(in.speed_mps.raw());
    const std::uint64_t step_q24 = ((speed * dt_ms) + (kMsPerSecond / 2U)) / kMsPerSecond;
    sinkwatch::fx::Status st;
    const LengthM step_m =
        LengthM::from_raw(sinkwatch::fx::detail::from_sign_magnitude<LengthQ::storage_type>(false, step_q24, st));
    const LengthM travelled{sinkwatch::fx::add(since_mark_m_.q(), step_m.q(), st)};
    if (!st.ok()) {
      return;
    }
    since_mark_m_ = travelled;
    if (!settled_) {
      settled_ = since_mark_m_ >= params.trend_span_m;
      if (settled_) {
        since_mark_m_ = LengthM::zero();
      }
      return;
    }
    const LengthM spacing = LengthM::from_raw(params.trend_span_m.raw() / kMarksPerSpan);
    if (since_mark_m_ < spacing) {
      return;
    }
    mark_newest_ = static_cast<std::uint8_t>((mark_newest_ + 1U) % kTractionTrendMarks);
    mark_rho_[mark_newest_] = rho_med;
    mark_gap_m_[mark_newest_] = since_mark_m_;
    since_mark_m_ = LengthM::zero();
    if (mark_count_ < kTractionTrendMarks) {
      ++mark_count_;
    }
  }

  bool ahead_of(Ratio rho_med, const TractionParams& params, Ratio& ahead, bool& overflow) const {
    ahead = rho_med;
    overflow = false;
    std::int64_t distance = since_mark_m_.raw();
    const std::int64_t span = params.trend_span_m.raw();
    std::uint8_t index = mark_newest_;
    for (std::uint8_t k = 0U; k < mark_count_; ++k) {
      if ((k > 0U) && (distance >= span)) {
        overflow = !carried_ahead(rho_med, mark_rho_[index], distance, params.lookahead_m, ahead);
        return true;
      }
      distance += mark_gap_m_[index].raw();
      index = static_cast<std::uint8_t>((index + kTractionTrendMarks - 1U) % kTractionTrendMarks);
    }
    return false;
  }

  void transition(const MonitorParams& monitor, TractionOutput& out) {
    if (state_ == TractionState::stop) {
      return;
    }
    if (count_bits(stop_history_, monitor.window_m) >= monitor.trip_n) {
      state_ = TractionState::stop;
      out.stop_tripped = true;
    } else if ((state_ == TractionState::nominal) &&
               (count_bits(caution_history_, monitor.window_m) >= monitor.trip_n)) {
      state_ = TractionState::caution;
    } else if ((state_ == TractionState::caution) &&
               (count_bits(clear_history_, monitor.window_m) >= monitor.clear_n)) {
      state_ = TractionState::nominal;
    } else {
    }
  }

  TractionState state_{TractionState::nominal};
  Ratio recent_[kTractionMedianSamples];
  std::uint8_t recent_count_{0U};
  std::uint8_t recent_next_{0U};
  Ratio mark_rho_[kTractionTrendMarks];
  LengthM mark_gap_m_[kTractionTrendMarks];
  std::uint8_t mark_count_{0U};
  std::uint8_t mark_newest_{0U};
  LengthM since_mark_m_;
  bool settled_{false};
  bool have_time_{false};
  TimeMs last_time_{0U};
  std::uint16_t caution_history_{0U};
  std::uint16_t stop_history_{0U};
  std::uint16_t clear_history_{0U};
};

}  // namespace before

namespace {

/// Random cycles for the differential test: a drive whose coefficient
/// wanders around the levels (so that every state is entered), with repeated
/// coefficients (equal ratios in the median), standing and missing odometry,
/// long gaps and clocks going backwards, refused samples of every kind, and
/// raw values at the ends of their ranges.
class TractionFuzz {
 public:
  explicit TractionFuzz(std::uint32_t seed) : rng_(seed) {}

  std::uint32_t below(std::uint32_t n) { return std::uniform_int_distribution<std::uint32_t>(0U, n - 1U)(rng_); }
  bool one_in(std::uint32_t n) { return below(n) == 0U; }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  std::int32_t any_raw() {
    constexpr std::int32_t kEdges[] = {std::numeric_limits<std::int32_t>::min(), -1, 0, 1,
                                       std::numeric_limits<std::int32_t>::max()};
    return one_in(2U) ? kEdges[below(5U)] : static_cast<std::int32_t>(rng_());
  }

  TractionParams params() {
    if (one_in(20U)) {
      return TractionParams{};  // the check off
    }
    TractionParams p = table().traction;
    p.caution_coefficient = q<Ratio>(uniform(0.1, 0.4));
    p.stop_coefficient = q<Ratio>(d(p.caution_coefficient) + uniform(0.0, 0.2));
    p.hysteresis = q<Ratio>(uniform(0.0, 0.09));
    p.lookahead_m = one_in(6U) ? q<LengthM>(-uniform(0.0, 3.0)) : q<LengthM>(uniform(0.0, 3.0));
    p.trend_span_m = q<LengthM>(uniform(0.005, 0.2));
    return p;
  }

  MonitorParams monitor() {
    MonitorParams m = table().monitor;
    m.window_m = static_cast<std::uint8_t>(below(18U));
    m.trip_n = static_cast<std::uint8_t>(below(static_cast<std::uint32_t>(m.window_m) + 2U));
    m.clear_n = static_cast<std::uint8_t>(below(static_cast<std::uint32_t>(m.window_m) + 2U));
    m.wheel_count = static_cast<std::uint8_t>(one_in(4U) ? below(9U) : kWheelCount);
    return m;
  }

  InverseRadius radius() {
    if (one_in(30U)) {
      return one_in(2U) ? InverseRadius{} : InverseRadius{static_cast<std::uint32_t>(rng_())};
    }
    return inverse_radius(q<LengthM>(uniform(0.05, 0.5)));
  }

  TractionInput input(std::uint32_t& time_ms, double& rho, double radius_m) {
    // Gaps beyond the integrated 2 s, up to it (with an extreme speed the
    // distance then leaves its format), and the usual cycles.
    if (one_in(40U)) {
      time_ms += 2001U + below(3000U);
    } else {
      time_ms += one_in(30U) ? (1000U + below(1001U)) : (50U + below(300U));
    }
    if (one_in(60U)) {
      time_ms -= below(1000U);  // a clock going backwards
    }
    if (!one_in(3U)) {
      rho += uniform(-0.02, 0.025);  // repeated otherwise: equal ratios in the median
    }
    TractionInput in = sample(time_ms, rho, uniform(-0.3, 0.6));
    const double wheel_torque = d(in.torque_nm[0]) * kRadiusM / radius_m;
    in.loads_valid = !one_in(25U);
    in.pull_assumed = one_in(40U);
    in.speed_valid = !one_in(15U);
    if (one_in(15U)) {
      in.speed_mps = q<SpeedMps>(uniform(-0.004, 0.004));  // standing
    }
    if (one_in(80U)) {
      in.speed_mps = SpeedMps::from_raw(any_raw());
    }
    const bool reverse = one_in(4U);
    for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
      in.torque_nm[i] = q<TorqueNm>(wheel_torque * uniform(0.9, 1.1) * (reverse ? -1.0 : 1.0));
      in.load_n[i] = q<WheelLoadN>(kLoadN * uniform(0.5, 1.5));
      in.drawbar_pull_n[i] = q<DrawbarPullN>(uniform(-2.0, 2.0));
      in.torque_valid[i] = !one_in(8U);
      in.direction[i] = reverse ? DriveDirection::reverse : DriveDirection::forward;
      if (one_in(50U)) {
        in.direction[i] = one_in(3U) ? static_cast<DriveDirection>(2U) : DriveDirection::reverse;
      }
      if (one_in(100U)) {
        in.torque_nm[i] = TorqueNm::from_raw(any_raw());
      }
      if (one_in(100U)) {
        in.load_n[i] = WheelLoadN::from_raw(any_raw());
      }
      if (one_in(100U)) {
        in.drawbar_pull_n[i] = DrawbarPullN::from_raw(any_raw());
      }
    }
    return in;
  }

 private:
  std::mt19937 rng_;
};

void expect_same_output(const TractionOutput& got, const TractionOutput& want, std::uint32_t k) {
  ASSERT_EQ(got.state, want.state) << "cycle " << k;
  ASSERT_EQ(got.sample, want.sample) << "cycle " << k;
  ASSERT_EQ(got.stop_tripped, want.stop_tripped) << "cycle " << k;
  ASSERT_EQ(got.rho_valid, want.rho_valid) << "cycle " << k;
  ASSERT_EQ(got.resistance.raw(), want.resistance.raw()) << "cycle " << k;
  ASSERT_EQ(got.resistance_median.raw(), want.resistance_median.raw()) << "cycle " << k;
  ASSERT_EQ(got.trend_known, want.trend_known) << "cycle " << k;
  ASSERT_EQ(got.resistance_ahead.raw(), want.resistance_ahead.raw()) << "cycle " << k;
}

}  // namespace

TEST(TractionRound12, TheMonitorGivesTheSameOutputsAsBeforeOnRandomDrives) {
  std::array<std::uint32_t, 9> samples{};  // per TractionSample: every kind is reached
  std::array<std::uint32_t, 4> states{};
  std::uint32_t trends = 0U;
  for (std::uint32_t seed = 1U; seed <= 150U; ++seed) {
    TractionFuzz f(seed);
    const TractionParams params = f.params();
    const MonitorParams monitor = f.monitor();
    const double radius_m = f.uniform(0.05, 0.5);
    const InverseRadius per_r = f.one_in(10U) ? f.radius() : inverse_radius(q<LengthM>(radius_m));
    before::TractionMonitor then;
    TractionMonitor in_place;
    TractionOutput out{};
    std::uint32_t time_ms = 1000U;
    double rho = f.uniform(0.0, 0.3);
    for (std::uint32_t k = 0U; k < 500U; ++k) {
      if (f.one_in(150U)) {
        then.clear_stop();
        in_place.clear_stop();
      }
      const TractionInput in = f.input(time_ms, rho, radius_m);
      const TractionOutput want = then.step(in, params, monitor, per_r);
      // The in-place form writes every field of the previous cycle's record.
      out.stop_tripped = !out.stop_tripped;
      out.rho_valid = !out.rho_valid;
      out.trend_known = !out.trend_known;
      out.resistance = Ratio::from_raw(out.resistance.raw() ^ 0x5A5A5A5A);
      out.resistance_median = Ratio::from_raw(~out.resistance_median.raw());
      out.resistance_ahead = Ratio::from_raw(out.resistance_ahead.raw() + 12345);
      in_place.step(in, params, monitor, per_r, out);
      expect_same_output(out, want, k);
      ASSERT_EQ(in_place.state(), then.state()) << "seed " << seed << " cycle " << k;
      if (::testing::Test::HasFatalFailure()) {
        FAIL() << "seed " << seed;
      }
      ++samples[static_cast<std::size_t>(want.sample)];
      ++states[static_cast<std::size_t>(want.state)];
      trends += want.trend_known ? 1U : 0U;
    }
  }
  for (std::size_t s = 0U; s < samples.size(); ++s) {
    EXPECT_GT(samples[s], 0U) << "sample kind " << s << " never reached";
  }
  for (std::size_t s = 0U; s < states.size(); ++s) {
    EXPECT_GT(states[s], 0U) << "state " << s << " never reached";
  }
  EXPECT_GT(trends, 1000U);
}
