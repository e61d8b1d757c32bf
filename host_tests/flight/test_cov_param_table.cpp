// test_cov_param_table.cpp: the parameter-table checks test_param_table.cpp
// does not reach: the per-section length checks, the reserved bytes of the
// correction and escape sections, the other end of every two-sided range
// check, an oversized correction table through the encoder, and the store's
// recovery after a rejection. Each case changes one thing of a good table
// and expects its own reason (param_table.hpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "quantity_support.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "table_bytes.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
using sinkwatch::test::q;
using sinkwatch::test::Bytes;
using sinkwatch::test::encode_table;
using sinkwatch::test::frame;
using sinkwatch::test::put_u16;
using sinkwatch::test::put_u32;
using sinkwatch::test::Section;
using sinkwatch::test::sections_of;

RejectReason decode_bytes(const Bytes& b) {
  ParameterTable out{};
  return decode(b.data(), b.size(), out);
}

// Index of the section with `id` in an encoded default table.
std::size_t index_of(const std::vector<Section>& s, SectionId id) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].id == static_cast<std::uint16_t>(id)) {
      return i;
    }
  }
  ADD_FAILURE() << "no section " << static_cast<int>(id);
  return 0;
}

class SectionEdit : public ::testing::Test {
 protected:
  const Bytes good_ = encode_table(default_parameter_table());
  std::vector<Section> secs_ = sections_of(good_);
  Bytes& payload(SectionId id) { return secs_[index_of(secs_, id)].payload; }
};

TEST_F(SectionEdit, TheFramerReproducesTheEncoder) { EXPECT_EQ(frame(secs_), good_); }

TEST_F(SectionEdit, MotorSectionOfTheWrongLengthIsRejected) {
  payload(SectionId::motor).push_back(0);
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, MonitorSectionOfTheWrongLengthIsRejected) {
  payload(SectionId::monitor).pop_back();
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, EscapeSectionOfTheWrongLengthIsRejected) {
  payload(SectionId::escape).push_back(0);
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, EstimatorSectionShorterThanARadiusIsRejected) {
  payload(SectionId::estimator).resize(2);
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, CorrectionSectionShorterThanItsHeaderIsRejected) {
  payload(SectionId::correction).resize(3);
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, CorrectionSectionWithMoreRowsAnnouncedThanPresentIsRejected) {
  payload(SectionId::correction)[0] = 6;  // five rows present
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, CorrectionSectionAnnouncingNineRowsIsACountError) {
  payload(SectionId::correction)[0] = 9;
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::correction_count_out_of_range);
}

TEST_F(SectionEdit, CorrectionReservedByteMustBeZero) {
  payload(SectionId::correction)[1] = 1;
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::reserved_not_zero);
}

TEST_F(SectionEdit, CorrectionReservedWordMustBeZero) {
  payload(SectionId::correction)[3] = 0x80;
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::reserved_not_zero);
}

TEST_F(SectionEdit, EscapeReservedWordMustBeZero) {
  payload(SectionId::escape)[10] = 1;  // after the two u32 phases and two u8 counts
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::reserved_not_zero);
}

TEST_F(SectionEdit, MonitorReservedWordMustBeZeroInItsHighByteToo) {
  payload(SectionId::monitor)[43] = 1;
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::reserved_not_zero);
}

TEST_F(SectionEdit, EmptyRoverSectionIsALengthMismatch) {
  secs_.push_back({static_cast<std::uint16_t>(SectionId::rover_geometry), {}});
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::section_length_mismatch);
}

TEST_F(SectionEdit, RoverSectionOfTheLayoutLengthWithZerosIsDecodedAndRefusedByValidation) {
  // Layout version 0 is the first field checked: the tag, not the values.
  secs_.push_back({static_cast<std::uint16_t>(SectionId::rover_geometry), Bytes(kRoverSectionBytes, 0U)});
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::extension_rejected);
  // With the right layout version, zero mass fails validate_rover_params().
  secs_.back().payload[0] = static_cast<std::uint8_t>(kRoverSectionLayout);
  EXPECT_EQ(decode_bytes(frame(secs_)), RejectReason::extension_rejected);
}

TEST(ParamTableDecode, OutputIsUntouchedWhenTheTableIsRejected) {
  ParameterTable t = default_parameter_table();
  t.monitor.window_m = 0;
  const Bytes b = encode_table(t);
  ParameterTable out{};
  out.table_version = 77;
  EXPECT_EQ(decode(b.data(), b.size(), out), RejectReason::window_out_of_range);
  EXPECT_EQ(out.table_version, 77U);
}

TEST(ParamTableEncode, OversizedCorrectionTableWritesEightRowsAndDecodeRefusesIt) {
  ParameterTable t = default_parameter_table();
  t.correction.count = 12;  // beyond kMaxCorrectionRows: encode() writes 8 rows
  Bytes b(kMaxTableBytes);
  const EncodeResult e = encode(t, b.data(), b.size());
  ASSERT_EQ(e.status, RejectReason::ok);
  b.resize(e.size);
  const std::vector<Section> s = sections_of(b);
  const Bytes& corr = s[index_of(s, SectionId::correction)].payload;
  EXPECT_EQ(corr.size(), 4U + (20U * kMaxCorrectionRows));
  EXPECT_EQ(corr[0], 12U);  // the count is written as given, for a test to see
  EXPECT_EQ(decode_bytes(b), RejectReason::correction_count_out_of_range);
}

TEST(ParamTableEncode, CapacityOneByteShortIsRefusedAndExactCapacityIsEnough) {
  const Bytes good = encode_table(default_parameter_table());
  Bytes b(good.size());
  EXPECT_EQ(encode(default_parameter_table(), b.data(), good.size() - 1U).status, RejectReason::buffer_too_small);
  const EncodeResult e = encode(default_parameter_table(), b.data(), b.size());
  EXPECT_EQ(e.status, RejectReason::ok);
  EXPECT_EQ(e.size, good.size());
  EXPECT_EQ(b, good);
}

// The other end of the two-sided checks, and the checks of a second field,
// which the table in test_param_table.cpp leaves out. One field changed per
// case; each must give exactly its own reason.
struct Mutation {
  const char* name;
  std::function<void(ParameterTable&)> change;
  RejectReason expected;
};

std::vector<Mutation> other_ends() {
  return {
      {"C1 4.5", [](ParameterTable& t) { t.correction.rows[2].c1 = q<Ratio>(4.5); }, RejectReason::c1_out_of_range},
      {"C2 5", [](ParameterTable& t) { t.correction.rows[2].c2 = q<Ratio>(5.0); }, RejectReason::c2_out_of_range},
      {"C3 -1.5", [](ParameterTable& t) { t.correction.rows[0].c3 = q<Ratio>(-1.5); }, RejectReason::c3_out_of_range},
      {"DPmax 2.5", [](ParameterTable& t) { t.correction.rows[4].dp_max_ratio = q<Ratio>(2.5); }, RejectReason::dp_max_out_of_range},
      {"DPmax < 0", [](ParameterTable& t) { t.correction.rows[4].dp_max_ratio = q<Ratio>(-0.5); }, RejectReason::dp_max_out_of_range},
      {"load < 0", [](ParameterTable& t) { t.correction.rows[0].load_n = q<WheelLoadN>(-1.0); }, RejectReason::load_breakpoint_out_of_range},
      {"loads falling", [](ParameterTable& t) { t.correction.rows[3].load_n = q<WheelLoadN>(50.0); }, RejectReason::load_breakpoints_not_increasing},
      {"gear 0.5", [](ParameterTable& t) { t.motor.gear_ratio = q<GearRatio>(0.5); }, RejectReason::gear_ratio_out_of_range},
      {"eta 0.005", [](ParameterTable& t) { t.motor.efficiency = q<Efficiency>(0.005); }, RejectReason::efficiency_out_of_range},
      {"Imax below I0", [](ParameterTable& t) { t.motor.current_abs_max_a = q<CurrentA>(0.05); }, RejectReason::current_range_out_of_range},
      {"allowed < 0", [](ParameterTable& t) { t.monitor.allowed_sinkage_m = q<SinkageM>(-0.01); }, RejectReason::allowed_sinkage_out_of_range},
      {"caution < 0", [](ParameterTable& t) { t.monitor.caution_sinkage_m = q<SinkageM>(-0.01); }, RejectReason::caution_sinkage_out_of_range},
      {"current hysteresis < 0", [](ParameterTable& t) { t.monitor.current_hysteresis_fraction = q<Ratio>(-0.01); }, RejectReason::current_hysteresis_out_of_range},
      {"fraction < 0", [](ParameterTable& t) { t.monitor.current_caution_fraction = q<Ratio>(-0.5); }, RejectReason::current_caution_fraction_out_of_range},
      {"load min < 0", [](ParameterTable& t) { t.monitor.load_min_n = q<WheelLoadN>(-1.0); }, RejectReason::load_envelope_out_of_range},
      {"load max 31000", [](ParameterTable& t) { t.monitor.load_max_n = q<WheelLoadN>(31000.0); }, RejectReason::load_envelope_out_of_range},
      {"clear > window", [](ParameterTable& t) { t.monitor.clear_n = 9; }, RejectReason::clear_count_out_of_range},
      {"wheels 0", [](ParameterTable& t) { t.monitor.wheel_count = 0; }, RejectReason::wheel_count_out_of_range},
      {"forward phase 20 min", [](ParameterTable& t) { t.escape.forward_phase_ms = 1200000; }, RejectReason::escape_phase_out_of_range},
      {"reverse phase 50 ms", [](ParameterTable& t) { t.escape.reverse_phase_ms = 50; }, RejectReason::escape_phase_out_of_range},
      {"cycles 101", [](ParameterTable& t) { t.escape.max_cycles = 101; }, RejectReason::escape_cycles_out_of_range},
      {"patience 0", [](ParameterTable& t) { t.escape.patience_cycles = 0; }, RejectReason::escape_patience_out_of_range},
      {"decrease >= stop", [](ParameterTable& t) { t.escape.min_decrease_m = t.monitor.stop_sinkage_m; }, RejectReason::escape_decrease_out_of_range},
      {"freed < 0", [](ParameterTable& t) { t.escape.freed_sinkage_m = q<SinkageM>(-0.01); }, RejectReason::escape_freed_out_of_range},
  };
}

TEST(ParamTableValidate, TheOtherEndOfEachRangeRejectsWithItsReason) {
  for (const Mutation& m : other_ends()) {
    ParameterTable t = default_parameter_table();
    m.change(t);
    EXPECT_EQ(validate(t), m.expected) << m.name;
    // The decoder reports the same reason for the same bytes.
    EXPECT_EQ(decode_bytes(encode_table(t)), m.expected) << m.name;
  }
}

TEST(ParamTableValidate, BoundaryValuesThemselvesAreAccepted) {
  ParameterTable t = default_parameter_table();
  t.correction.rows[0].c1 = q<Ratio>(0.25);
  t.correction.rows[1].c2 = q<Ratio>(4.0);
  t.correction.rows[2].c3 = q<Ratio>(-1.0);
  t.correction.rows[3].c3 = q<Ratio>(1.0);
  t.correction.rows[4].dp_max_ratio = q<Ratio>(2.0);
  t.motor.gear_ratio = q<GearRatio>(10000.0);
  t.motor.efficiency = q<Efficiency>(1.0);
  t.monitor.window_m = kMaxWindow;
  t.monitor.clear_n = kMaxWindow;
  t.monitor.stale_timeout_ms = 60000U;
  t.escape.forward_phase_ms = 100U;
  t.escape.reverse_phase_ms = 600000U;
  t.escape.max_cycles = 100U;
  t.escape.patience_cycles = 100U;
  t.escape.min_decrease_m = SinkageM::zero();
  t.rover_geometry = RoverSection{true, yutu_like_rover_params(kGravityMoon)};
  EXPECT_EQ(validate(t), RejectReason::ok);
  EXPECT_EQ(decode_bytes(encode_table(t)), RejectReason::ok);
}

TEST(ParamTableStore, GoodTableAfterARejectionClearsTheLastRejection) {
  ParameterStore store;
  ParameterTable bad = default_parameter_table();
  bad.escape.max_cycles = 0;
  const Bytes b = encode_table(bad);
  EXPECT_EQ(store.load(b.data(), b.size()), RejectReason::escape_cycles_out_of_range);
  EXPECT_EQ(store.last_rejection(), RejectReason::escape_cycles_out_of_range);
  EXPECT_EQ(store.load(nullptr, 10U), RejectReason::null_buffer);
  EXPECT_EQ(store.rejected_count(), 2U);
  ParameterTable good = default_parameter_table();
  good.table_version = 9;
  const Bytes g = encode_table(good);
  ASSERT_EQ(store.load(g.data(), g.size()), RejectReason::ok);
  EXPECT_EQ(store.last_rejection(), RejectReason::ok);
  EXPECT_EQ(store.rejected_count(), 2U);  // counts rejections only
  EXPECT_EQ(store.active().table_version, 9U);
  EXPECT_EQ(store.active_crc(), crc32(g.data(), g.size() - kTableCrcBytes));
}

}  // namespace
