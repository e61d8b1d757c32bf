// The parameter table's byte format (param_table.hpp; the layout is drawn in
// docs/flight.md): every section's fields listed once, walked by the encoder,
// the decoder and the size computation (table_codec.hpp).
#include "table_codec.hpp"

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using codec::CorrectionFields;
using codec::CorrectionHeadFields;
using codec::CorrectionRowFields;
using codec::Decoder;
using codec::Encoder;
using codec::EscapeFields;
using codec::EstimatorFields;
using codec::fixed_bytes;
using codec::HeaderFields;
using codec::HealthFields;
using codec::TractionFields;
using codec::MonitorFields;
using codec::MotorFields;
using codec::RoverFields;
using codec::Sizer;
using codec::TableHeader;

// The byte format is the one of format version 1, unchanged by the field
// lists: these are its section sizes (docs/flight.md), and the golden table
// bytes of host_tests check every byte.
constexpr std::uint16_t kCorrectionHeadBytes = fixed_bytes<CorrectionHeadFields, CorrectionTable>();
constexpr std::uint16_t kCorrectionRowBytes = fixed_bytes<CorrectionRowFields, CorrectionRow>();
static_assert(fixed_bytes<HeaderFields, TableHeader>() == kTableHeaderBytes, "table header: 16 bytes");
static_assert(fixed_bytes<EstimatorFields, LengthM>() == 4U, "section 1: 4 bytes");
static_assert(fixed_bytes<MotorFields, MotorParams>() == 20U, "section 2: 20 bytes");
static_assert((kCorrectionHeadBytes == 4U) && (kCorrectionRowBytes == 20U), "section 3: 4 + 20 per row");
static_assert(fixed_bytes<MonitorFields, MonitorParams>() == 44U, "section 4: 44 bytes");
static_assert(fixed_bytes<EscapeFields, EscapeParams>() == 20U, "section 5: 20 bytes");
static_assert(fixed_bytes<RoverFields, RoverParams>() == kRoverSectionBytes, "section 6: 80 bytes");
static_assert(fixed_bytes<HealthFields, HealthParams>() == 24U, "section 7: 24 bytes");
static_assert(fixed_bytes<TractionFields, TractionParams>() == 20U, "section 8: 20 bytes");
// Eight section headers, every section at its largest, header and CRC.
constexpr std::size_t kLargestTableBytes = kTableHeaderBytes + (std::size_t{8U} * std::size_t{4U}) +
                                           std::size_t{4U + 20U + 4U} +
                                           (std::size_t{kMaxCorrectionRows} * std::size_t{20U}) +
                                           std::size_t{44U + 20U + 80U + 24U + 20U} + kTableCrcBytes;
static_assert(kLargestTableBytes <= kMaxTableBytes, "the largest table fits the decoder's limit");

// ---- writers: encoder and size ------------------------------------------------

/// Section 7: a table whose health checks are all zero (off) leaves it out,
/// so that tables written before it existed keep their bytes.
bool health_present(const HealthParams& h) noexcept {
  return (h.policy != LossPolicy::stop) || (h.stuck_cycles != 0U) || (h.implausible_cycles != 0U) ||
         (h.recover_cycles != 0U) || (h.max_blind_wheels != 0U) || (h.bridge_ms != 0U) ||
         (h.current_step_a.raw() != 0) || (h.attitude_step_rad.raw() != 0) || (h.joint_step_rad.raw() != 0);
}

/// One section: its header (the payload's length counted by a Sizer walk of
/// the same list), then the payload.
template <typename Fields, typename V, typename Section>
void put_section(V& v, SectionId id, const Section& s) noexcept {
  Sizer payload{};
  Fields::walk(payload, s);
  v.section(id, static_cast<std::uint16_t>(payload.bytes()));
  Fields::walk(v, s);
}

/// Every section of `t` in id order, the optional ones when present: run by
/// a Sizer for the total length and the count, then by the Encoder.
template <typename V>
void put_sections(V& v, const ParameterTable& t) noexcept {
  put_section<EstimatorFields>(v, SectionId::estimator, t.wheel_radius_m);
  put_section<MotorFields>(v, SectionId::motor, t.motor);
  put_section<CorrectionFields>(v, SectionId::correction, t.correction);
  put_section<MonitorFields>(v, SectionId::monitor, t.monitor);
  put_section<EscapeFields>(v, SectionId::escape, t.escape);
  if (t.rover_geometry.present) {
    put_section<RoverFields>(v, SectionId::rover_geometry, t.rover_geometry.params);
  }
  if (health_present(t.health)) {
    put_section<HealthFields>(v, SectionId::health, t.health);
  }
  if (traction_check_on(t.traction)) {
    put_section<TractionFields>(v, SectionId::traction, t.traction);
  }
}

// "SWPT" as the little-endian u32 of kTableMagic's four bytes.
constexpr std::uint32_t kTableMagicWord =
    static_cast<std::uint32_t>(kTableMagic[0]) | (static_cast<std::uint32_t>(kTableMagic[1]) << 8U) |
    (static_cast<std::uint32_t>(kTableMagic[2]) << 16U) | (static_cast<std::uint32_t>(kTableMagic[3]) << 24U);

}  // namespace

std::size_t encoded_size(const ParameterTable& t) noexcept {
  Sizer s{};
  put_sections(s, t);
  return kTableHeaderBytes + s.bytes() + kTableCrcBytes;
}

EncodeResult encode(const ParameterTable& t, std::uint8_t* out, std::size_t capacity) noexcept {
  if (out == nullptr) {
    return EncodeResult{0U, RejectReason::null_buffer};
  }
  Sizer sections{};
  put_sections(sections, t);
  const std::size_t total = kTableHeaderBytes + sections.bytes() + kTableCrcBytes;
  if (total > capacity) {
    return EncodeResult{0U, RejectReason::buffer_too_small};
  }
  Encoder e(out, capacity);
  const TableHeader header{kTableMagicWord, kTableFormatVersion, t.table_version, static_cast<std::uint32_t>(total),
                           sections.sections()};
  HeaderFields::walk(e, header);
  put_sections(e, t);
  const std::uint32_t crc = crc32(out, e.pos());
  e.u32(crc);
  if (e.full() || (e.pos() != total)) {
    // GCOVR_EXCL_START defensive, unreachable: sized above (docs/coverage.md)
    return EncodeResult{0U, RejectReason::buffer_too_small};
    // GCOVR_EXCL_STOP
  }
  return EncodeResult{total, RejectReason::ok};
}

std::uint32_t table_crc(const std::uint8_t* bytes, std::size_t size) noexcept {
  if ((bytes == nullptr) || (size < kTableCrcBytes)) {
    return 0U;
  }
  Decoder d(bytes, size, size - kTableCrcBytes);
  return d.get_u32();
}

namespace {

// ---- reader -------------------------------------------------------------------

constexpr std::uint16_t kMaxSectionId = 8U;
constexpr std::uint16_t kCoreSections = 5U;
// Bit id of a section set, ids 1..kCoreSections: the sections every table has.
constexpr std::uint32_t kCoreSectionBits = (1U << (kCoreSections + 1U)) - 2U;
constexpr std::size_t kSectionHeaderBytes = 4U;

// The header after the size checks, its checks in byte order.
RejectReason read_table_header(Decoder& d, std::size_t size, std::uint16_t& table_version,
                               std::uint16_t& section_count) noexcept {
  TableHeader h{};
  HeaderFields::walk(d, h);
  const RejectReason reserved = d.verdict();
  if (h.magic != kTableMagicWord) {
    return RejectReason::bad_magic;
  }
  if (h.format_version != kTableFormatVersion) {
    return RejectReason::unsupported_format_version;
  }
  if (h.total_bytes != size) {
    return RejectReason::length_mismatch;
  }
  table_version = h.table_version;
  section_count = h.section_count;
  return reserved;
}

/// A fixed-size section: the length must be the list's, then one walk; the
/// walk's first report (reserved byte, tag, enum) is the section's verdict.
template <typename Fields, typename Section>
RejectReason read_fixed(Decoder& d, std::uint16_t length, Section& s) noexcept {
  constexpr std::uint16_t kBytes = fixed_bytes<Fields, Section>();
  if (length != kBytes) {
    return RejectReason::section_length_mismatch;
  }
  Fields::walk(d, s);
  return d.verdict();
}

RejectReason read_correction(Decoder& d, std::uint16_t length, CorrectionTable& c) noexcept {
  if (length < kCorrectionHeadBytes) {
    return RejectReason::section_length_mismatch;
  }
  CorrectionHeadFields::walk(d, c);
  const RejectReason reserved = d.verdict();
  // The row count's range and the length it implies come before the
  // reserved bytes: a wrong count is the more useful reason.
  if ((c.count == 0U) || (c.count > kMaxCorrectionRows)) {
    return RejectReason::correction_count_out_of_range;
  }
  if (length != (kCorrectionHeadBytes + (kCorrectionRowBytes * c.count))) {
    return RejectReason::section_length_mismatch;
  }
  for (std::uint8_t i = 0U; i < c.count; ++i) {
    CorrectionRowFields::walk(d, c.rows[i]);
  }
  return reserved;
}

RejectReason read_rover(Decoder& d, std::uint16_t length, RoverSection& rover) noexcept {
  const RejectReason reason = read_fixed<RoverFields>(d, length, rover.params);
  rover.present = (reason == RejectReason::ok);
  return reason;
}

RejectReason read_section_payload(Decoder& d, SectionId id, std::uint16_t length, ParameterTable& t) noexcept {
  switch (id) {
    case SectionId::estimator:
      return read_fixed<EstimatorFields>(d, length, t.wheel_radius_m);
    case SectionId::motor:
      return read_fixed<MotorFields>(d, length, t.motor);
    case SectionId::correction:
      return read_correction(d, length, t.correction);
    case SectionId::monitor:
      return read_fixed<MonitorFields>(d, length, t.monitor);
    case SectionId::escape:
      return read_fixed<EscapeFields>(d, length, t.escape);
    case SectionId::rover_geometry:
      return read_rover(d, length, t.rover_geometry);
    case SectionId::health:
      return read_fixed<HealthFields>(d, length, t.health);
    case SectionId::traction:
      return read_fixed<TractionFields>(d, length, t.traction);
    // GCOVR_EXCL_START MISRA 16.4.1's default; read_section() refuses other ids first (docs/coverage.md)
    default:
      return RejectReason::unknown_section;
      // GCOVR_EXCL_STOP
  }
}

// One section, header and payload; `d` stands at its header, `crc_at` is
// where the sections end. `seen` collects bit id of every section read.
RejectReason read_section(Decoder& d, std::size_t crc_at, ParameterTable& t, std::uint32_t& seen) noexcept {
  if ((crc_at - d.pos()) < kSectionHeaderBytes) {
    return RejectReason::section_truncated;
  }
  const std::uint16_t id = d.get_u16();
  const std::uint16_t length = d.get_u16();
  if ((crc_at - d.pos()) < length) {
    return RejectReason::section_truncated;
  }
  if ((id == 0U) || (id > kMaxSectionId)) {
    return RejectReason::unknown_section;
  }
  const std::uint32_t bit = 1U << static_cast<std::uint32_t>(id);
  if ((seen & bit) != 0U) {
    return RejectReason::duplicate_section;
  }
  seen |= bit;
  const std::size_t start = d.pos();
  const RejectReason reason = read_section_payload(d, static_cast<SectionId>(id), length, t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  if ((d.pos() - start) != length) {
    // GCOVR_EXCL_START defensive, unreachable: lengths checked per id (docs/coverage.md)
    return RejectReason::section_length_mismatch;
    // GCOVR_EXCL_STOP
  }
  return RejectReason::ok;
}

// Every section up to the CRC, then the count and the core sections.
RejectReason read_sections(Decoder& d, std::size_t crc_at, std::uint16_t section_count, ParameterTable& t) noexcept {
  // At most one section per id, ids 1..8, so at most 8 iterations do work;
  // the loop bound also covers a corrupt count that passed the CRC.
  std::uint32_t seen = 0U;
  std::uint16_t parsed = 0U;
  while ((d.pos() < crc_at) && (parsed <= kMaxSectionId)) {
    const RejectReason reason = read_section(d, crc_at, t, seen);
    if (reason != RejectReason::ok) {
      return reason;
    }
    ++parsed;
  }
  if ((d.pos() != crc_at) || (parsed != section_count)) {
    return RejectReason::section_count_mismatch;
  }
  if ((seen & kCoreSectionBits) != kCoreSectionBits) {
    return RejectReason::missing_section;
  }
  return RejectReason::ok;
}

}  // namespace

RejectReason decode(const std::uint8_t* bytes, std::size_t size, ParameterTable& out) noexcept {
  if (bytes == nullptr) {
    return RejectReason::null_buffer;
  }
  if (size < (kTableHeaderBytes + kTableCrcBytes)) {
    return RejectReason::too_short;
  }
  if (size > kMaxTableBytes) {
    return RejectReason::too_long;
  }
  Decoder d(bytes, size);
  ParameterTable t{};
  std::uint16_t section_count = 0U;
  RejectReason reason = read_table_header(d, size, t.table_version, section_count);
  if (reason != RejectReason::ok) {
    return reason;
  }
  const std::size_t crc_at = size - kTableCrcBytes;
  if (table_crc(bytes, size) != crc32(bytes, crc_at)) {
    return RejectReason::crc_mismatch;
  }
  reason = read_sections(d, crc_at, section_count, t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  // The one validation of every value, section 6's rover included.
  reason = validate(t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  out = t;
  return RejectReason::ok;
}

}  // namespace flight
}  // namespace sinkwatch
