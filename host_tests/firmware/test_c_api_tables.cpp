// test_c_api_tables.cpp: the C interface (sinkwatch.h) from C++, for what the
// C11 test (test_c_api.c) cannot build: real parameter tables, with and
// without a rover-geometry section, made by the flight module's encoders.
// Also every entry point with a null or never-initialised context, and a
// direction code that is neither forward nor reverse.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/sinkwatch.h"
#include "../flight/table_bytes.hpp"

namespace {

namespace flight = sinkwatch::flight;
using sinkwatch::test::Bytes;
using sinkwatch::test::encode_table;

// fx::constant is for constant expressions only (literal.hpp).
constexpr flight::MassKg kLightRoverKg{sinkwatch::fx::constant<flight::MassQ>(100.0)};
constexpr flight::MassKg kTooHeavyRoverKg{sinkwatch::fx::constant<flight::MassQ>(2000.0)};  // beyond 1000 kg

std::uint32_t table_crc(const Bytes& b) { return flight::crc32(b.data(), b.size() - flight::kTableCrcBytes); }

// A table with the rover of `params` in its geometry section.
Bytes table_with_rover(const flight::RoverParams& params, std::uint16_t version) {
  flight::ParameterTable t = flight::default_parameter_table();
  t.table_version = version;
  t.rover_geometry = flight::RoverSection{true, params};
  return encode_table(t);
}

// Level ground, every wheel driving forward at 0.2 A.
sw_telemetry level_sample(std::uint32_t time_ms) {
  sw_telemetry t{};
  t.time_ms = time_ms;
  t.valid = 1U;
  for (unsigned i = 0U; i < SW_WHEELS; ++i) {
    t.direction[i] = SW_DIRECTION_FORWARD;
    t.current_a_q20[i] = 1 << 18;  // 0.25 A
  }
  t.accel_valid = 1U;
  t.speed_valid = 1U;
  t.speed_mps_q24 = 838861;  // 0.05 m/s
  t.rim_speed_valid = 1U;
  t.rim_speed_mps_q24 = 922747;  // 0.055 m/s
  return t;
}

// Sum of the six wheel loads of one level-ground step, in newtons.
double load_sum_n(sw_context& ctx, std::uint32_t time_ms) {
  sw_cycle_result out{};
  const sw_telemetry t = level_sample(time_ms);
  EXPECT_EQ(sw_step(&ctx, &t, time_ms, &out), SW_OK);
  EXPECT_EQ(out.loads_valid, 1U);
  std::int64_t sum_q16 = 0;
  for (const sw_wheel_result& w : out.wheel) {
    sum_q16 += w.load_n_q16;
  }
  return static_cast<double>(sum_q16) / 65536.0;
}

TEST(CApiTables, ValidTableIsPutInForceAndItsCrcReported) {
  static sw_context ctx;
  ASSERT_EQ(sw_init(&ctx), SW_OK);
  flight::ParameterTable t = flight::default_parameter_table();
  t.table_version = 5;
  const Bytes b = encode_table(t);
  EXPECT_EQ(sw_load_table(&ctx, b.data(), b.size()), 0U);
  EXPECT_EQ(sw_active_table_crc(&ctx), table_crc(b));
  EXPECT_NE(sw_active_table_crc(&ctx), 0U);
  // The rover is still the Yutu-like default: 140 kg on the Moon.
  EXPECT_NEAR(load_sum_n(ctx, 1000U), 140.0 * 1.62, 0.5);
}

TEST(CApiTables, RoverSectionReplacesTheRoverAndATableWithoutOneRestoresTheDefault) {
  static sw_context ctx;
  ASSERT_EQ(sw_init(&ctx), SW_OK);
  flight::RoverParams light = flight::yutu_like_rover_params(flight::kGravityMoon);
  light.mass_kg = kLightRoverKg;
  const Bytes with_rover = table_with_rover(light, 6);
  ASSERT_EQ(sw_load_table(&ctx, with_rover.data(), with_rover.size()), 0U);
  EXPECT_EQ(sw_active_table_crc(&ctx), table_crc(with_rover));
  EXPECT_NEAR(load_sum_n(ctx, 1000U), 100.0 * 1.62, 0.5);

  const Bytes plain = encode_table(flight::default_parameter_table());
  ASSERT_EQ(sw_load_table(&ctx, plain.data(), plain.size()), 0U);
  EXPECT_NEAR(load_sum_n(ctx, 1100U), 140.0 * 1.62, 0.5);
}

TEST(CApiTables, TableWithAnInvalidRoverIsRejectedAndTheRoverKept) {
  static sw_context ctx;
  ASSERT_EQ(sw_init(&ctx), SW_OK);
  flight::RoverParams heavy = flight::yutu_like_rover_params(flight::kGravityMoon);
  heavy.mass_kg = kTooHeavyRoverKg;
  const Bytes b = table_with_rover(heavy, 7);
  EXPECT_EQ(sw_load_table(&ctx, b.data(), b.size()), static_cast<std::uint8_t>(flight::RejectReason::extension_rejected));
  EXPECT_EQ(sw_active_table_crc(&ctx), 0U);
  EXPECT_NEAR(load_sum_n(ctx, 1000U), 140.0 * 1.62, 0.5);
}

TEST(CApiArguments, NullContextIsRefusedByEveryEntryPoint) {
  const Bytes b = encode_table(flight::default_parameter_table());
  EXPECT_EQ(sw_load_table(nullptr, b.data(), b.size()), static_cast<std::uint8_t>(flight::RejectReason::null_buffer));
  EXPECT_EQ(sw_active_table_crc(nullptr), 0U);
  sw_clear_stop(nullptr);  // must simply return
  sw_event e{};
  EXPECT_EQ(sw_last_event(nullptr, 0U, &e), 0);
  sw_stop_record r{};
  EXPECT_EQ(sw_last_stop(nullptr, &r), 0);
}

TEST(CApiArguments, ContextNeverInitialisedIsRefusedByEveryEntryPoint) {
  static sw_context fresh;
  std::memset(&fresh, 0, sizeof fresh);
  const Bytes b = encode_table(flight::default_parameter_table());
  EXPECT_EQ(sw_load_table(&fresh, b.data(), b.size()), static_cast<std::uint8_t>(flight::RejectReason::null_buffer));
  EXPECT_EQ(sw_active_table_crc(&fresh), 0U);
  sw_clear_stop(&fresh);
  sw_event e{};
  EXPECT_EQ(sw_last_event(&fresh, 0U, &e), 0);
  sw_stop_record r{};
  EXPECT_EQ(sw_last_stop(&fresh, &r), 0);
  sw_cycle_result out{};
  const sw_telemetry t = level_sample(100U);
  EXPECT_EQ(sw_step(&fresh, &t, 100U, &out), SW_NOT_INITIALISED);
  // Nothing above may have initialised it behind the caller's back.
  EXPECT_EQ(sw_active_table_crc(&fresh), 0U);
}

TEST(CApiEvents, NoEventBeforeAnyWheelStopped) {
  static sw_context ctx;
  ASSERT_EQ(sw_init(&ctx), SW_OK);
  sw_event e{};
  e.wheel = 0xAA;
  EXPECT_EQ(sw_last_event(&ctx, 0U, &e), 0);
  EXPECT_EQ(sw_last_event(&ctx, SW_WHEELS - 1U, &e), 0);
  EXPECT_EQ(sw_last_event(&ctx, SW_WHEELS, &e), 0);  // no such wheel
  EXPECT_EQ(e.wheel, 0xAA);                          // untouched
}

TEST(CApiTelemetry, UnknownDirectionCodeIsReportedForThatWheelOnly) {
  static sw_context ctx;
  ASSERT_EQ(sw_init(&ctx), SW_OK);
  sw_telemetry t = level_sample(1000U);
  t.direction[2] = 7U;  // neither SW_DIRECTION_FORWARD nor SW_DIRECTION_REVERSE
  t.direction[4] = SW_DIRECTION_REVERSE;
  sw_cycle_result out{};
  static_cast<void>(sw_step(&ctx, &t, 1000U, &out));
  EXPECT_EQ(out.wheel[2].sample_status, 6U);  // SampleStatus::direction_invalid
  EXPECT_EQ(out.wheel[2].estimate_valid, 0U);
  EXPECT_EQ(out.wheel[0].sample_status, 0U);
  EXPECT_NE(out.wheel[4].sample_status, 6U);  // reverse is a defined code
}

}  // namespace
