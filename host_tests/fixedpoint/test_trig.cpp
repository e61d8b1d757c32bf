// test_trig.cpp: worked examples and error paths of sin, cos, asin, acos and
// entry_angle, the wheel-sinkage example that motivates the 2 asin(sqrt(z /
// 2r)) form, and checks of the integer constants against long double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;
using fx::Q3_28;
using QInt32 = fx::Q<std::int32_t, 0>;
using QInt64 = fx::Q<std::int64_t, 0>;

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }
constexpr long double k_pi = 3.141592653589793238462643383279502884L;

/// Error of a result in LSB of its format against a long double value.
template <typename QT>
long double lsb_error(QT r, long double exact) {
  return static_cast<long double>(r.raw()) - std::ldexp(exact, QT::frac_bits);
}

// ---------------------------------------------------------------- constexpr

constexpr std::int32_t constexpr_cos0() {
  fx::Status s;
  return fx::cos(Q15_16::zero(), s).raw();
}
constexpr std::int32_t constexpr_asin1() {
  fx::Status s;
  return fx::asin(Q1_30::from_raw(1 << 30), s).raw();
}
constexpr std::int32_t constexpr_entry2() {
  fx::Status s;
  return fx::entry_angle(QInt32::from_raw(2), s).raw();
}
constexpr bool constexpr_asin_domain() {
  fx::Status s;
  const Q3_28 r = fx::asin(Q1_30::from_raw((1 << 30) + 1), s);
  return s.has(Flag::domain) && r.raw() == 0;
}
static_assert(constexpr_cos0() == (1 << 30), "cos(0) = 1 exactly, at compile time");
static_assert(constexpr_asin1() == 421657428, "asin(1) = round(pi/2 2^28) at compile time");
static_assert(constexpr_entry2() == 843314857, "theta1(z/r = 2) = round(pi 2^28) at compile time");
static_assert(constexpr_asin_domain(), "asin(1 + LSB) raises domain at compile time");

// ---------------------------------------------------------------- sin, cos

TEST(FxSinCos, ExactPoints) {
  fx::Status s;
  EXPECT_EQ(fx::sin(Q15_16::zero(), s).raw(), 0);
  EXPECT_EQ(fx::cos(Q15_16::zero(), s).raw(), 1 << 30);
  EXPECT_EQ(fx::sin(Q31_32::zero(), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxSinCos, WorkedExamplesWithinOneLsb) {
  fx::Status s;
  constexpr Q1_30 pi_6 = fx::constant<Q1_30>(0.52359877559829887);
  EXPECT_LE(std::fabs(lsb_error(fx::sin(pi_6, s), sinl(std::ldexp(static_cast<long double>(pi_6.raw()), -30)))), 1.0L);
  EXPECT_NEAR(static_cast<double>(fx::sin(pi_6, s).raw()), 536870912.0, 2.0);  // 0.5
  constexpr Q31_32 pi_3 = fx::constant<Q31_32>(1.0471975511965976);
  EXPECT_NEAR(static_cast<double>(fx::cos(pi_3, s).raw()), 536870912.0, 2.0);
  constexpr Q15_16 minus_pi_2 = fx::constant<Q15_16>(-1.5707963267948966);
  EXPECT_NEAR(static_cast<double>(fx::sin(minus_pi_2, s).raw()), -1073741824.0, 1.0);
  constexpr Q15_16 pi = fx::constant<Q15_16>(3.141592653589793);
  EXPECT_NEAR(static_cast<double>(fx::cos(pi, s).raw()), -1073741824.0, 1.0);
  EXPECT_TRUE(s.ok());
}

TEST(FxSinCos, TopOfEveryFormatDoesNotOverflow) {
  // The classic bug: cos(x) as sin(x + pi/2) overflows x + pi/2 at max.
  fx::Status s;
  const Q15_16 xs[] = {Q15_16::max(), Q15_16::min(), fx::neg(Q15_16::max(), s)};
  for (const Q15_16 x : xs) {
    const long double v = std::ldexp(static_cast<long double>(x.raw()), -16);
    EXPECT_LE(std::fabs(lsb_error(fx::sin(x, s), sinl(v))), 1.0L) << x.raw();
    EXPECT_LE(std::fabs(lsb_error(fx::cos(x, s), cosl(v))), 1.0L) << x.raw();
  }
  // An int64 angle is exact in long double only where it has 64 digits
  // (x86-64); elsewhere (ARM: long double is double) the reference would be
  // the sine of a different angle.
  const QInt64 big[] = {QInt64::max(), QInt64::min()};
  for (const QInt64 x : big) {
    if (std::numeric_limits<long double>::digits < 64) {
      break;
    }
    const long double v = static_cast<long double>(x.raw());
    EXPECT_LE(std::fabs(lsb_error(fx::sin(x, s), sinl(v))), 1.0L) << x.raw();
    EXPECT_LE(std::fabs(lsb_error(fx::cos(x, s), cosl(v))), 1.0L) << x.raw();
  }
  EXPECT_TRUE(s.ok());
}

TEST(FxSinCos, SymmetricBitForBit) {
  fx::Status s;
  for (std::int32_t raw : {1, 7, 12345, 102944, 205887, 411775, 2000000000}) {
    const Q15_16 x = Q15_16::from_raw(raw);
    const Q15_16 mx = fx::neg(x, s);
    EXPECT_EQ(fx::sin(mx, s).raw(), -fx::sin(x, s).raw()) << raw;
    EXPECT_EQ(fx::cos(mx, s).raw(), fx::cos(x, s).raw()) << raw;
  }
  EXPECT_TRUE(s.ok());
}

TEST(FxSinCos, NeverRaiseAndKeepEarlierFlags) {
  fx::Status s;
  s.raise(Flag::div_by_zero);
  static_cast<void>(fx::sin(Q15_16::max(), s));
  static_cast<void>(fx::cos(Q15_16::min(), s));
  EXPECT_EQ(s.bits(), only(Flag::div_by_zero));
}

// ---------------------------------------------------------------- asin, acos

TEST(FxAsinAcos, WorkedExamples) {
  fx::Status s;
  const Q1_30 one = Q1_30::from_raw(1 << 30);
  EXPECT_EQ(fx::asin(one, s).raw(), 421657428);                 // pi/2
  EXPECT_EQ(fx::asin(fx::neg(one, s), s).raw(), -421657428);
  EXPECT_EQ(fx::acos(one, s).raw(), 0);
  EXPECT_EQ(fx::acos(fx::neg(one, s), s).raw(), 843314857);     // pi
  EXPECT_EQ(fx::asin(Q1_30::zero(), s).raw(), 0);
  EXPECT_EQ(fx::acos(Q1_30::zero(), s).raw(), 421657428);
  const Q1_30 half = Q1_30::from_raw(1 << 29);
  EXPECT_LE(std::fabs(lsb_error(fx::asin(half, s), k_pi / 6.0L)), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::acos(half, s), k_pi / 3.0L)), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::acos(fx::neg(half, s), s), 2.0L * k_pi / 3.0L)), 1.0L);
  // Integer input: only -1, 0, 1 are in the domain.
  EXPECT_EQ(fx::asin(QInt32::from_raw(-1), s).raw(), -421657428);
  EXPECT_TRUE(s.ok());
}

TEST(FxAsinAcos, OneLsbInsideTheDomainIsAccurate) {
  fx::Status s;
  const Q1_30 below = Q1_30::from_raw((1 << 30) - 1);
  const long double v = std::ldexp(static_cast<long double>(below.raw()), -30);
  EXPECT_LE(std::fabs(lsb_error(fx::asin(below, s), asinl(v))), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::acos(below, s), acosl(v))), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::asin(fx::neg(below, s), s), -asinl(v))), 1.0L);
  EXPECT_TRUE(s.ok());
}

TEST(FxAsinAcos, OneLsbOutsideTheDomainIsReportedNotClamped) {
  const Q1_30 above = Q1_30::from_raw((1 << 30) + 1);
  const Q1_30 below = Q1_30::from_raw(-(1 << 30) - 1);
  for (const Q1_30 x : {above, below, Q1_30::max(), Q1_30::min()}) {
    fx::Status s1;
    EXPECT_EQ(fx::asin(x, s1).raw(), 0) << x.raw();
    EXPECT_EQ(s1.bits(), only(Flag::domain));
    fx::Status s2;
    EXPECT_EQ(fx::acos(x, s2).raw(), 0) << x.raw();
    EXPECT_EQ(s2.bits(), only(Flag::domain));
  }
  fx::Status s3;
  EXPECT_EQ(fx::asin(Q31_32::from_raw((std::int64_t{1} << 32) + 1), s3).raw(), 0);
  EXPECT_EQ(s3.bits(), only(Flag::domain));
  fx::Status s4;
  EXPECT_EQ(fx::acos(QInt32::from_raw(2), s4).raw(), 0);
  EXPECT_EQ(s4.bits(), only(Flag::domain));
}

// ---------------------------------------------------------------- entry angle

TEST(FxEntryAngle, EndsAndMiddle) {
  fx::Status s;
  using Q2_29 = fx::Q<std::int32_t, 29>;
  EXPECT_EQ(fx::entry_angle(Q2_29::zero(), s).raw(), 0);
  EXPECT_EQ(fx::entry_angle(Q2_29::from_raw(1 << 29), s).raw(), 421657428);  // z = r: pi/2
  EXPECT_EQ(fx::entry_angle(Q2_29::from_raw(1 << 30), s).raw(), 843314857);  // z = 2r: pi
  EXPECT_TRUE(s.ok());
}

TEST(FxEntryAngle, WheelExampleMatchesArccos) {
  // A 0.13 m wheel sunk 5 mm: theta1 = arccos(1 - 0.005/0.13) = 0.27808 rad.
  fx::Status s;
  constexpr Q15_16 z_m = fx::constant<Q15_16>(0.005);
  constexpr Q15_16 r_m = fx::constant<Q15_16>(0.13);
  const Q1_30 ratio = fx::div<Q1_30>(z_m, r_m, s);
  const Q3_28 theta1 = fx::entry_angle(ratio, s);
  EXPECT_TRUE(s.ok());
  const long double exact_ratio = std::ldexp(static_cast<long double>(ratio.raw()), -30);
  EXPECT_LE(std::fabs(lsb_error(theta1, acosl(1.0L - exact_ratio))), 1.0L);
  // Against the unrounded wheel: z and r rounded to Q15_16 move z/r by 4e-5
  // and theta1 by 3e-4 rad (d theta1 / d(z/r) = 1 / sin(theta1) = 3.6).
  EXPECT_NEAR(static_cast<double>(theta1.raw()) / 268435456.0, std::acos(1.0 - 0.005 / 0.13), 1e-3);
}

TEST(FxEntryAngle, StaysAccurateAtTinySinkageWhereOneMinusRatioLosesIt) {
  // z/r = 2^-32, the smallest Q31_32 ratio. 1 - z/r rounded into Q1_30 is
  // exactly 1 and arccos of it is 0; the entry angle keeps
  // 2 asin(sqrt(z / 2r)) = sqrt(2) 2^-16 = 2.16e-5 rad.
  fx::Status s;
  const Q31_32 ratio = Q31_32::lsb();
  const Q1_30 naive_y = fx::rescale<Q1_30>(fx::sub(Q31_32::from_raw(std::int64_t{1} << 32), ratio, s), s);
  EXPECT_EQ(naive_y.raw(), 1 << 30);
  EXPECT_EQ(fx::acos(naive_y, s).raw(), 0);
  const Q3_28 theta1 = fx::entry_angle(ratio, s);
  EXPECT_TRUE(s.ok());
  const long double exact = 2.0L * asinl(sqrtl(std::ldexp(1.0L, -33)));
  EXPECT_LE(std::fabs(lsb_error(theta1, exact)), 1.0L);
  EXPECT_EQ(theta1.raw(), 5793);  // 2.158e-5 rad * 2^28 = 5792.6
}

TEST(FxEntryAngle, OutsideZeroToTwoIsADomainError) {
  using Q2_29 = fx::Q<std::int32_t, 29>;
  for (const Q2_29 x : {Q2_29::from_raw(-1), Q2_29::from_raw((1 << 30) + 1), Q2_29::min(), Q2_29::max()}) {
    fx::Status s;
    EXPECT_EQ(fx::entry_angle(x, s).raw(), 0) << x.raw();
    EXPECT_EQ(s.bits(), only(Flag::domain));
  }
  fx::Status s2;
  EXPECT_EQ(fx::entry_angle(QInt32::from_raw(3), s2).raw(), 0);
  EXPECT_EQ(s2.bits(), only(Flag::domain));
}

// ---------------------------------------------------------------- atan2

TEST(FxAtan2, EveryAxisAndDiagonal) {
  fx::Status s;
  const Q15_16 one = Q15_16::from_raw(1 << 16);
  const Q15_16 m_one = Q15_16::from_raw(-(1 << 16));
  const Q15_16 zero = Q15_16::zero();
  EXPECT_EQ(fx::atan2(zero, one, s).raw(), 0);
  EXPECT_EQ(fx::atan2(one, zero, s).raw(), 421657428);    // pi/2
  EXPECT_EQ(fx::atan2(m_one, zero, s).raw(), -421657428);
  EXPECT_EQ(fx::atan2(zero, m_one, s).raw(), 843314857);  // pi, not -pi: the range is (-pi, pi]
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(one, one, s), k_pi / 4.0L)), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(m_one, m_one, s), -3.0L * k_pi / 4.0L)), 1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(one, m_one, s), 3.0L * k_pi / 4.0L)), 1.0L);
  EXPECT_EQ(fx::atan2(Q15_16::min(), Q15_16::min(), s), fx::atan2(m_one, m_one, s));
  // Just below the negative x axis: close to -pi, not +pi.
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(fx::neg(Q15_16::lsb(), s), Q15_16::min(), s),
                                atan2l(-1.0L, -2147483648.0L))), 1.0L);
  EXPECT_TRUE(s.ok());
}

TEST(FxAtan2, WideFormatsAndAttitudeExample) {
  fx::Status s;
  // Pitch from accelerometer components (m/s^2): atan2(1.2, 9.7) = 0.12313 rad.
  constexpr Q31_32 ax = fx::constant<Q31_32>(1.2);
  constexpr Q31_32 az = fx::constant<Q31_32>(9.7);
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(ax, az, s), atan2l(std::ldexp(static_cast<long double>(ax.raw()), -32),
                                                               std::ldexp(static_cast<long double>(az.raw()), -32)))),
            1.0L);
  EXPECT_LE(std::fabs(lsb_error(fx::atan2(QInt64::max(), QInt64::from_raw(1), s), atan2l(9223372036854775807.0L, 1.0L))), 1.0L);
  EXPECT_TRUE(s.ok());
}

TEST(FxAtan2, OriginIsADomainError) {
  fx::Status s;
  EXPECT_EQ(fx::atan2(Q15_16::zero(), Q15_16::zero(), s).raw(), 0);
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

// ---------------------------------------------------------------- constants

TEST(FxTrigConstants, MatchLongDouble) {
  namespace t = fx::detail::trig;
  // 1/(2 pi): as many leading bits of the 128-bit constant as long double
  // can check (60 on x86-64; 49 where long double is double, as on ARM).
  const int bits = std::min(std::numeric_limits<long double>::digits - 4, 60);
  const std::uint64_t top64 = (static_cast<std::uint64_t>(t::k_inv_two_pi[0]) << 32U) | t::k_inv_two_pi[1];
  const long double inv = std::ldexp(1.0L / (2.0L * k_pi), bits);
  EXPECT_LE(std::fabs(static_cast<long double>(top64 >> static_cast<unsigned>(64 - bits)) - inv), 1.0L);
  EXPECT_LE(std::fabs(static_cast<long double>(t::k_half_pi_q32) - std::ldexp(k_pi / 2.0L, 32)), 0.5L);
  // sin and cos Taylor coefficients (pi/4)^k / k!, rounded to 32 bits.
  long double term = 1.0L;  // (pi/4)^k / k!
  for (int k = 1; k <= 12; ++k) {
    term *= (k_pi / 4.0L) / static_cast<long double>(k);
    const int i = (k - 1) / 2;
    if (k % 2 == 1) {
      EXPECT_LE(std::fabs(static_cast<long double>(t::k_sin_a[i]) - std::ldexp(term, 32 + static_cast<int>(t::k_sin_shift[i]))), 0.5L) << k;
    } else {
      const int j = k / 2 - 1;
      EXPECT_LE(std::fabs(static_cast<long double>(t::k_cos_b[j]) - std::ldexp(term, 32 + static_cast<int>(t::k_cos_shift[j]))), 0.5L) << k;
    }
  }
  // asin Taylor coefficients C(2n, n) / (4^n (2n + 1)).
  long double central = 1.0L;  // C(2n, n) / 4^n
  for (int n = 1; n <= 12; ++n) {
    central *= static_cast<long double>(2 * n - 1) / static_cast<long double>(2 * n);
    const long double c = central / static_cast<long double>(2 * n + 1);
    EXPECT_LE(std::fabs(static_cast<long double>(t::k_asin_c[n - 1]) - std::ldexp(c, 32)), 0.5L) << n;
  }
}

}  // namespace

namespace {

// ---------------------------------------------------------------- same bits everywhere

/// FNV-1a over the raw results of a sweep of every trig function (and sqrt,
/// div for the 64- and 128-bit paths). The expected hash was computed on the
/// x86-64 host; the arm-linux build runs this same test under qemu-arm, so a
/// target that computes one bit differently fails here.
std::uint64_t sweep_hash() {
  std::uint64_t h = 14695981039346656037ULL;
  auto mix = [&h](std::int64_t v) {
    for (int byte = 0; byte < 8; ++byte) {
      h ^= (static_cast<std::uint64_t>(v) >> (8 * byte)) & 0xFFU;
      h *= 1099511628211ULL;
    }
  };
  fx::Status s;
  for (std::int32_t k = -(1 << 14); k <= (1 << 14); ++k) {
    const Q15_16 angle = Q15_16::from_raw(k * 127 + 3);
    mix(fx::sin(angle, s).raw());
    mix(fx::cos(angle, s).raw());
    const Q31_32 wide_angle = Q31_32::from_raw(static_cast<std::int64_t>(k) * 0x12345678901LL);
    mix(fx::sin(wide_angle, s).raw());
    const Q1_30 x = Q1_30::from_raw(k * 65535);
    mix(fx::asin(x, s).raw());
    mix(fx::acos(x, s).raw());
    mix(fx::entry_angle(fx::Q<std::int32_t, 29>::from_raw((k + (1 << 14)) * 32767), s).raw());
    mix(fx::sqrt(Q31_32::from_raw(static_cast<std::int64_t>(k + (1 << 14)) * 0x7654321ABCLL), s).raw());
    mix(fx::atan2(angle, Q15_16::from_raw(k * 3 - 7), s).raw());
    mix(fx::atan2(wide_angle, Q31_32::from_raw(0x123456789LL), s).raw());
    mix(fx::div(Q31_32::from_raw(static_cast<std::int64_t>(k) * 0x123456789LL), Q31_32::from_raw(0x2345678901LL), s).raw());
  }
  mix(s.bits());
  return h;
}

TEST(FxGolden, SameBitsOnEveryTarget) {
  EXPECT_EQ(sweep_hash(), 1888557263652701335ULL);
}

}  // namespace
