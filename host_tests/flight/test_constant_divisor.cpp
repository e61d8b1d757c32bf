// Division by prepared table constants (constant_divisor.hpp, issue 10): the
// same bits and flags as fx::div for every format pair the per-cycle chain
// uses, at the edges (divisor 1 and 2^31 - 1, dividends at 2^64 after the
// scaling, negative operands, zero) and on random operands; and the
// corrections and the motor inverse through prepared divisors equal their
// plain forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "dividing_oracle.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/constant_divisor.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace {

using flight::WideQ;

/// Both divisions of `a` by `b`: value and status flags agree.
template <typename Out, typename QA, typename QB>
bool agrees(QA a, QB b) {
  fx::Status s_plain;
  fx::Status s_prepared;
  const Out plain = fx::div<Out>(a, b, s_plain);
  const Out prepared = flight::div_by_constant<Out>(a, flight::make_divisor(b), s_prepared);
  return (plain == prepared) && (s_plain.bits() == s_prepared.bits());
}

template <typename S>
S random_raw(std::mt19937_64& rng) {
  // A random magnitude at a random bit length, either sign.
  constexpr std::uint32_t bits = (sizeof(S) * 8U) - 1U;
  const std::uint32_t len = static_cast<std::uint32_t>(rng() % (bits + 1U));
  const std::uint64_t mag = (len == 0U) ? 0U : (rng() >> (64U - len));
  const S v = static_cast<S>(mag);
  return ((rng() & 1U) != 0U) ? static_cast<S>(-v) : v;
}

template <typename Out, typename QA, typename QB>
std::uint64_t mismatches(int cases, std::uint64_t seed) {
  using SA = typename QA::storage_type;
  using SB = typename QB::storage_type;
  std::mt19937_64 rng(seed);
  std::uint64_t bad = 0U;
  const SA edge_a[] = {0, 1, -1, std::numeric_limits<SA>::max(), std::numeric_limits<SA>::min(),
                       static_cast<SA>(std::numeric_limits<SA>::max() / 2)};
  const SB edge_b[] = {1, -1, 2, 3, 7, std::numeric_limits<SB>::max(), std::numeric_limits<SB>::min(),
                       static_cast<SB>(std::numeric_limits<SB>::max() / 3)};
  for (const SA a : edge_a) {
    for (const SB b : edge_b) {
      bad += agrees<Out>(QA::from_raw(a), QB::from_raw(b)) ? 0U : 1U;
    }
  }
  for (int i = 0; i < cases; ++i) {
    const SB b = random_raw<SB>(rng);
    bad += agrees<Out>(QA::from_raw(random_raw<SA>(rng)), QB::from_raw((b == 0) ? SB{1} : b)) ? 0U : 1U;
  }
  return bad;
}

TEST(ConstantDivisor, SameBitsAsFxDivForTheStepsFormats) {
  // The interpolation fraction, T/N, then / eta and / Kt.
  EXPECT_EQ((mismatches<WideQ, flight::LoadQ, flight::LoadQ>(300000, 1U)), 0U);
  EXPECT_EQ((mismatches<WideQ, flight::LoadQ, flight::GearQ>(300000, 2U)), 0U);
  EXPECT_EQ((mismatches<WideQ, WideQ, flight::EfficiencyQ>(300000, 3U)), 0U);
  EXPECT_EQ((mismatches<WideQ, WideQ, flight::KtQ>(300000, 4U)), 0U);
}

TEST(ConstantDivisor, SameBitsAsFxDivForOtherFormats) {
  // Narrow outputs saturate and raise overflow exactly as fx::div does.
  EXPECT_EQ((mismatches<flight::LoadQ, flight::LoadQ, flight::LoadQ>(200000, 5U)), 0U);
  EXPECT_EQ((mismatches<flight::CurrentQ, WideQ, flight::KtQ>(200000, 6U)), 0U);
  EXPECT_EQ((mismatches<flight::LengthQ, WideQ, flight::RatioQ>(200000, 7U)), 0U);
  EXPECT_EQ((mismatches<WideQ, fx::Q<std::int32_t, 0>, fx::Q<std::int32_t, 0>>(200000, 8U)), 0U);
}

TEST(ConstantDivisor, ExactQuotientsAroundEveryRoundingBoundary) {
  // n = q d + r for r in {0, d/2 - 1, d/2, d/2 + 1, d - 1}: ties and their
  // neighbours, where an approximate reciprocal would round the other way.
  std::mt19937_64 rng(9U);
  std::uint64_t bad = 0U;
  for (int i = 0; i < 100000; ++i) {
    const std::int32_t d = static_cast<std::int32_t>((rng() % 0x7FFFFFFFU) + 1U);
    const std::int64_t q = static_cast<std::int64_t>(rng() % (std::uint64_t{1} << 31U));
    const std::int64_t half = d / 2;
    for (const std::int64_t r : {std::int64_t{0}, half - 1, half, half + 1, std::int64_t{d} - 1}) {
      // a / b with a in Q31.32 and b in Q0.31-like Q<int32, 0>: k = 0, so the
      // dividend is a's raw value itself.
      const std::int64_t n = (q * d) + ((r < 0) ? 0 : r);
      bad += agrees<fx::Q<std::int64_t, 0>>(fx::Q<std::int64_t, 0>::from_raw(n),
                                            fx::Q<std::int32_t, 0>::from_raw(d))
                 ? 0U
                 : 1U;
    }
  }
  EXPECT_EQ(bad, 0U);
}

TEST(ConstantDivisor, RoundedQuotientOfSixtyFourBitOperandsIsExact) {
  // Any 64-bit divisor (the drawbar split divides by a sum of six loads, up
  // to 2^34): round half up of n / d, against the built-in 64-bit division.
  std::mt19937_64 rng(13U);
  std::uint64_t bad = 0U;
  for (int i = 0; i < 1000000; ++i) {
    const std::uint32_t dlen = static_cast<std::uint32_t>(rng() % 64U) + 1U;
    const std::uint64_t d = std::max<std::uint64_t>(rng() >> (64U - dlen), 1U);
    const std::uint64_t n = ((i % 3) == 0) ? (d * (rng() % 1000U)) + (d / 2U) : rng();
    const std::uint64_t q = n / d;
    const std::uint64_t r = n % d;
    const std::uint64_t expected = (r >= (d - r)) ? (q + 1U) : q;
    bad += (flight::rounded_quotient(n, d, flight::reciprocal_of(d)) == expected) ? 0U : 1U;
  }
  EXPECT_EQ(bad, 0U);
  EXPECT_EQ(flight::reciprocal_of(0U), 0U);
  EXPECT_EQ(flight::rounded_quotient(~std::uint64_t{0U}, 1U, flight::reciprocal_of(1U)), ~std::uint64_t{0U});
  EXPECT_EQ(flight::rounded_quotient(7U, 2U, flight::reciprocal_of(2U)), 4U);  // 3.5 rounds up
}

TEST(ConstantDivisor, ReciprocalOfAQ31_32ValueHasFxDivsBits) {
  // 1 / v in Q31.32 for every divisor from 3 raw (2 would give 2^63, beyond
  // Q31.32; the statics' levers are at least 1 mm, 2^22 raw) up, near powers of two (remainder r = d and
  // exact halves), against fx::div(1, v).
  using W = fx::Q<std::int64_t, 32>;
  constexpr W one = fx::constant<W>(1.0);  // constexpr: fx::constant only in constant evaluation (D-01)
  std::mt19937_64 rng(15U);
  std::uint64_t bad = 0U;
  for (int i = 0; i < 1000000; ++i) {
    const std::uint32_t dlen = static_cast<std::uint32_t>(rng() % 62U) + 2U;
    std::uint64_t d = std::max<std::uint64_t>(rng() >> (64U - dlen), 3U);
    if ((i % 4) == 0) {
      d = std::max<std::uint64_t>((std::uint64_t{1U} << (dlen - 1U)) + (rng() % 5U) - 2U, 3U);
    }
    fx::Status st;
    const W expected = fx::div(one, W::from_raw(static_cast<std::int64_t>(d)), st);
    bad += (st.ok() && (flight::rounded_reciprocal_q32(d) == static_cast<std::uint64_t>(expected.raw()))) ? 0U : 1U;
  }
  EXPECT_EQ(bad, 0U);
  EXPECT_EQ(flight::rounded_reciprocal_q32(4U), std::uint64_t{1U} << 62U);  // r = d: exact
  // Below 3 the quotient leaves Q31.32: its largest value, as fx::div saturates.
  fx::Status st;
  EXPECT_EQ(flight::rounded_reciprocal_q32(2U), static_cast<std::uint64_t>(fx::div(one, W::from_raw(2), st).raw()));
  EXPECT_FALSE(st.ok());
  EXPECT_EQ(flight::rounded_reciprocal_q32(0U), std::uint64_t{0x7FFFFFFFFFFFFFFFU});
  EXPECT_EQ(flight::rounded_reciprocal_q32(3U), 6148914691236517205U);  // 2^64 / 3 = ...205.33
}

TEST(ConstantDivisor, ZeroDivisorFallsBackToFxDiv) {
  const flight::ConstantDivisor<flight::LoadQ> zero = flight::make_divisor(flight::LoadQ::zero());
  EXPECT_EQ(zero.reciprocal, 0U);
  fx::Status st;
  EXPECT_EQ(flight::div_by_constant<WideQ>(flight::LoadQ::from_raw(5), zero, st), WideQ::max());
  EXPECT_TRUE(st.has(fx::Flag::div_by_zero));
}

/// The flight current against the oracle's within oracle::current_tolerance_a;
/// where one overflows Q11.20 the other must be within it of the limit.
void expect_current_near_oracle(const flight::CurrentResult& oracle_i, const flight::CurrentResult& flight_i,
                                const flight::MotorParams& m) {
  const double lsb = std::ldexp(1.0, -20);
  const double a = static_cast<double>(oracle_i.current_a.raw()) * lsb;
  const double b = static_cast<double>(flight_i.current_a.raw()) * lsb;
  const double allowed = oracle::current_tolerance_a(m, oracle_i.current_a);
  if (oracle_i.status == flight_i.status) {
    EXPECT_LE(std::fabs(a - b), allowed) << a << " " << b;
    return;
  }
  const double ok_value = (oracle_i.status == flight::EstimateStatus::ok) ? a : b;
  EXPECT_GE(std::fabs(ok_value), 2048.0 - allowed - lsb) << a << " " << b;
}

TEST(ConstantDivisor, PreparedCorrectionsEqualAndMotorIsWithinItsBoundOfTheDividingOracle) {
  for (const flight::ParameterTable& table : {flight::default_parameter_table(), flight::eq15_parameter_table()}) {
    const flight::CorrectionDivisors cd = flight::make_correction_divisors(table.correction);
    for (std::int32_t raw = -5; raw < (260 << 16); raw += 997) {
      const flight::WheelLoadN w = flight::WheelLoadN::from_raw(raw);
      const flight::CorrectionResult a = oracle::corrections_at(table.correction, w);
      const flight::CorrectionResult b = flight::corrections_at(table.correction, cd, w);
      ASSERT_EQ(a.status, b.status) << raw;
      ASSERT_EQ(a.clamp, b.clamp) << raw;
      ASSERT_EQ(a.coefficients.c1, b.coefficients.c1) << raw;
      ASSERT_EQ(a.coefficients.c2, b.coefficients.c2) << raw;
      ASSERT_EQ(a.coefficients.c3, b.coefficients.c3) << raw;
      ASSERT_EQ(a.dp_max_ratio, b.dp_max_ratio) << raw;
    }
    const flight::MotorDivisors md = flight::make_motor_divisors(table.motor);
    std::mt19937_64 rng(11U);
    for (int i = 0; i < 200000; ++i) {
      const flight::TorqueNm t = flight::TorqueNm::from_raw(random_raw<std::int32_t>(rng));
      const flight::DriveDirection dir = ((i & 1) != 0) ? flight::DriveDirection::reverse
                                                        : flight::DriveDirection::forward;
      const flight::CurrentResult a = oracle::current_from_torque(table.motor, t, dir);
      const flight::CurrentResult b = flight::current_from_torque(table.motor, md, t, dir);
      expect_current_near_oracle(a, b, table.motor);
    }
    const flight::CorrectionResult c = flight::corrections_at(table.correction, cd, flight::WheelLoadN::from_raw(90 << 16));
    const flight::CurrentLimitResult plain = oracle::current_limit(
        c, table.motor, table.wheel_radius_m, flight::WheelLoadN::from_raw(90 << 16), table.monitor.allowed_sinkage_m);
    const flight::CurrentLimitResult prepared =
        flight::current_limit(c, table.motor, md, table.wheel_radius_m, flight::WheelLoadN::from_raw(90 << 16),
                              table.monitor.allowed_sinkage_m);
    EXPECT_EQ(plain.status, flight::EstimateStatus::ok);
    EXPECT_EQ(prepared.status, flight::EstimateStatus::ok);
    EXPECT_EQ(plain.torque_limit_nm, prepared.torque_limit_nm);
    expect_current_near_oracle({plain.current_limit_a, plain.status}, {prepared.current_limit_a, prepared.status},
                               table.motor);
  }
}

TEST(ConstantDivisor, MotorReciprocalOfOtherMotorsIsWithinItsBoundOfTheDividingOracle) {
  // Random valid motors over the validated ranges (gear, eta, Kt).
  std::mt19937_64 rng(12U);
  flight::MotorParams m = flight::default_parameter_table().motor;
  for (int i = 0; i < 2000; ++i) {
    m.gear_ratio = flight::GearRatio::from_raw(static_cast<std::int32_t>((rng() % (10000U << 16U)) + 1U));
    m.efficiency = flight::Efficiency::from_raw(static_cast<std::int32_t>((rng() % 0x40000000U) + 1U));
    m.kt_nm_per_a = flight::TorqueConstantNmPerA::from_raw(static_cast<std::int32_t>((rng() % 0x7FFFFFFFU) + 1U));
    const flight::MotorDivisors md = flight::make_motor_divisors(m);
    for (int j = 0; j < 100; ++j) {
      const flight::TorqueNm t = flight::TorqueNm::from_raw(random_raw<std::int32_t>(rng));
      const flight::CurrentResult a = oracle::current_from_torque(m, t, flight::DriveDirection::forward);
      const flight::CurrentResult b = flight::current_from_torque(m, md, t, flight::DriveDirection::forward);
      expect_current_near_oracle(a, b, m);
    }
  }
}

}  // namespace
}  // namespace sinkwatch
