// The parameter table's byte format under random tables and random damage:
// valid tables round-trip exactly, any single-bit flip is rejected and leaves
// the table in force, and arbitrary bytes never get through.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace {

using namespace sinkwatch::flight;
using Bytes = std::vector<std::uint8_t>;

/// A valid table: the default with fields moved inside their ranges.
ParameterTable gen_valid_table() {
  ParameterTable t = default_parameter_table();
  t.table_version = *rc::gen::arbitrary<std::uint16_t>();
  t.motor.gear_ratio = GearRatio::from_raw(*rc::gen::inRange<std::int32_t>(1 << 16, 10000 << 16));
  t.motor.efficiency = Efficiency::from_raw(*rc::gen::inRange<std::int32_t>(10737419, (1 << 30) + 1));
  t.correction.count = static_cast<std::uint8_t>(*rc::gen::inRange(1, 9));
  std::int32_t load = 0;
  for (std::uint8_t i = 0; i < t.correction.count; ++i) {
    load += *rc::gen::inRange<std::int32_t>(1, 1000 << 16);
    t.correction.rows[i].load_n = WheelLoadN::from_raw(load);
    t.correction.rows[i].c1 = Ratio::from_raw(*rc::gen::inRange<std::int32_t>(1 << 22, (4 << 24) + 1));
    t.correction.rows[i].c2 = Ratio::from_raw(*rc::gen::inRange<std::int32_t>(1 << 22, (4 << 24) + 1));
    t.correction.rows[i].c3 = Ratio::from_raw(*rc::gen::inRange<std::int32_t>(-(1 << 24), (1 << 24) + 1));
    t.correction.rows[i].dp_max_ratio = Ratio::from_raw(*rc::gen::inRange<std::int32_t>(1, (2 << 24) + 1));
  }
  t.monitor.window_m = static_cast<std::uint8_t>(*rc::gen::inRange(1, 17));
  t.monitor.trip_n = static_cast<std::uint8_t>(*rc::gen::inRange(1, t.monitor.window_m + 1));
  t.monitor.clear_n = static_cast<std::uint8_t>(*rc::gen::inRange(1, t.monitor.window_m + 1));
  t.monitor.wheel_count = static_cast<std::uint8_t>(*rc::gen::inRange(1, 7));
  t.monitor.rover_stop_k = static_cast<std::uint8_t>(*rc::gen::inRange(1, t.monitor.wheel_count + 1));
  // Section 7: sometimes left out (all zero), else anywhere in its ranges.
  if (*rc::gen::arbitrary<bool>()) {
    t.health = HealthParams{};
  } else {
    t.health.policy = *rc::gen::element(LossPolicy::stop, LossPolicy::continue_degraded);
    t.health.stuck_cycles = *rc::gen::arbitrary<std::uint8_t>();
    t.health.implausible_cycles = *rc::gen::arbitrary<std::uint8_t>();
    t.health.recover_cycles = *rc::gen::arbitrary<std::uint8_t>();
    t.health.max_blind_wheels = static_cast<std::uint8_t>(*rc::gen::inRange(0, static_cast<int>(t.monitor.wheel_count)));
    t.health.bridge_ms = *rc::gen::inRange<std::uint32_t>(0U, 60001U);
    t.health.current_step_a = CurrentA::from_raw(*rc::gen::inRange<std::int32_t>(0, t.motor.current_abs_max_a.raw() + 1));
    t.health.attitude_step_rad = AngleRad::from_raw(*rc::gen::inRange<std::int32_t>(0, 421657428 + 1));
    t.health.joint_step_rad = AngleRad::from_raw(*rc::gen::inRange<std::int32_t>(0, 421657428 + 1));
  }
  // Section 6: sometimes absent, else the Yutu-like rover with its mass,
  // gravity and lateral centre of mass (+-0.25 m, negative included) moved
  // inside their ranges (rover_geometry.hpp).
  if (*rc::gen::arbitrary<bool>()) {
    RoverParams& p = t.rover_geometry.params;
    t.rover_geometry.present = true;
    p = yutu_like_rover_params(kGravityMoon);
    p.mass_kg = MassKg::from_raw(*rc::gen::inRange<std::int32_t>(1, (1000 << 16) + 1));
    p.gravity_mps2 = AccelMps2::from_raw(*rc::gen::inRange<std::int32_t>(1, (10 << 24) + 1));
    p.com_y_m = LengthM::from_raw(*rc::gen::inRange<std::int32_t>(-(1 << 22), (1 << 22) + 1));
  }
  // A drawn motor too weak for the table's own current limit (validate():
  // envelope_overflow, e.g. N = 1, eta = 0.01: I_max = T_max / 2.5e-4 N m/A)
  // is made stronger step by step, so that the other fields keep their
  // spread: the gear ratio doubled (up to its 10,000), then eta raised to 1.
  for (int i = 0; (i < 16) && (validate(t) == RejectReason::envelope_overflow); ++i) {
    const std::int32_t doubled = std::min<std::int32_t>(t.motor.gear_ratio.raw(), 5000 << 16) * 2;
    t.motor.gear_ratio = GearRatio::from_raw(doubled);
  }
  if (validate(t) == RejectReason::envelope_overflow) {
    t.motor.efficiency = Efficiency::from_raw(1 << 30);
  }
  return t;
}

Bytes encode_bytes(const ParameterTable& t) {
  Bytes b(kMaxTableBytes);
  const EncodeResult e = encode(t, b.data(), b.size());
  RC_ASSERT(e.status == RejectReason::ok);
  b.resize(e.size);
  return b;
}

RC_GTEST_PROP(ParamTableProps, ValidTablesRoundTripExactly, ()) {
  const ParameterTable t = gen_valid_table();
  RC_ASSERT(validate(t) == RejectReason::ok);
  const Bytes b = encode_bytes(t);
  ParameterTable back{};
  RC_ASSERT(decode(b.data(), b.size(), back) == RejectReason::ok);
  RC_ASSERT(encode_bytes(back) == b);
}

RC_GTEST_PROP(ParamTableProps, AnySingleBitFlipIsRejectedAndTheTableStays, ()) {
  const ParameterTable t = gen_valid_table();
  Bytes b = encode_bytes(t);
  ParameterStore store;
  RC_ASSERT(store.load(b.data(), b.size()) == RejectReason::ok);
  const Bytes in_force = encode_bytes(store.active());
  const std::size_t byte = *rc::gen::inRange<std::size_t>(0, b.size());
  const int bit = *rc::gen::inRange(0, 8);
  b[byte] = static_cast<std::uint8_t>(b[byte] ^ (1U << bit));
  RC_ASSERT(store.load(b.data(), b.size()) != RejectReason::ok);
  RC_ASSERT(encode_bytes(store.active()) == in_force);
}

RC_GTEST_PROP(ParamTableProps, RandomBytesAreRejected, ()) {
  const auto bytes = *rc::gen::container<Bytes>(rc::gen::arbitrary<std::uint8_t>());
  ParameterTable out{};
  RC_ASSERT(decode(bytes.data(), bytes.size(), out) != RejectReason::ok);
}

RC_GTEST_PROP(ParamTableProps, RandomPayloadBehindAValidHeaderIsRejected, ()) {
  // Gets past the magic and the length checks, so the CRC and the section
  // parser are what stand in the way.
  Bytes b = encode_bytes(default_parameter_table());
  for (std::size_t i = 16; i < b.size(); ++i) {
    b[i] = *rc::gen::arbitrary<std::uint8_t>();
  }
  ParameterTable out{};
  RC_ASSERT(decode(b.data(), b.size(), out) != RejectReason::ok);
}

}  // namespace
