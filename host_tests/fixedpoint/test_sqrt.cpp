// test_sqrt.cpp: worked examples and error paths of sqrt and reciprocal.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

constexpr std::int32_t constexpr_sqrt2() {
  fx::Status s;
  return fx::sqrt(Q15_16::from_raw(2 << 16), s).raw();
}
static_assert(constexpr_sqrt2() == 92682, "sqrt(2) = 92681.9 / 65536 rounds to 92682 at compile time");

TEST(FxSqrt, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::sqrt(Q15_16::from_raw(2 << 16), s).raw(), 92682);
  EXPECT_EQ(fx::sqrt(Q15_16::from_raw(9 << 16), s).raw(), 3 << 16);
  EXPECT_EQ(fx::sqrt(Q15_16::zero(), s).raw(), 0);
  EXPECT_EQ(fx::sqrt(Q15_16::lsb(), s).raw(), 256);  // sqrt(2^-16) = 2^-8
  // sqrt(max) of Q15_16 is 181.02 -> 11863283.2 raw
  EXPECT_EQ(fx::sqrt(Q15_16::max(), s).raw(), 11863283);
  // Output format with more fraction bits: sqrt(2) in Q1_30 from Q15_16.
  EXPECT_EQ(fx::sqrt<Q1_30>(Q15_16::from_raw(2 << 16), s).raw(), 1518500250);  // 1518500249.99
  EXPECT_EQ(fx::sqrt(Q31_32::from_raw(std::int64_t{2} << 32), s).raw(), 6074001000LL);  // 6074000999.95
  EXPECT_TRUE(s.ok());
}

TEST(FxSqrt, NegativeIsADomainErrorReturningZero) {
  fx::Status s1;
  EXPECT_EQ(fx::sqrt(fx::neg(Q15_16::lsb(), s1), s1).raw(), 0);
  EXPECT_EQ(s1.bits(), only(Flag::domain));
  fx::Status s2;
  EXPECT_EQ(fx::sqrt(Q31_32::min(), s2).raw(), 0);
  EXPECT_EQ(s2.bits(), only(Flag::domain));
}

TEST(FxSqrt, ResultBeyondTheOutputFormatSaturates) {
  fx::Status s;
  EXPECT_EQ(fx::sqrt<Q1_30>(Q15_16::from_raw(16 << 16), s), Q1_30::max());  // 4 > 2
  EXPECT_EQ(s.bits(), only(Flag::overflow));
}

TEST(FxReciprocal, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::from_raw(4 << 16), s).raw(), 1 << 14);
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::from_raw(-3 * 65536), s).raw(), -21845);
  EXPECT_EQ(fx::reciprocal<Q1_30>(Q15_16::from_raw(3 << 16), s).raw(), 357913941);  // 2^30/3 = 357913941.33
  EXPECT_TRUE(s.ok());
}

TEST(FxReciprocal, OfZeroIsDivByZero) {
  fx::Status s;
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::zero(), s), Q15_16::max());
  EXPECT_EQ(s.bits(), only(Flag::div_by_zero));
}

TEST(FxReciprocal, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::lsb(), s1), Q15_16::max());  // 65536 > 32767
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::from_raw(-1), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  // 1 / 2^-15 = 32768: one past max, but exactly min when negative.
  fx::Status s3;
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::from_raw(-2), s3), Q15_16::min());
  EXPECT_TRUE(s3.ok());
  EXPECT_EQ(fx::reciprocal<Q15_16>(Q15_16::from_raw(2), s3), Q15_16::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

}  // namespace
