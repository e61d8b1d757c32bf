// sinkwatch_c.cpp: the C interface (sinkwatch.h) over the per-cycle step and
// the parameter-table loader. It only converts: raw Q integers to strong
// types on the way in, and back on the way out. No logic of its own, so that
// C callers get exactly the C++ module's behaviour.
//
// MISRA C++:2023 deviation D-03 (docs/misra.md): the context lives in storage
// the C caller owns (an 8-byte aligned union), so the state is constructed
// there with placement new and reached through a cast from void*. Size and
// alignment are checked at compile time; a magic word catches use before
// sw_init.
#include "sinkwatch/sinkwatch.h"

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>

#include "sinkwatch/flight/load.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"

namespace {

using sinkwatch::flight::AccelMps2;
using sinkwatch::flight::AngleRad;
using sinkwatch::flight::CurrentA;
using sinkwatch::flight::DriveDirection;
using sinkwatch::flight::PreparedParameters;
using sinkwatch::flight::RejectReason;
using sinkwatch::flight::RoverStep;
using sinkwatch::flight::RoverStepOutput;
using sinkwatch::flight::RoverTelemetry;
using sinkwatch::flight::SpeedMps;
using sinkwatch::flight::TimeMs;

constexpr std::uint32_t kContextMagic = 0x53574358U;  // "SWCX"

struct Context {
  std::uint32_t magic{0U};
  /// The table in force and its rover, checked once per load (load()): the
  /// step does no validation per cycle.
  PreparedParameters prepared;
  RoverStep step;
  /// The cycle's telemetry converted from C and the step's output: kept in
  /// the caller's storage, not on sw_step's stack (424 B on the M0 that the
  /// worst-case stack of a cycle would otherwise carry, docs/performance.md).
  RoverTelemetry telemetry;
  RoverStepOutput result;
};

static_assert(sizeof(Context) <= SW_CONTEXT_BYTES, "SW_CONTEXT_BYTES is too small for the flight state");
static_assert(alignof(Context) <= alignof(std::uint64_t), "sw_context's alignment is too weak");
static_assert(std::is_trivially_destructible<Context>::value, "the context is never destroyed, only rebuilt");
static_assert(SW_WHEELS == sinkwatch::flight::kWheelCount, "wheel count differs between C and C++");
static_assert(SW_STOP_RECORD_SAMPLES == sinkwatch::flight::kStopRecordSamples, "stop-record window differs between C and C++");

// Every sw_reject_reason is the RejectReason of the same name.
static_assert(SW_REJECT_OK == static_cast<int>(RejectReason::ok), "C and C++ reject reasons differ");
static_assert(SW_REJECT_NULL_BUFFER == static_cast<int>(RejectReason::null_buffer), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TOO_SHORT == static_cast<int>(RejectReason::too_short), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TOO_LONG == static_cast<int>(RejectReason::too_long), "C and C++ reject reasons differ");
static_assert(SW_REJECT_BAD_MAGIC == static_cast<int>(RejectReason::bad_magic), "C and C++ reject reasons differ");
static_assert(SW_REJECT_UNSUPPORTED_FORMAT_VERSION == static_cast<int>(RejectReason::unsupported_format_version), "C and C++ reject reasons differ");
static_assert(SW_REJECT_LENGTH_MISMATCH == static_cast<int>(RejectReason::length_mismatch), "C and C++ reject reasons differ");
static_assert(SW_REJECT_RESERVED_NOT_ZERO == static_cast<int>(RejectReason::reserved_not_zero), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CRC_MISMATCH == static_cast<int>(RejectReason::crc_mismatch), "C and C++ reject reasons differ");
static_assert(SW_REJECT_SECTION_TRUNCATED == static_cast<int>(RejectReason::section_truncated), "C and C++ reject reasons differ");
static_assert(SW_REJECT_SECTION_LENGTH_MISMATCH == static_cast<int>(RejectReason::section_length_mismatch), "C and C++ reject reasons differ");
static_assert(SW_REJECT_UNKNOWN_SECTION == static_cast<int>(RejectReason::unknown_section), "C and C++ reject reasons differ");
static_assert(SW_REJECT_DUPLICATE_SECTION == static_cast<int>(RejectReason::duplicate_section), "C and C++ reject reasons differ");
static_assert(SW_REJECT_MISSING_SECTION == static_cast<int>(RejectReason::missing_section), "C and C++ reject reasons differ");
static_assert(SW_REJECT_SECTION_COUNT_MISMATCH == static_cast<int>(RejectReason::section_count_mismatch), "C and C++ reject reasons differ");
static_assert(SW_REJECT_RADIUS_OUT_OF_RANGE == static_cast<int>(RejectReason::radius_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_GEAR_RATIO_OUT_OF_RANGE == static_cast<int>(RejectReason::gear_ratio_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_EFFICIENCY_OUT_OF_RANGE == static_cast<int>(RejectReason::efficiency_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TORQUE_CONSTANT_OUT_OF_RANGE == static_cast<int>(RejectReason::torque_constant_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_NO_LOAD_CURRENT_OUT_OF_RANGE == static_cast<int>(RejectReason::no_load_current_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CURRENT_RANGE_OUT_OF_RANGE == static_cast<int>(RejectReason::current_range_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CORRECTION_COUNT_OUT_OF_RANGE == static_cast<int>(RejectReason::correction_count_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_LOAD_BREAKPOINT_OUT_OF_RANGE == static_cast<int>(RejectReason::load_breakpoint_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_LOAD_BREAKPOINTS_NOT_INCREASING == static_cast<int>(RejectReason::load_breakpoints_not_increasing), "C and C++ reject reasons differ");
static_assert(SW_REJECT_C1_OUT_OF_RANGE == static_cast<int>(RejectReason::c1_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_C2_OUT_OF_RANGE == static_cast<int>(RejectReason::c2_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_C3_OUT_OF_RANGE == static_cast<int>(RejectReason::c3_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_DP_MAX_OUT_OF_RANGE == static_cast<int>(RejectReason::dp_max_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ALLOWED_SINKAGE_OUT_OF_RANGE == static_cast<int>(RejectReason::allowed_sinkage_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CAUTION_SINKAGE_OUT_OF_RANGE == static_cast<int>(RejectReason::caution_sinkage_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_STOP_SINKAGE_OUT_OF_RANGE == static_cast<int>(RejectReason::stop_sinkage_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_SINKAGE_HYSTERESIS_OUT_OF_RANGE == static_cast<int>(RejectReason::sinkage_hysteresis_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CURRENT_CAUTION_FRACTION_OUT_OF_RANGE == static_cast<int>(RejectReason::current_caution_fraction_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CURRENT_HYSTERESIS_OUT_OF_RANGE == static_cast<int>(RejectReason::current_hysteresis_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_LOAD_ENVELOPE_OUT_OF_RANGE == static_cast<int>(RejectReason::load_envelope_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_STALE_TIMEOUT_OUT_OF_RANGE == static_cast<int>(RejectReason::stale_timeout_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_WINDOW_OUT_OF_RANGE == static_cast<int>(RejectReason::window_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TRIP_COUNT_OUT_OF_RANGE == static_cast<int>(RejectReason::trip_count_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_CLEAR_COUNT_OUT_OF_RANGE == static_cast<int>(RejectReason::clear_count_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_INVALID_LIMIT_OUT_OF_RANGE == static_cast<int>(RejectReason::invalid_limit_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_WHEEL_COUNT_OUT_OF_RANGE == static_cast<int>(RejectReason::wheel_count_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ROVER_STOP_K_OUT_OF_RANGE == static_cast<int>(RejectReason::rover_stop_k_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ESCAPE_PHASE_OUT_OF_RANGE == static_cast<int>(RejectReason::escape_phase_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ESCAPE_CYCLES_OUT_OF_RANGE == static_cast<int>(RejectReason::escape_cycles_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ESCAPE_PATIENCE_OUT_OF_RANGE == static_cast<int>(RejectReason::escape_patience_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ESCAPE_DECREASE_OUT_OF_RANGE == static_cast<int>(RejectReason::escape_decrease_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ESCAPE_FREED_OUT_OF_RANGE == static_cast<int>(RejectReason::escape_freed_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_EXTENSION_TOO_LONG == static_cast<int>(RejectReason::extension_too_long), "C and C++ reject reasons differ");
static_assert(SW_REJECT_EXTENSION_REJECTED == static_cast<int>(RejectReason::extension_rejected), "C and C++ reject reasons differ");
static_assert(SW_REJECT_BUFFER_TOO_SMALL == static_cast<int>(RejectReason::buffer_too_small), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ROVER_RADIUS_MISMATCH == static_cast<int>(RejectReason::rover_radius_mismatch), "C and C++ reject reasons differ");
static_assert(SW_REJECT_HEALTH_POLICY_OUT_OF_RANGE == static_cast<int>(RejectReason::health_policy_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_HEALTH_BLIND_WHEELS_OUT_OF_RANGE == static_cast<int>(RejectReason::health_blind_wheels_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_HEALTH_STEP_OUT_OF_RANGE == static_cast<int>(RejectReason::health_step_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_HEALTH_BRIDGE_OUT_OF_RANGE == static_cast<int>(RejectReason::health_bridge_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_ENVELOPE_OVERFLOW == static_cast<int>(RejectReason::envelope_overflow), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TRACTION_LEVEL_OUT_OF_RANGE == static_cast<int>(RejectReason::traction_level_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_REJECT_TRACTION_DISTANCE_OUT_OF_RANGE == static_cast<int>(RejectReason::traction_distance_out_of_range), "C and C++ reject reasons differ");
static_assert(SW_SENSOR_CHANNELS == sinkwatch::flight::kSensorChannelCount, "C and C++ sensor channels differ");
static_assert(SW_CHANNEL_CLOCK == static_cast<int>(sinkwatch::flight::SensorChannel::clock), "C and C++ sensor channels differ");
static_assert(SW_HEALTH_RECOVERING == static_cast<int>(sinkwatch::flight::SensorHealth::recovering), "C and C++ sensor health differs");
static_assert(SW_SENSOR_LOST == static_cast<int>(sinkwatch::flight::RoverStepStatus::sensor_lost), "C and C++ step status differs");
static_assert(SW_REJECT_REASON_COUNT == sinkwatch::flight::kRejectReasonCount, "C and C++ reject reasons differ");


Context* context_of(sw_context* ctx) noexcept {
  Context* const c = static_cast<Context*>(static_cast<void*>(&ctx->opaque));
  return (c->magic == kContextMagic) ? c : nullptr;
}

const Context* context_of(const sw_context* ctx) noexcept {
  const Context* const c = static_cast<const Context*>(static_cast<const void*>(&ctx->opaque));
  return (c->magic == kContextMagic) ? c : nullptr;
}

std::uint8_t flag(bool value) noexcept { return value ? 1U : 0U; }

/// Every field of `t` from `in` (the context's record of the previous
/// cycle is overwritten whole).
void from_c(const sw_telemetry& in, RoverTelemetry& t) noexcept {
  t.time = TimeMs{in.time_ms};
  t.valid = in.valid != 0U;
  for (std::uint32_t i = 0U; i < SW_WHEELS; ++i) {
    t.current_a[i] = CurrentA::from_raw(in.current_a_q20[i]);
    // Anything but the two defined codes is passed on as an invalid
    // direction value, which the monitor reports instead of guessing.
    t.direction[i] = (in.direction[i] == SW_DIRECTION_FORWARD)   ? DriveDirection::forward
                     : (in.direction[i] == SW_DIRECTION_REVERSE) ? DriveDirection::reverse
                                                                 : static_cast<DriveDirection>(in.direction[i]);
  }
  t.attitude.pitch_rad = AngleRad::from_raw(in.pitch_rad_q28);
  t.attitude.roll_rad = AngleRad::from_raw(in.roll_rad_q28);
  for (std::uint32_t side = 0U; side < 2U; ++side) {
    t.joints.rocker_rad[side] = AngleRad::from_raw(in.rocker_rad_q28[side]);
    t.joints.bogie_rad[side] = AngleRad::from_raw(in.bogie_rad_q28[side]);
  }
  t.accel_valid = in.accel_valid != 0U;
  t.accel_mps2 = AccelMps2::from_raw(in.accel_mps2_q24);
  t.speed_valid = in.speed_valid != 0U;
  t.speed_mps = SpeedMps::from_raw(in.speed_mps_q24);
  t.rim_speed_valid = in.rim_speed_valid != 0U;
  t.rim_speed_mps = SpeedMps::from_raw(in.rim_speed_mps_q24);
  for (std::uint32_t i = 0U; i < SW_WHEELS; ++i) {
    t.presence.current_missing[i] = in.current_missing[i] != 0U;
  }
  t.presence.attitude_missing = in.attitude_missing != 0U;
  t.presence.joints_missing = in.joints_missing != 0U;
}

void to_c(const RoverStepOutput& r, sw_cycle_result& out) noexcept {
  out.status = static_cast<std::uint8_t>(r.status);
  out.decision = static_cast<std::uint8_t>(r.decision);
  out.loads_valid = flag(r.loads_valid);
  out.drawbar_valid = flag(r.drawbar_valid);
  out.wheels_in_stop = r.monitor.wheels_in_stop;
  out.wheels_in_caution = r.monitor.wheels_in_caution;
  out.wheels_blind = r.monitor.wheels_blind;
  out.degraded = flag(r.monitor.degraded);
  out.attitude_bridged = flag(r.health.attitude_bridged);
  out.joints_bridged = flag(r.health.joints_bridged);
  for (std::uint32_t c = 0U; c < SW_SENSOR_CHANNELS; ++c) {
    out.sensor_health[c] = static_cast<std::uint8_t>(r.health.channel[c]);
  }
  for (std::uint32_t i = 0U; i < SW_WHEELS; ++i) {
    const sinkwatch::flight::WheelOutput& w = r.monitor.wheels[i];
    sw_wheel_result& o = out.wheel[i];
    o.state = static_cast<std::uint8_t>(w.state);
    o.sample_status = static_cast<std::uint8_t>(w.sample_status);
    o.stop_reason = static_cast<std::uint8_t>(w.stop_reason);
    o.stop_tripped = flag(w.stop_tripped);
    o.estimate_valid = flag(w.estimate_valid);
    o.limit_valid = flag(w.limit_valid);
    o.load_n_q16 = r.load_n[i].raw();
    o.drawbar_pull_n_q16 = r.drawbar_pull_n[i].raw();
    o.torque_nm_q16 = w.torque_nm.raw();
    o.sinkage_m_q24 = w.sinkage_m.raw();
    o.current_limit_a_q20 = w.current_limit_a.raw();
  }
}

}  // namespace

extern "C" {

sw_status sw_init(sw_context* ctx) {
  if (ctx == nullptr) {
    return SW_NULL_ARGUMENT;
  }
  // D-03: constructed in the caller's storage, never deleted (trivially
  // destructible state, reused by the next sw_init). Context declares no
  // operator new, so this is the standard placement form (written without
  // "::", which cppcheck 2.10 misparses).
  void* const storage = static_cast<void*>(&ctx->opaque);
  Context* const c = new (storage) Context;  // NOLINT(cppcoreguidelines-owning-memory) D-03
  sinkwatch::flight::load_default(c->prepared);
  c->magic = kContextMagic;
  return SW_OK;
}

uint8_t sw_load_table(sw_context* ctx, const uint8_t* bytes, size_t size) {
  if (ctx == nullptr) {
    return static_cast<std::uint8_t>(RejectReason::null_buffer);
  }
  Context* const c = context_of(ctx);
  if (c == nullptr) {
    return static_cast<std::uint8_t>(RejectReason::null_buffer);
  }
  // load() writes the parameters only when it accepts the bytes: a rejected
  // table leaves the table and the rover in force.
  return static_cast<std::uint8_t>(sinkwatch::flight::load(bytes, size, c->prepared));
}

const char* sw_reject_reason_name(uint8_t reason) {
  return (reason < sinkwatch::flight::kRejectReasonCount)
             ? sinkwatch::flight::reason_name(static_cast<RejectReason>(reason))
             : "unknown";
}

uint32_t sw_active_table_crc(const sw_context* ctx) {
  if (ctx == nullptr) {
    return 0U;
  }
  const Context* const c = context_of(ctx);
  return (c == nullptr) ? 0U : c->prepared.table_crc();
}

sw_status sw_step(sw_context* ctx, const sw_telemetry* telemetry, uint32_t now_ms, sw_cycle_result* out) {
  if ((ctx == nullptr) || (telemetry == nullptr) || (out == nullptr)) {
    return SW_NULL_ARGUMENT;
  }
  Context* const c = context_of(ctx);
  if (c == nullptr) {
    return SW_NOT_INITIALISED;
  }
  from_c(*telemetry, c->telemetry);
  c->step.step(c->telemetry, TimeMs{now_ms}, c->prepared, c->result);
  to_c(c->result, *out);
  return static_cast<sw_status>(c->result.status);
}

void sw_clear_stop(sw_context* ctx) {
  if (ctx == nullptr) {
    return;
  }
  Context* const c = context_of(ctx);
  if (c != nullptr) {
    c->step.clear_stop();
  }
}

int sw_last_event(const sw_context* ctx, uint8_t wheel, sw_event* out) {
  if ((ctx == nullptr) || (out == nullptr) || (wheel >= SW_WHEELS)) {
    return 0;
  }
  const Context* const c = context_of(ctx);
  if (c == nullptr) {
    return 0;
  }
  const sinkwatch::flight::WheelMonitor& m = c->step.monitor().wheel(wheel);
  if (!m.has_event()) {
    return 0;
  }
  const sinkwatch::flight::EventRecord& e = m.last_event();
  out->wheel = e.wheel;
  out->reason = static_cast<std::uint8_t>(e.reason);
  out->peak_sinkage_valid = flag(e.peak_sinkage_valid);
  out->max_estimate_valid = flag(e.max_estimate_valid);
  out->time_ms = e.time.ms;
  out->peak_current_a_q20 = e.peak_current_a.raw();
  out->load_at_peak_n_q16 = e.load_at_peak_n.raw();
  out->peak_sinkage_m_q24 = e.peak_sinkage_m.raw();
  out->max_estimate_m_q24 = e.max_estimated_sinkage_m.raw();
  return 1;
}

int sw_last_stop(const sw_context* ctx, sw_stop_record* out) {
  if ((ctx == nullptr) || (out == nullptr)) {
    return 0;
  }
  const Context* const c = context_of(ctx);
  if ((c == nullptr) || !c->step.stops().has_record()) {
    return 0;
  }
  const sinkwatch::flight::RoverStopRecord& r = c->step.stops().last_record();
  out->time_ms = r.time.ms;
  out->reason = static_cast<std::uint8_t>(r.reason);
  out->deepest_wheel = r.deepest_wheel;
  out->samples = r.samples;
  out->sinkage_valid = flag(r.sinkage_valid);
  out->recent_sinkage_m_q24 = r.recent_sinkage_m.raw();
  return 1;
}

}  // extern "C"
