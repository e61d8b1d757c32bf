// One control cycle from raw telemetry to the rover's decision; see
// rover_step.hpp and docs/rover-loads.md, section 8.
#include "sinkwatch/flight/rover_step.hpp"

#include "of_valid.hpp"

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/motor.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using W = WideQ;

/// The monitor's samples when the cycle has no numbers: WheelInput's
/// defaults (no load, no pull, no torque, no sensor fault).
constexpr TorqueResult kNoDriveTorque{TorqueNm::zero(), EstimateStatus::invalid_current};
static_assert(kWheelCount == 6U, "one default per wheel below");
constexpr TorqueResult kNoWheelTorques[kWheelCount]{kNoDriveTorque, kNoDriveTorque, kNoDriveTorque,
                                                    kNoDriveTorque, kNoDriveTorque, kNoDriveTorque};
constexpr WheelLoadN kNoLoads[kWheelCount]{};
constexpr DrawbarPullN kNoPulls[kWheelCount]{};
constexpr bool kEveryCurrentUsable[kWheelCount]{true, true, true, true, true, true};

template <typename Quantity>
bool within(Quantity v, Quantity limit) noexcept {
  return (v <= limit) && (v.raw() >= -limit.raw());
}

/// The acceleration from two successive speeds, (v - v_prev) / dt. The
/// factor 1000 and dt are integers (Q.0): in Q31.32 the product and the
/// quotient by them are the one-word product and the 64-bit division of
/// fx::mul and fx::div (no 128-bit arithmetic), the bits of multiplying
/// and dividing by 1000 and dt in Q31.32 (the same integers, rounded alike).
bool differenced_accel(SpeedMps speed, SpeedMps previous, std::uint32_t dt_ms, AccelMps2& out) noexcept {
  using Integer = fx::Q<std::int64_t, 0>;
  fx::Status st;
  const W dv = fx::sub(fx::rescale<W>(speed.q(), st), fx::rescale<W>(previous.q(), st), st);
  const W per_second = fx::mul<W>(dv, Integer::from_raw(1000), st);
  const W accel = fx::div<W>(per_second, Integer::from_raw(static_cast<std::int64_t>(dt_ms)), st);
  const AccelQ a = fx::rescale<AccelQ>(accel, st);
  out = AccelMps2{a};
  return st.ok();
}

/// Every motion input that is flagged valid lies in its accepted range.
bool motion_in_range(const RoverTelemetry& t) noexcept {
  return (!t.accel_valid || within(t.accel_mps2, kMaxAbsAccel)) &&
         (!t.speed_valid || within(t.speed_mps, kMaxAbsSpeed)) &&
         (!t.rim_speed_valid || within(t.rim_speed_mps, kMaxAbsSpeed));
}

/// The six values of `from` into `to`, one by one: GCC turns a copy loop
/// into a memcpy call (on the Cortex-M0, about 65 instructions for 24
/// bytes), and the Cortex-M4 copies the loop in three two-word steps.
template <typename T>
void copy_six(const T (&from)[kWheelCount], T (&to)[kWheelCount]) noexcept {
  static_assert(kWheelCount == 6U, "one assignment per wheel below");
  to[0] = from[0];
  to[1] = from[1];
  to[2] = from[2];
  to[3] = from[3];
  to[4] = from[4];
  to[5] = from[5];
}

/// Stage 2: the wheel loads' result into `out`; ok, tip_over or loads_failed.
RoverStepStatus load_stage(const WheelLoadResult& loads, RoverStepOutput& out) noexcept {
  out.load_status = loads.status;
  out.torque_fallback_mask = loads.torque_fallback_mask;
  out.torque_overload = loads.torque_overload;
  if (loads.status == WheelLoadStatus::tip_over) {
    out.lifting_wheel = loads.lifting_wheel;
    return RoverStepStatus::tip_over;
  }
  if (loads.status != WheelLoadStatus::ok) {
    return RoverStepStatus::loads_failed;
  }
  out.loads_valid = true;
  copy_six(loads.load_n, out.load_n);
  return RoverStepStatus::ok;
}

/// Stage 4: the corrections at each load into `corr` (kept for the monitor,
/// which needs the same C(W) for Eq. 15 and I_max), then the drawbar pulls
/// into `out`. `loads` is stage 2's ok result (it also carries sin(pitch));
/// the pitch is the health monitor's, the one the loads took. Out of line:
/// its input and result records are then not in compute's frame, which is
/// live below it during the wheel loads (the deepest call of a cycle).
[[gnu::noinline]] RoverStepStatus drawbar_stage(const PreparedParameters& prepared, const WheelLoadResult& loads,
                              CorrectionResult (&corr)[kWheelCount], RoverStepOutput& out) noexcept {
  // The six loads in one call, the results written in place (round 14: a
  // call per wheel, its result record copied field by field, before). A
  // failed wheel fails the stage; the monitor reads `corr` only when it
  // did not.
  if (!corrections_at(prepared.table().correction, prepared.correction_divisors(), out.load_n, corr)) {
    out.drawbar_status = DrawbarStatus::invalid_input;
    return RoverStepStatus::drawbar_failed;
  }
  // Built whole, every field given (a zeroed input filled in afterwards was
  // a memset per cycle on the Cortex-M0).
  static_assert(kWheelCount == 6U, "one ratio per wheel below");
  const DrawbarInput in{out.accel_mps2,
                        out.health.attitude.pitch_rad,
                        out.slip_known,
                        out.slip,
                        {corr[0].dp_max_ratio, corr[1].dp_max_ratio, corr[2].dp_max_ratio, corr[3].dp_max_ratio,
                         corr[4].dp_max_ratio, corr[5].dp_max_ratio}};
  // The pulls past drawbar_pulls()'s range checks, written in place (round
  // 15): the loads are ok (load_stage), so the pitch is within the
  // attitude limit and the loads' sine is this pitch's; the acceleration
  // passed motion_in_range or the differenced one's test; the slip is
  // clamped to [-1, 1]; every load is positive and every ratio in (0, 2]
  // (corrections_at refuses a load <= 0, and interpolates between ratios
  // the validated table holds in (0, 2]).
  DrawbarPullN total_n{};
  std::uint8_t capped_mask = 0U;
  const DrawbarStatus dp_status = detail::pulls_in_range(prepared.rover(), loads, in, loads.sin_pitch,
                                                         out.drawbar_pull_n, total_n, capped_mask);
  out.drawbar_status = dp_status;
  if (!usable(dp_status)) {
    // Defensive, unreachable on prepared parameters (docs/coverage.md).
    return RoverStepStatus::drawbar_failed;  // GCOVR_EXCL_LINE
  }
  out.drawbar_valid = true;
  return RoverStepStatus::ok;
}

/// Wheel i into `sums` when the monitor has its torque (estimate_valid).
SW_FX_INLINE void add_if_estimated(const RoverTelemetry& t, const RoverStepOutput& out, std::uint32_t i,
                                   TractionSums& sums) noexcept {
  const WheelOutput& w = out.monitor.wheels[i];
  if (w.estimate_valid) {
    sums.add(w.torque_nm, out.drawbar_pull_n[i], out.load_n[i], t.direction[i]);
  }
}

/// Stage 6's input into `in`: this cycle's loads, pulls and the wheel
/// monitors' directed torques summed over the wheels with a torque (the
/// monitor's estimate_valid), and the odometry. The sums are made from the
/// step's own arrays, in place (round 16: the arrays were copied into a
/// TractionInput every cycle and summed from the copy), and only for a
/// cycle with loads: the check reads them only then (TractionMonitor::
/// resistance_of refuses a cycle without loads first), so a cycle without
/// keeps the previous cycle's, unread. Every wheel is asked: the monitor
/// leaves a wheel beyond wheel_count with WheelOutput{}'s estimate_valid,
/// false (RoverMonitor::step_all), which is TractionInput's first
/// wheel_count. The wheels one by one (round 17: a loop before, whose
/// three pointers and bound cost five instructions a wheel). Out of line:
/// inline, the step's pointers kept live across the wheels made it spill.
[[gnu::noinline]] void traction_input(const RoverTelemetry& t, const RoverStepOutput& out,
                                      TractionCycle& in) noexcept {
  in.time = t.time;
  in.loads_valid = (out.status == RoverStepStatus::ok);
  in.pull_assumed = (out.drawbar_status == DrawbarStatus::saturated);
  in.speed_valid = t.speed_valid;
  in.speed_mps = t.speed_mps;
  if (!in.loads_valid) {
    return;
  }
  TractionSums sums{};
  static_assert(kWheelCount == 6U, "one sum per wheel below");
  add_if_estimated(t, out, 0U, sums);
  add_if_estimated(t, out, 1U, sums);
  add_if_estimated(t, out, 2U, sums);
  add_if_estimated(t, out, 3U, sums);
  add_if_estimated(t, out, 4U, sums);
  add_if_estimated(t, out, 5U, sums);
  in.sums = sums;
}

/// The loads and pulls of a cycle that did not end ok, zero where no stage
/// wrote them: the pulls (a cycle with pulls is ok), and the loads unless
/// loads_valid. A cycle that ends ok has written both (load_stage,
/// drawbar_stage), so it does not zero them first (round 17: twelve words
/// stored every cycle before). Out of line: not in the step's frame.
[[gnu::noinline]] void zero_unwritten(RoverStepOutput& out) noexcept {
  // One array per loop: GCC distributes a loop that stores into two arrays
  // into two memset calls (about 60 Cortex-M0 instructions each for 24 bytes).
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    out.drawbar_pull_n[i] = DrawbarPullN::zero();
  }
  if (!out.loads_valid) {
    for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
      out.load_n[i] = WheelLoadN::zero();
    }
  }
}

/// The step's defaults in `out`, field by field: status ok until a stage
/// refuses (the loads and pulls are zeroed by zero_unwritten() when one
/// does). Not `out = RoverStepOutput{}`, which GCC builds as a temporary
/// on the step's stack (328 B on the M0) and then copies. The health,
/// monitor and traction records are written whole later in every cycle
/// (assess and monitor_stage, or refuse_table).
void reset_cycle_fields(RoverStepOutput& out) noexcept {
  out.status = RoverStepStatus::ok;
  out.load_status = WheelLoadStatus::invalid_params;
  out.drawbar_status = DrawbarStatus::invalid_loads;
  out.loads_valid = false;
  out.drawbar_valid = false;
  out.accel_valid = false;
  out.accel_mps2 = AccelMps2::zero();
  out.slip_known = false;
  out.slip = Ratio::zero();
  out.lifting_wheel = kWheelCount;
  out.torque_fallback_mask = kEveryTorqueFallsBack;
  out.torque_overload = false;
  out.decision = RoverDecision::continue_drive;
}

/// A table that failed validation: the monitor has no thresholds, so the
/// step stops, fail-safe, with no health, monitor or traction figures.
/// Kept out of line: its default records are not built on the stack of
/// every cycle.
[[gnu::noinline]] void refuse_table(RoverStepOutput& out) noexcept {
  zero_unwritten(out);
  out.status = RoverStepStatus::invalid_table;
  out.decision = RoverDecision::stop_and_replan;
  out.health = SensorHealthReport{};
  out.monitor = RoverOutput{};
  out.traction = TractionOutput{};
}

}  // namespace

Ratio detail::slip_in_range(SpeedMps speed, SpeedMps rim) noexcept {
  constexpr Ratio kOneRatio{fx::constant<RatioQ>(1.0)};
  constexpr std::int32_t kOneRaw = kOneRatio.raw();
  const std::uint32_t a = fx::detail::magnitude32(speed.raw());
  const std::uint32_t b = fx::detail::magnitude32(rim.raw());  // > 0: above kMinRimSpeedForSlip
  if ((speed.raw() < 0) != (rim.raw() < 0)) {
    return Ratio::from_raw(kOneRaw);
  }
  const bool whole = a >= b;
  const std::uint32_t rest = whole ? (a - b) : a;
  if (rest >= b) {
    return Ratio::from_raw(-kOneRaw);
  }
  // rest < b < 2^(32 - shift): the normalised dividend's high word is below v.
  const std::uint32_t shift = 32U - fx::wide::bit_length32(b);
  const std::uint32_t v = b << shift;
  const std::uint32_t q = fx::wide::quotient_64_by_32(static_cast<std::uint64_t>(rest << shift) << 32U, v);
  // rest 2^(32 + shift) - q v is the remainder, below v: its low word.
  const std::uint32_t remainder = 0U - (q * v);
  const std::uint64_t m = (std::uint64_t{whole ? 1U : 0U} << 32U) + q + ((remainder >= (v - remainder)) ? 1U : 0U);
  constexpr std::uint64_t kOne = std::uint64_t{1U} << 32U;  // 1 in Q31.32
  constexpr std::uint64_t kHalf = std::uint64_t{1U} << 7U;  // half a Q7.24 LSB in Q31.32
  if (m <= kOne) {
    return Ratio::from_raw(static_cast<std::int32_t>((kOne - m + kHalf) >> 8U));
  }
  return Ratio::from_raw(-static_cast<std::int32_t>((m - kOne + kHalf) >> 8U));
}

RoverStep::RoverStep() noexcept = default;

void RoverStep::clear_stop() noexcept {
  monitor_.clear_stop();
  traction_.clear_stop();
  stops_.clear_stop();
  health_.accept_levels();
}

RoverStepStatus RoverStep::classify(const RoverTelemetry& t, TimeMs now, const ParameterTable& table) noexcept {
  if (!t.valid) {
    return RoverStepStatus::telemetry_invalid;
  }
  // A time stamp after `now` wraps to a huge age: stale as well.
  if (elapsed_ms(t.time, now) > table.monitor.stale_timeout_ms) {
    return RoverStepStatus::telemetry_stale;
  }
  if (have_time_ && (t.time.ms == last_time_.ms)) {
    return RoverStepStatus::telemetry_repeated;
  }
  have_time_ = true;
  last_time_ = t.time;
  return RoverStepStatus::ok;
}

void RoverStep::motion(const RoverTelemetry& t, const ParameterTable& table, RoverStepOutput& out) noexcept {
  if (t.accel_valid) {
    out.accel_valid = true;
    out.accel_mps2 = t.accel_mps2;
  } else if (t.speed_valid && have_speed_) {
    // The difference needs a previous speed that is neither this sample's
    // own time nor older than the stale timeout.
    const std::uint32_t dt = elapsed_ms(last_speed_time_, t.time);
    AccelMps2 a{};
    if ((dt > 0U) && (dt <= table.monitor.stale_timeout_ms) && differenced_accel(t.speed_mps, last_speed_, dt, a) &&
        within(a, kMaxAbsAccel)) {
      out.accel_valid = true;
      out.accel_mps2 = a;
    }
  } else {
    // Neither a measurement nor two speeds: no acceleration this cycle.
  }
  if (t.speed_valid) {
    have_speed_ = true;
    last_speed_ = t.speed_mps;
    last_speed_time_ = t.time;
  }
  // s = 1 - v / v_rim, limited to [-1, 1] (beyond 1 the rover moves against
  // its wheels; below -1 it skids faster than twice the rim speed). Both
  // speeds passed motion_in_range: the slip always exists here.
  if (t.speed_valid && t.rim_speed_valid && !within(t.rim_speed_mps, kMinRimSpeedForSlip)) {
    out.slip_known = true;
    out.slip = detail::slip_in_range(t.speed_mps, t.rim_speed_mps);
  }
}

RoverStepStatus RoverStep::admit(const RoverTelemetry& t, TimeMs now, const PreparedParameters& prepared) noexcept {
  // The telemetry itself, by the monitor's own rules, then the parameters
  // (checked by prepare(), reported only for a fresh sample).
  const RoverStepStatus status = classify(t, now, prepared.table());
  if (status != RoverStepStatus::ok) {
    return status;
  }
  if (prepared.status() == PrepareStatus::invalid_rover_params) {
    return RoverStepStatus::invalid_rover_params;
  }
  if (prepared.status() == PrepareStatus::radius_mismatch) {
    return RoverStepStatus::radius_mismatch;
  }
  return RoverStepStatus::ok;
}

void RoverStep::assess(const RoverTelemetry& t, const PreparedParameters& prepared, bool clock_jump,
                       RoverStepOutput& out) noexcept {
  const HealthParams& hp = prepared.table().health;
  constexpr std::uint8_t kClock = static_cast<std::uint8_t>(SensorChannel::clock);
  if ((out.status == RoverStepStatus::telemetry_repeated) || (out.status == RoverStepStatus::telemetry_stale)) {
    last_health_.channel[kClock] = health_.clock_refused(out.status == RoverStepStatus::telemetry_repeated, hp);
  } else if (out.status == RoverStepStatus::ok) {
    // A view of the telemetry, and the report written in place: no record
    // is built and copied.
    const HealthSample s{t.time, t.current_a, t.direction, t.attitude, t.joints, t.presence,
                         t.rim_speed_valid && !within(t.rim_speed_mps, kMinRimSpeedForSlip), clock_jump};
    health_.update(s, hp, prepared.table().motor.no_load_current_a, prepared.table().motor.current_abs_max_a,
                   last_health_);
  } else {
    // Flagged invalid or refused parameters: nothing new about the sensors.
  }
  out.health = last_health_;
}

RoverStepStatus RoverStep::compute(const RoverTelemetry& t, const PreparedParameters& prepared,
                                   RoverStepOutput& out) noexcept {
  // 2. The drive torques (once, for the loads and the monitor), the loads.
  // Each wheel's drive torque from its current, once per cycle: the loads
  // and the monitor (WheelInput::drive_torque) take the same result, all
  // six written in place (round 14), and in the same loop the loads'
  // torques (usable when the health monitor passes the current and the
  // torque exists; otherwise the statics fall back for that wheel; round
  // 17). The validated table's motor: no check_motor() per wheel
  // (of_valid.hpp), nor the tests validate() has made impossible (motor.cpp).
  detail::torques_of_validated_motor(prepared.table().motor, t.current_a, t.direction, out.health.current_usable,
                                     terms_.torque, terms_.drive);
  // Initialised from the call, not assigned: a WheelLoadResult assigned
  // through a reference is built in a temporary and copied, which put both
  // in this frame, live during the wheel loads (the deepest call of a cycle).
  // The attitude and joints are the health monitor's (measured or bridged).
  const WheelLoadResult loads = wheel_loads(prepared, out.health.attitude, out.health.joints, terms_.drive);
  RoverStepStatus status = load_stage(loads, out);
  // 3. Motion. Kept up to date even when the loads failed, so that the speed
  //    difference is ready on the next good cycle.
  if (!motion_in_range(t)) {
    return (status == RoverStepStatus::ok) ? RoverStepStatus::motion_out_of_range : status;
  }
  motion(t, prepared.table(), out);
  if (status != RoverStepStatus::ok) {
    return status;
  }
  if (!out.accel_valid) {
    return RoverStepStatus::no_acceleration;
  }
  // 4. DP_max/W and the drawbar pulls.
  status = drawbar_stage(prepared, loads, terms_.corr, out);
  return status;
}

// Inline into monitor_stage, its one caller: a call that only passed its
// arguments on (round 16).
SW_FX_INLINE void RoverStep::traction_stage(const RoverTelemetry& t, const PreparedParameters& prepared,
                                            RoverStepOutput& out) noexcept {
  traction_input(t, out, traction_in_);
  traction_.step(traction_in_, prepared.table().traction, prepared.table().monitor, prepared.traction_inverse_radius(),
                 out.traction);
}

void RoverStep::monitor_stage(const RoverTelemetry& t, TimeMs now, const PreparedParameters& prepared,
                              RoverStepOutput& out) noexcept {
  // The monitor sees every cycle: numbers when they all exist, else an
  // invalid sample it counts (and a stale one it classifies itself). Its
  // samples are views of this cycle's arrays, read in place (WheelSamples):
  // no per-wheel input records built and read again. Without numbers they
  // are the WheelInput defaults: no load, pull, torque or corrections.
  // Built whole in each case, every field given: a zeroed record filled in
  // afterwards is a memset per cycle.
  const bool usable_sample = (out.status == RoverStepStatus::ok);
  const bool pass_as_stale = (out.status == RoverStepStatus::telemetry_stale);
  const WheelSamples samples =
      usable_sample
          ? WheelSamples{t.time, true, out.drawbar_status == DrawbarStatus::saturated, &t.current_a, &t.direction,
                         &out.load_n, &out.drawbar_pull_n, &out.health.current_usable, &terms_.corr, &terms_.torque}
          : WheelSamples{t.time, pass_as_stale, false, &t.current_a, &t.direction, &kNoLoads, &kNoPulls,
                         &kEveryCurrentUsable, nullptr, &kNoWheelTorques};
  monitor_.step(samples, now, prepared, out.monitor);
  traction_stage(t, prepared, out);
  out.decision = out.monitor.decision;
  if ((out.status == RoverStepStatus::tip_over) || (out.traction.state == TractionState::stop)) {
    out.decision = RoverDecision::stop_and_replan;
  }
  stops_.observe(out.monitor, out.traction.stop_tripped, out.decision, now, prepared.table().monitor.wheel_count);
}

void RoverStep::step(const RoverTelemetry& t, TimeMs now, const PreparedParameters& prepared,
                     RoverStepOutput& out) noexcept {
  reset_cycle_fields(out);
  if (!prepared.table_valid()) {
    refuse_table(out);
    return;
  }
  // 1. Telemetry and parameters; 1b. sensor health; 2..4. loads, motion,
  //    drawbar pulls on the health monitor's attitude and joints (measured
  //    or bridged).
  const bool clock_jump =
      have_time_ && (elapsed_ms(last_time_, t.time) > prepared.table().monitor.stale_timeout_ms);
  out.status = admit(t, now, prepared);
  assess(t, prepared, clock_jump, out);
  if ((out.status == RoverStepStatus::ok) && !(out.health.attitude_usable && out.health.joints_usable)) {
    out.status = RoverStepStatus::sensor_lost;
  }
  if (out.status == RoverStepStatus::ok) {
    out.status = compute(t, prepared, out);
  }
  if (out.status != RoverStepStatus::ok) {
    zero_unwritten(out);
  }
  // 5. The monitor.
  monitor_stage(t, now, prepared, out);
}

}  // namespace flight
}  // namespace sinkwatch
