// test_cov_literal.cpp: every path of the decimal-to-Q conversion
// (literal.hpp's detail::from_double, reached at run time through
// host_convert.hpp) for one format, Q15.16: NaN, signs, values past 2^52,
// both saturation directions and a negative value that rounds to zero.
// One format only on purpose: gcov reports a template's branches only where
// a translation unit instantiates it once (docs/coverage.md).
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

TEST(FxFromDoubleQ15_16, NanRaisesDomainAndGivesZero) {
  fx::Status s;
  EXPECT_EQ(fx::from_double<Q15_16>(std::numeric_limits<double>::quiet_NaN(), s), Q15_16::zero());
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

TEST(FxFromDoubleQ15_16, NegativeValuesRoundSymmetrically) {
  fx::Status s;
  EXPECT_EQ(fx::from_double<Q15_16>(-1.5, s).raw(), -98304);
  EXPECT_EQ(fx::from_double<Q15_16>(-0.13, s).raw(), -8520);  // -8519.68
  EXPECT_EQ(fx::from_double<Q15_16>(0.13, s).raw(), 8520);
  EXPECT_EQ(fx::from_double<Q15_16>(-32768.0, s), Q15_16::min());  // exactly min: fits
  EXPECT_TRUE(s.ok());
}

TEST(FxFromDoubleQ15_16, TinyNegativeRoundsToPlainZero) {
  fx::Status s;
  const Q15_16 z = fx::from_double<Q15_16>(-1.0e-9, s);
  EXPECT_EQ(z.raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxFromDoubleQ15_16, ValuesBeyondTwoToThe52SaturateBothWays) {
  fx::Status up;
  EXPECT_EQ(fx::from_double<Q15_16>(1.0e20, up), Q15_16::max());
  EXPECT_EQ(up.bits(), only(Flag::overflow));
  fx::Status down;
  EXPECT_EQ(fx::from_double<Q15_16>(-1.0e20, down), Q15_16::min());
  EXPECT_EQ(down.bits(), only(Flag::overflow));
}

TEST(FxFromDoubleQ15_16, JustPastEitherEndSaturates) {
  fx::Status up;
  EXPECT_EQ(fx::from_double<Q15_16>(32768.0, up), Q15_16::max());
  EXPECT_EQ(up.bits(), only(Flag::overflow));
  fx::Status down;
  EXPECT_EQ(fx::from_double<Q15_16>(-32768.00001, down), Q15_16::min());
  EXPECT_EQ(down.bits(), only(Flag::overflow));
}

}  // namespace
