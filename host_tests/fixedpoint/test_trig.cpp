// test_trig.cpp: worked examples and error paths of sin, cos, asin, acos and
// entry_angle, the wheel-sinkage example that motivates the 2 asin(sqrt(z /
// 2r)) form, checks of the integer constants against long double, and the
// sine and cosine kernels against their round-12 forms kept verbatim as an
// oracle (every cheaper form must give the same bits).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "sinkwatch/fixedpoint/bounded.hpp"
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

// ------------------------------------------- round-12 kernels, the oracle
//
// The reduction, square and kernels of sin, cos and sincos as they were
// before the word-sized forms (round 13), kept verbatim: every product 64
// bits wide, mul_round_by's rounding on 64 bits. The current forms must give
// the same bits for every input the kernels can receive.
namespace kernels_by_64_bit_products {

namespace t = fx::detail::trig;
namespace wide = fx::wide;

template <std::uint32_t Shift>
constexpr std::uint64_t mul_round_by(std::uint32_t a, std::uint32_t b) noexcept {
  static_assert((Shift >= 1U) && (Shift <= 63U), "a rounding shift of 1 to 63 bits");
  return (wide::mul_32x32_64(a, b) + (std::uint64_t{1U} << (Shift - 1U))) >> Shift;
}

constexpr std::uint32_t word(std::uint64_t v) noexcept { return static_cast<std::uint32_t>(v); }

template <std::int32_t F, std::int32_t J, std::int32_t I>
constexpr std::uint64_t turn_part(std::uint32_t limb) noexcept {
  constexpr std::int32_t s = (32 + (32 * (J - I))) - F;
  if constexpr ((s < 64) && (s > -64)) {
    const std::uint64_t p = wide::mul_32x32_64(limb, t::k_inv_two_pi[I]);
    if constexpr (s >= 0) {
      return p << static_cast<std::uint32_t>(s);
    } else {
      return p >> static_cast<std::uint32_t>(-s);
    }
  } else {
    return 0U;
  }
}

template <std::int32_t F, std::int32_t J>
constexpr std::uint64_t turn_parts(std::uint32_t limb) noexcept {
  return turn_part<F, J, 0>(limb) + turn_part<F, J, 1>(limb) + turn_part<F, J, 2>(limb) + turn_part<F, J, 3>(limb);
}

template <std::int32_t F>
constexpr std::uint64_t turns(std::uint64_t m) noexcept {
  const std::uint32_t low = word(m & 0xFFFFFFFFU);
  const std::uint32_t high = word(m >> 32U);
  const std::uint64_t from_high = (high != 0U) ? turn_parts<F, 1>(high) : 0U;
  return turn_parts<F, 0>(low) + from_high;
}

struct Reduced {
  std::uint32_t quadrant;
  bool negative;
  std::uint64_t m;
};

constexpr Reduced reduce(std::uint64_t turn_fraction) noexcept {
  const std::uint64_t eighth = std::uint64_t{1U} << 61U;
  const std::uint64_t u = turn_fraction + eighth;
  const std::uint32_t quadrant = static_cast<std::uint32_t>(u >> 62U);
  const std::uint64_t g = u & ((std::uint64_t{1U} << 62U) - 1U);
  if (g >= eighth) {
    return Reduced{quadrant, false, g - eighth};
  }
  return Reduced{quadrant, true, eighth - g};
}

constexpr std::uint64_t square_q31(std::uint64_t m) noexcept {
  const std::uint64_t m_hi = m >> 30U;
  const std::uint64_t m_lo = m & 0x3FFFFFFFU;
  const std::uint64_t sum = wide::mul_32x32_64(word(m_hi), word(m_hi)) + (wide::mul_32x32_64(word(m_hi), word(m_lo)) >> 29U);
  return (sum + (std::uint64_t{1U} << 30U)) >> 31U;
}

constexpr std::uint64_t sin_kernel(std::uint64_t m, std::uint64_t w) noexcept {
  const std::uint32_t w32 = word(w);
  std::uint64_t b = t::k_sin_a[5];
  b = t::k_sin_a[4] - mul_round_by<(31U + t::k_sin_shift[5]) - t::k_sin_shift[4]>(w32, word(b));
  b = t::k_sin_a[3] - mul_round_by<(31U + t::k_sin_shift[4]) - t::k_sin_shift[3]>(w32, word(b));
  b = t::k_sin_a[2] - mul_round_by<(31U + t::k_sin_shift[3]) - t::k_sin_shift[2]>(w32, word(b));
  b = t::k_sin_a[1] - mul_round_by<(31U + t::k_sin_shift[2]) - t::k_sin_shift[1]>(w32, word(b));
  b = t::k_sin_a[0] - mul_round_by<(31U + t::k_sin_shift[1]) - t::k_sin_shift[0]>(w32, word(b));
  const std::uint64_t m_hi = m >> 30U;
  const std::uint64_t m_lo = m & 0x3FFFFFFFU;
  const std::uint64_t tt = wide::mul_32x32_64(word(m_hi), word(b)) + (wide::mul_32x32_64(word(m_lo), word(b)) >> 30U);
  return (tt + (std::uint64_t{1U} << 32U)) >> 33U;
}

constexpr std::uint64_t cos_kernel(std::uint64_t w) noexcept {
  const std::uint32_t w32 = word(w);
  std::uint64_t b = t::k_cos_b[5];
  b = t::k_cos_b[4] - mul_round_by<(31U + t::k_cos_shift[5]) - t::k_cos_shift[4]>(w32, word(b));
  b = t::k_cos_b[3] - mul_round_by<(31U + t::k_cos_shift[4]) - t::k_cos_shift[3]>(w32, word(b));
  b = t::k_cos_b[2] - mul_round_by<(31U + t::k_cos_shift[3]) - t::k_cos_shift[2]>(w32, word(b));
  b = t::k_cos_b[1] - mul_round_by<(31U + t::k_cos_shift[2]) - t::k_cos_shift[1]>(w32, word(b));
  b = t::k_cos_b[0] - mul_round_by<(31U + t::k_cos_shift[1]) - t::k_cos_shift[0]>(w32, word(b));
  return (std::uint64_t{1U} << 30U) - mul_round_by<34U>(w32, word(b));
}

constexpr bool sin_negative(const Reduced& r, bool angle_negative) noexcept {
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  const bool negative = odd_quadrant ? (r.quadrant == 3U) : (r.negative != (r.quadrant == 2U));
  return negative != angle_negative;
}

constexpr bool cos_negative(const Reduced& r) noexcept {
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  return odd_quadrant ? (r.negative != (r.quadrant == 1U)) : (r.quadrant == 2U);
}

constexpr std::int32_t signed_raw(bool negative, std::uint64_t mag) noexcept {
  const std::int32_t v = static_cast<std::int32_t>(mag);
  return negative ? -v : v;
}

/// fx::sincos's raw sine and cosine as they were.
template <typename S, std::int32_t F>
std::pair<std::int32_t, std::int32_t> sincos(fx::Q<S, F> angle) noexcept {
  const Reduced r = reduce(turns<F>(fx::detail::magnitude(angle.raw())));
  const std::uint64_t w = square_q31(r.m);
  const std::uint64_t sin_r = sin_kernel(r.m, w);
  const std::uint64_t cos_r = cos_kernel(w);
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  return {signed_raw(sin_negative(r, angle.raw() < 0), odd_quadrant ? cos_r : sin_r),
          signed_raw(cos_negative(r), odd_quadrant ? sin_r : cos_r)};
}

}  // namespace kernels_by_64_bit_products

namespace old = kernels_by_64_bit_products;

/// m in [0, 2^61], the reduced residual the kernels receive: the ends, the
/// powers of two and their neighbours, then uniform draws.
std::vector<std::uint64_t> residual_edges() {
  std::vector<std::uint64_t> out{0U, 1U, 2U, (std::uint64_t{1U} << 61U), (std::uint64_t{1U} << 61U) - 1U};
  for (std::uint32_t k = 0U; k < 61U; ++k) {
    const std::uint64_t p = std::uint64_t{1U} << k;
    out.push_back(p);
    out.push_back(p + 1U);
    out.push_back(p - 1U);
    out.push_back((std::uint64_t{1U} << 61U) - p);
  }
  // The borders of the m_hi / m_lo split at 2^30.
  for (std::uint64_t hi = 0U; hi < 4U; ++hi) {
    out.push_back((hi << 30U) | 0x3FFFFFFFU);
    out.push_back(((std::uint64_t{0x7FFFFFFFU} - hi) << 30U) | 0x3FFFFFFFU);
  }
  return out;
}

/// The rounding of the high word against the 64-bit rounding, for one shift.
template <std::uint32_t Shift>
bool round_high_matches(std::uint32_t a, std::uint32_t b) {
  return fx::detail::trig::mul_round_high<Shift>(a, b) == old::mul_round_by<Shift>(a, b);
}

/// ... for every shift the kernels use, and the ends.
bool round_high_matches_all(std::uint32_t a, std::uint32_t b) {
  return round_high_matches<33U>(a, b) && round_high_matches<34U>(a, b) && round_high_matches<35U>(a, b) &&
         round_high_matches<36U>(a, b) && round_high_matches<37U>(a, b) && round_high_matches<38U>(a, b) &&
         round_high_matches<39U>(a, b) && round_high_matches<63U>(a, b);
}

TEST(FxTrigKernels, RoundingOnTheHighWordIsTheRoundingOnSixtyFourBits) {
  std::mt19937_64 rng(151U);
  for (std::uint32_t i = 0U; i < 1000000U; ++i) {
    const std::uint64_t r = rng();
    const auto a = static_cast<std::uint32_t>(r) >> 1U;  // a < 2^31
    const auto b = static_cast<std::uint32_t>(r >> 32U);
    ASSERT_TRUE(round_high_matches_all(a, b)) << a << " " << b;
  }
  // a = 2^31 (w at v = 1), and products at and beside a rounding boundary:
  // 2^31 b = k 2^Shift +- 2^(Shift - 1).
  const std::uint32_t bs[] = {0U, 1U, 3U, 4U, 5U, 0xBFU, 0xC0U, 0xC1U, 0x7FFFFFFFU, 0xFFFFFFFFU};
  for (const std::uint32_t b : bs) {
    ASSERT_TRUE(round_high_matches_all(0x80000000U, b)) << b;
    ASSERT_TRUE(round_high_matches_all(0x7FFFFFFFU, b)) << b;
  }
}

TEST(FxTrigKernels, SameBitsAsTheSixtyFourBitKernelsOverTheWholeDomain) {
  namespace t = fx::detail::trig;
  std::vector<std::uint64_t> ms = residual_edges();
  std::mt19937_64 rng(61U);
  for (std::uint32_t i = 0U; i < 3000000U; ++i) {
    ms.push_back(rng() % ((std::uint64_t{1U} << 61U) + 1U));
  }
  for (const std::uint64_t m : ms) {
    const std::uint64_t w_old = old::square_q31(m);
    const std::uint32_t w = t::square_q31(m);
    ASSERT_EQ(w, w_old) << m;
    ASSERT_EQ(t::sin_kernel(m, w), old::sin_kernel(m, w_old)) << m;
    ASSERT_EQ(t::cos_kernel(w), old::cos_kernel(w_old)) << m;
  }
  // Every w <= 2^31 the square can give, strided, and its ends: the
  // polynomials depend on w alone.
  for (std::uint64_t w = 0U; w <= (std::uint64_t{1U} << 31U); w += 997U) {
    ASSERT_EQ(t::cos_kernel(static_cast<std::uint32_t>(w)), old::cos_kernel(w)) << w;
    ASSERT_EQ(t::sin_kernel(std::uint64_t{1U} << 61U, static_cast<std::uint32_t>(w)),
              old::sin_kernel(std::uint64_t{1U} << 61U, w))
        << w;
  }
  for (std::uint64_t w = (std::uint64_t{1U} << 31U) - 4096U; w <= (std::uint64_t{1U} << 31U); ++w) {
    ASSERT_EQ(t::cos_kernel(static_cast<std::uint32_t>(w)), old::cos_kernel(w)) << w;
  }
}

/// fx::sincos, fx::sin and fx::cos against the round-12 composition for one
/// angle.
template <typename S, std::int32_t F>
bool sincos_matches(fx::Q<S, F> angle) {
  fx::Status s;
  const fx::SinCos now = fx::sincos(angle, s);
  const auto was = old::sincos(angle);
  return (now.sin.raw() == was.first) && (now.cos.raw() == was.second) && (fx::sin(angle, s).raw() == was.first) &&
         (fx::cos(angle, s).raw() == was.second) && s.ok();
}

TEST(FxTrigKernels, SinCosSameBitsAsTheSixtyFourBitFormsInEveryFormat) {
  const std::int32_t edges32[] = {0, 1, -1, 2, std::numeric_limits<std::int32_t>::max(),
                                  std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min() + 1,
                                  421657428, 421657429, 843314857, -843314857, 210828714, 1686629713};
  for (const std::int32_t raw : edges32) {
    ASSERT_TRUE(sincos_matches(Q3_28::from_raw(raw))) << raw;
    ASSERT_TRUE(sincos_matches(Q15_16::from_raw(raw))) << raw;
    ASSERT_TRUE(sincos_matches(Q1_30::from_raw(raw))) << raw;
    ASSERT_TRUE(sincos_matches(QInt32::from_raw(raw))) << raw;
  }
  const std::int64_t edges64[] = {0, 1, -1, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min(),
                                  std::numeric_limits<std::int64_t>::min() + 1, 0x100000000LL, 0xFFFFFFFFLL};
  for (const std::int64_t raw : edges64) {
    ASSERT_TRUE(sincos_matches(Q31_32::from_raw(raw))) << raw;
    ASSERT_TRUE(sincos_matches(QInt64::from_raw(raw))) << raw;
  }
  std::mt19937_64 rng(28U);
  for (std::uint32_t i = 0U; i < 1000000U; ++i) {
    const std::uint64_t r = rng();
    const auto raw32 = static_cast<std::int32_t>(static_cast<std::uint32_t>(r));
    ASSERT_TRUE(sincos_matches(Q3_28::from_raw(raw32))) << raw32;
    if ((i % 8U) == 0U) {
      ASSERT_TRUE(sincos_matches(Q15_16::from_raw(raw32))) << raw32;
      ASSERT_TRUE(sincos_matches(Q31_32::from_raw(static_cast<std::int64_t>(r)))) << r;
      // Small 64-bit angles, whose high limb is zero or small.
      ASSERT_TRUE(sincos_matches(Q31_32::from_raw(static_cast<std::int64_t>(r >> 28U) - (std::int64_t{1} << 35U)))) << r;
    }
  }
  // Every Q3.28 angle of the rover's range, strided: |angle| <= pi/2.
  for (std::int32_t raw = -421657429; raw <= 421657429; raw += 4093) {
    ASSERT_TRUE(sincos_matches(Q3_28::from_raw(raw))) << raw;
  }
}

// ------------------------------------------- sincos of a bounded angle
//
// fx::sincos of an fx::Bounded angle reduces with two products and two
// quadrants; it must give the bits of fx::sincos of the same angle for every
// angle within its bound.

namespace near {

namespace t = fx::detail::trig;

/// The rover's bounds (flight/src/wheel_load.cpp: a joint, the attitude, the
/// sum of two joints) and the largest bound the bounded form accepts.
constexpr std::uint32_t kJoint = 214748365U;
constexpr std::uint32_t kAttitude = 281857229U;
constexpr std::uint32_t kJointSum = 429496730U;
constexpr std::uint32_t kLimit28 = static_cast<std::uint32_t>(t::k_near_limit<28>);

/// The bounded sincos of raw against fx::sincos of the same Q3.28 angle.
template <std::uint32_t M>
bool matches(std::int32_t raw) {
  fx::Status s;
  const fx::SinCos bounded = fx::sincos(fx::Bounded<Q3_28, M>::trusted(raw), s);
  const fx::SinCos full = fx::sincos(Q3_28::from_raw(raw), s);
  return (bounded.sin == full.sin) && (bounded.cos == full.cos) && s.ok();
}

/// The smallest magnitude whose turn fraction reaches `turn` (2^-64 units).
std::int32_t first_reaching(std::uint64_t turn) {
  std::uint32_t lo = 0U;
  std::uint32_t hi = kLimit28;
  while (lo < hi) {
    const std::uint32_t mid = lo + ((hi - lo) / 2U);
    if (t::near_turns<28>(mid) >= turn) {
      hi = mid;
    } else {
      lo = mid + 1U;
    }
  }
  return static_cast<std::int32_t>(lo);
}

/// Every edge of the bounded range: zero, the bounds, multiples of pi/4 and
/// the raw angles where the turn fraction crosses 1/8 and 1/4 turn (the
/// quadrant's and the cosine's sign's edges), each with its neighbours and
/// both signs.
std::vector<std::int32_t> edges() {
  std::vector<std::int32_t> centres{0,
                                    static_cast<std::int32_t>(kJoint),
                                    static_cast<std::int32_t>(kAttitude),
                                    static_cast<std::int32_t>(kJointSum),
                                    static_cast<std::int32_t>(kLimit28),
                                    210828714,  // pi/4
                                    421657428,  // pi/2
                                    first_reaching(std::uint64_t{1U} << 61U),
                                    first_reaching(std::uint64_t{1U} << 62U)};
  std::vector<std::int32_t> out;
  for (const std::int32_t c : centres) {
    for (std::int32_t d = -4; d <= 4; ++d) {
      const std::int32_t raw = c + d;
      if ((raw >= 0) && (raw <= static_cast<std::int32_t>(kLimit28))) {
        out.push_back(raw);
        out.push_back(-raw);
      }
    }
  }
  return out;
}

}  // namespace near

TEST(FxSinCosBounded, TurnFractionIsTheFullReductionsBelowItsLimit) {
  namespace t = fx::detail::trig;
  std::mt19937_64 rng(2015U);
  for (std::uint32_t i = 0U; i < 1000000U; ++i) {
    const auto limb = static_cast<std::uint32_t>(rng() % (std::uint64_t{near::kLimit28} + 1U));
    ASSERT_EQ(t::near_turns<28>(limb), t::angle_turns<28>(static_cast<std::int32_t>(limb))) << limb;
  }
  ASSERT_EQ(t::near_turns<28>(near::kLimit28), t::angle_turns<28>(static_cast<std::int32_t>(near::kLimit28)));
  // One past the limit the third product is one unit: the forms part.
  ASSERT_NE(t::near_turns<28>(near::kLimit28 + 1U), t::angle_turns<28>(static_cast<std::int32_t>(near::kLimit28 + 1U)));
  // Q15.16 and Q1.30 (s = 16 and 2) at their limits and every 4099th limb.
  for (std::uint64_t limb = 0U; limb <= t::k_near_limit<16>; limb += 1U) {
    ASSERT_EQ(t::near_turns<16>(static_cast<std::uint32_t>(limb)), t::angle_turns<16>(static_cast<std::int32_t>(limb)));
  }
  for (std::uint64_t limb = 0U; limb <= 0x7FFFFFFFU; limb += 4099U) {
    ASSERT_EQ(t::near_turns<30>(static_cast<std::uint32_t>(limb)), t::angle_turns<30>(static_cast<std::int32_t>(limb)));
  }
}

TEST(FxSinCosBounded, ReductionIsTheFullReductionsBelowThreeEighthsOfATurn) {
  namespace t = fx::detail::trig;
  const std::uint64_t eighth = std::uint64_t{1U} << 61U;
  std::vector<std::uint64_t> us{0U, 1U, eighth - 1U, eighth, eighth + 1U, 2U * eighth - 1U, 2U * eighth, 2U * eighth + 1U,
                                3U * eighth - 1U};
  std::mt19937_64 rng(38U);
  for (std::uint32_t i = 0U; i < 1000000U; ++i) {
    us.push_back(rng() % (3U * eighth));
  }
  for (const std::uint64_t u : us) {
    const t::NearReduced near_r = t::reduce_near(u);
    const t::Reduced r = t::reduce(u);
    ASSERT_EQ(near_r.m, r.m) << u;
    ASSERT_EQ(near_r.odd_quadrant, (r.quadrant & 1U) != 0U) << u;
    ASSERT_EQ(near_r.beyond_half_pi, t::cos_negative(r)) << u;
    ASSERT_FALSE(t::sin_negative(r, false)) << u;
    ASSERT_TRUE(t::sin_negative(r, true)) << u;
  }
}

TEST(FxSinCosBounded, SameBitsAsSinCosAtEveryEdgeAndRandomAngles) {
  for (const std::int32_t raw : near::edges()) {
    ASSERT_TRUE(near::matches<near::kLimit28>(raw)) << raw;
    if ((raw <= static_cast<std::int32_t>(near::kJointSum)) && (raw >= -static_cast<std::int32_t>(near::kJointSum))) {
      ASSERT_TRUE(near::matches<near::kJointSum>(raw)) << raw;
    }
  }
  std::mt19937_64 rng(1600U);
  const std::uint64_t span = (2U * std::uint64_t{near::kLimit28}) + 1U;
  for (std::uint32_t i = 0U; i < 2000000U; ++i) {
    const std::int32_t raw = static_cast<std::int32_t>(rng() % span) - static_cast<std::int32_t>(near::kLimit28);
    ASSERT_TRUE(near::matches<near::kLimit28>(raw)) << raw;
  }
  // The rover's bounds, as wheel_load.cpp instantiates them, at their ends.
  for (std::int32_t d = 0; d <= 2; ++d) {
    ASSERT_TRUE(near::matches<near::kJoint>(static_cast<std::int32_t>(near::kJoint) - d));
    ASSERT_TRUE(near::matches<near::kJoint>(d - static_cast<std::int32_t>(near::kJoint)));
    ASSERT_TRUE(near::matches<near::kAttitude>(static_cast<std::int32_t>(near::kAttitude) - d));
    ASSERT_TRUE(near::matches<near::kAttitude>(d - static_cast<std::int32_t>(near::kAttitude)));
  }
  // Other formats: Q1.30 over its whole range but INT32_MIN (below 2 rad),
  // Q15.16 to its limit.
  for (std::int64_t raw = -0x7FFFFFFF; raw <= 0x7FFFFFFF; raw += 65521) {
    fx::Status s;
    const auto r32 = static_cast<std::int32_t>(raw);
    const fx::SinCos b = fx::sincos(fx::Bounded<Q1_30, 0x7FFFFFFFU>::trusted(r32), s);
    const fx::SinCos f = fx::sincos(Q1_30::from_raw(r32), s);
    ASSERT_TRUE((b.sin == f.sin) && (b.cos == f.cos)) << raw;
  }
  constexpr auto kLimit16 = static_cast<std::uint32_t>(fx::detail::trig::k_near_limit<16>);
  for (std::int32_t raw = -static_cast<std::int32_t>(kLimit16); raw <= static_cast<std::int32_t>(kLimit16); ++raw) {
    fx::Status s;
    const fx::SinCos b = fx::sincos(fx::Bounded<Q15_16, kLimit16>::trusted(raw), s);
    const fx::SinCos f = fx::sincos(Q15_16::from_raw(raw), s);
    ASSERT_TRUE((b.sin == f.sin) && (b.cos == f.cos)) << raw;
  }
}

// Every Q3.28 angle the bounded form accepts, |raw| <= k_near_limit<28>
// (2.015 rad; the rover's angles are within 1.6 rad): 1.08 10^9 angles, a
// few minutes on one core, so disabled by default. Run it with
//   test_fixedpoint_trig --gtest_also_run_disabled_tests
//     --gtest_filter='*EveryAngleWithinItsLimit*'
// (docs/fixedpoint.md quotes its result).
TEST(FxSinCosBounded, DISABLED_SameBitsAsSinCosForEveryAngleWithinItsLimit) {
  const auto limit = static_cast<std::int32_t>(near::kLimit28);
  std::uint64_t differing = 0U;
  for (std::int32_t raw = -limit;; ++raw) {
    differing += near::matches<near::kLimit28>(raw) ? 0U : 1U;
    if (raw == limit) {
      break;
    }
  }
  EXPECT_EQ(differing, 0U);
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
