// test_literal.cpp: fx::constant (compile-time decimal constants) and the
// host-only from_double / to_double: rounding, ties, NaN, infinities and
// overflow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

// round(0.13 * 65536) = round(8519.68) = 8520.
static_assert(fx::constant<Q15_16>(0.13).raw() == 8520, "constant rounds to nearest");
static_assert(fx::constant<Q15_16>(-0.13).raw() == -8520, "constant rounds negatives symmetrically");
static_assert(fx::constant<Q1_30>(1.0).raw() == (1 << 30), "1.0 in Q1_30");
static_assert(fx::constant<Q31_32>(-32768.5).raw() == -(std::int64_t{65537} << 31), "exact constant in Q31_32");
// Ties: 1.5 and 2.5 LSB both round away from zero.
static_assert(fx::constant<Q15_16>(1.5 / 65536.0).raw() == 2, "tie 1.5 LSB -> 2");
static_assert(fx::constant<Q15_16>(2.5 / 65536.0).raw() == 3, "tie 2.5 LSB -> 3 (not to even)");
static_assert(fx::constant<Q15_16>(-2.5 / 65536.0).raw() == -3, "tie -2.5 LSB -> -3");
static_assert(fx::constant<Q15_16>(-32768.0) == Q15_16::min(), "min is representable");

TEST(FxFromDouble, NanIsADomainErrorReturningZero) {
  fx::Status s;
  EXPECT_EQ(fx::from_double<Q15_16>(std::numeric_limits<double>::quiet_NaN(), s).raw(), 0);
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

TEST(FxFromDouble, InfinitiesAndHugeValuesSaturate) {
  fx::Status s1;
  EXPECT_EQ(fx::from_double<Q15_16>(std::numeric_limits<double>::infinity(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::from_double<Q15_16>(-std::numeric_limits<double>::infinity(), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::from_double<Q31_32>(1e300, s3), Q31_32::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  fx::Status s4;
  EXPECT_EQ(fx::from_double<Q15_16>(32768.0, s4), Q15_16::max());
  EXPECT_EQ(s4.bits(), only(Flag::overflow));
  // Rounds to max, which fits: not an overflow.
  fx::Status s5;
  EXPECT_EQ(fx::from_double<Q15_16>(32767.99999, s5), Q15_16::max());
  EXPECT_TRUE(s5.ok());
  // Just below -32768 - 0.5 LSB: past min.
  fx::Status s6;
  EXPECT_EQ(fx::from_double<Q15_16>(-32768.00001, s6), Q15_16::min());
  EXPECT_EQ(s6.bits(), only(Flag::overflow));
}

TEST(FxFromDouble, RoundsToNearestTiesAwayFromZero) {
  fx::Status s;
  EXPECT_EQ(fx::from_double<Q15_16>(0.5 / 65536.0, s).raw(), 1);
  EXPECT_EQ(fx::from_double<Q15_16>(-0.5 / 65536.0, s).raw(), -1);
  EXPECT_EQ(fx::from_double<Q15_16>(0.49 / 65536.0, s).raw(), 0);
  EXPECT_EQ(fx::from_double<Q15_16>(-0.49 / 65536.0, s).raw(), 0);
  // The largest double below 0.5: (m + 0.5) would round it up to 1.
  using QInt32 = fx::Q<std::int32_t, 0>;
  EXPECT_EQ(fx::from_double<QInt32>(0.49999999999999994, s).raw(), 0);
  EXPECT_EQ(fx::from_double<QInt32>(-0.49999999999999994, s).raw(), 0);
  EXPECT_EQ(fx::from_double<QInt32>(0.5, s).raw(), 1);
  EXPECT_EQ(fx::from_double<QInt32>(-2.5, s).raw(), -3);
  EXPECT_EQ(fx::from_double<Q15_16>(-0.0, s).raw(), 0);
  EXPECT_EQ(fx::from_double<Q15_16>(std::numeric_limits<double>::denorm_min(), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxToDouble, IsExactForInt32Storage) {
  EXPECT_EQ(fx::to_double(Q15_16::from_raw(-3)), -3.0 / 65536.0);
  EXPECT_EQ(fx::to_double(Q1_30::max()), (2147483647.0) / 1073741824.0);
  EXPECT_EQ(fx::to_double(Q15_16::min()), -32768.0);
  fx::Status s;
  EXPECT_EQ(fx::from_double<Q15_16>(fx::to_double(Q15_16::from_raw(123456789)), s).raw(), 123456789);
  EXPECT_TRUE(s.ok());
}

}  // namespace
