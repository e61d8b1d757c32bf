// test_cov_wheel_load.cpp: wheel_loads (wheel_load.hpp) with parameters that
// pass validate_rover_params but sit at the edge of its ranges: a rocker
// whose front axle is 5.5 mm ahead of its pivot and a bogie pivot 1.1 mm
// behind it. The load solution then divides by levers of a few millimetres
// and an intermediate leaves Q31.32: the result must be the overflow status,
// never loads. Found by a random search over valid parameters (one case in
// 14.6 million); the values are the raw integers it printed.
#include <gtest/gtest.h>

#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace {

using namespace sinkwatch::flight;

RoverParams edge_rover() {
  RoverParams p = yutu_like_rover_params(kGravityMoon);
  p.mass_kg = MassKg::from_raw(44843363);              // 684.3 kg
  p.gravity_mps2 = AccelMps2::from_raw(70844758);      // 4.22 m/s^2
  p.wheel_radius_m = LengthM::from_raw(1257371);       // 0.075 m
  p.track_width_m = LengthM::from_raw(17982918);       // 1.072 m
  p.com_x_m = LengthM::from_raw(-30890866);            // -1.841 m
  p.com_y_m = LengthM::from_raw(-4067800);             // -0.242 m
  p.com_z_m = LengthM::from_raw(-25162605);            // -1.500 m
  p.rocker_front_axle = SidePointM{LengthM::from_raw(92540), LengthM::from_raw(-23068015)};     // 5.5 mm, -1.375 m
  p.rocker_bogie_pivot = SidePointM{LengthM::from_raw(-17804), LengthM::from_raw(-23989935)};   // -1.1 mm, -1.430 m
  p.bogie_middle_axle = SidePointM{LengthM::from_raw(31117171), LengthM::from_raw(11953817)};   // 1.855 m, 0.713 m
  p.bogie_rear_axle = SidePointM{LengthM::from_raw(-25849548), LengthM::from_raw(-87804)};      // -1.541 m, -5.2 mm
  p.rocker_limit_rad = AngleRad::from_raw(214748365);    // 0.8 rad
  p.bogie_limit_rad = AngleRad::from_raw(214748365);     // 0.8 rad
  p.attitude_limit_rad = AngleRad::from_raw(281857229);  // 1.05 rad
  return p;
}

TEST(WheelLoadAtTheEdgeOfTheRanges, IntermediateBeyondQ31_32IsOverflowNotLoads) {
  const RoverParams p = edge_rover();
  ASSERT_EQ(validate_rover_params(p), RoverParamStatus::ok);
  const RoverAttitude attitude{AngleRad::from_raw(-168791173), AngleRad::from_raw(-42756740)};  // -0.629, -0.159 rad
  JointAnglesRad joints{};
  joints.rocker_rad[0] = AngleRad::from_raw(-107096556);  // -0.399 rad
  joints.rocker_rad[1] = AngleRad::from_raw(-60749518);   // -0.226 rad
  joints.bogie_rad[0] = AngleRad::from_raw(-131018337);   // -0.488 rad
  joints.bogie_rad[1] = AngleRad::from_raw(121485577);    // 0.453 rad
  const WheelLoadResult r = wheel_loads(p, attitude, joints, kNoDriveTorques);
  EXPECT_EQ(r.status, WheelLoadStatus::overflow);
  for (const WheelLoadN& l : r.load_n) {
    EXPECT_EQ(l, WheelLoadN::zero());
  }
  EXPECT_EQ(r.lifting_wheel, kWheelCount);
  // Level, with the joints at rest, the same rover gives a status that is not
  // overflow: the edge is in the combination, not in one value.
  const WheelLoadResult level = wheel_loads(p, RoverAttitude{}, JointAnglesRad{}, kNoDriveTorques);
  EXPECT_NE(level.status, WheelLoadStatus::overflow);
}

}  // namespace
