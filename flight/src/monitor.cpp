// The per-wheel monitor and the rover decision (monitor.hpp).
#include "sinkwatch/flight/monitor.hpp"

#include "n_of_m.hpp"
#include "of_valid.hpp"

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"

#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"

namespace sinkwatch {
namespace flight {

namespace {

using n_of_m::count_bits;
using n_of_m::shift_in;

/// The current in the direction of motion: the quantity the limit bounds.
CurrentA directional(CurrentA current_a, DriveDirection direction, fx::Status& st) noexcept {
  return (direction == DriveDirection::reverse) ? CurrentA(fx::neg(current_a.q(), st)) : current_a;
}

/// f * I_max, in amperes, for a fraction f in (0, 1] (validate() accepts
/// the caution fraction in (0, 1] and the hysteresis in [0, f), so f and
/// f - h both are): |f I_max| <= |I_max| fits, and the product is fx::mul's
/// rounding (ties away from zero) without its saturation test.
CurrentA fraction_of(std::int32_t fraction_raw, CurrentA limit) noexcept {
  constexpr std::int32_t kShift = RatioQ::frac_bits;  // Q7.24 x Q11.20 -> Q11.20
  return CurrentA(CurrentQ::from_raw(fx::detail::product_rounded<kShift>(fraction_raw, limit.raw())));
}

/// Is the sample usable? The checks go from the cheapest and most
/// fundamental (the source's own flag) to the physical ranges.
SampleStatus classify_sample(const WheelInput& input, TimeMs now, bool have_last_time, TimeMs last_time,
                             const PreparedParameters& prepared) noexcept {
  const ParameterTable& table = prepared.table();
  const MonitorParams& mp = table.monitor;
  // Without a valid table there are no thresholds: the sample is unusable,
  // which the zeroed limits turn into STOP (fail-safe). RoverStep never
  // gets here with one.
  if ((!input.valid) || (!prepared.table_valid())) {
    return SampleStatus::flagged_invalid;
  }
  // A time stamp after `now` wraps to a huge age: stale as well.
  if (elapsed_ms(input.time, now) > mp.stale_timeout_ms) {
    return SampleStatus::stale;
  }
  if (have_last_time && (input.time.ms == last_time.ms)) {
    return SampleStatus::repeated_time;
  }
  if ((input.direction != DriveDirection::forward) && (input.direction != DriveDirection::reverse)) {
    return SampleStatus::direction_invalid;
  }
  if (input.sensor_fault) {
    return SampleStatus::sensor_fault;
  }
  fx::Status range_status;
  const CurrentQ magnitude = fx::abs(input.current_a.q(), range_status);
  if ((!range_status.ok()) || (magnitude > table.motor.current_abs_max_a.q())) {
    return SampleStatus::current_out_of_range;
  }
  if ((input.load_n < mp.load_min_n) || (input.load_n > mp.load_max_n)) {
    return SampleStatus::load_out_of_range;
  }
  return SampleStatus::ok;
}

/// Stage 2 from the sample's corrections `corr` (for its load): T, z and
/// I_max into `out`; false when one of them has no number. Out of line: the
/// Eq. 11 and limit cores inlined here (of_valid.hpp) keep their registers
/// to themselves, not beside WheelMonitor::step's.
[[gnu::noinline]] bool estimate_from(const CorrectionResult& corr, const WheelInput& input,
                                     const PreparedParameters& prepared, WheelOutput& out) noexcept {
  const ParameterTable& table = prepared.table();
  // The caller's torque (WheelInput::drive_torque), the one the loads used.
  const TorqueResult& torque = input.drive_torque;
  out.clamp = corr.clamp;
  // The coefficients, radius and load checked once for Eq. 11 and the limit
  // (the corrections may be the caller's); the motor is the validated
  // table's (of_valid.hpp).
  const EstimateStatus inputs = (corr.status == EstimateStatus::ok)
                                    ? detail::estimator_inputs_status(corr.coefficients, table.wheel_radius_m, input.load_n)
                                    : corr.status;
  if ((torque.status != EstimateStatus::ok) || (inputs != EstimateStatus::ok)) {
    return false;
  }
  // Eq. 11 and the limit in this one function (their cores are inline,
  // of_valid.hpp): no call, argument record or result record per wheel
  // between them.
  const SinkageResult sink = detail::sinkage_of_valid(corr.coefficients, table.wheel_radius_m, input.load_n,
                                                      torque.torque_nm, input.drawbar_pull_n);
  const TorqueLimitResult torque_max =
      detail::torque_limit_of_valid(corr.coefficients, corr.dp_max_ratio, table.wheel_radius_m, input.load_n,
                                    table.monitor.allowed_sinkage_m);
  const CurrentLimitResult limit =
      detail::limit_from_torque(corr, table.motor, prepared.motor_divisors(), torque_max);
  if ((sink.status != EstimateStatus::ok) || (limit.status != EstimateStatus::ok)) {
    return false;
  }
  out.estimate_valid = true;
  out.torque_nm = torque.torque_nm;
  out.sinkage_m = sink.sinkage_m;
  out.limit_valid = true;
  out.current_limit_a = limit.current_limit_a;
  return true;
}

/// Stage 2 of a usable sample. The caller's corrections (RoverStep's) are
/// read in place, not copied (20 bytes per wheel).
bool estimate(const WheelInput& input, const PreparedParameters& prepared, WheelOutput& out) noexcept {
  if (input.corrections != nullptr) {
    return estimate_from(*input.corrections, input, prepared, out);
  }
  const CorrectionResult own =
      corrections_at(prepared.table().correction, prepared.correction_divisors(), input.load_n);
  return estimate_from(own, input, prepared, out);
}

/// No estimate and no limit this cycle (an unusable sample, or one whose
/// estimate failed).
void clear_estimate(WheelOutput& out) noexcept {
  out.estimate_valid = false;
  out.limit_valid = false;
  out.torque_nm = TorqueNm::zero();
  out.sinkage_m = SinkageM::zero();
  out.current_limit_a = CurrentA::zero();
}

/// One usable sample's evidence for the state machine.
struct Evidence {
  bool caution{true};  ///< fail-safe default for an unusable sample
  bool stop{false};
  bool clear{false};
  bool current_stop{false};
  bool slip_stop{false};  ///< stop evidence from high slip alone
};

Evidence evidence_of(CurrentA directed, const WheelOutput& out, const MonitorParams& mp) noexcept {
  // The thresholds of a validated table (monitor.hpp): f - h and the
  // caution level less its hysteresis are positive and exact (h in [0, f),
  // the hysteresis in [0, caution)), so no threshold saturates.
  const std::int32_t f = mp.current_caution_fraction.raw();
  const CurrentA caution_current = fraction_of(f, out.current_limit_a);
  const CurrentA clear_current = fraction_of(f - mp.current_hysteresis_fraction.raw(), out.current_limit_a);
  const SinkageM clear_sinkage(LengthQ::from_raw(mp.caution_sinkage_m.raw() - mp.sinkage_hysteresis_m.raw()));
  Evidence e{};
  e.current_stop = directed >= out.current_limit_a;
  e.stop = e.current_stop || (out.sinkage_m >= mp.stop_sinkage_m);
  e.caution = e.stop || (directed >= caution_current) || (out.sinkage_m >= mp.caution_sinkage_m);
  e.clear = (directed < clear_current) && (out.sinkage_m < clear_sinkage);
  return e;
}

/// One more sample, and one more of its status; each counter saturates.
/// A free function with one caller (not a member), so that GCC inlines it
/// at -Os (session 18: a call per wheel and cycle less on the Cortex-M0).
void count_sample(WheelCounters& counters, SampleStatus status) noexcept {
  const std::uint8_t index = static_cast<std::uint8_t>(status);
  if ((index < kSampleStatusCount) && (counters.by_status[index] < 0xFFFFFFFFU)) {
    ++counters.by_status[index];
  }
  if (counters.samples < 0xFFFFFFFFU) {
    ++counters.samples;
  }
}

}  // namespace

WheelMonitor::WheelMonitor(std::uint8_t wheel_index) noexcept : wheel_(wheel_index) {}

void WheelMonitor::clear_stop() noexcept {
  state_ = WheelState::nominal;
  stop_reason_ = StopReason::none;
  caution_history_ = 0U;
  stop_history_ = 0U;
  clear_history_ = 0U;
  consecutive_unusable_ = 0U;
  have_peak_ = false;
  have_max_estimate_ = false;
}

void WheelMonitor::hold_in_caution() noexcept {
  if (state_ == WheelState::nominal) {
    state_ = WheelState::caution;
    clear_history_ = 0U;
  }
}

SW_FX_INLINE void WheelMonitor::track_episode(CurrentA directed, WheelLoadN load_n, SinkageM sinkage_m) noexcept {
  if ((!have_peak_) || (directed > peak_current_a_)) {
    have_peak_ = true;
    peak_current_a_ = directed;
    load_at_peak_n_ = load_n;
  }
  if ((!have_max_estimate_) || (sinkage_m > max_estimate_m_)) {
    have_max_estimate_ = true;
    max_estimate_m_ = sinkage_m;
  }
}

[[gnu::noinline]] EventRecord WheelMonitor::stop_event(TimeMs now, StopReason reason,
                                                       const PreparedParameters& prepared) const noexcept {
  const ParameterTable& table = prepared.table();
  EventRecord e{};
  e.wheel = wheel_;
  e.time = now;
  e.reason = reason;
  e.peak_current_a = have_peak_ ? peak_current_a_ : CurrentA::zero();
  e.load_at_peak_n = have_peak_ ? load_at_peak_n_ : WheelLoadN::zero();
  e.peak_sinkage_valid = false;
  e.peak_sinkage_m = SinkageM::zero();
  if (have_peak_) {
    // Section 7: the sinkage the peak current implies at DP = DP_max.
    const TorqueResult t = torque_from_current(table.motor, peak_current_a_, DriveDirection::forward);
    const CorrectionResult c = corrections_at(table.correction, prepared.correction_divisors(), load_at_peak_n_);
    fx::Status st;
    const DrawbarPullN dp_max(fx::mul<LoadQ>(c.dp_max_ratio.q(), load_at_peak_n_.q(), st));
    if ((t.status == EstimateStatus::ok) && (c.status == EstimateStatus::ok) && st.ok()) {
      const SinkageResult z =
          sinkage_from_pull(c.coefficients, table.wheel_radius_m, load_at_peak_n_, t.torque_nm, dp_max);
      if (z.status == EstimateStatus::ok) {
        e.peak_sinkage_valid = true;
        e.peak_sinkage_m = z.sinkage_m;
      }
    }
  }
  e.max_estimate_valid = have_max_estimate_;
  e.max_estimated_sinkage_m = have_max_estimate_ ? max_estimate_m_ : SinkageM::zero();
  return e;
}

SW_FX_INLINE void WheelMonitor::transition(StopReason sample_reason, TimeMs now,
                                           const PreparedParameters& prepared, WheelOutput& out) noexcept {
  const MonitorParams& mp = prepared.table().monitor;
  if (state_ == WheelState::stop) {
    return;  // STOP is latched until clear_stop()
  }
  if ((consecutive_unusable_ >= mp.invalid_to_stop) || (count_bits(stop_history_, mp.window_m) >= mp.trip_n)) {
    const StopReason reason = (consecutive_unusable_ >= mp.invalid_to_stop)
                                  ? StopReason::telemetry
                                  : sample_reason;
    state_ = WheelState::stop;
    stop_reason_ = reason;
    out.stop_tripped = true;
    event_ = stop_event(now, reason, prepared);
    has_event_ = true;
  } else if ((state_ == WheelState::nominal) && (count_bits(caution_history_, mp.window_m) >= mp.trip_n)) {
    state_ = WheelState::caution;
    // Leaving CAUTION needs clear_n clear samples seen from here on.
    clear_history_ = 0U;
  } else if ((state_ == WheelState::caution) && (count_bits(clear_history_, mp.window_m) >= mp.clear_n)) {
    state_ = WheelState::nominal;
    caution_history_ = 0U;
    have_peak_ = false;
    have_max_estimate_ = false;
  } else {
    // no transition
  }
}

void WheelMonitor::step(const WheelInput& input, TimeMs now, const PreparedParameters& prepared,
                        WheelOutput& out) noexcept {
  const ParameterTable& table = prepared.table();
  // Every field of `out` is written below: state, sample_status and
  // stop_reason at the end, stop_tripped here, the estimate's fields and the
  // clamp once, by estimate() or by clear_estimate() (field by field: a
  // whole-struct reset costs the Cortex-M0 a memcpy per wheel).
  out.stop_tripped = false;

  // 1. Is the sample usable?
  SampleStatus status = classify_sample(input, now, have_last_time_, last_time_, prepared);
  if ((status != SampleStatus::flagged_invalid) && (status != SampleStatus::stale) &&
      (status != SampleStatus::repeated_time)) {
    have_last_time_ = true;
    last_time_ = input.time;
  }

  // 2. The estimate and the limit, only from a usable sample.
  CurrentA directed = CurrentA::zero();
  if (status == SampleStatus::ok) {
    fx::Status dir_status;
    directed = directional(input.current_a, input.direction, dir_status);
    // estimate() writes the clamp and, when it succeeds, every estimate field.
    if (!estimate(input, prepared, out) || !dir_status.ok()) {
      clear_estimate(out);
      status = SampleStatus::estimate_failed;
    }
  } else {
    clear_estimate(out);
    out.clamp = LoadClamp::none;
  }
  out.sample_status = status;
  count_sample(counters_, status);

  // 3. Evidence for the state machine.
  Evidence e{};
  // A blind wheel under continue_degraded is held in CAUTION by its
  // unusable evidence but does not trip invalid_to_stop (monitor.hpp).
  const bool tolerated_blind =
      (status == SampleStatus::sensor_fault) && (table.health.policy == LossPolicy::continue_degraded);
  if (status != SampleStatus::ok) {
    if ((consecutive_unusable_ < 0xFFU) && !tolerated_blind) {
      ++consecutive_unusable_;
    }
  } else {
    consecutive_unusable_ = 0U;
    e = evidence_of(directed, out, table.monitor);
    if (input.drawbar_assumed) {
      // DP = DP_max assumed at high slip: the estimate is a lower bound and
      // the wheel makes no headway (WheelInput::drawbar_assumed).
      e.slip_stop = !e.stop;
      e.stop = true;
      e.caution = true;
      e.clear = false;
    }
    track_episode(directed, input.load_n, out.sinkage_m);
  }
  caution_history_ = shift_in(caution_history_, e.caution);
  stop_history_ = shift_in(stop_history_, e.stop);
  clear_history_ = shift_in(clear_history_, e.clear);

  // 4. Transitions (STOP is latched).
  const StopReason sample_reason =
      e.current_stop ? StopReason::current : (e.slip_stop ? StopReason::slip : StopReason::sinkage);
  transition(sample_reason, now, prepared, out);
  out.state = state_;
  out.stop_reason = stop_reason_;
}

RoverMonitor::RoverMonitor() noexcept
    : wheels_{WheelMonitor(0U), WheelMonitor(1U), WheelMonitor(2U), WheelMonitor(3U), WheelMonitor(4U),
              WheelMonitor(5U)} {}

void RoverMonitor::step_all(const WheelInput (&inputs)[kMaxWheels], TimeMs now, const PreparedParameters& prepared,
                            RoverOutput& out) noexcept {
  const ParameterTable& table = prepared.table();
  out.wheels_in_stop = 0U;
  out.wheels_in_caution = 0U;
  out.wheels_blind = 0U;
  // Wheels beyond wheel_count are not monitored: their outputs are default.
  for (std::uint8_t i = 0U; i < kMaxWheels; ++i) {
    const bool monitored = i < table.monitor.wheel_count;
    if (monitored) {
      wheels_[i].step(inputs[i], now, prepared, out.wheels[i]);
    } else {
      out.wheels[i] = WheelOutput{};
    }
    if (monitored && (out.wheels[i].state == WheelState::stop)) {
      ++out.wheels_in_stop;
    } else if (monitored && (out.wheels[i].state == WheelState::caution)) {
      ++out.wheels_in_caution;
    } else {
      // nominal, or not monitored
    }
  }
  rover_rules(table, out);
}

void RoverMonitor::rover_rules(const ParameterTable& table, RoverOutput& out) noexcept {
  const std::uint8_t count = (table.monitor.wheel_count < kMaxWheels) ? table.monitor.wheel_count : kMaxWheels;
  const bool embedding_seen = (out.wheels_in_stop + out.wheels_in_caution) > 0U;
  for (std::uint8_t i = 0U; i < count; ++i) {
    WheelOutput& w = out.wheels[i];
    if (w.sample_status == SampleStatus::sensor_fault) {
      ++out.wheels_blind;
    }
    if (embedding_seen && (w.sample_status != SampleStatus::ok) && (w.state == WheelState::nominal)) {
      wheels_[i].hold_in_caution();
      w.state = WheelState::caution;
      ++out.wheels_in_caution;
    }
  }
  const std::uint8_t k = (table.monitor.rover_stop_k == 0U) ? 1U : table.monitor.rover_stop_k;
  const bool degraded_policy = table.health.policy == LossPolicy::continue_degraded;
  const bool too_blind = degraded_policy && (out.wheels_blind > table.health.max_blind_wheels);
  out.decision =
      ((out.wheels_in_stop >= k) || too_blind) ? RoverDecision::stop_and_replan : RoverDecision::continue_drive;
  out.degraded = degraded_policy && (out.wheels_blind > 0U) && !too_blind;
}

void RoverMonitor::step(const WheelInput (&inputs)[kMaxWheels], TimeMs now, const PreparedParameters& prepared,
                        RoverOutput& out) noexcept {
  if (prepared.table_valid()) {
    step_all(inputs, now, prepared, out);
  } else {
    // No thresholds: stop, fail-safe, no wheel stepped.
    out = RoverOutput{};
    out.decision = RoverDecision::stop_and_replan;
  }
}

void RoverMonitor::clear_stop() noexcept {
  for (WheelMonitor& w : wheels_) {
    w.clear_stop();
  }
}

const WheelMonitor& RoverMonitor::wheel(std::uint8_t index) const& noexcept {
  return wheels_[(index < kMaxWheels) ? index : (kMaxWheels - 1U)];
}

}  // namespace flight
}  // namespace sinkwatch
