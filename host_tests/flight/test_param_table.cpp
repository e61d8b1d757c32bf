// The parameter table: CRC, byte format, every rejection reason, the store.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "table_bytes.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
using sinkwatch::test::Bytes;
using sinkwatch::test::encode_table;
using sinkwatch::test::fix_crc;
using sinkwatch::test::frame;
using sinkwatch::test::put_u16;
using sinkwatch::test::put_u32;
using sinkwatch::test::Section;
using sinkwatch::test::sections_of;

template <typename Qty>
Qty q(double v) {
  fx::Status st;
  return Qty(fx::from_double<typename Qty::q_type>(v, st));
}

RejectReason decode_bytes(const Bytes& b) {
  ParameterTable out{};
  return decode(b.data(), b.size(), out);
}

RoverParams moon_rover() { return yutu_like_rover_params(kGravityMoon); }

TEST(Crc32, CheckValue) {
  const std::string s = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0xCBF43926U);
  EXPECT_EQ(crc32(nullptr, 0U), 0U);
}

TEST(ParamTable, DefaultIsValidAndRoundTrips) {
  const ParameterTable t = default_parameter_table();
  EXPECT_EQ(validate(t), RejectReason::ok);
  const Bytes b = encode_table(t);
  // Sections 1..5, section 7 (sensor health, 24 bytes), section 8 (the
  // motion-resistance check, 20 bytes), then the CRC.
  EXPECT_EQ(b.size(), 16U + (4 + 4) + (4 + 20) + (4 + 4 + 5 * 20) + (4 + 44) + (4 + 20) + (4 + 24) + (4 + 20) + 4U);
  ParameterTable back{};
  ASSERT_EQ(decode(b.data(), b.size(), back), RejectReason::ok);
  EXPECT_EQ(encode_table(back), b);
  EXPECT_EQ(back.correction.rows[4].c3, t.correction.rows[4].c3);
  EXPECT_EQ(back.monitor.window_m, t.monitor.window_m);
  EXPECT_EQ(back.escape.freed_sinkage_m, t.escape.freed_sinkage_m);
  EXPECT_EQ(back.health.current_step_a, t.health.current_step_a);
  EXPECT_EQ(back.health.bridge_ms, t.health.bridge_ms);
  EXPECT_EQ(back.traction.stop_coefficient, t.traction.stop_coefficient);
  EXPECT_EQ(back.traction.trend_span_m, t.traction.trend_span_m);
}

TEST(ParamTable, ATableWithoutTheTractionSectionHasTheCheckOff) {
  ParameterTable t = default_parameter_table();
  t.traction = TractionParams{};
  EXPECT_EQ(validate(t), RejectReason::ok);
  const Bytes b = encode_table(t);
  EXPECT_EQ(b[12], 6U);  // section 8 left out: a table written before it existed
  ParameterTable back{};
  ASSERT_EQ(decode(b.data(), b.size(), back), RejectReason::ok);
  EXPECT_FALSE(traction_check_on(back.traction));
  EXPECT_EQ(encode_table(back), b);
}

TEST(ParamTable, TractionLevelsAndDistancesOutsideTheirRangesAreRejected) {
  struct Case {
    const char* what;
    void (*change)(TractionParams&);
    RejectReason expected;
  };
  const Case cases[] = {
      {"caution zero", [](TractionParams& p) { p.caution_coefficient = Ratio::zero(); },
       RejectReason::traction_level_out_of_range},
      {"caution above stop", [](TractionParams& p) { p.caution_coefficient = q<Ratio>(0.5); },
       RejectReason::traction_level_out_of_range},
      {"stop above 4", [](TractionParams& p) { p.stop_coefficient = q<Ratio>(4.5); },
       RejectReason::traction_level_out_of_range},
      {"hysteresis negative", [](TractionParams& p) { p.hysteresis = q<Ratio>(-0.01); },
       RejectReason::traction_level_out_of_range},
      {"hysteresis as large as caution", [](TractionParams& p) { p.hysteresis = p.caution_coefficient; },
       RejectReason::traction_level_out_of_range},
      {"lookahead negative", [](TractionParams& p) { p.lookahead_m = q<LengthM>(-1.0); },
       RejectReason::traction_distance_out_of_range},
      {"lookahead 11 m", [](TractionParams& p) { p.lookahead_m = q<LengthM>(11.0); },
       RejectReason::traction_distance_out_of_range},
      {"span 0.1 m", [](TractionParams& p) { p.trend_span_m = q<LengthM>(0.1); },
       RejectReason::traction_distance_out_of_range},
      {"span 6 m", [](TractionParams& p) { p.trend_span_m = q<LengthM>(6.0); },
       RejectReason::traction_distance_out_of_range},
  };
  for (const Case& c : cases) {
    ParameterTable t = default_parameter_table();
    c.change(t.traction);
    EXPECT_EQ(validate(t), c.expected) << c.what;
    EXPECT_EQ(decode_bytes(encode_table(t)), c.expected) << c.what;
  }
  ParameterTable t = default_parameter_table();
  t.traction.lookahead_m = LengthM::zero();  // the present coefficient only: allowed
  EXPECT_EQ(validate(t), RejectReason::ok);
}

TEST(ParamTable, ATableWithoutTheHealthSectionHasEveryCheckOff) {
  ParameterTable t = default_parameter_table();
  t.health = HealthParams{};
  t.traction = TractionParams{};
  const Bytes b = encode_table(t);
  EXPECT_EQ(b[12], 5U);  // sections 7 and 8 left out: a table written before they existed
  ParameterTable back{};
  ASSERT_EQ(decode(b.data(), b.size(), back), RejectReason::ok);
  EXPECT_EQ(back.health.policy, LossPolicy::stop);
  EXPECT_EQ(back.health.stuck_cycles, 0U);
  EXPECT_EQ(back.health.current_step_a, CurrentA::zero());
  EXPECT_EQ(encode_table(back), b);
}

TEST(ParamTable, HealthSectionReservedBytesAndPolicyAreChecked) {
  const Bytes good = encode_table(default_parameter_table());
  std::vector<Section> secs = sections_of(good);
  secs.pop_back();  // section 8: optional, not needed here
  ASSERT_EQ(secs.back().id, 7U);
  ParameterTable out{};
  Section bad_policy = secs.back();
  bad_policy.payload[0] = 2U;
  std::vector<Section> with_policy = secs;
  with_policy.back() = bad_policy;
  EXPECT_EQ(decode(frame(with_policy).data(), frame(with_policy).size(), out), RejectReason::health_policy_out_of_range);
  Section bad_reserved = secs.back();
  bad_reserved.payload[6] = 1U;
  std::vector<Section> with_reserved = secs;
  with_reserved.back() = bad_reserved;
  EXPECT_EQ(decode(frame(with_reserved).data(), frame(with_reserved).size(), out), RejectReason::reserved_not_zero);
  Section short_section = secs.back();
  short_section.payload.pop_back();
  std::vector<Section> with_short = secs;
  with_short.back() = short_section;
  EXPECT_EQ(decode(frame(with_short).data(), frame(with_short).size(), out), RejectReason::section_length_mismatch);
}

TEST(ParamTable, ByteLayoutIsLittleEndianAsDocumented) {
  const Bytes b = encode_table(default_parameter_table());
  EXPECT_EQ(Bytes(b.begin(), b.begin() + 4), (Bytes{'S', 'W', 'P', 'T'}));
  EXPECT_EQ(b[4], 1U);  // format version 1, little-endian
  EXPECT_EQ(b[5], 0U);
  EXPECT_EQ(b[8] | (b[9] << 8), static_cast<int>(b.size()));
  EXPECT_EQ(b[12], 7U);  // five sections, section 7 (sensor health) and 8 (motion resistance)
  // Section 1 at offset 16: id 1, length 4, radius 0.15 m in Q7.24 = 2516582 = 0x00266666.
  EXPECT_EQ(Bytes(b.begin() + 16, b.begin() + 24), (Bytes{1, 0, 4, 0, 0x66, 0x66, 0x26, 0x00}));
}

TEST(ParamTable, Eq15TableIsValid) { EXPECT_EQ(validate(eq15_parameter_table()), RejectReason::ok); }

TEST(ParamTable, RoverSectionIsCarriedTypedAndValidatedByDecode) {
  ParameterTable t = default_parameter_table();
  t.rover_geometry = RoverSection{true, moon_rover()};
  const Bytes b = encode_table(t);
  EXPECT_EQ(b[12], 8U);  // sections 1..8
  const std::vector<Section> secs = sections_of(b);
  ASSERT_EQ(secs[5].id, 6U);
  EXPECT_EQ(secs[5].payload.size(), kRoverSectionBytes);
  ParameterTable back{};
  ASSERT_EQ(decode(b.data(), b.size(), back), RejectReason::ok);
  EXPECT_TRUE(back.rover_geometry.present);
  EXPECT_EQ(back.rover_geometry.params.mass_kg, t.rover_geometry.params.mass_kg);
  EXPECT_EQ(back.rover_geometry.params.bogie_rear_axle.z_m, t.rover_geometry.params.bogie_rear_axle.z_m);
  EXPECT_EQ(encode_table(back), b);
  t.rover_geometry.params.mass_kg = MassKg::zero();
  EXPECT_EQ(decode_bytes(encode_table(t)), RejectReason::extension_rejected);
}

// Every validation reason, by changing one field of a good table.
struct Mutation {
  const char* name;
  std::function<void(ParameterTable&)> change;
  RejectReason expected;
};

std::vector<Mutation> mutations() {
  return {
      {"radius 0", [](ParameterTable& t) { t.wheel_radius_m = LengthM::zero(); }, RejectReason::radius_out_of_range},
      {"radius 3 m", [](ParameterTable& t) { t.wheel_radius_m = q<LengthM>(3.0); }, RejectReason::radius_out_of_range},
      {"gear 0", [](ParameterTable& t) { t.motor.gear_ratio = GearRatio::zero(); }, RejectReason::gear_ratio_out_of_range},
      {"gear 20000", [](ParameterTable& t) { t.motor.gear_ratio = q<GearRatio>(20000.0); }, RejectReason::gear_ratio_out_of_range},
      {"eta 0", [](ParameterTable& t) { t.motor.efficiency = Efficiency::zero(); }, RejectReason::efficiency_out_of_range},
      {"eta 1.1", [](ParameterTable& t) { t.motor.efficiency = q<Efficiency>(1.1); }, RejectReason::efficiency_out_of_range},
      {"Kt 0", [](ParameterTable& t) { t.motor.kt_nm_per_a = TorqueConstantNmPerA::zero(); }, RejectReason::torque_constant_out_of_range},
      {"Kt 5", [](ParameterTable& t) { t.motor.kt_nm_per_a = q<TorqueConstantNmPerA>(5.0); }, RejectReason::torque_constant_out_of_range},
      {"I0 < 0", [](ParameterTable& t) { t.motor.no_load_current_a = q<CurrentA>(-0.1); }, RejectReason::no_load_current_out_of_range},
      {"I0 200", [](ParameterTable& t) { t.motor.no_load_current_a = q<CurrentA>(200.0); }, RejectReason::no_load_current_out_of_range},
      {"Imax <= I0", [](ParameterTable& t) { t.motor.current_abs_max_a = t.motor.no_load_current_a; }, RejectReason::current_range_out_of_range},
      {"Imax 1500", [](ParameterTable& t) { t.motor.current_abs_max_a = q<CurrentA>(1500.0); }, RejectReason::current_range_out_of_range},
      {"rows 0", [](ParameterTable& t) { t.correction.count = 0; }, RejectReason::correction_count_out_of_range},
      {"rows 9", [](ParameterTable& t) { t.correction.count = 9; }, RejectReason::correction_count_out_of_range},
      {"load 0", [](ParameterTable& t) { t.correction.rows[0].load_n = WheelLoadN::zero(); }, RejectReason::load_breakpoint_out_of_range},
      {"load 31000", [](ParameterTable& t) { t.correction.rows[4].load_n = q<WheelLoadN>(31000.0); }, RejectReason::load_breakpoint_out_of_range},
      {"loads equal", [](ParameterTable& t) { t.correction.rows[2].load_n = t.correction.rows[1].load_n; }, RejectReason::load_breakpoints_not_increasing},
      {"C1 0.2", [](ParameterTable& t) { t.correction.rows[1].c1 = q<Ratio>(0.2); }, RejectReason::c1_out_of_range},
      {"C2 0", [](ParameterTable& t) { t.correction.rows[1].c2 = Ratio::zero(); }, RejectReason::c2_out_of_range},
      {"C2 -0.08 (Table 1 OLS)", [](ParameterTable& t) { t.correction.rows[0].c2 = q<Ratio>(-0.079); }, RejectReason::c2_out_of_range},
      {"C3 1.2", [](ParameterTable& t) { t.correction.rows[3].c3 = q<Ratio>(1.2); }, RejectReason::c3_out_of_range},
      {"DPmax 0", [](ParameterTable& t) { t.correction.rows[3].dp_max_ratio = Ratio::zero(); }, RejectReason::dp_max_out_of_range},
      {"allowed 0", [](ParameterTable& t) { t.monitor.allowed_sinkage_m = SinkageM::zero(); }, RejectReason::allowed_sinkage_out_of_range},
      {"allowed > r", [](ParameterTable& t) { t.monitor.allowed_sinkage_m = q<SinkageM>(0.2); }, RejectReason::allowed_sinkage_out_of_range},
      {"caution 0", [](ParameterTable& t) { t.monitor.caution_sinkage_m = SinkageM::zero(); }, RejectReason::caution_sinkage_out_of_range},
      {"caution >= stop", [](ParameterTable& t) { t.monitor.caution_sinkage_m = t.monitor.stop_sinkage_m; }, RejectReason::caution_sinkage_out_of_range},
      {"stop > r", [](ParameterTable& t) { t.monitor.stop_sinkage_m = q<SinkageM>(0.2); }, RejectReason::stop_sinkage_out_of_range},
      {"hysteresis >= caution", [](ParameterTable& t) { t.monitor.sinkage_hysteresis_m = t.monitor.caution_sinkage_m; }, RejectReason::sinkage_hysteresis_out_of_range},
      {"hysteresis < 0", [](ParameterTable& t) { t.monitor.sinkage_hysteresis_m = q<SinkageM>(-0.001); }, RejectReason::sinkage_hysteresis_out_of_range},
      {"fraction 0", [](ParameterTable& t) { t.monitor.current_caution_fraction = Ratio::zero(); }, RejectReason::current_caution_fraction_out_of_range},
      {"fraction 1.1", [](ParameterTable& t) { t.monitor.current_caution_fraction = q<Ratio>(1.1); }, RejectReason::current_caution_fraction_out_of_range},
      {"current hysteresis >= fraction", [](ParameterTable& t) { t.monitor.current_hysteresis_fraction = t.monitor.current_caution_fraction; }, RejectReason::current_hysteresis_out_of_range},
      {"load min 0", [](ParameterTable& t) { t.monitor.load_min_n = WheelLoadN::zero(); }, RejectReason::load_envelope_out_of_range},
      {"load max <= min", [](ParameterTable& t) { t.monitor.load_max_n = t.monitor.load_min_n; }, RejectReason::load_envelope_out_of_range},
      {"stale 0", [](ParameterTable& t) { t.monitor.stale_timeout_ms = 0; }, RejectReason::stale_timeout_out_of_range},
      {"stale 2 min", [](ParameterTable& t) { t.monitor.stale_timeout_ms = 120000; }, RejectReason::stale_timeout_out_of_range},
      {"window 0", [](ParameterTable& t) { t.monitor.window_m = 0; }, RejectReason::window_out_of_range},
      {"window 17", [](ParameterTable& t) { t.monitor.window_m = 17; }, RejectReason::window_out_of_range},
      {"trip > window", [](ParameterTable& t) { t.monitor.trip_n = 9; }, RejectReason::trip_count_out_of_range},
      {"trip 0", [](ParameterTable& t) { t.monitor.trip_n = 0; }, RejectReason::trip_count_out_of_range},
      {"clear 0", [](ParameterTable& t) { t.monitor.clear_n = 0; }, RejectReason::clear_count_out_of_range},
      {"invalid limit 0", [](ParameterTable& t) { t.monitor.invalid_to_stop = 0; }, RejectReason::invalid_limit_out_of_range},
      {"wheels 7", [](ParameterTable& t) { t.monitor.wheel_count = 7; }, RejectReason::wheel_count_out_of_range},
      {"k 0", [](ParameterTable& t) { t.monitor.rover_stop_k = 0; }, RejectReason::rover_stop_k_out_of_range},
      {"k > wheels", [](ParameterTable& t) { t.monitor.wheel_count = 4; t.monitor.rover_stop_k = 5; }, RejectReason::rover_stop_k_out_of_range},
      {"phase 50 ms", [](ParameterTable& t) { t.escape.forward_phase_ms = 50; }, RejectReason::escape_phase_out_of_range},
      {"reverse phase 20 min", [](ParameterTable& t) { t.escape.reverse_phase_ms = 1200000; }, RejectReason::escape_phase_out_of_range},
      {"cycles 0", [](ParameterTable& t) { t.escape.max_cycles = 0; }, RejectReason::escape_cycles_out_of_range},
      {"patience > cycles", [](ParameterTable& t) { t.escape.patience_cycles = 11; }, RejectReason::escape_patience_out_of_range},
      {"decrease < 0", [](ParameterTable& t) { t.escape.min_decrease_m = q<SinkageM>(-0.001); }, RejectReason::escape_decrease_out_of_range},
      {"freed 0", [](ParameterTable& t) { t.escape.freed_sinkage_m = SinkageM::zero(); }, RejectReason::escape_freed_out_of_range},
      {"freed >= stop", [](ParameterTable& t) { t.escape.freed_sinkage_m = t.monitor.stop_sinkage_m; }, RejectReason::escape_freed_out_of_range},
      {"health policy 2", [](ParameterTable& t) { t.health.policy = static_cast<LossPolicy>(2U); }, RejectReason::health_policy_out_of_range},
      {"blind wheels = wheels", [](ParameterTable& t) { t.health.max_blind_wheels = t.monitor.wheel_count; }, RejectReason::health_blind_wheels_out_of_range},
      {"current step < 0", [](ParameterTable& t) { t.health.current_step_a = q<CurrentA>(-0.1); }, RejectReason::health_step_out_of_range},
      {"current step > range", [](ParameterTable& t) { t.health.current_step_a = q<CurrentA>(11.0); }, RejectReason::health_step_out_of_range},
      {"attitude step 2 rad", [](ParameterTable& t) { t.health.attitude_step_rad = q<AngleRad>(2.0); }, RejectReason::health_step_out_of_range},
      {"joint step < 0", [](ParameterTable& t) { t.health.joint_step_rad = q<AngleRad>(-0.01); }, RejectReason::health_step_out_of_range},
      {"bridge 61 s", [](ParameterTable& t) { t.health.bridge_ms = 61000U; }, RejectReason::health_bridge_out_of_range},
      // Every field in its range, but N = 1, eta = 0.01, Kt = 0.0001 N m/A put
      // I_max = T_max / 1e-6 far beyond Q11.20's 2048 A at every load.
      {"weakest motor", [](ParameterTable& t) { t.motor.gear_ratio = q<GearRatio>(1.0); t.motor.efficiency = q<Efficiency>(0.01); t.motor.kt_nm_per_a = q<TorqueConstantNmPerA>(0.0001); }, RejectReason::envelope_overflow},
      {"rover mass 0", [](ParameterTable& t) { t.rover_geometry = RoverSection{true, moon_rover()}; t.rover_geometry.params.mass_kg = MassKg::zero(); }, RejectReason::extension_rejected},
      {"rover wheel 0.2 m", [](ParameterTable& t) { t.rover_geometry = RoverSection{true, moon_rover()}; t.rover_geometry.params.wheel_radius_m = q<LengthM>(0.2); }, RejectReason::rover_radius_mismatch},
  };
}

TEST(ParamTable, EveryRangeCheckRejectsWithItsReasonAndTheStoreKeepsItsTable) {
  std::set<RejectReason> covered;
  for (const Mutation& m : mutations()) {
    ParameterTable t = default_parameter_table();
    m.change(t);
    EXPECT_EQ(validate(t), m.expected) << m.name;
    Bytes b(kMaxTableBytes);
    const EncodeResult e = encode(t, b.data(), b.size());
    ASSERT_EQ(e.status, RejectReason::ok) << m.name;
    b.resize(e.size);
    ParameterStore store;
    const ParameterTable before = store.active();
    EXPECT_EQ(store.load(b.data(), b.size()), m.expected) << m.name;
    EXPECT_EQ(store.rejected_count(), 1U);
    EXPECT_EQ(store.last_rejection(), m.expected);
    EXPECT_EQ(encode_table(store.active()), encode_table(before)) << m.name;
    covered.insert(m.expected);
  }
  EXPECT_EQ(covered.size(), 39U);  // every validate() reason
}

// A table whose current limit fits at every breakpoint and at both ends of
// its load envelope, but not in between: on the segment from 15 kg to
// 30,000 N, L = r (DP_max/W + C3) + C2 z_max falls from 6.05 m to 0.045 m,
// so T_max = W L / C1 peaks near 15,000 N at about 45,000 N m, beyond
// Q15.16's 32,768 N m, while the ends give 890 and 1,350 N m. validate()
// bounds every segment (W_hi max|L| / min C1), so it is refused: the step
// would otherwise fail its estimate at every sample near the peak.
TEST(ParamTable, ACurrentLimitOverflowingInsideASegmentIsRefused) {
  ParameterTable t = default_parameter_table();
  t.wheel_radius_m = q<LengthM>(2.0);
  t.monitor.load_max_n = q<WheelLoadN>(30000.0);
  t.correction.rows[3].dp_max_ratio = q<Ratio>(2.0);
  t.correction.rows[3].c3 = q<Ratio>(1.0);
  t.correction.rows[4].load_n = q<WheelLoadN>(30000.0);
  t.correction.rows[4].dp_max_ratio = Ratio::from_raw(1);
  t.correction.rows[4].c3 = Ratio::zero();
  const CorrectionDivisors cd = make_correction_divisors(t.correction);
  const MotorDivisors md = make_motor_divisors(t.motor);
  const auto limit_at = [&](WheelLoadN w) {
    return current_limit(corrections_at(t.correction, cd, w), t.motor, md, t.wheel_radius_m, w,
                         t.monitor.allowed_sinkage_m)
        .status;
  };
  for (std::uint8_t i = 0U; i < t.correction.count; ++i) {
    EXPECT_EQ(limit_at(t.correction.rows[i].load_n), EstimateStatus::ok) << int{i};
  }
  EXPECT_EQ(limit_at(t.monitor.load_min_n), EstimateStatus::ok);
  EXPECT_EQ(limit_at(t.monitor.load_max_n), EstimateStatus::ok);
  EXPECT_EQ(limit_at(q<WheelLoadN>(15000.0)), EstimateStatus::overflow);
  EXPECT_EQ(validate(t), RejectReason::envelope_overflow);
  // The same table with the peak brought down (DP_max/W = 0.5, C3 = 0 at
  // 15 kg: L falls from 1.045 m, T_max peaks near 7,800 N m, I_max near
  // 1,300 A of Q11.20's 2,048) is accepted: the bound is not so loose as to
  // refuse it.
  t.correction.rows[3].dp_max_ratio = q<Ratio>(0.5);
  t.correction.rows[3].c3 = Ratio::zero();
  EXPECT_EQ(validate(t), RejectReason::ok);
}

TEST(ParamTable, TheSensorsWholeRangeMustGiveATorque) {
  ParameterTable t = default_parameter_table();
  t.motor.gear_ratio = q<GearRatio>(9000.0);
  t.motor.efficiency = q<Efficiency>(1.0);
  t.motor.current_abs_max_a = q<CurrentA>(1000.0);
  // N eta Kt I = 9000 x Kt x 1000 A: beyond Q15.16 for the default Kt.
  EXPECT_EQ(torque_from_current(t.motor, t.motor.current_abs_max_a, DriveDirection::forward).status,
            EstimateStatus::overflow);
  EXPECT_EQ(validate(t), RejectReason::envelope_overflow);
}

TEST(ParamTable, FramingRejections) {
  const Bytes good = encode_table(default_parameter_table());
  const std::vector<Section> secs = sections_of(good);
  ASSERT_EQ(secs.size(), 7U);  // sections 1..5, 7 and 8
  ASSERT_EQ(frame(secs), good);  // the test's framer agrees with encode()

  ParameterTable out{};
  EXPECT_EQ(decode(nullptr, 100, out), RejectReason::null_buffer);
  EXPECT_EQ(decode(good.data(), 10, out), RejectReason::too_short);
  Bytes big(kMaxTableBytes + 1, 0);
  EXPECT_EQ(decode_bytes(big), RejectReason::too_long);

  Bytes b = good;
  b[0] = 'X';
  EXPECT_EQ(decode_bytes(b), RejectReason::bad_magic);
  b = good;
  b[4] = 2;
  EXPECT_EQ(decode_bytes(b), RejectReason::unsupported_format_version);
  b = good;
  b.pop_back();
  EXPECT_EQ(decode_bytes(b), RejectReason::length_mismatch);
  b = good;
  b[14] = 1;
  EXPECT_EQ(decode_bytes(b), RejectReason::reserved_not_zero);
  b = good;
  b[20] ^= 0x01;  // one bit of the radius
  EXPECT_EQ(decode_bytes(b), RejectReason::crc_mismatch);

  // A section whose length runs past the end.
  b = good;
  put_u16(b, 18, 600);
  fix_crc(b);
  EXPECT_EQ(decode_bytes(b), RejectReason::section_truncated);
  // A section header cut by the CRC.
  std::vector<Section> s = secs;
  Bytes cut = frame(s);
  cut.insert(cut.end() - 4, {1, 0});
  put_u32(cut, 8, static_cast<std::uint32_t>(cut.size()));
  fix_crc(cut);
  EXPECT_EQ(decode_bytes(cut), RejectReason::section_truncated);

  s = secs;
  s[0].payload.push_back(0);  // radius section of 5 bytes
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::section_length_mismatch);
  s = secs;
  s.push_back({9, {1, 2, 3, 4}});
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::unknown_section);
  s = secs;
  s.push_back({0, {}});
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::unknown_section);
  s = secs;
  s.push_back(secs[0]);
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::duplicate_section);
  s = secs;
  s.erase(s.begin() + 4);  // no escape section (section 7 is optional)
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::missing_section);
  EXPECT_EQ(decode_bytes(frame(secs, 4)), RejectReason::section_count_mismatch);
  s = secs;
  s[3].payload[42] = 1;  // monitor section's reserved bytes
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::reserved_not_zero);
  s = secs;
  s[2].payload[0] = 0;  // zero correction rows
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::correction_count_out_of_range);
  s = secs;
  s[2].payload[0] = 4;  // four rows announced, five present
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::section_length_mismatch);
  s = secs;
  s.push_back({6, Bytes(300, 0)});  // section 6 is typed: 80 bytes or refused
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::section_length_mismatch);
  // Sections in another order are fine.
  s = secs;
  std::swap(s[0], s[4]);
  EXPECT_EQ(decode_bytes(frame(s)), RejectReason::ok);
}

TEST(ParamTable, EncoderChecksItsBuffer) {
  std::uint8_t small[10];
  EXPECT_EQ(encode(default_parameter_table(), small, sizeof small).status, RejectReason::buffer_too_small);
  EXPECT_EQ(encode(default_parameter_table(), nullptr, 100).status, RejectReason::null_buffer);
}

TEST(ParamTable, StoreAcceptsAGoodTableAndRemembersItsCrc) {
  ParameterTable t = default_parameter_table();
  t.table_version = 42;
  t.monitor.trip_n = 4;
  const Bytes b = encode_table(t);
  ParameterStore store;
  EXPECT_EQ(store.active_crc(), 0U);
  ASSERT_EQ(store.load(b.data(), b.size()), RejectReason::ok);
  EXPECT_EQ(store.active().table_version, 42U);
  EXPECT_EQ(store.active().monitor.trip_n, 4U);
  EXPECT_EQ(store.active_crc(), crc32(b.data(), b.size() - 4));
  // A bad one afterwards leaves this one in force.
  Bytes bad = b;
  bad[30] ^= 0xFF;
  EXPECT_EQ(store.load(bad.data(), bad.size()), RejectReason::crc_mismatch);
  EXPECT_EQ(store.active().table_version, 42U);
  EXPECT_EQ(store.rejected_count(), 1U);
}

}  // namespace
