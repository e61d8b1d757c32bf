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

/// count_bits(history, window) >= n. On a table validate() accepted (n >= 1:
/// trip_n and clear_n are at least 1) an empty history, a quiet wheel's
/// usual one, reaches no count: answered without the call. On any other
/// table the count is taken as it is (n may be 0 there).
template <bool kValidTable>
SW_FX_INLINE bool window_reaches(std::uint32_t history, std::uint8_t window, std::uint8_t n) noexcept {
  if constexpr (kValidTable) {
    return (history != 0U) && (count_bits(history, window) >= n);
  } else {
    return count_bits(history, window) >= n;
  }
}

/// The current in the direction of motion: the quantity the limit bounds.
SW_FX_INLINE CurrentA directional(CurrentA current_a, DriveDirection direction, fx::Status& st) noexcept {
  return (direction == DriveDirection::reverse) ? CurrentA(fx::neg(current_a.q(), st)) : current_a;
}

/// f * I_max, in amperes, for a fraction f in (0, 1] (validate() accepts
/// the caution fraction in (0, 1] and the hysteresis in [0, f), so f and
/// f - h both are): |f I_max| <= |I_max| fits, and the product is fx::mul's
/// rounding (ties away from zero) without its saturation test, in place
/// (round 14: one multiply-accumulate on the Cortex-M4, the words' form on
/// ARMv6-M; M4 -61, M0 -75 instructions per step against the call).
SW_FX_INLINE CurrentA fraction_of(std::int32_t fraction_raw, CurrentA limit) noexcept {
  constexpr std::int32_t kShift = RatioQ::frac_bits;  // Q7.24 x Q11.20 -> Q11.20
  return CurrentA(CurrentQ::from_raw(fx::detail::product_rounded_inlined<kShift>(fraction_raw, limit.raw())));
}

/// The levels below which a usable sample is clear (evidence_of): f - h, and
/// the caution sinkage less its hysteresis. Both positive and exact on a
/// validated table (f in (0, 1], h in [0, f); the sinkage hysteresis in
/// [0, caution)): no subtraction saturates.
struct ClearLevels {
  std::int32_t fraction_raw;  ///< f - h, RatioQ
  SinkageM sinkage_m;
};

SW_FX_INLINE ClearLevels clear_levels_of(const MonitorParams& mp) noexcept {
  return ClearLevels{mp.current_caution_fraction.raw() - mp.current_hysteresis_fraction.raw(),
                     SinkageM(LengthQ::from_raw(mp.caution_sinkage_m.raw() - mp.sinkage_hysteresis_m.raw()))};
}

/// A WheelInput's sample, as WheelMonitor::step_sample reads it.
class InputSample {
 public:
  /// WheelMonitor::step takes any parameters, a table that failed validate() too.
  static constexpr bool kValidTable = false;
  explicit InputSample(const WheelInput& input) noexcept : in_(input) {}
  /// flagged_invalid, stale or ok: the sample's flag and age, asked per wheel.
  [[nodiscard]] SW_FX_INLINE SampleStatus fresh_status(TimeMs now, const PreparedParameters& prepared) const noexcept {
    // Without a valid table there are no thresholds: the sample is
    // unusable, which the zeroed limits turn into STOP (fail-safe).
    if ((!in_.valid) || (!prepared.table_valid())) {
      return SampleStatus::flagged_invalid;
    }
    // A time stamp after `now` wraps to a huge age: stale as well.
    return (elapsed_ms(in_.time, now) > prepared.table().monitor.stale_timeout_ms) ? SampleStatus::stale
                                                                                    : SampleStatus::ok;
  }
  [[nodiscard]] SW_FX_INLINE TimeMs time() const noexcept { return in_.time; }
  [[nodiscard]] SW_FX_INLINE CurrentA current_a() const noexcept { return in_.current_a; }
  [[nodiscard]] SW_FX_INLINE DriveDirection direction() const noexcept { return in_.direction; }
  [[nodiscard]] SW_FX_INLINE WheelLoadN load_n() const noexcept { return in_.load_n; }
  [[nodiscard]] SW_FX_INLINE DrawbarPullN drawbar_pull_n() const noexcept { return in_.drawbar_pull_n; }
  [[nodiscard]] SW_FX_INLINE bool drawbar_assumed() const noexcept { return in_.drawbar_assumed; }
  [[nodiscard]] SW_FX_INLINE bool sensor_fault() const noexcept { return in_.sensor_fault; }
  [[nodiscard]] SW_FX_INLINE const CorrectionResult* corrections() const noexcept { return in_.corrections; }
  [[nodiscard]] SW_FX_INLINE const TorqueResult& drive_torque() const noexcept { return in_.drive_torque; }
  /// The clear levels, from the table per wheel (one wheel per call).
  [[nodiscard]] SW_FX_INLINE ClearLevels clear_levels(const MonitorParams& mp) const noexcept {
    return clear_levels_of(mp);
  }

 private:
  const WheelInput& in_;
};

/// The flag and age of a WheelSamples' cycle: flagged_invalid, stale or ok.
/// Every wheel shares the cycle's flag and time stamp, so RoverMonitor asks
/// once per cycle what InputSample::fresh_status asks per wheel (the same
/// tests in the same order, on a table known valid).
SW_FX_INLINE SampleStatus cycle_fresh_status(const WheelSamples& samples, TimeMs now,
                                             const MonitorParams& mp) noexcept {
  if (!samples.valid) {
    return SampleStatus::flagged_invalid;
  }
  // A time stamp after `now` wraps to a huge age: stale as well.
  return (elapsed_ms(samples.time, now) > mp.stale_timeout_ms) ? SampleStatus::stale : SampleStatus::ok;
}

/// Wheel `index`'s sample of a WheelSamples, read in place: the WheelInput
/// it stands for (monitor.hpp), field by field.
class CycleSample {
 public:
  /// Built only by RoverMonitor::step on WheelSamples, for a valid table,
  /// and only on a cycle whose cycle_fresh_status is ok (the other cycles'
  /// wheels take WheelMonitor::step_unfresh).
  static constexpr bool kValidTable = true;
  CycleSample(const WheelSamples& samples, const ClearLevels& levels, std::uint8_t index) noexcept
      : s_(samples), levels_(levels), i_(index) {}
  [[nodiscard]] SW_FX_INLINE SampleStatus fresh_status(TimeMs /*now*/,
                                                       const PreparedParameters& /*prepared*/) const noexcept {
    return SampleStatus::ok;
  }
  [[nodiscard]] SW_FX_INLINE TimeMs time() const noexcept { return s_.time; }
  [[nodiscard]] SW_FX_INLINE CurrentA current_a() const noexcept { return (*s_.current_a)[i_]; }
  [[nodiscard]] SW_FX_INLINE DriveDirection direction() const noexcept { return (*s_.direction)[i_]; }
  [[nodiscard]] SW_FX_INLINE WheelLoadN load_n() const noexcept { return (*s_.load_n)[i_]; }
  [[nodiscard]] SW_FX_INLINE DrawbarPullN drawbar_pull_n() const noexcept { return (*s_.drawbar_pull_n)[i_]; }
  [[nodiscard]] SW_FX_INLINE bool drawbar_assumed() const noexcept { return s_.drawbar_assumed; }
  [[nodiscard]] SW_FX_INLINE bool sensor_fault() const noexcept { return !(*s_.current_usable)[i_]; }
  [[nodiscard]] SW_FX_INLINE const CorrectionResult* corrections() const noexcept {
    return (s_.corrections != nullptr) ? &(*s_.corrections)[i_] : nullptr;
  }
  [[nodiscard]] SW_FX_INLINE const TorqueResult& drive_torque() const noexcept { return (*s_.drive_torque)[i_]; }
  /// The clear levels the cycle's wheels share, taken once per cycle.
  [[nodiscard]] SW_FX_INLINE ClearLevels clear_levels(const MonitorParams& /*mp*/) const noexcept { return levels_; }

 private:
  const WheelSamples& s_;
  const ClearLevels& levels_;
  std::uint8_t i_;
};

/// |I| > I_max, the sensor range (fx::abs's |I|, and its refusal of
/// INT32_MIN, whose magnitude has no number: out of range as well), for the
/// I_max > 0 of a table validate() accepted (above the no-load current,
/// itself at least zero). As one unsigned comparison: I + I_max, taken
/// modulo 2^32, maps [-I_max, I_max] onto [0, 2 I_max] (2 I_max < 2^32) and,
/// one to one, every other I above it (round 15: no magnitude, no test of
/// its sign or of INT32_MIN per wheel).
SW_FX_INLINE bool beyond_magnitude(CurrentA current_a, CurrentA abs_max_a) noexcept {
  const auto max_word = static_cast<std::uint32_t>(abs_max_a.raw());
  return (static_cast<std::uint32_t>(current_a.raw()) + max_word) > (max_word << 1U);
}

/// Is the sample usable? The checks go from the cheapest and most
/// fundamental (the source's own flag) to the physical ranges.
template <typename Sample>
SW_FX_INLINE SampleStatus classify_sample(Sample input, TimeMs now, bool have_last_time, TimeMs last_time,
                             const PreparedParameters& prepared) noexcept {
  const ParameterTable& table = prepared.table();
  const MonitorParams& mp = table.monitor;
  // The flag, the table and the age first (CycleSample: the cycle's,
  // asked once for every wheel).
  const SampleStatus fresh = input.fresh_status(now, prepared);
  if (fresh != SampleStatus::ok) {
    return fresh;
  }
  if (have_last_time && (input.time().ms == last_time.ms)) {
    return SampleStatus::repeated_time;
  }
  const DriveDirection direction = input.direction();
  if ((direction != DriveDirection::forward) && (direction != DriveDirection::reverse)) {
    return SampleStatus::direction_invalid;
  }
  if (input.sensor_fault()) {
    return SampleStatus::sensor_fault;
  }
  if (beyond_magnitude(input.current_a(), table.motor.current_abs_max_a)) {
    return SampleStatus::current_out_of_range;
  }
  const WheelLoadN load_n = input.load_n();
  if ((load_n < mp.load_min_n) || (load_n > mp.load_max_n)) {
    return SampleStatus::load_out_of_range;
  }
  return SampleStatus::ok;
}

/// Stage 2 from the sample's corrections `corr` (for its load): T, z and
/// I_max into `out`; false when one of them has no number. Out of line: the
/// Eq. 11 and limit cores inlined here (of_valid.hpp) keep their registers
/// to themselves, not beside WheelMonitor::step's.
[[gnu::noinline]] bool estimate_from(const CorrectionResult& corr, const TorqueResult& torque, WheelLoadN load_n,
                                     DrawbarPullN drawbar_pull_n, const PreparedParameters& prepared,
                                     WheelOutput& out) noexcept {
  const ParameterTable& table = prepared.table();
  // `torque` is the caller's (WheelInput::drive_torque), the one the loads used.
  out.clamp = corr.clamp;
  // The inputs checked once for Eq. 11 and the limit (the corrections may
  // be the caller's); the motor is the validated table's (of_valid.hpp).
  // Only the coefficients can fail check_estimator_inputs() here: this runs
  // for a sample classify_sample() found usable, which needs a valid table,
  // and validate() holds the radius in [kMinRadiusM, kMaxRadiusM] and
  // load_min above zero, so the load, within [load_min, load_max], is
  // positive (round 14: the radius and load tests left out, the same bits).
  if ((torque.status != EstimateStatus::ok) || (corr.status != EstimateStatus::ok) ||
      !detail::coefficients_in_range(corr.coefficients)) {
    return false;
  }
  // Eq. 11 and the limit in this one function (their cores are inline,
  // of_valid.hpp): no call, argument record or result record per wheel
  // between them. A false return makes the caller clear every estimate
  // field (WheelMonitor::step_sample), so the torque and the sinkage are
  // written as soon as they are known and a refusal returns at once: the
  // limit is not computed for a sinkage that overflowed, and the sinkage
  // is not kept in a register across the limit (round 15).
  std::int32_t z_raw = 0;
  if (!detail::sinkage_raw_of_valid(corr.coefficients, table.wheel_radius_m, load_n, torque.torque_nm,
                                    drawbar_pull_n, z_raw)) {
    return false;
  }
  out.torque_nm = torque.torque_nm;
  out.sinkage_m = SinkageM(LengthQ::from_raw(z_raw));
  std::int32_t t_max_raw = 0;
  std::int32_t current_raw = 0;
  if ((!detail::torque_limit_raw_of_valid(corr.coefficients, corr.dp_max_ratio, table.wheel_radius_m, load_n,
                                          table.monitor.allowed_sinkage_m, prepared.correction_divisors(),
                                          t_max_raw)) ||
      (!detail::current_raw_from_validated_torque(table.motor, prepared.motor_divisors(), t_max_raw,
                                                   current_raw))) {
    return false;
  }
  out.estimate_valid = true;
  out.limit_valid = true;
  out.current_limit_a = CurrentA(CurrentQ::from_raw(current_raw));
  return true;
}

/// Stage 2 of a usable sample. The caller's corrections (RoverStep's) are
/// read in place, not copied (20 bytes per wheel).
template <typename Sample>
SW_FX_INLINE bool estimate(Sample input, const PreparedParameters& prepared, WheelOutput& out) noexcept {
  const CorrectionResult* const given = input.corrections();
  if (given != nullptr) {
    return estimate_from(*given, input.drive_torque(), input.load_n(), input.drawbar_pull_n(), prepared, out);
  }
  const CorrectionResult own =
      corrections_at(prepared.table().correction, prepared.correction_divisors(), input.load_n());
  return estimate_from(own, input.drive_torque(), input.load_n(), input.drawbar_pull_n(), prepared, out);
}

/// No estimate and no limit this cycle (an unusable sample, or one whose
/// estimate failed).
SW_FX_INLINE void clear_estimate(WheelOutput& out) noexcept {
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

SW_FX_INLINE Evidence evidence_of(CurrentA directed, const WheelOutput& out, const MonitorParams& mp,
                                  const ClearLevels& levels) noexcept {
  // The thresholds of a validated table (monitor.hpp): the clear levels
  // (clear_levels_of) are positive and exact, so no threshold saturates.
  const CurrentA clear_current = fraction_of(levels.fraction_raw, out.current_limit_a);
  Evidence e{};
  e.clear = (directed < clear_current) && (out.sinkage_m < levels.sinkage_m);
  if (e.clear && (out.current_limit_a >= CurrentA::zero())) {
    // A clear sample on a limit I_max >= 0 is below every level, a quiet
    // wheel's usual sample: (f - h) I_max <= f I_max <= I_max (0 < f - h
    // <= f <= 1, and rounding keeps the order), and clear < caution < stop
    // in sinkage (validate()). Neither f I_max nor a comparison more.
    e.caution = false;
    return e;
  }
  const CurrentA caution_current = fraction_of(mp.current_caution_fraction.raw(), out.current_limit_a);
  e.current_stop = directed >= out.current_limit_a;
  e.stop = e.current_stop || (out.sinkage_m >= mp.stop_sinkage_m);
  e.caution = e.stop || (directed >= caution_current) || (out.sinkage_m >= mp.caution_sinkage_m);
  return e;
}

/// No thresholds: stop, fail-safe, no wheel stepped. Out of line: the
/// default record is not built in the frame of a cycle that has a table.
[[gnu::noinline]] void refuse_table(RoverOutput& out) noexcept {
  out = RoverOutput{};
  out.decision = RoverDecision::stop_and_replan;
}

/// One more sample, and one more of its status; each counter saturates.
/// A free function with one caller (not a member), so that GCC inlines it
/// at -Os (session 18: a call per wheel and cycle less on the Cortex-M0).
SW_FX_INLINE void count_sample(WheelCounters& counters, SampleStatus status) noexcept {
  // Each count plus one, kept unless it wrapped to zero: the saturation
  // test is the increment's own result (round 16: one instruction less
  // per counter on the Cortex-M4 than a comparison with the maximum, and
  // the wheel loop's registers fall better: M4 -56 instructions per step
  // against either comparison form). cppcheck's value flow assumes that
  // an unsigned increment does not wrap, which is the case tested here
  // (0xFFFFFFFF + 1 is 0): its "always true" is a false positive.
  const std::uint8_t index = static_cast<std::uint8_t>(status);
  if (index < kSampleStatusCount) {
    const std::uint32_t by_status = counters.by_status[index] + 1U;
    // cppcheck-suppress knownConditionTrueFalse
    if (by_status != 0U) {
      counters.by_status[index] = by_status;
    }
  }
  const std::uint32_t samples = counters.samples + 1U;
  // cppcheck-suppress knownConditionTrueFalse
  if (samples != 0U) {
    counters.samples = samples;
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
}

void WheelMonitor::hold_in_caution() noexcept {
  if (state_ == WheelState::nominal) {
    state_ = WheelState::caution;
    clear_history_ = 0U;
  }
}

SW_FX_INLINE void WheelMonitor::track_episode(CurrentA directed, WheelLoadN load_n, SinkageM sinkage_m) noexcept {
  // The peak and the largest estimate start and end together (one flag):
  // the episode's first usable sample sets both, and the episode's steady
  // cycles test the flag once (round 16).
  if (!have_peak_) {
    have_peak_ = true;
    peak_current_a_ = directed;
    load_at_peak_n_ = load_n;
    max_estimate_m_ = sinkage_m;
    return;
  }
  if (directed > peak_current_a_) {
    peak_current_a_ = directed;
    load_at_peak_n_ = load_n;
  }
  if (sinkage_m > max_estimate_m_) {
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
  e.max_estimate_valid = have_peak_;
  e.max_estimated_sinkage_m = have_peak_ ? max_estimate_m_ : SinkageM::zero();
  return e;
}

template <bool kValidTable>
SW_FX_INLINE void WheelMonitor::transition(bool current_stop, bool slip_stop, const Histories& h, TimeMs now,
                                           const PreparedParameters& prepared, WheelOutput& out) noexcept {
  const MonitorParams& mp = prepared.table().monitor;
  if (state_ == WheelState::stop) {
    return;  // STOP is latched until clear_stop()
  }
  if constexpr (kValidTable) {
    // A quiet NOMINAL wheel's usual cycle: no stop and no caution evidence
    // in either window, which no count of a validated table (trip_n >= 1)
    // reaches. Its sample was usable (an unusable one is caution evidence),
    // so consecutive_unusable_ is 0, below invalid_to_stop (>= 1): no
    // limit is read.
    if ((state_ == WheelState::nominal) && ((h.stop | h.caution) == 0U)) {
      return;
    }
  }
  const bool unusable_trip = consecutive_unusable_ >= mp.invalid_to_stop;
  if (unusable_trip || window_reaches<kValidTable>(h.stop, mp.window_m, mp.trip_n)) {
    // The sample's reason is named only here, on the cycle that trips.
    const StopReason sample_reason =
        current_stop ? StopReason::current : (slip_stop ? StopReason::slip : StopReason::sinkage);
    const StopReason reason = unusable_trip ? StopReason::telemetry : sample_reason;
    state_ = WheelState::stop;
    stop_reason_ = reason;
    out.stop_tripped = true;
    event_ = stop_event(now, reason, prepared);
    has_event_ = true;
  } else if ((state_ == WheelState::nominal) && window_reaches<kValidTable>(h.caution, mp.window_m, mp.trip_n)) {
    state_ = WheelState::caution;
    // Leaving CAUTION needs clear_n clear samples seen from here on.
    clear_history_ = 0U;
  } else if ((state_ == WheelState::caution) && window_reaches<kValidTable>(h.clear, mp.window_m, mp.clear_n)) {
    state_ = WheelState::nominal;
    caution_history_ = 0U;
    have_peak_ = false;
  } else {
    // no transition
  }
}

template <typename Sample>
SW_FX_INLINE void WheelMonitor::step_body(Sample input, TimeMs now, const PreparedParameters& prepared,
                                          WheelOutput& out, std::uint8_t& blind_wheels) noexcept {
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
    last_time_ = input.time();
  }

  // 2. The estimate and the limit, only from a usable sample.
  CurrentA directed = CurrentA::zero();
  if (status == SampleStatus::ok) {
    fx::Status dir_status;
    directed = directional(input.current_a(), input.direction(), dir_status);
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
  if (status != SampleStatus::ok) {
    // A blind wheel is tallied here, on the unusable sample's path, not
    // tested again by the caller per wheel. Under continue_degraded it is
    // held in CAUTION by its unusable evidence but does not trip
    // invalid_to_stop (monitor.hpp).
    bool tolerated_blind = false;
    if (status == SampleStatus::sensor_fault) {
      ++blind_wheels;
      tolerated_blind = table.health.policy == LossPolicy::continue_degraded;
    }
    if ((consecutive_unusable_ < 0xFFU) && !tolerated_blind) {
      ++consecutive_unusable_;
    }
  } else {
    consecutive_unusable_ = 0U;
    e = evidence_of(directed, out, table.monitor, input.clear_levels(table.monitor));
    if (input.drawbar_assumed()) {
      // DP = DP_max assumed at high slip: the estimate is a lower bound and
      // the wheel makes no headway (WheelInput::drawbar_assumed).
      e.slip_stop = !e.stop;
      e.stop = true;
      e.caution = true;
      e.clear = false;
    }
    track_episode(directed, input.load_n(), out.sinkage_m);
  }
  // The new histories as words (bit 16: the dropped sample, which the
  // windows' count ignores) for the transitions, cut to 16 bits by the store.
  const Histories h{n_of_m::shifted_in(caution_history_, e.caution), n_of_m::shifted_in(stop_history_, e.stop),
                    n_of_m::shifted_in(clear_history_, e.clear)};
  caution_history_ = static_cast<std::uint16_t>(h.caution);
  stop_history_ = static_cast<std::uint16_t>(h.stop);
  clear_history_ = static_cast<std::uint16_t>(h.clear);

  // 4. Transitions (STOP is latched).
  transition<Sample::kValidTable>(e.current_stop, e.slip_stop, h, now, prepared, out);
  out.state = state_;
  out.stop_reason = stop_reason_;
}

template <typename Sample>
[[gnu::noinline]] void WheelMonitor::step_sample(Sample input, TimeMs now, const PreparedParameters& prepared,
                                                 WheelOutput& out, std::uint8_t& blind_wheels) noexcept {
  step_body(input, now, prepared, out, blind_wheels);
}

void WheelMonitor::step(const WheelInput& input, TimeMs now, const PreparedParameters& prepared,
                        WheelOutput& out) noexcept {
  std::uint8_t blind_wheels = 0U;  // a lone wheel has no rover tally
  step_sample(InputSample(input), now, prepared, out, blind_wheels);
}

RoverMonitor::RoverMonitor() noexcept
    : wheels_{WheelMonitor(0U), WheelMonitor(1U), WheelMonitor(2U), WheelMonitor(3U), WheelMonitor(4U),
              WheelMonitor(5U)} {}

namespace {

/// RoverMonitor::step_all's wheels from six WheelInput records.
class InputWheels {
 public:
  /// Through the out-of-line WheelMonitor::step_sample, shared with step().
  static constexpr bool kInlineStep = false;
  explicit InputWheels(const WheelInput (&inputs)[kMaxWheels]) noexcept : inputs_(inputs) {}
  [[nodiscard]] InputSample sample(std::uint8_t i) const noexcept { return InputSample(inputs_[i]); }

 private:
  const WheelInput (&inputs_)[kMaxWheels];
};

/// RoverMonitor::step_all's wheels on a cycle of a WheelSamples whose flag
/// or age is not ok: each wheel's sample is the WheelInput of the cycle's
/// flag and time stamp, which classify_sample() refuses before it reads
/// anything else (flagged_invalid or stale), so the rest is never read.
/// Through the WheelInput body: no third copy of a wheel's step for the
/// rare cycle.
class UnfreshWheels {
 public:
  static constexpr bool kInlineStep = false;
  explicit UnfreshWheels(const WheelSamples& samples) noexcept {
    input_.time = samples.time;
    input_.valid = samples.valid;
  }
  [[nodiscard]] InputSample sample(std::uint8_t /*i*/) const noexcept { return InputSample(input_); }

 private:
  WheelInput input_{};
};

/// RoverMonitor::step_all's wheels from a WheelSamples, read in place, on
/// a cycle whose flag and age are ok (cycle_fresh_status).
class CycleWheels {
 public:
  /// step_all's loop takes WheelMonitor::step_body in place: this is its
  /// only caller on a CycleSample, so no code is copied.
  static constexpr bool kInlineStep = true;
  CycleWheels(const WheelSamples& samples, const MonitorParams& mp) noexcept
      : samples_(samples), levels_(clear_levels_of(mp)) {}
  [[nodiscard]] CycleSample sample(std::uint8_t i) const noexcept { return CycleSample(samples_, levels_, i); }

 private:
  const WheelSamples& samples_;
  ClearLevels levels_;  ///< once per cycle, not per wheel
};

}  // namespace

template <typename Wheels>
void RoverMonitor::step_all(const Wheels& wheels, TimeMs now, const PreparedParameters& prepared,
                            RoverOutput& out) noexcept {
  const ParameterTable& table = prepared.table();
  const std::uint8_t count = (table.monitor.wheel_count < kMaxWheels) ? table.monitor.wheel_count : kMaxWheels;
  // The states' tallies in one local word, stored once: each wheel's step
  // may write any memory as far as the compiler knows, so counts kept in
  // `out` were reloaded and stored per wheel. A wheel in state s adds
  // s << 2s (WheelState: nominal 0 adds 0, caution 1 adds 4, stop 2 adds
  // 32): bits 2-4 count the wheels in CAUTION (at most kMaxWheels = 6, so
  // no carry into bit 5) and bits 5 on those in STOP; two shifts and an add
  // per wheel, no branch per state (round 17: one instruction fewer per
  // wheel than a byte per state, 1 << 8s). The blind wheels are counted in `out`
  // by the wheel's step, on a sensor fault's path only (round 16: no test
  // of every wheel's status here; M4 -49, M0 -20 instructions per step).
  static_assert((kMaxWheels <= 7U) && (static_cast<std::uint32_t>(WheelState::caution) == 1U) &&
                    (static_cast<std::uint32_t>(WheelState::stop) == 2U),
                "the tally's CAUTION count fits bits 2-4");
  std::uint32_t tally = 0U;
  out.wheels_blind = 0U;
  for (std::uint32_t i = 0U; i < count; ++i) {
    WheelOutput& w = out.wheels[i];
    if constexpr (Wheels::kInlineStep) {
      wheels_[i].step_body(wheels.sample(static_cast<std::uint8_t>(i)), now, prepared, w, out.wheels_blind);
    } else {
      wheels_[i].step_sample(wheels.sample(static_cast<std::uint8_t>(i)), now, prepared, w, out.wheels_blind);
    }
    const auto state = static_cast<std::uint32_t>(w.state);
    tally += state << (state << 1U);
  }
  // Wheels beyond wheel_count are not monitored: their outputs are default.
  for (std::uint8_t i = count; i < kMaxWheels; ++i) {
    out.wheels[i] = WheelOutput{};
  }
  out.wheels_in_stop = static_cast<std::uint8_t>(tally >> 5U);
  out.wheels_in_caution = static_cast<std::uint8_t>((tally >> 2U) & 7U);
  rover_rules(table, count, out);
}

void RoverMonitor::rover_rules(const ParameterTable& table, std::uint8_t count, RoverOutput& out) noexcept {
  // Without a wheel in CAUTION or STOP no wheel is held: the pass over the
  // wheels is only made when one is.
  if ((out.wheels_in_stop + out.wheels_in_caution) > 0U) {
    for (std::uint8_t i = 0U; i < count; ++i) {
      WheelOutput& w = out.wheels[i];
      if ((w.sample_status != SampleStatus::ok) && (w.state == WheelState::nominal)) {
        wheels_[i].hold_in_caution();
        w.state = WheelState::caution;
        ++out.wheels_in_caution;
      }
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
    step_all(InputWheels(inputs), now, prepared, out);
  } else {
    refuse_table(out);
  }
}

void RoverMonitor::step(const WheelSamples& samples, TimeMs now, const PreparedParameters& prepared,
                        RoverOutput& out) noexcept {
  if (prepared.table_valid()) {
    // The cycle's flag and age once, not per wheel: they are every wheel's.
    const SampleStatus fresh = cycle_fresh_status(samples, now, prepared.table().monitor);
    if (fresh == SampleStatus::ok) {
      step_all(CycleWheels(samples, prepared.table().monitor), now, prepared, out);
    } else {
      step_unfresh(samples, now, prepared, out);
    }
  } else {
    refuse_table(out);
  }
}

[[gnu::noinline]] void RoverMonitor::step_unfresh(const WheelSamples& samples, TimeMs now,
                                                  const PreparedParameters& prepared, RoverOutput& out) noexcept {
  step_all(UnfreshWheels(samples), now, prepared, out);
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
