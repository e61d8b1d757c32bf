// test_cov_sqrt.cpp: sqrt into the finest 64-bit format, Q0.62, from an
// integer format: the radicand raw * 2^124 is the only one in the library
// that can exceed 128 bits, and sqrt must then saturate with overflow
// rather than return the root of a truncated radicand.
#include <gtest/gtest.h>

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using QInt64 = fx::Q<std::int64_t, 0>;
using Q0_62 = fx::Q<std::int64_t, 62>;

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

TEST(FxSqrtIntoQ0_62, RootOfOneIsExactlyOne) {
  fx::Status s;
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::from_raw(1), s).raw(), std::int64_t{1} << 62);
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::zero(), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxSqrtIntoQ0_62, RadicandPastTwoToThe128SaturatesWithOverflow) {
  fx::Status s;
  // 16 * 2^124 = 2^128: the scaled radicand does not fit 128 bits.
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::from_raw(16), s), Q0_62::max());
  EXPECT_EQ(s.bits(), only(Flag::overflow));
  fx::Status big;
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::max(), big), Q0_62::max());
  EXPECT_EQ(big.bits(), only(Flag::overflow));
}

TEST(FxSqrtIntoQ0_62, RootAboveTheFormatButRadicandInRangeAlsoSaturates) {
  fx::Status s;
  // sqrt(4) = 2 > max of Q0.62 (2 - 2^-62); 4 * 2^124 = 2^126 still fits.
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::from_raw(4), s), Q0_62::max());
  EXPECT_EQ(s.bits(), only(Flag::overflow));
}

TEST(FxSqrtIntoQ0_62, NegativeIsADomainError) {
  fx::Status s;
  EXPECT_EQ(fx::sqrt<Q0_62>(QInt64::from_raw(-1), s), Q0_62::zero());
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

}  // namespace
