// param_table.hpp: every configurable number of the flight module in one
// versioned, CRC-protected table, and its byte format.
//
// The table is uploaded as bytes (docs/flight.md, "Parameter table layout"):
//
//   header   16 bytes  magic "SWPT", format version, table version,
//                      total length, section count, reserved
//   sections           each: u16 id, u16 length, payload
//   trailer   4 bytes  CRC-32 (crc32.hpp) of every byte before it
//
// All integers little-endian, every Q value as its raw two's-complement
// integer, written byte by byte (never by memcpy of a struct, whose layout
// and endianness belong to the compiler). Each section's fields are listed
// once (param_table.cpp), and the encoder, the decoder and the size
// computation walk that one list (src/table_codec.hpp). Sections 1..5, 7 and 8
// are this module's parameters; section 6, optional, is the rover geometry
// (rover_geometry.hpp) as a typed section. A new section takes the next id.
//
// decode() checks the framing, the CRC and then every value's range
// (validate(), the rover section's included); each rejection has its own
// reason. ParameterStore keeps the table in force when a new one is rejected.
#ifndef SINKWATCH_FLIGHT_PARAM_TABLE_HPP
#define SINKWATCH_FLIGHT_PARAM_TABLE_HPP

#include <cstddef>
#include <cstdint>

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

constexpr std::uint8_t kMaxWheels = limits::kWheelCount;
/// Longest N-of-M window: the history is a 16-bit mask.
constexpr std::uint8_t kMaxWindow = 16U;
constexpr std::size_t kMaxTableBytes = 1024U;

constexpr std::uint8_t kTableMagic[4] = {0x53U, 0x57U, 0x50U, 0x54U};  // "SWPT"
constexpr std::uint16_t kTableFormatVersion = 1U;
constexpr std::size_t kTableHeaderBytes = 16U;
constexpr std::size_t kTableCrcBytes = 4U;

/// Section ids of the byte format. Append new ids; never renumber.
enum class SectionId : std::uint16_t {
  estimator = 1U,       ///< wheel radius
  motor = 2U,           ///< MotorParams
  correction = 3U,      ///< CorrectionTable
  monitor = 4U,         ///< MonitorParams
  escape = 5U,          ///< EscapeParams
  rover_geometry = 6U,  ///< RoverSection; optional: absent means the Yutu-like rover on the Moon (load.hpp)
  health = 7U,          ///< HealthParams; optional: absent means every check off
  traction = 8U,        ///< TractionParams; optional: absent means the check off
};

// Every field of the parameter structs defaults to zero: a zero count,
// window, timeout or phase fails validate(), so a table nobody filled in can
// never be put in force (fail-safe default, MISRA C++:2023 11.6.1).

/// Thresholds, persistence and fail-safe limits of the monitor (monitor.hpp).
struct MonitorParams {
  SinkageM allowed_sinkage_m{};         ///< z_max of section 7: sets the current limit
  SinkageM caution_sinkage_m{};         ///< estimate at or above: CAUTION evidence
  SinkageM stop_sinkage_m{};            ///< estimate at or above: STOP evidence
  SinkageM sinkage_hysteresis_m{};      ///< clear only below caution - hysteresis
  Ratio current_caution_fraction{};     ///< CAUTION evidence at I >= f * I_max (f <= 1)
  Ratio current_hysteresis_fraction{};  ///< clear only below (f - h) * I_max
  WheelLoadN load_min_n{};              ///< loads outside [min, max] are invalid telemetry
  WheelLoadN load_max_n{};
  std::uint32_t stale_timeout_ms{0U};   ///< a sample older than this is stale
  std::uint8_t window_m{0U};            ///< M: samples in the persistence window, 1..16
  std::uint8_t trip_n{0U};              ///< N: samples in the window needed to trip
  std::uint8_t clear_n{0U};             ///< clear samples in the window needed to leave CAUTION
  std::uint8_t invalid_to_stop{0U};     ///< consecutive unusable samples that force STOP
  std::uint8_t wheel_count{0U};         ///< wheels monitored, 1..kMaxWheels
  std::uint8_t rover_stop_k{0U};        ///< wheels in STOP that stop the rover (1 = any)
};

/// The alternating forward/reverse escape (escape.hpp).
struct EscapeParams {
  std::uint32_t forward_phase_ms{0U};
  std::uint32_t reverse_phase_ms{0U};
  std::uint8_t max_cycles{0U};         ///< forward+reverse pairs before giving up
  std::uint8_t patience_cycles{0U};    ///< consecutive cycles without progress before aborting
  SinkageM min_decrease_m{};           ///< progress: the sinkage fell by at least this per cycle
  SinkageM freed_sinkage_m{};          ///< at or below: the wheel is free
};

/// What the rover does when evidence is lost for good (section 7 of the table).
enum class LossPolicy : std::uint8_t {
  stop = 0U,               ///< a blind wheel stops after invalid_to_stop samples (fail-safe)
  continue_degraded = 1U,  ///< blind wheels held in CAUTION; stop when more than max_blind_wheels
};

/// Section 7: the sensor health checks (sensor_health.hpp). A zero cycle count or step switches that
/// check off (a sensor known to quantise coarsely); a table without section 7
/// has every check off and LossPolicy::stop, the behaviour before it existed.
struct HealthParams {
  LossPolicy policy{LossPolicy::stop};
  std::uint8_t stuck_cycles{0U};      ///< identical raw samples while driving: stuck (0: off)
  std::uint8_t implausible_cycles{0U};  ///< free-wheel or stall samples in a row (0: off)
  std::uint8_t recover_cycles{0U};    ///< good samples before `recovering` becomes `ok`
  std::uint8_t max_blind_wheels{0U};  ///< with continue_degraded: blind wheels tolerated
  std::uint32_t bridge_ms{0U};        ///< an IMU or joint fault bridged by the last good value
  CurrentA current_step_a{};          ///< |I - I_prev| beyond it: a spike (0: off)
  AngleRad attitude_step_rad{};       ///< |pitch or roll change| beyond it: a spike (0: off)
  AngleRad joint_step_rad{};          ///< |joint change| beyond it: a spike (0: off)
};

/// Section 8: the motion-resistance check (traction.hpp, docs/traction.md).
/// All zero (a table without section 8) switches it off, the behaviour
/// before it existed.
struct TractionParams {
  Ratio caution_coefficient{};  ///< rho ahead at or above: CAUTION evidence
  Ratio stop_coefficient{};     ///< rho ahead at or above: STOP evidence
  Ratio hysteresis{};           ///< clear only below caution - hysteresis
  LengthM lookahead_m{};        ///< how far ahead the rising trend is carried
  LengthM trend_span_m{};       ///< the travelled distance the trend is measured over
};

/// True when section 8 switches the check on (any field non-zero).
[[nodiscard]] constexpr bool traction_check_on(const TractionParams& p) noexcept {
  return (p.caution_coefficient.raw() != 0) || (p.stop_coefficient.raw() != 0) || (p.hysteresis.raw() != 0) ||
         (p.lookahead_m.raw() != 0) || (p.trend_span_m.raw() != 0);
}

/// Section 6: the rover geometry (rover_geometry.hpp, layout there), decoded
/// and validated (validate_rover_params()) with the rest of the table.
struct RoverSection {
  bool present{false};
  RoverParams params{};  ///< meaningful only when present
};

struct ParameterTable {
  std::uint16_t table_version{0U};  ///< the operators' revision number, echoed in telemetry
  LengthM wheel_radius_m{};
  MotorParams motor{};
  CorrectionTable correction{};
  MonitorParams monitor{};
  EscapeParams escape{};
  RoverSection rover_geometry{};  ///< section 6, written only when present
  HealthParams health{};  ///< section 7, written only when not all zero
  TractionParams traction{};  ///< section 8, written only when the check is on
};

/// Why a table was refused. One reason per check, so the ground knows which
/// number to fix.
enum class RejectReason : std::uint8_t {
  ok = 0U,
  // framing
  null_buffer,
  too_short,
  too_long,
  bad_magic,
  unsupported_format_version,
  length_mismatch,
  reserved_not_zero,
  crc_mismatch,
  section_truncated,
  section_length_mismatch,
  unknown_section,
  duplicate_section,
  missing_section,
  section_count_mismatch,
  // estimator and motor
  radius_out_of_range,
  gear_ratio_out_of_range,
  efficiency_out_of_range,
  torque_constant_out_of_range,
  no_load_current_out_of_range,
  current_range_out_of_range,
  // correction table
  correction_count_out_of_range,
  load_breakpoint_out_of_range,
  load_breakpoints_not_increasing,
  c1_out_of_range,
  c2_out_of_range,
  c3_out_of_range,
  dp_max_out_of_range,
  // monitor
  allowed_sinkage_out_of_range,
  caution_sinkage_out_of_range,
  stop_sinkage_out_of_range,
  sinkage_hysteresis_out_of_range,
  current_caution_fraction_out_of_range,
  current_hysteresis_out_of_range,
  load_envelope_out_of_range,
  stale_timeout_out_of_range,
  window_out_of_range,
  trip_count_out_of_range,
  clear_count_out_of_range,
  invalid_limit_out_of_range,
  wheel_count_out_of_range,
  rover_stop_k_out_of_range,
  // escape
  escape_phase_out_of_range,
  escape_cycles_out_of_range,
  escape_patience_out_of_range,
  escape_decrease_out_of_range,
  escape_freed_out_of_range,
  // section 6 (the values keep their numbers; the names are the C API's)
  extension_too_long,  ///< retired: section 6 is typed, a wrong length is section_length_mismatch
  extension_rejected,  ///< section 6: wrong layout version, or validate_rover_params() refuses it
  // encoder
  buffer_too_small,
  // the rover section's wheel radius (or, without one, the Yutu-like
  // rover's in load()) is not the table's: the statics and Eq. 15 must
  // describe the same wheel
  rover_radius_mismatch,
  // sensor health (section 7); appended, so that no value changes
  health_policy_out_of_range,
  health_blind_wheels_out_of_range,
  health_step_out_of_range,
  health_bridge_out_of_range,
  // the table's own numbers overflow a Q format within its envelope (the
  // torque of the sensor's largest current, or the current limit somewhere
  // in [load_min_n, load_max_n]); appended, so that no value changes
  envelope_overflow,
  // the motion-resistance check (section 8); appended
  traction_level_out_of_range,
  traction_distance_out_of_range,
};

/// Number of RejectReason values (for tests and telemetry tables).
constexpr std::uint8_t kRejectReasonCount =
    static_cast<std::uint8_t>(RejectReason::traction_distance_out_of_range) + 1U;

/// The enumerator's name ("crc_mismatch"); "unknown" for a value outside the
/// enum. Static storage.
[[nodiscard]] const char* reason_name(RejectReason reason) noexcept;

/// The default table: Table 2's corrections (C1 = C2 = 1, C3 = 0.20 .. 0.13
/// at 3..20 kg x 9.81 N/kg), r = 0.15 m and illustrative motor values
/// (docs/flight.md lists each value and where it comes from).
[[nodiscard]] ParameterTable default_parameter_table() noexcept;

/// The Eq. 15 variant of the default: C3 = 0.13 at every load.
[[nodiscard]] ParameterTable eq15_parameter_table() noexcept;

/// Every range check, in the order of the struct; the first failure is
/// returned. A present rover section is checked by validate_rover_params()
/// (extension_rejected) and must have the table's wheel radius
/// (rover_radius_mismatch). Last, the table's own envelope: the torque of
/// the sensor's largest current either way, and a bound of the section 7
/// current limit over every load of [load_min_n, load_max_n] (per segment of
/// the correction table: W_hi max|L| / min C1, docs/flight.md), must fit
/// their Q formats, else envelope_overflow. `ok` means every flight function
/// accepts the table.
[[nodiscard]] RejectReason validate(const ParameterTable& table) noexcept;

/// Parses and validates `size` bytes into `out` (every section, the rover
/// geometry of section 6 included, decoded once and validated once by
/// validate()). `out` is written only when the result is ok.
[[nodiscard]] RejectReason decode(const std::uint8_t* bytes, std::size_t size, ParameterTable& out) noexcept;

/// The CRC-32 trailer of a table's bytes: the last 4 bytes, little-endian,
/// which decode() checked against crc32() of the bytes before them. 0 for a
/// null buffer or fewer than 4 bytes. The CRC the ground quotes and the
/// telemetry echoes (PreparedParameters::table_crc()).
[[nodiscard]] std::uint32_t table_crc(const std::uint8_t* bytes, std::size_t size) noexcept;

/// The number of bytes encode() writes for `table`: the encoder's own walk
/// of the field lists, run by a byte counter.
[[nodiscard]] std::size_t encoded_size(const ParameterTable& table) noexcept;

struct EncodeResult {
  std::size_t size{0U};                                 ///< bytes written; 0 unless status == ok
  RejectReason status{RejectReason::buffer_too_small};  ///< ok, null_buffer or buffer_too_small
};

/// Writes the table's bytes into `out` (capacity bytes). Does not validate:
/// a ground tool may want to produce a bad table on purpose (tests); call
/// validate() first to refuse one.
[[nodiscard]] EncodeResult encode(const ParameterTable& table, std::uint8_t* out, std::size_t capacity) noexcept;

/// The table in force and the loader that replaces it only with a good one.
class ParameterStore {
 public:
  /// Starts with default_parameter_table().
  ParameterStore() noexcept;

  /// Decodes and validates; on ok the new table is in force, otherwise the
  /// old one stays and the reason is returned and remembered.
  RejectReason load(const std::uint8_t* bytes, std::size_t size) noexcept;


  [[nodiscard]] const ParameterTable& active() const& noexcept { return active_; }
  const ParameterTable& active() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// CRC of the bytes the active table came from (0 for the built-in default).
  [[nodiscard]] std::uint32_t active_crc() const noexcept { return active_crc_; }
  [[nodiscard]] std::uint32_t rejected_count() const noexcept { return rejected_count_; }
  [[nodiscard]] RejectReason last_rejection() const noexcept { return last_rejection_; }

 private:
  ParameterTable active_;
  std::uint32_t active_crc_;
  std::uint32_t rejected_count_;
  RejectReason last_rejection_;
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_PARAM_TABLE_HPP
