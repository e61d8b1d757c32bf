// test_cov_rover_params.cpp: the rover-parameter rules (rover_geometry.hpp,
// validate_rover_params) at the ends test_wheel_load.cpp does not try: the
// upper bound of each range, the negative side of each centre-of-mass and
// link coordinate, the order of the inner links, and the values on the
// boundaries themselves, which must pass. Also the rover section's reserved
// word and a section one field too long.
#include <gtest/gtest.h>

#include <cstdint>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "../flight/quantity_support.hpp"

namespace {

using namespace sinkwatch;
using flight::RoverParams;
using S = flight::RoverParamStatus;

using sinkwatch::test::q;

RoverParams moon() { return flight::yutu_like_rover_params(flight::kGravityMoon); }

struct Mutation {
  const char* name;
  void (*apply)(RoverParams&);
  S expected;
};

TEST(RoverParamsValidate, TheOtherEndOfEachRuleRejectsWithItsReason) {
  ASSERT_EQ(flight::validate_rover_params(moon()), S::ok);
  const Mutation mutations[] = {
      {"mass < 0", [](RoverParams& p) { p.mass_kg = q<flight::MassKg>(-1.0); }, S::bad_mass},
      {"gravity 0", [](RoverParams& p) { p.gravity_mps2 = flight::AccelMps2::zero(); }, S::bad_gravity},
      {"radius 1.5 m", [](RoverParams& p) { p.wheel_radius_m = q<flight::LengthM>(1.5); }, S::bad_wheel_radius},
      {"track 4.5 m", [](RoverParams& p) { p.track_width_m = q<flight::LengthM>(4.5); }, S::bad_track_width},
      {"track < 0", [](RoverParams& p) { p.track_width_m = q<flight::LengthM>(-0.9); }, S::bad_track_width},
      {"com x 2.5 m", [](RoverParams& p) { p.com_x_m = q<flight::LengthM>(2.5); }, S::bad_com},
      {"com x -2.5 m", [](RoverParams& p) { p.com_x_m = q<flight::LengthM>(-2.5); }, S::bad_com},
      {"com z -2.5 m", [](RoverParams& p) { p.com_z_m = q<flight::LengthM>(-2.5); }, S::bad_com},
      {"com y 2.5 m", [](RoverParams& p) { p.com_y_m = q<flight::LengthM>(2.5); }, S::bad_com},
      {"com y on the left track", [](RoverParams& p) { p.com_y_m = q<flight::LengthM>(-0.45); }, S::bad_com},
      {"front axle x 2.5 m", [](RoverParams& p) { p.rocker_front_axle.x_m = q<flight::LengthM>(2.5); }, S::bad_link_length},
      {"bogie pivot z 2.5 m", [](RoverParams& p) { p.rocker_bogie_pivot.z_m = q<flight::LengthM>(2.5); }, S::bad_link_length},
      {"rear axle x -2.5 m", [](RoverParams& p) { p.bogie_rear_axle.x_m = q<flight::LengthM>(-2.5); }, S::bad_link_length},
      {"bogie pivot ahead", [](RoverParams& p) { p.rocker_bogie_pivot.x_m = q<flight::LengthM>(0.1); }, S::bad_link_order},
      {"middle axle behind", [](RoverParams& p) { p.bogie_middle_axle.x_m = q<flight::LengthM>(-0.1); }, S::bad_link_order},
      {"bogie limit 0", [](RoverParams& p) { p.bogie_limit_rad = flight::AngleRad::zero(); }, S::bad_joint_limit},
      {"rocker limit 0.9", [](RoverParams& p) { p.rocker_limit_rad = q<flight::AngleRad>(0.9); }, S::bad_joint_limit},
      {"attitude limit 0", [](RoverParams& p) { p.attitude_limit_rad = flight::AngleRad::zero(); }, S::bad_attitude_limit},
      {"high slip 0", [](RoverParams& p) { p.high_slip = flight::Ratio::zero(); }, S::bad_high_slip},
  };
  for (const Mutation& m : mutations) {
    RoverParams p = moon();
    m.apply(p);
    EXPECT_EQ(flight::validate_rover_params(p), m.expected) << m.name;
  }
}

TEST(RoverParamsValidate, ValuesOnTheBoundariesAreAccepted) {
  RoverParams p = moon();
  p.mass_kg = q<flight::MassKg>(1000.0);
  p.gravity_mps2 = q<flight::AccelMps2>(10.0);
  p.track_width_m = q<flight::LengthM>(4.0);
  p.wheel_radius_m = q<flight::LengthM>(0.01);
  p.com_x_m = q<flight::LengthM>(2.0);
  p.com_z_m = q<flight::LengthM>(-2.0);
  p.rocker_limit_rad = q<flight::AngleRad>(0.8);
  p.bogie_limit_rad = q<flight::AngleRad>(0.8);
  p.attitude_limit_rad = q<flight::AngleRad>(1.05);
  p.high_slip = q<flight::Ratio>(1.0);
  EXPECT_EQ(flight::validate_rover_params(p), S::ok);
  p.wheel_radius_m = q<flight::LengthM>(1.0);
  EXPECT_EQ(flight::validate_rover_params(p), S::ok);
}

TEST(RoverParamSectionFraming, NonZeroReservedWordIsABadEncoding) {
  flight::ExtensionSection s{};
  flight::encode_rover_section(moon(), s);
  RoverParams out{};
  ASSERT_EQ(flight::decode_rover_section(s, out), S::ok);
  s.bytes[3] = 1U;
  EXPECT_EQ(flight::decode_rover_section(s, out), S::bad_encoding);
  EXPECT_FALSE(flight::rover_section_valid(s));
}

TEST(RoverParamSectionFraming, SectionLongerThanTheLayoutIsABadEncoding) {
  flight::ExtensionSection s{};
  flight::encode_rover_section(moon(), s);
  s.length = static_cast<std::uint16_t>(s.length + 4U);
  RoverParams out{};
  EXPECT_EQ(flight::decode_rover_section(s, out), S::bad_encoding);
}

TEST(RoverParamSectionFraming, DecodedParametersEqualTheEncodedOnes) {
  RoverParams p = moon();
  p.mass_kg = q<flight::MassKg>(123.25);
  p.com_y_m = q<flight::LengthM>(-0.125);
  p.rocker_bogie_pivot.z_m = q<flight::LengthM>(-0.2);
  flight::ExtensionSection s{};
  flight::encode_rover_section(p, s);
  EXPECT_EQ(s.length, flight::kRoverSectionBytes);
  RoverParams out{};
  ASSERT_EQ(flight::decode_rover_section(s, out), S::ok);
  EXPECT_EQ(out.mass_kg, p.mass_kg);
  EXPECT_EQ(out.com_y_m, p.com_y_m);  // a negative value survives the byte format
  EXPECT_EQ(out.rocker_bogie_pivot.z_m, p.rocker_bogie_pivot.z_m);
  EXPECT_EQ(out.high_slip, p.high_slip);
}

}  // namespace
