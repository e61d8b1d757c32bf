// test_load.cpp: load() (flight/load.hpp), the one path from table bytes to
// prepared parameters: what it accepts, which named reason each refusal
// carries, that a refusal leaves the parameters in force untouched, and that
// what it prepares is what prepare() would have prepared from the same table.
#include <gtest/gtest.h>

#include <cstdint>

#include "sinkwatch/flight/load.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "../flight/quantity_support.hpp"
#include "../flight/table_bytes.hpp"

namespace {

using namespace sinkwatch;
using flight::RejectReason;
using sinkwatch::test::q;

flight::ParameterTable with_rover(flight::RoverParams rover) {
  flight::ParameterTable t = flight::default_parameter_table();
  t.rover_geometry = flight::RoverSection{true, rover};
  return t;
}

std::uint32_t trailer(const test::Bytes& b) {
  const std::size_t n = b.size();
  return static_cast<std::uint32_t>(b[n - 4U]) | (static_cast<std::uint32_t>(b[n - 3U]) << 8U) |
         (static_cast<std::uint32_t>(b[n - 2U]) << 16U) | (static_cast<std::uint32_t>(b[n - 1U]) << 24U);
}

TEST(Load, TheDefaultTableLoadsWithTheYutuRoverAndItsCrc) {
  const test::Bytes bytes = test::encode_table(flight::default_parameter_table());
  flight::PreparedParameters p;
  ASSERT_EQ(flight::load(bytes.data(), bytes.size(), p), RejectReason::ok);
  EXPECT_TRUE(p.ready());
  EXPECT_EQ(p.table_crc(), trailer(bytes));
  EXPECT_NE(p.table_crc(), 0U);
  const flight::RoverParams moon = flight::yutu_like_rover_params(flight::kGravityMoon);
  EXPECT_EQ(p.rover().mass_kg, moon.mass_kg);
  EXPECT_EQ(p.rover().gravity_mps2, moon.gravity_mps2);
}

TEST(Load, PreparesWhatPrepareWouldFromTheSameTableAndRover) {
  flight::RoverParams mars = flight::yutu_like_rover_params(flight::kGravityMars);
  mars.mass_kg = q<flight::MassKg>(210.0);
  const flight::ParameterTable table = with_rover(mars);
  const test::Bytes bytes = test::encode_table(table);
  flight::PreparedParameters loaded;
  ASSERT_EQ(flight::load(bytes.data(), bytes.size(), loaded), RejectReason::ok);
  flight::PreparedParameters prepared;
  ASSERT_EQ(flight::prepare(table, mars, prepared), flight::PrepareStatus::ok);
  EXPECT_EQ(loaded.rover().mass_kg, prepared.rover().mass_kg);
  EXPECT_EQ(loaded.rover().gravity_mps2, prepared.rover().gravity_mps2);
  EXPECT_EQ(loaded.table().wheel_radius_m, prepared.table().wheel_radius_m);
  for (std::uint8_t i = 0U; i < flight::kMaxCorrectionRows; ++i) {
    EXPECT_EQ(loaded.correction_divisors().width[i].normalised, prepared.correction_divisors().width[i].normalised);
    EXPECT_EQ(loaded.correction_divisors().width[i].shift, prepared.correction_divisors().width[i].shift);
  }
  EXPECT_NE(loaded.motor_divisors().inverse_gain.mantissa, 0U);
  EXPECT_EQ(loaded.motor_divisors().inverse_gain.mantissa, prepared.motor_divisors().inverse_gain.mantissa);
  EXPECT_EQ(loaded.motor_divisors().inverse_gain.scale, prepared.motor_divisors().inverse_gain.scale);
}

void expect_refused_and_untouched(const test::Bytes& bytes, RejectReason expected) {
  flight::PreparedParameters p;
  flight::load_default(p);
  const std::uint32_t before = p.table_crc();
  EXPECT_EQ(flight::load(bytes.data(), bytes.size(), p), expected);
  EXPECT_EQ(p.table_crc(), before);
  EXPECT_TRUE(p.ready());
  EXPECT_EQ(p.rover().gravity_mps2, flight::kGravityMoon);
}

TEST(Load, AnInvalidRoverSectionIsRefusedAsExtensionRejected) {
  flight::RoverParams bad = flight::yutu_like_rover_params(flight::kGravityMars);
  bad.mass_kg = q<flight::MassKg>(-1.0);
  expect_refused_and_untouched(test::encode_table(with_rover(bad)), RejectReason::extension_rejected);
}

TEST(Load, ARoverWheelOtherThanTheTablesIsRefused) {
  flight::RoverParams other = flight::yutu_like_rover_params(flight::kGravityMars);
  other.wheel_radius_m = q<flight::LengthM>(0.20);
  ASSERT_EQ(flight::validate_rover_params(other), flight::RoverParamStatus::ok);
  expect_refused_and_untouched(test::encode_table(with_rover(other)), RejectReason::rover_radius_mismatch);
  // Without a rover section the Yutu-like rover (0.15 m) must match the table.
  flight::ParameterTable t = flight::default_parameter_table();
  t.wheel_radius_m = q<flight::LengthM>(0.20);
  expect_refused_and_untouched(test::encode_table(t), RejectReason::rover_radius_mismatch);
}

TEST(Load, FramingAndRangeRefusalsKeepTheirReasons) {
  test::Bytes bytes = test::encode_table(flight::default_parameter_table());
  bytes[20] ^= 0x01U;  // past the header: the CRC no longer matches
  expect_refused_and_untouched(bytes, RejectReason::crc_mismatch);
  flight::ParameterTable t = flight::default_parameter_table();
  t.motor.efficiency = flight::Efficiency::zero();
  expect_refused_and_untouched(test::encode_table(t), RejectReason::efficiency_out_of_range);
  flight::PreparedParameters p;
  EXPECT_EQ(flight::load(nullptr, 0U, p), RejectReason::null_buffer);
  EXPECT_FALSE(p.table_valid());
}

TEST(Load, TheDefaultIsReadyWithCrcZero) {
  flight::PreparedParameters p;
  flight::load_default(p);
  EXPECT_TRUE(p.ready());
  EXPECT_EQ(p.table_crc(), 0U);
  EXPECT_EQ(p.table().wheel_radius_m, p.rover().wheel_radius_m);
}

TEST(Load, EveryReasonHasItsOwnName) {
  EXPECT_STREQ(flight::reason_name(RejectReason::crc_mismatch), "crc_mismatch");
  EXPECT_STREQ(flight::reason_name(RejectReason::rover_radius_mismatch), "rover_radius_mismatch");
  EXPECT_STREQ(flight::reason_name(static_cast<RejectReason>(flight::kRejectReasonCount)), "unknown");
}

}  // namespace
