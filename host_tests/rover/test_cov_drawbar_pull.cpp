// test_cov_drawbar_pull.cpp: drawbar_pulls (drawbar_pull.hpp) given wheel
// loads that the load model itself would not produce, as a caller with its
// own load source could: every load zero, one load negative, and loads at
// the top of the load format whose DP_max (up to twice the load) does not
// fit it; and a downhill slope past the attitude limit. Each must be refused
// with its status, never turned into pulls.
#include <gtest/gtest.h>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "../flight/quantity_support.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

using sinkwatch::test::q;

RoverParams moon() { return yutu_like_rover_params(kGravityMoon); }

WheelLoadResult loads_of(double each_n) {
  WheelLoadResult r{};
  for (WheelLoadN& l : r.load_n) {
    l = q<WheelLoadN>(each_n);
  }
  r.weight_normal_n = q<WheelLoadN>(6.0 * each_n > 30000.0 ? 30000.0 : 6.0 * each_n);
  r.status = WheelLoadStatus::ok;
  return r;
}

DrawbarInput level_input(double dp_max_ratio) {
  DrawbarInput in{};
  in.accel_mps2 = AccelMps2::zero();
  in.pitch_rad = AngleRad::zero();
  for (Ratio& r : in.dp_max_ratio) {
    r = q<Ratio>(dp_max_ratio);
  }
  return in;
}

TEST(DrawbarPullsGivenLoads, AllLoadsZeroIsInvalidLoads) {
  const DrawbarResult r = drawbar_pulls(moon(), loads_of(0.0), level_input(0.5));
  EXPECT_EQ(r.status, DrawbarStatus::invalid_loads);
  EXPECT_FALSE(usable(r.status));
}

TEST(DrawbarPullsGivenLoads, NegativeLoadIsInvalidInput) {
  WheelLoadResult loads = loads_of(37.8);
  loads.load_n[4] = q<WheelLoadN>(-1.0);
  EXPECT_EQ(drawbar_pulls(moon(), loads, level_input(0.5)).status, DrawbarStatus::invalid_input);
}

TEST(DrawbarPullsGivenLoads, DownhillBeyondTheAttitudeLimitIsInvalidInput) {
  DrawbarInput in = level_input(0.5);
  in.pitch_rad = q<AngleRad>(-1.01);  // the Yutu-like limit is 1.0 rad
  EXPECT_EQ(drawbar_pulls(moon(), loads_of(37.8), in).status, DrawbarStatus::invalid_input);
  in.pitch_rad = q<AngleRad>(-0.99);
  EXPECT_TRUE(usable(drawbar_pulls(moon(), loads_of(37.8), in).status));
}

TEST(DrawbarPullsGivenLoads, SaturatedPullBeyondTheLoadFormatIsOverflowNotANumber) {
  DrawbarInput in = level_input(2.0);
  in.slip_known = true;
  in.slip = q<Ratio>(0.9);  // above high_slip (0.6): every wheel at DP_max = 2 W
  // 20000 N per wheel: DP_max = 40000 N does not fit Q15.16 (max 32768 N).
  const DrawbarResult big = drawbar_pulls(moon(), loads_of(20000.0), in);
  EXPECT_EQ(big.status, DrawbarStatus::overflow);
  EXPECT_EQ(big.dp_n[0], DrawbarPullN::zero());
  // The control: 10000 N per wheel gives 20000 N, which fits.
  const DrawbarResult fits = drawbar_pulls(moon(), loads_of(10000.0), in);
  ASSERT_EQ(fits.status, DrawbarStatus::saturated);
  EXPECT_NEAR(fx::to_double(fits.dp_n[0].q()), 20000.0, 0.01);
}

}  // namespace
