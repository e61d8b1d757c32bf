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

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"

namespace {

using sinkwatch::flight::AccelMps2;
using sinkwatch::flight::AngleRad;
using sinkwatch::flight::CurrentA;
using sinkwatch::flight::DriveDirection;
using sinkwatch::flight::ParameterStore;
using sinkwatch::flight::PreparedParameters;
using sinkwatch::flight::RejectReason;
using sinkwatch::flight::RoverParams;
using sinkwatch::flight::RoverParamStatus;
using sinkwatch::flight::RoverStep;
using sinkwatch::flight::RoverStepOutput;
using sinkwatch::flight::RoverTelemetry;
using sinkwatch::flight::SpeedMps;
using sinkwatch::flight::TimeMs;

constexpr std::uint32_t kContextMagic = 0x53574358U;  // "SWCX"

struct Context {
  std::uint32_t magic{0U};
  ParameterStore store;
  RoverParams rover;
  /// store.active() and rover, checked once per load (prepare()): the step
  /// does no validation per cycle.
  PreparedParameters prepared;
  RoverStep step;
};

static_assert(sizeof(Context) <= SW_CONTEXT_BYTES, "SW_CONTEXT_BYTES is too small for the flight state");
static_assert(alignof(Context) <= alignof(std::uint64_t), "sw_context's alignment is too weak");
static_assert(std::is_trivially_destructible<Context>::value, "the context is never destroyed, only rebuilt");
static_assert(SW_WHEELS == sinkwatch::flight::kWheelCount, "wheel count differs between C and C++");

Context* context_of(sw_context* ctx) noexcept {
  Context* const c = static_cast<Context*>(static_cast<void*>(&ctx->opaque));
  return (c->magic == kContextMagic) ? c : nullptr;
}

const Context* context_of(const sw_context* ctx) noexcept {
  const Context* const c = static_cast<const Context*>(static_cast<const void*>(&ctx->opaque));
  return (c->magic == kContextMagic) ? c : nullptr;
}

std::uint8_t flag(bool value) noexcept { return value ? 1U : 0U; }

RoverTelemetry from_c(const sw_telemetry& in) noexcept {
  RoverTelemetry t{};
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
  return t;
}

void to_c(const RoverStepOutput& r, sw_cycle_result& out) noexcept {
  out.status = static_cast<std::uint8_t>(r.status);
  out.decision = static_cast<std::uint8_t>(r.decision);
  out.loads_valid = flag(r.loads_valid);
  out.drawbar_valid = flag(r.drawbar_valid);
  out.wheels_in_stop = r.monitor.wheels_in_stop;
  out.wheels_in_caution = r.monitor.wheels_in_caution;
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

/// The rover parameters a table carries, or the Yutu-like default.
RoverParamStatus rover_params_of(const sinkwatch::flight::ParameterTable& table, RoverParams& out) noexcept {
  if (!table.rover_geometry.present) {
    out = sinkwatch::flight::yutu_like_rover_params(sinkwatch::flight::kGravityMoon);
    return RoverParamStatus::ok;
  }
  return sinkwatch::flight::decode_rover_section(table.rover_geometry, out);
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
  c->rover = sinkwatch::flight::yutu_like_rover_params(sinkwatch::flight::kGravityMoon);
  static_cast<void>(sinkwatch::flight::prepare(c->store.active(), c->rover, c->prepared));
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
  // The rover section's validator is a full decode, so a table the store
  // accepts always yields rover parameters; a rejected table leaves both the
  // table and the rover in force.
  const RejectReason reason = c->store.load(bytes, size, &sinkwatch::flight::rover_section_valid);
  if (reason == RejectReason::ok) {
    static_cast<void>(rover_params_of(c->store.active(), c->rover));
    static_cast<void>(sinkwatch::flight::prepare(c->store.active(), c->rover, c->prepared));
  }
  return static_cast<std::uint8_t>(reason);
}

uint32_t sw_active_table_crc(const sw_context* ctx) {
  if (ctx == nullptr) {
    return 0U;
  }
  const Context* const c = context_of(ctx);
  return (c == nullptr) ? 0U : c->store.active_crc();
}

sw_status sw_step(sw_context* ctx, const sw_telemetry* telemetry, uint32_t now_ms, sw_cycle_result* out) {
  if ((ctx == nullptr) || (telemetry == nullptr) || (out == nullptr)) {
    return SW_NULL_ARGUMENT;
  }
  Context* const c = context_of(ctx);
  if (c == nullptr) {
    return SW_NOT_INITIALISED;
  }
  const RoverStepOutput r = c->step.step(from_c(*telemetry), TimeMs{now_ms}, c->prepared);
  to_c(r, *out);
  return static_cast<sw_status>(r.status);
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

}  // extern "C"
