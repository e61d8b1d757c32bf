// The names of the parameter-table reject reasons (param_table.hpp), for
// telemetry, the ground tools and the C interface (sw_reject_reason_name).
#include <cstdint>

#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace flight {
namespace {

/// Indexed by the enumerator's value.
constexpr const char* kReasonNames[kRejectReasonCount] = {
    "ok",
    "null_buffer",
    "too_short",
    "too_long",
    "bad_magic",
    "unsupported_format_version",
    "length_mismatch",
    "reserved_not_zero",
    "crc_mismatch",
    "section_truncated",
    "section_length_mismatch",
    "unknown_section",
    "duplicate_section",
    "missing_section",
    "section_count_mismatch",
    "radius_out_of_range",
    "gear_ratio_out_of_range",
    "efficiency_out_of_range",
    "torque_constant_out_of_range",
    "no_load_current_out_of_range",
    "current_range_out_of_range",
    "correction_count_out_of_range",
    "load_breakpoint_out_of_range",
    "load_breakpoints_not_increasing",
    "c1_out_of_range",
    "c2_out_of_range",
    "c3_out_of_range",
    "dp_max_out_of_range",
    "allowed_sinkage_out_of_range",
    "caution_sinkage_out_of_range",
    "stop_sinkage_out_of_range",
    "sinkage_hysteresis_out_of_range",
    "current_caution_fraction_out_of_range",
    "current_hysteresis_out_of_range",
    "load_envelope_out_of_range",
    "stale_timeout_out_of_range",
    "window_out_of_range",
    "trip_count_out_of_range",
    "clear_count_out_of_range",
    "invalid_limit_out_of_range",
    "wheel_count_out_of_range",
    "rover_stop_k_out_of_range",
    "escape_phase_out_of_range",
    "escape_cycles_out_of_range",
    "escape_patience_out_of_range",
    "escape_decrease_out_of_range",
    "escape_freed_out_of_range",
    "extension_too_long",
    "extension_rejected",
    "buffer_too_small",
    "rover_radius_mismatch",
    "health_policy_out_of_range",
    "health_blind_wheels_out_of_range",
    "health_step_out_of_range",
    "health_bridge_out_of_range",
    "envelope_overflow",
    "traction_level_out_of_range",
    "traction_distance_out_of_range",
};

}  // namespace

const char* reason_name(RejectReason reason) noexcept {
  const std::uint8_t index = static_cast<std::uint8_t>(reason);
  return (index < kRejectReasonCount) ? kReasonNames[index] : "unknown";
}

}  // namespace flight
}  // namespace sinkwatch
