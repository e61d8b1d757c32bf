// table_codec.hpp (private to the flight library): the one little-endian
// codec of the parameter table, as three visitors of the same field lists.
//
// Each section of the table lists its fields once, in byte order, as a
// `walk(visitor, section)` template (below; table_codec.cpp frames them into
// a table). The walk is run by
//   Encoder  writes every field to a bounded output buffer,
//   Decoder  reads every field from a bounded input buffer,
//   Sizer    counts the bytes (constexpr, so a section's size is a constant),
// so the writer, the reader and the size computation cannot disagree (the
// scheme of F´'s Serializable, with templates instead of virtual calls: no
// function pointer, no heap, no recursion; every loop is bounded by the
// section's own constant row count).
//
// The primitives: u8, u16, u32 little-endian; i32 as the two's-complement bit
// pattern through uint32 (int32 -> uint32 is defined modulo 2^32; the way back
// is to_i32(), which never converts an out-of-range value); every Q value is
// its raw i32. A reserved field writes 0 and the reader reports a non-zero
// one; a tag writes a constant and the reader reports another value; an enum
// is a u8 and the reader reports a value above the enum's last one. The first
// such report of a walk is kept (Decoder::verdict()).
#ifndef SINKWATCH_FLIGHT_TABLE_CODEC_HPP
#define SINKWATCH_FLIGHT_TABLE_CODEC_HPP

#include <cstddef>
#include <cstdint>

#include "sinkwatch/flight/byte_view.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace flight {
namespace codec {

/// The int32 whose two's-complement bit pattern is `u`, without an
/// implementation-defined conversion: above INT32_MAX, ~u is at most
/// INT32_MAX and -(~u) - 1 is the value (down to INT32_MIN).
[[nodiscard]] constexpr std::int32_t to_i32(std::uint32_t u) noexcept {
  if (u <= 0x7FFFFFFFU) {
    return static_cast<std::int32_t>(u);
  }
  return -static_cast<std::int32_t>(~u) - 1;
}

/// The bit pattern of `v` (the conversion to unsigned is modular, defined).
[[nodiscard]] constexpr std::uint32_t from_i32(std::int32_t v) noexcept { return static_cast<std::uint32_t>(v); }

static_assert(to_i32(0x80000000U) == (-2147483647 - 1), "INT32_MIN round trip");
static_assert(to_i32(0xFFFFFFFFU) == -1, "-1 round trip");
static_assert(to_i32(0x7FFFFFFFU) == 2147483647, "INT32_MAX round trip");
static_assert(from_i32(-1) == 0xFFFFFFFFU, "-1 bit pattern");

/// Writes fields; a write past the capacity writes nothing and sets full()
/// (encode() sizes the buffer with a Sizer first, so it never happens).
class Encoder {
 public:
  Encoder(std::uint8_t* out, std::size_t capacity) noexcept : out_(out, capacity) {}

  void u8(std::uint8_t v) noexcept {
    if (!out_.set(pos_, v)) {
      // GCOVR_EXCL_START defensive, unreachable: encode() sizes the buffer first (docs/coverage.md)
      full_ = true;
      return;
      // GCOVR_EXCL_STOP
    }
    ++pos_;
  }
  void u16(std::uint16_t v) noexcept {
    u8(static_cast<std::uint8_t>(v & 0xFFU));
    u8(static_cast<std::uint8_t>((static_cast<std::uint32_t>(v) >> 8U) & 0xFFU));
  }
  void u32(std::uint32_t v) noexcept {
    for (std::uint32_t k = 0U; k < 4U; ++k) {
      u8(static_cast<std::uint8_t>((v >> (8U * k)) & 0xFFU));
    }
  }
  void i32(std::int32_t v) noexcept { u32(from_i32(v)); }
  template <typename Quantity>
  void q(const Quantity& v) noexcept {
    i32(v.raw());
  }
  void reserved8() noexcept { u8(0U); }
  void reserved16() noexcept { u16(0U); }
  void tag16(std::uint16_t tag, RejectReason /*if_other*/) noexcept { u16(tag); }
  template <typename Enum>
  void enum8(const Enum& v, Enum /*last*/, RejectReason /*if_above*/) noexcept {
    u8(static_cast<std::uint8_t>(v));
  }
  /// A section's header: id, then the payload's length.
  void section(SectionId id, std::uint16_t length) noexcept {
    u16(static_cast<std::uint16_t>(id));
    u16(length);
  }

  [[nodiscard]] std::size_t pos() const noexcept { return pos_; }
  [[nodiscard]] bool full() const noexcept { return full_; }

 private:
  MutableByteView out_;
  std::size_t pos_{0U};
  bool full_{false};
};

/// Reads fields into the struct the walk names. A read past the end reads 0
/// (the decoder checks every length against the bytes left before it walks).
class Decoder {
 public:
  /// Reads `size` bytes at `in`, from byte `start` on.
  Decoder(const std::uint8_t* in, std::size_t size, std::size_t start = 0U) noexcept : in_(in, size), pos_(start) {}

  // Primitives that return the value (framing: header, section ids).
  std::uint8_t get_u8() noexcept {
    if (pos_ >= in_.size()) {
      return 0U;  // GCOVR_EXCL_LINE defensive, unreachable: decode() checks lengths first (docs/coverage.md)
    }
    const std::uint8_t v = in_.at(pos_);
    ++pos_;
    return v;
  }
  std::uint16_t get_u16() noexcept {
    const std::uint32_t lo = get_u8();
    const std::uint32_t hi = get_u8();
    return static_cast<std::uint16_t>(lo | (hi << 8U));
  }
  std::uint32_t get_u32() noexcept {
    std::uint32_t v = 0U;
    for (std::uint32_t k = 0U; k < 4U; ++k) {
      v |= static_cast<std::uint32_t>(get_u8()) << (8U * k);
    }
    return v;
  }

  // The visitor interface of the field lists.
  void u8(std::uint8_t& v) noexcept { v = get_u8(); }
  void u16(std::uint16_t& v) noexcept { v = get_u16(); }
  void u32(std::uint32_t& v) noexcept { v = get_u32(); }
  void i32(std::int32_t& v) noexcept { v = to_i32(get_u32()); }
  template <typename Quantity>
  void q(Quantity& v) noexcept {
    v = Quantity::from_raw(to_i32(get_u32()));
  }
  void reserved8() noexcept {
    if (get_u8() != 0U) {
      note(RejectReason::reserved_not_zero);
    }
  }
  void reserved16() noexcept {
    if (get_u16() != 0U) {
      note(RejectReason::reserved_not_zero);
    }
  }
  void tag16(std::uint16_t tag, RejectReason if_other) noexcept {
    if (get_u16() != tag) {
      note(if_other);
    }
  }
  /// A value above `last` leaves `v` as it was and is reported.
  template <typename Enum>
  void enum8(Enum& v, Enum last, RejectReason if_above) noexcept {
    const std::uint8_t raw = get_u8();
    if (raw > static_cast<std::uint8_t>(last)) {
      note(if_above);
      return;
    }
    v = static_cast<Enum>(raw);
  }

  /// The first report since the last verdict() (ok when none), then clears it.
  [[nodiscard]] RejectReason verdict() noexcept {
    const RejectReason r = first_;
    first_ = RejectReason::ok;
    return r;
  }
  [[nodiscard]] std::size_t pos() const noexcept { return pos_; }

 private:
  void note(RejectReason r) noexcept {
    if (first_ == RejectReason::ok) {
      first_ = r;
    }
  }

  ByteView in_;
  std::size_t pos_;
  RejectReason first_{RejectReason::ok};
};

/// Counts the bytes a walk writes, and the sections.
class Sizer {
 public:
  constexpr void u8(std::uint8_t /*v*/) noexcept { bytes_ += 1U; }
  constexpr void u16(std::uint16_t /*v*/) noexcept { bytes_ += 2U; }
  constexpr void u32(std::uint32_t /*v*/) noexcept { bytes_ += 4U; }
  constexpr void i32(std::int32_t /*v*/) noexcept { bytes_ += 4U; }
  template <typename Quantity>
  constexpr void q(const Quantity& /*v*/) noexcept {
    bytes_ += 4U;
  }
  constexpr void reserved8() noexcept { bytes_ += 1U; }
  constexpr void reserved16() noexcept { bytes_ += 2U; }
  constexpr void tag16(std::uint16_t /*tag*/, RejectReason /*if_other*/) noexcept { bytes_ += 2U; }
  template <typename Enum>
  constexpr void enum8(const Enum& /*v*/, Enum /*last*/, RejectReason /*if_above*/) noexcept {
    bytes_ += 1U;
  }
  constexpr void section(SectionId /*id*/, std::uint16_t /*length*/) noexcept {
    bytes_ += 4U;
    ++sections_;
  }

  [[nodiscard]] constexpr std::size_t bytes() const noexcept { return bytes_; }
  [[nodiscard]] constexpr std::uint16_t sections() const noexcept { return sections_; }

 private:
  std::size_t bytes_{0U};
  std::uint16_t sections_{0U};
};

// ---- the field lists -------------------------------------------------------
// One struct per section (and one for the table header), each with a single
// `walk`: the fields in byte order. `Section` is the struct or its const, so
// the same list serves the reader (which assigns) and the writers (which read).

/// The table header's values; the struct is the codec's, not the table's.
struct TableHeader {
  std::uint32_t magic{0U};
  std::uint16_t format_version{0U};
  std::uint16_t table_version{0U};
  std::uint32_t total_bytes{0U};
  std::uint16_t section_count{0U};
};

struct HeaderFields {
  template <typename V, typename H>
  static constexpr void walk(V& v, H& h) noexcept {
    v.u32(h.magic);
    v.u16(h.format_version);
    v.u16(h.table_version);
    v.u32(h.total_bytes);
    v.u16(h.section_count);
    v.reserved16();
  }
};

/// Section 1: the wheel radius of Eq. 15.
struct EstimatorFields {
  template <typename V, typename R>
  static constexpr void walk(V& v, R& radius_m) noexcept {
    v.q(radius_m);
  }
};

/// Section 2: MotorParams.
struct MotorFields {
  template <typename V, typename M>
  static constexpr void walk(V& v, M& m) noexcept {
    v.q(m.gear_ratio);
    v.q(m.efficiency);
    v.q(m.kt_nm_per_a);
    v.q(m.no_load_current_a);
    v.q(m.current_abs_max_a);
  }
};

/// Section 3, its head: the row count and padding.
struct CorrectionHeadFields {
  template <typename V, typename C>
  static constexpr void walk(V& v, C& c) noexcept {
    v.u8(c.count);
    v.reserved8();
    v.reserved16();
  }
};

/// Section 3, one row of Table 2.
struct CorrectionRowFields {
  template <typename V, typename R>
  static constexpr void walk(V& v, R& row) noexcept {
    v.q(row.load_n);
    v.q(row.c1);
    v.q(row.c2);
    v.q(row.c3);
    v.q(row.dp_max_ratio);
  }
};

/// Section 3 as the writers walk it: the head, then the rows. A count above
/// kMaxCorrectionRows is written as it is (a ground tool may build a bad table
/// on purpose) with kMaxCorrectionRows rows, which also bounds the loop. The
/// decoder walks the head and the rows apart, with the count and length
/// checks between them (read_correction below).
struct CorrectionFields {
  template <typename V, typename C>
  static constexpr void walk(V& v, C& c) noexcept {
    CorrectionHeadFields::walk(v, c);
    const std::uint8_t rows = (c.count > kMaxCorrectionRows) ? kMaxCorrectionRows : c.count;
    for (std::uint8_t i = 0U; i < rows; ++i) {
      CorrectionRowFields::walk(v, c.rows[i]);
    }
  }
};

/// Section 4: MonitorParams.
struct MonitorFields {
  template <typename V, typename M>
  static constexpr void walk(V& v, M& m) noexcept {
    v.q(m.allowed_sinkage_m);
    v.q(m.caution_sinkage_m);
    v.q(m.stop_sinkage_m);
    v.q(m.sinkage_hysteresis_m);
    v.q(m.current_caution_fraction);
    v.q(m.current_hysteresis_fraction);
    v.q(m.load_min_n);
    v.q(m.load_max_n);
    v.u32(m.stale_timeout_ms);
    v.u8(m.window_m);
    v.u8(m.trip_n);
    v.u8(m.clear_n);
    v.u8(m.invalid_to_stop);
    v.u8(m.wheel_count);
    v.u8(m.rover_stop_k);
    v.reserved16();
  }
};

/// Section 5: EscapeParams.
struct EscapeFields {
  template <typename V, typename E>
  static constexpr void walk(V& v, E& e) noexcept {
    v.u32(e.forward_phase_ms);
    v.u32(e.reverse_phase_ms);
    v.u8(e.max_cycles);
    v.u8(e.patience_cycles);
    v.reserved16();
    v.q(e.min_decrease_m);
    v.q(e.freed_sinkage_m);
  }
};

/// Section 6: RoverParams, after its layout version (rover_geometry.hpp).
struct RoverFields {
  template <typename V, typename P>
  static constexpr void walk(V& v, P& p) noexcept {
    v.tag16(kRoverSectionLayout, RejectReason::extension_rejected);
    v.reserved16();
    v.q(p.mass_kg);
    v.q(p.gravity_mps2);
    v.q(p.com_x_m);
    v.q(p.com_y_m);
    v.q(p.com_z_m);
    v.q(p.track_width_m);
    v.q(p.wheel_radius_m);
    v.q(p.rocker_front_axle.x_m);
    v.q(p.rocker_front_axle.z_m);
    v.q(p.rocker_bogie_pivot.x_m);
    v.q(p.rocker_bogie_pivot.z_m);
    v.q(p.bogie_middle_axle.x_m);
    v.q(p.bogie_middle_axle.z_m);
    v.q(p.bogie_rear_axle.x_m);
    v.q(p.bogie_rear_axle.z_m);
    v.q(p.rocker_limit_rad);
    v.q(p.bogie_limit_rad);
    v.q(p.attitude_limit_rad);
    v.q(p.high_slip);
  }
};

/// Section 7: HealthParams.
struct HealthFields {
  template <typename V, typename H>
  static constexpr void walk(V& v, H& h) noexcept {
    v.enum8(h.policy, LossPolicy::continue_degraded, RejectReason::health_policy_out_of_range);
    v.u8(h.stuck_cycles);
    v.u8(h.implausible_cycles);
    v.u8(h.recover_cycles);
    v.u8(h.max_blind_wheels);
    v.reserved8();
    v.reserved16();
    v.u32(h.bridge_ms);
    v.q(h.current_step_a);
    v.q(h.attitude_step_rad);
    v.q(h.joint_step_rad);
  }
};

/// Section 8: TractionParams.
struct TractionFields {
  template <typename V, typename P>
  static constexpr void walk(V& v, P& p) noexcept {
    v.q(p.caution_coefficient);
    v.q(p.stop_coefficient);
    v.q(p.hysteresis);
    v.q(p.lookahead_m);
    v.q(p.trend_span_m);
  }
};

/// The bytes of one walk of `Fields` over a value-initialised `Section`: the
/// size of a fixed-size section, as a compile-time constant.
template <typename Fields, typename Section>
[[nodiscard]] constexpr std::uint16_t fixed_bytes() noexcept {
  Sizer s{};
  Section probe{};
  Fields::walk(s, probe);
  return static_cast<std::uint16_t>(s.bytes());
}

}  // namespace codec
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_TABLE_CODEC_HPP
