// test_cov_rover_params.cpp: the rover-parameter rules (rover_geometry.hpp,
// validate_rover_params) at the ends test_wheel_load.cpp does not try: the
// upper bound of each range, the negative side of each centre-of-mass and
// link coordinate, the order of the inner links, and the values on the
// boundaries themselves, which must pass. Also the rover section's reserved
// word and a section one field too long.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "../flight/quantity_support.hpp"
#include "../flight/table_bytes.hpp"

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

// Section 6 goes through the table's codec (param_table.hpp): these take a
// table that carries the rover apart into its sections, change section 6's
// payload and frame it again with a correct CRC.
std::vector<test::Section> sections_with(const RoverParams& p) {
  flight::ParameterTable t = flight::default_parameter_table();
  t.rover_geometry = flight::RoverSection{true, p};
  return test::sections_of(test::encode_table(t));
}

test::Bytes& rover_payload(std::vector<test::Section>& sections) {
  for (test::Section& s : sections) {
    if (s.id == static_cast<std::uint16_t>(flight::SectionId::rover_geometry)) {
      return s.payload;
    }
  }
  ADD_FAILURE() << "no section 6";
  return sections.front().payload;
}

flight::RejectReason decode_framed(const std::vector<test::Section>& sections, flight::ParameterTable& out) {
  const test::Bytes b = test::frame(sections);
  return flight::decode(b.data(), b.size(), out);
}

TEST(RoverParamSectionFraming, NonZeroReservedWordIsRefused) {
  std::vector<test::Section> secs = sections_with(moon());
  flight::ParameterTable out{};
  ASSERT_EQ(decode_framed(secs, out), flight::RejectReason::ok);
  rover_payload(secs)[3] = 1U;
  EXPECT_EQ(decode_framed(secs, out), flight::RejectReason::reserved_not_zero);
}

TEST(RoverParamSectionFraming, AnotherLayoutVersionIsRefusedAsExtensionRejected) {
  std::vector<test::Section> secs = sections_with(moon());
  rover_payload(secs)[0] = 2U;
  flight::ParameterTable out{};
  EXPECT_EQ(decode_framed(secs, out), flight::RejectReason::extension_rejected);
}

TEST(RoverParamSectionFraming, SectionLongerOrShorterThanTheLayoutIsALengthMismatch) {
  std::vector<test::Section> longer = sections_with(moon());
  rover_payload(longer).resize(flight::kRoverSectionBytes + 4U, 0U);
  flight::ParameterTable out{};
  EXPECT_EQ(decode_framed(longer, out), flight::RejectReason::section_length_mismatch);
  std::vector<test::Section> shorter = sections_with(moon());
  rover_payload(shorter).resize(flight::kRoverSectionBytes - 4U);
  EXPECT_EQ(decode_framed(shorter, out), flight::RejectReason::section_length_mismatch);
}

TEST(RoverParamSectionFraming, DecodedParametersEqualTheEncodedOnes) {
  RoverParams p = moon();
  p.mass_kg = q<flight::MassKg>(123.25);
  p.com_y_m = q<flight::LengthM>(-0.125);
  p.rocker_bogie_pivot.z_m = q<flight::LengthM>(-0.2);
  std::vector<test::Section> secs = sections_with(p);
  EXPECT_EQ(rover_payload(secs).size(), flight::kRoverSectionBytes);
  flight::ParameterTable back{};
  ASSERT_EQ(decode_framed(secs, back), flight::RejectReason::ok);
  ASSERT_TRUE(back.rover_geometry.present);
  const RoverParams& out = back.rover_geometry.params;
  EXPECT_EQ(out.mass_kg, p.mass_kg);
  EXPECT_EQ(out.com_y_m, p.com_y_m);  // a negative value survives the byte format
  EXPECT_EQ(out.rocker_bogie_pivot.z_m, p.rocker_bogie_pivot.z_m);
  EXPECT_EQ(out.high_slip, p.high_slip);
}

}  // namespace
