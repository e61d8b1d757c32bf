// test_table_codec.cpp: the parameter table's one codec (flight/src/
// table_codec.hpp, private to the flight library): every section's field
// list, walked by the encoder, the decoder and the byte counter, agrees with
// itself at the extremes of every field (INT32_MIN and INT32_MAX in each Q
// value, negatives in section 6, 0xFF in every count), and encode(),
// encoded_size() and decode() agree on whole tables. The byte format itself
// is pinned by the golden table bytes (test_param_table.cpp, the calibration
// tests, host_tests/flight/golden): this file checks the machinery.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "table_bytes.hpp"
#include "table_codec.hpp"

namespace {

using namespace sinkwatch::flight;
using sinkwatch::test::Bytes;
using sinkwatch::test::encode_table;
using sinkwatch::test::sections_of;

constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();

/// A visitor that writes extreme values into every field a list names: the
/// Q values cycle through INT32_MIN, INT32_MAX, -1 and 1 (so that every
/// section sees negatives, both ends and both signs), the integers take
/// their maximum, an enum its last value.
class Extremes {
 public:
  void u8(std::uint8_t& v) noexcept { v = 0xFFU; }
  void u16(std::uint16_t& v) noexcept { v = 0xFFFFU; }
  void u32(std::uint32_t& v) noexcept { v = 0xFFFFFFFFU; }
  template <typename Quantity>
  void q(Quantity& v) noexcept {
    constexpr std::int32_t kCycle[4] = {kMin, kMax, -1, 1};
    v = Quantity::from_raw(kCycle[next_ % 4U]);
    ++next_;
  }
  void reserved8() noexcept {}
  void reserved16() noexcept {}
  void tag16(std::uint16_t /*tag*/, RejectReason /*if_other*/) noexcept {}
  template <typename Enum>
  void enum8(Enum& v, Enum last, RejectReason /*if_above*/) noexcept {
    v = last;
  }
  [[nodiscard]] unsigned quantities() const noexcept { return next_; }

 private:
  unsigned next_{0U};
};

/// Encodes `s` with Fields' list, checks the byte count against the Sizer's,
/// decodes into a fresh struct and returns both encodings (they must match).
template <typename Fields, typename Section>
void expect_round_trip(const Section& s, Section& back) {
  std::array<std::uint8_t, 256> first{};
  codec::Encoder e(first.data(), first.size());
  Fields::walk(e, s);
  codec::Sizer sizer{};
  Fields::walk(sizer, s);
  EXPECT_EQ(e.pos(), sizer.bytes());
  EXPECT_FALSE(e.full());

  codec::Decoder d(first.data(), e.pos());
  Fields::walk(d, back);
  EXPECT_EQ(d.pos(), e.pos());  // the reader takes exactly what the writer wrote
  EXPECT_EQ(d.verdict(), RejectReason::ok);

  std::array<std::uint8_t, 256> second{};
  codec::Encoder again(second.data(), second.size());
  Fields::walk(again, back);
  ASSERT_EQ(again.pos(), e.pos());
  EXPECT_EQ(first, second);
}

template <typename Fields, typename Section>
Section extremes_of() {
  Section s{};
  Extremes x;
  Fields::walk(x, s);
  EXPECT_GT(x.quantities(), 0U);
  return s;
}

TEST(TableCodec, TwosComplementPrimitivesRoundTripTheInt32Ends) {
  for (const std::int32_t v : {kMin, kMin + 1, -1, 0, 1, kMax - 1, kMax}) {
    EXPECT_EQ(codec::to_i32(codec::from_i32(v)), v) << v;
    std::array<std::uint8_t, 4> b{};
    codec::Encoder e(b.data(), b.size());
    e.i32(v);
    codec::Decoder d(b.data(), b.size());
    std::int32_t back = 0;
    d.i32(back);
    EXPECT_EQ(back, v) << v;
  }
  // INT32_MIN is 00 00 00 80 little-endian; -1 is FF FF FF FF.
  std::array<std::uint8_t, 8> b{};
  codec::Encoder e(b.data(), b.size());
  e.i32(kMin);
  e.i32(-1);
  EXPECT_EQ(b, (std::array<std::uint8_t, 8>{0x00, 0x00, 0x00, 0x80, 0xFF, 0xFF, 0xFF, 0xFF}));
}

TEST(TableCodec, EveryFixedSectionRoundTripsItsExtremes) {
  const LengthM radius = extremes_of<codec::EstimatorFields, LengthM>();
  LengthM radius_back{};
  expect_round_trip<codec::EstimatorFields>(radius, radius_back);
  EXPECT_EQ(radius_back.raw(), kMin);

  const MotorParams motor = extremes_of<codec::MotorFields, MotorParams>();
  MotorParams motor_back{};
  expect_round_trip<codec::MotorFields>(motor, motor_back);
  EXPECT_EQ(motor_back.efficiency.raw(), kMax);

  const MonitorParams monitor = extremes_of<codec::MonitorFields, MonitorParams>();
  MonitorParams monitor_back{};
  expect_round_trip<codec::MonitorFields>(monitor, monitor_back);
  EXPECT_EQ(monitor_back.stale_timeout_ms, 0xFFFFFFFFU);
  EXPECT_EQ(monitor_back.rover_stop_k, 0xFFU);

  const EscapeParams escape = extremes_of<codec::EscapeFields, EscapeParams>();
  EscapeParams escape_back{};
  expect_round_trip<codec::EscapeFields>(escape, escape_back);
  EXPECT_EQ(escape_back.min_decrease_m.raw(), kMin);

  const HealthParams health = extremes_of<codec::HealthFields, HealthParams>();
  HealthParams health_back{};
  expect_round_trip<codec::HealthFields>(health, health_back);
  EXPECT_EQ(health_back.policy, LossPolicy::continue_degraded);
  EXPECT_EQ(health_back.joint_step_rad.raw(), -1);  // the third Q field of the cycle
}

TEST(TableCodec, CorrectionRowsRoundTripTheirExtremes) {
  const CorrectionRow row = extremes_of<codec::CorrectionRowFields, CorrectionRow>();
  CorrectionRow row_back{};
  expect_round_trip<codec::CorrectionRowFields>(row, row_back);
  EXPECT_EQ(row_back.c2.raw(), -1);  // the third Q field of the cycle
  EXPECT_EQ(row_back.load_n.raw(), kMin);
  CorrectionTable table{};
  table.count = kMaxCorrectionRows;
  for (std::uint8_t i = 0U; i < kMaxCorrectionRows; ++i) {
    table.rows[i] = row;
  }
  codec::Sizer sizer{};
  codec::CorrectionFields::walk(sizer, table);
  EXPECT_EQ(sizer.bytes(), 4U + (20U * kMaxCorrectionRows));
}

TEST(TableCodec, RoverSectionRoundTripsNegativeAndExtremeValues) {
  RoverParams rover = extremes_of<codec::RoverFields, RoverParams>();
  rover.com_y_m = LengthM::from_raw(kMin);
  rover.rocker_bogie_pivot.z_m = LengthM::from_raw(-1);
  rover.bogie_rear_axle.x_m = LengthM::from_raw(kMax);
  RoverParams back{};
  expect_round_trip<codec::RoverFields>(rover, back);
  EXPECT_EQ(back.com_y_m.raw(), kMin);
  EXPECT_EQ(back.rocker_bogie_pivot.z_m.raw(), -1);
  EXPECT_EQ(back.bogie_rear_axle.x_m.raw(), kMax);
  EXPECT_EQ(back.mass_kg.raw(), kMin);
  EXPECT_EQ(back.high_slip.raw(), rover.high_slip.raw());
  EXPECT_EQ((codec::fixed_bytes<codec::RoverFields, RoverParams>()), kRoverSectionBytes);
}

TEST(TableCodec, RoverSectionBytesAreTheDocumentedLayout) {
  // u16 layout version, u16 zero, then the raw int32 of every field in
  // declaration order: com_y is the fourth field, at payload offset 16.
  ParameterTable t = default_parameter_table();
  t.rover_geometry = RoverSection{true, yutu_like_rover_params(kGravityMoon)};
  t.rover_geometry.params.com_y_m = LengthM::from_raw(-2);
  const std::vector<sinkwatch::test::Section> secs = sections_of(encode_table(t));
  const Bytes& payload = secs[5].payload;
  ASSERT_EQ(secs[5].id, 6U);
  EXPECT_EQ(Bytes(payload.begin(), payload.begin() + 4), (Bytes{1, 0, 0, 0}));
  EXPECT_EQ(Bytes(payload.begin() + 16, payload.begin() + 20), (Bytes{0xFE, 0xFF, 0xFF, 0xFF}));
}

TEST(TableCodec, DecoderReportsTheFirstBadReservedTagOrEnum) {
  // A health section whose policy is 2 and whose reserved byte is set: the
  // policy comes first in byte order and is the reported reason.
  std::array<std::uint8_t, 24> b{};
  b[0] = 2U;
  b[5] = 1U;
  codec::Decoder d(b.data(), b.size());
  HealthParams h{};
  codec::HealthFields::walk(d, h);
  EXPECT_EQ(d.verdict(), RejectReason::health_policy_out_of_range);
  EXPECT_EQ(h.policy, LossPolicy::stop);  // left as it was
  EXPECT_EQ(d.verdict(), RejectReason::ok);  // verdict() clears
  std::array<std::uint8_t, 80> r{};
  r[0] = 2U;  // layout version 2
  codec::Decoder rd(r.data(), r.size());
  RoverParams p{};
  codec::RoverFields::walk(rd, p);
  EXPECT_EQ(rd.verdict(), RejectReason::extension_rejected);
}

TEST(TableCodec, EncodeEncodedSizeAndDecodeAgreeOnWholeTables) {
  std::vector<ParameterTable> tables;
  tables.push_back(default_parameter_table());
  tables.push_back(eq15_parameter_table());
  ParameterTable no_health = default_parameter_table();
  no_health.health = HealthParams{};
  tables.push_back(no_health);
  ParameterTable with_rover = default_parameter_table();
  with_rover.rover_geometry = RoverSection{true, yutu_like_rover_params(kGravityMars)};
  tables.push_back(with_rover);
  ParameterTable oversized = default_parameter_table();
  oversized.correction.count = 200U;  // written with kMaxCorrectionRows rows
  tables.push_back(oversized);
  for (const ParameterTable& t : tables) {
    Bytes b(kMaxTableBytes);
    const EncodeResult e = encode(t, b.data(), b.size());
    ASSERT_EQ(e.status, RejectReason::ok);
    EXPECT_EQ(encoded_size(t), e.size);
    b.resize(e.size);
    EXPECT_EQ(table_crc(b.data(), b.size()), sinkwatch::flight::crc32(b.data(), b.size() - kTableCrcBytes));
    ParameterTable back{};
    if (decode(b.data(), b.size(), back) == RejectReason::ok) {
      EXPECT_EQ(encode_table(back), b);
    } else {
      EXPECT_EQ(t.correction.count, 200U);  // only the deliberately bad one is refused
    }
  }
  EXPECT_EQ(table_crc(nullptr, 8U), 0U);
  const Bytes any = encode_table(tables[0]);
  EXPECT_EQ(table_crc(any.data(), 3U), 0U);
}

}  // namespace
