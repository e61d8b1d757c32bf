// test_q.cpp: worked examples and every error path of the core Q operations
// (add, sub, neg, abs, min, max, clamp, from_int, rescale, mul, div) and of
// the sticky Status; constexpr evaluation checked with static_assert.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;
using QInt32 = fx::Q<std::int32_t, 0>;

constexpr std::int32_t k_one = 1 << 16;  // 1.0 in Q15_16

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

Q15_16 q(std::int32_t raw) { return Q15_16::from_raw(raw); }

// ---------------------------------------------------------------- constexpr

constexpr std::int32_t constexpr_mul() {
  fx::Status s;
  return fx::mul(Q15_16::from_raw(3 * k_one / 2), Q15_16::from_raw(-9 * k_one / 4), s).raw();
}
constexpr std::int32_t constexpr_div() {
  fx::Status s;
  return fx::div(Q15_16::from_raw(k_one), Q15_16::from_raw(3 * k_one), s).raw();
}
constexpr bool constexpr_overflow_flag() {
  fx::Status s;
  const Q15_16 r = fx::add(Q15_16::max(), Q15_16::lsb(), s);
  return s.has(Flag::overflow) && r == Q15_16::max();
}
constexpr std::int64_t constexpr_wide_mul() {
  fx::Status s;
  return fx::mul(Q31_32::from_raw(std::int64_t{3} << 31), Q31_32::from_raw(-(std::int64_t{5} << 32)), s).raw();
}
static_assert(constexpr_mul() == -27 * k_one / 8, "1.5 * -2.25 = -3.375 at compile time");
static_assert(constexpr_div() == 21845, "1/3 rounds to 21845 / 65536 at compile time");
static_assert(constexpr_overflow_flag(), "overflow reported at compile time");
static_assert(constexpr_wide_mul() == -(std::int64_t{15} << 31), "1.5 * -5 = -7.5 in Q31_32 at compile time");

// ---------------------------------------------------------------- from_int, one

TEST(FxFromInt, ExactInsideTheRange) {
  fx::Status s;
  EXPECT_EQ(Q15_16::from_int(3, s).raw(), 3 * k_one);
  EXPECT_EQ(Q15_16::from_int(-32768, s), Q15_16::min());
  EXPECT_EQ(Q1_30::one(s).raw(), 1 << 30);
  EXPECT_EQ(QInt32::from_int(std::numeric_limits<std::int32_t>::max(), s), QInt32::max());
  EXPECT_TRUE(s.ok());
}

TEST(FxFromInt, SaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(Q15_16::from_int(32768, s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(Q15_16::from_int(-32769, s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(Q31_32::from_int(std::numeric_limits<std::int64_t>::min(), s3), Q31_32::min());
  EXPECT_TRUE(s3.has(Flag::overflow));
}

// ---------------------------------------------------------------- add, sub

TEST(FxAddSub, WorkedExample) {
  fx::Status s;
  EXPECT_EQ(fx::add(q(3 * k_one / 2), q(9 * k_one / 4), s).raw(), 15 * k_one / 4);
  EXPECT_EQ(fx::sub(q(3 * k_one / 2), q(9 * k_one / 4), s).raw(), -3 * k_one / 4);
  EXPECT_EQ(fx::add(Q15_16::min(), Q15_16::max(), s).raw(), -1);
  EXPECT_TRUE(s.ok());
}

TEST(FxAddSub, OverflowSaturatesUpward) {
  fx::Status s1;
  EXPECT_EQ(fx::add(Q15_16::max(), Q15_16::lsb(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::sub(Q15_16::max(), q(-1), s2), Q15_16::max());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::sub(Q31_32::zero(), Q31_32::min(), s3), Q31_32::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

TEST(FxAddSub, OverflowSaturatesDownward) {
  fx::Status s1;
  EXPECT_EQ(fx::add(Q15_16::min(), q(-1), s1), Q15_16::min());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::sub(Q15_16::min(), Q15_16::lsb(), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::add(Q31_32::min(), Q31_32::min(), s3), Q31_32::min());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

// ---------------------------------------------------------------- neg, abs, min, max, clamp

TEST(FxNegAbs, MostNegativeValueSaturatesToMax) {
  fx::Status s1;
  EXPECT_EQ(fx::neg(Q15_16::min(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::abs(Q15_16::min(), s2), Q15_16::max());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::abs(Q31_32::min(), s3), Q31_32::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

TEST(FxNegAbs, EverythingElseIsExact) {
  fx::Status s;
  EXPECT_EQ(fx::neg(Q15_16::max(), s).raw(), std::numeric_limits<std::int32_t>::min() + 1);
  EXPECT_EQ(fx::neg(q(5), s).raw(), -5);
  EXPECT_EQ(fx::abs(q(-5), s).raw(), 5);
  EXPECT_EQ(fx::abs(Q15_16::zero(), s).raw(), 0);
  EXPECT_EQ(fx::abs(fx::neg(Q15_16::max(), s), s), Q15_16::max());
  EXPECT_TRUE(s.ok());
}

TEST(FxMinMaxClamp, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::min(q(-3), q(2)).raw(), -3);
  EXPECT_EQ(fx::max(q(-3), q(2)).raw(), 2);
  EXPECT_EQ(fx::clamp(q(7), q(-2), q(5), s).raw(), 5);
  EXPECT_EQ(fx::clamp(q(-7), q(-2), q(5), s).raw(), -2);
  EXPECT_EQ(fx::clamp(q(1), q(-2), q(5), s).raw(), 1);
  EXPECT_EQ(fx::clamp(q(1), q(1), q(1), s).raw(), 1);
  EXPECT_TRUE(s.ok());
}

TEST(FxMinMaxClamp, LoAboveHiIsReportedNotGuessed) {
  fx::Status s;
  EXPECT_EQ(fx::clamp(q(0), q(5), q(-2), s).raw(), 5);
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

// ---------------------------------------------------------------- rescale

TEST(FxRescale, WideningIsExact) {
  fx::Status s;
  EXPECT_EQ(fx::rescale<Q31_32>(q(-3 * k_one / 2), s).raw(), -(std::int64_t{3} << 31));
  EXPECT_EQ(fx::rescale<Q31_32>(Q15_16::min(), s).raw(), -(std::int64_t{32768} << 32));
  EXPECT_TRUE(s.ok());
}

TEST(FxRescale, NarrowingRoundsHalfAwayFromZeroSymmetrically) {
  using Q16_15 = fx::Q<std::int32_t, 15>;
  fx::Status s;
  // raw 3 in Q15_16 is 1.5 LSB of Q16_15: rounds to 2, and -1.5 to -2.
  EXPECT_EQ(fx::rescale<Q16_15>(q(3), s).raw(), 2);
  EXPECT_EQ(fx::rescale<Q16_15>(q(-3), s).raw(), -2);
  // 0.5 LSB: away from zero, both signs. An arithmetic shift would give 0 and -1.
  EXPECT_EQ(fx::rescale<Q16_15>(q(1), s).raw(), 1);
  EXPECT_EQ(fx::rescale<Q16_15>(q(-1), s).raw(), -1);
  // Below the tie: towards the nearest.
  EXPECT_EQ(fx::rescale<QInt32>(q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_EQ(fx::rescale<QInt32>(q(-k_one / 2 + 1), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxRescale, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::rescale<Q15_16>(Q31_32::from_raw(std::int64_t{40000} << 32), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::rescale<Q15_16>(Q31_32::from_raw(-(std::int64_t{40000} << 32)), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::rescale<Q1_30>(q(2 * k_one), s3), Q1_30::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  // Rounding up into the top of the range is not an overflow; past it is.
  fx::Status s4;
  EXPECT_EQ(fx::rescale<QInt32>(Q31_32::from_raw((std::int64_t{2147483647} << 32) + 0x7FFFFFFF), s4), QInt32::max());
  EXPECT_TRUE(s4.ok());
  EXPECT_EQ(fx::rescale<QInt32>(Q31_32::from_raw((std::int64_t{2147483647} << 32) + 0x80000000LL), s4), QInt32::max());
  EXPECT_EQ(s4.bits(), only(Flag::overflow));
}

TEST(FxRescale, WideningPastSixtyFourBitsSaturatesBySign) {
  // A 64-bit integer moved to 32 fraction bits: 2^40 needs 73 bits, past
  // every format, and the 64-bit intermediate reports it.
  using QInt64 = fx::Q<std::int64_t, 0>;
  fx::Status up;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(std::int64_t{1} << 40), up), Q31_32::max());
  EXPECT_EQ(up.bits(), only(Flag::overflow));
  fx::Status down;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(-(std::int64_t{1} << 40)), down), Q31_32::min());
  EXPECT_EQ(down.bits(), only(Flag::overflow));
  fx::Status zero;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(0), zero).raw(), 0);
  EXPECT_TRUE(zero.ok());
}

// ---------------------------------------------------------------- mul

TEST(FxMul, SixtyFourBitPathGivesTheSameBitsAsTheWidePath) {
  // Q31.32 products of two magnitudes below 2^32 take the 64-bit path; at
  // and around the 2^32 boundary the two paths must agree with the exact
  // rounded product, (|a| |b| + 2^31) >> 32 in the library's 128-bit helpers
  // (no __int128: this test also runs on ARM32).
  const std::int64_t values[] = {1, 3, 0x7FFFFFFF, 0x80000000LL, 0xFFFFFFFFLL, 0x100000000LL, 0x100000001LL,
                                 0x1234567890LL};
  for (std::int64_t a : values) {
    for (std::int64_t b : values) {
      for (int sign = 0; sign < 4; ++sign) {
        const std::int64_t sa = (sign & 1) != 0 ? -a : a;
        const std::int64_t sb = (sign & 2) != 0 ? -b : b;
        fx::Status s;
        const Q31_32 got = fx::mul(Q31_32::from_raw(sa), Q31_32::from_raw(sb), s);
        namespace w = fx::wide;
        const w::U128 exact = w::shr(w::add(w::mul_full(static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b)),
                                            w::make_u128(std::uint64_t{1} << 31U)),
                                     32U);
        ASSERT_EQ(exact.hi, 0U);
        const auto want = static_cast<std::int64_t>(exact.lo);
        EXPECT_EQ(got.raw(), ((sa < 0) != (sb < 0)) ? -want : want) << sa << " * " << sb;
        EXPECT_TRUE(s.ok());
      }
    }
  }
}

TEST(FxMul, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::mul(q(3 * k_one / 2), q(-9 * k_one / 4), s).raw(), -27 * k_one / 8);
  EXPECT_EQ(fx::mul(Q15_16::min(), q(k_one), s), Q15_16::min());
  EXPECT_EQ(fx::mul<Q31_32>(q(100 * k_one), q(1000 * k_one), s).raw(), std::int64_t{100000} << 32);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, TiesRoundAwayFromZeroSymmetrically) {
  fx::Status s;
  const Q15_16 half = q(k_one / 2);
  EXPECT_EQ(fx::mul(q(1), half, s).raw(), 1);    // 0.5 LSB
  EXPECT_EQ(fx::mul(q(-1), half, s).raw(), -1);  // -0.5 LSB, not 0
  EXPECT_EQ(fx::mul(q(3), half, s).raw(), 2);    // 1.5 LSB
  EXPECT_EQ(fx::mul(q(-3), half, s).raw(), -2);  // -1.5 LSB, not -1
  EXPECT_EQ(fx::mul(q(1), q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_EQ(fx::mul(q(-1), q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, UnderflowToZeroIsNotAnError) {
  fx::Status s;
  EXPECT_EQ(fx::mul(Q15_16::lsb(), Q15_16::lsb(), s).raw(), 0);
  EXPECT_EQ(fx::mul(fx::neg(Q15_16::lsb(), s), Q15_16::lsb(), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::mul(q(256 * k_one), q(128 * k_one), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::mul(q(256 * k_one), q(-129 * k_one), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::mul(Q15_16::min(), Q15_16::min(), s3), Q15_16::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  // -32768 * 1 fits exactly, +32768 does not.
  fx::Status s4;
  EXPECT_EQ(fx::mul(q(-256 * k_one), q(128 * k_one), s4), Q15_16::min());
  EXPECT_TRUE(s4.ok());
  EXPECT_EQ(fx::mul(q(-256 * k_one), q(-128 * k_one), s4), Q15_16::max());
  EXPECT_EQ(s4.bits(), only(Flag::overflow));
  fx::Status s5;
  EXPECT_EQ(fx::mul(Q31_32::max(), Q31_32::min(), s5), Q31_32::min());
  EXPECT_EQ(s5.bits(), only(Flag::overflow));
}

// ---------------------------------------------------------------- div

TEST(FxDiv, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::div(q(k_one), q(3 * k_one), s).raw(), 21845);       // 21845.33
  EXPECT_EQ(fx::div(q(-k_one), q(3 * k_one), s).raw(), -21845);
  EXPECT_EQ(fx::div(q(2 * k_one), q(3 * k_one), s).raw(), 43691);   // 43690.67
  EXPECT_EQ(fx::div(q(2 * k_one), q(-3 * k_one), s).raw(), -43691);
  EXPECT_EQ(fx::div<Q31_32>(q(k_one), q(3 * k_one), s).raw(), 1431655765);  // 2^32 / 3 = 1431655765.33
  EXPECT_EQ(fx::div<QInt32>(Q1_30::from_raw(3 << 28), q(k_one / 4), s).raw(), 3);
  EXPECT_TRUE(s.ok());
}

TEST(FxDiv, TiesRoundAwayFromZeroSymmetrically) {
  fx::Status s;
  EXPECT_EQ(fx::div(q(1), q(2 * k_one), s).raw(), 1);
  EXPECT_EQ(fx::div(q(-1), q(2 * k_one), s).raw(), -1);
  EXPECT_EQ(fx::div(q(1), q(-2 * k_one), s).raw(), -1);
  EXPECT_EQ(fx::div(q(-3), q(2 * k_one), s).raw(), -2);
  EXPECT_TRUE(s.ok());
}

TEST(FxDiv, ByZeroReportsAndSaturatesBySignOfDividend) {
  fx::Status s1;
  EXPECT_EQ(fx::div(q(5), Q15_16::zero(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::div_by_zero));
  fx::Status s2;
  EXPECT_EQ(fx::div(q(-5), Q15_16::zero(), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::div_by_zero));
  fx::Status s3;
  EXPECT_EQ(fx::div(Q15_16::zero(), Q15_16::zero(), s3), Q15_16::zero());
  EXPECT_EQ(s3.bits(), only(Flag::div_by_zero));
  fx::Status s4;
  EXPECT_EQ(fx::div<Q31_32>(q(-5), QInt32::zero(), s4), Q31_32::min());
  EXPECT_EQ(s4.bits(), only(Flag::div_by_zero));
}

TEST(FxDiv, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::div(q(30000 * k_one), q(65), s1), Q15_16::max());  // / 0.001
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::div(q(-30000 * k_one), q(65), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::div(Q15_16::min(), q(-k_one), s3), Q15_16::max());  // -(-32768)
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  fx::Status s4;
  EXPECT_EQ(fx::div(Q15_16::min(), q(k_one), s4), Q15_16::min());
  EXPECT_TRUE(s4.ok());
  fx::Status s5;
  EXPECT_EQ(fx::div<Q31_32>(Q31_32::max(), Q31_32::lsb(), s5), Q31_32::max());
  EXPECT_EQ(s5.bits(), only(Flag::overflow));
}

// ---------------------------------------------------------------- status

TEST(FxStatus, IsStickyAcrossOperations) {
  fx::Status s;
  const Q15_16 big = fx::add(Q15_16::max(), Q15_16::max(), s);  // overflow
  const Q15_16 fine = fx::add(q(1), q(2), s);                     // clean op
  EXPECT_EQ(fine.raw(), 3);
  EXPECT_EQ(big, Q15_16::max());
  EXPECT_TRUE(s.has(Flag::overflow));
  static_cast<void>(fx::div(fine, Q15_16::zero(), s));
  EXPECT_TRUE(s.has(Flag::overflow));
  EXPECT_TRUE(s.has(Flag::div_by_zero));
  EXPECT_FALSE(s.has(Flag::domain));
  EXPECT_FALSE(s.ok());
  fx::Status other;
  other.raise(Flag::domain);
  s.merge(other);
  EXPECT_EQ(s.bits(), only(Flag::overflow) | only(Flag::div_by_zero) | only(Flag::domain));
  s.clear();
  EXPECT_TRUE(s.ok());
}

}  // namespace
