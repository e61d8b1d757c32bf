// The motion-resistance check (traction.hpp; docs/traction.md).
#include "sinkwatch/flight/traction.hpp"

#include "median.hpp"
#include "n_of_m.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using W = WideQ;
using n_of_m::count_bits;
using n_of_m::shift_in;

constexpr W kSecondsPerMs{fx::constant<W>(0.001)};
/// A gap between usable samples longer than this is not integrated: the
/// odometry cannot say where the rover was in between.
constexpr std::uint32_t kMaxGapMs = 2000U;
/// Marks per trend span (kTractionTrendMarks / 2: the history reaches back
/// two spans).
constexpr std::int32_t kMarksPerSpan = 8;

/// The directed sums of the wheels with a torque: T, DP (along the drive
/// direction) and W.
struct WheelSums {
  W torque{};
  W pull{};
  W load{};
  std::uint8_t wheels{0U};
  bool mixed{false};
};

WheelSums sum_wheels(const TractionInput& in, std::uint8_t wheels, fx::Status& st) noexcept {
  WheelSums s{};
  bool have_direction = false;
  DriveDirection direction = DriveDirection::forward;
  for (std::uint8_t i = 0U; (i < wheels) && (i < kWheelCount); ++i) {
    if (in.torque_valid[i]) {
      if (have_direction && (in.direction[i] != direction)) {
        s.mixed = true;
      }
      have_direction = true;
      direction = in.direction[i];
      const W pull = fx::rescale<W>(in.drawbar_pull_n[i].q(), st);
      // Reverse: the pull that drives the rover backwards is -DP.
      s.pull = fx::add(s.pull, (direction == DriveDirection::reverse) ? fx::neg(pull, st) : pull, st);
      s.torque = fx::add(s.torque, fx::rescale<W>(in.torque_nm[i].q(), st), st);
      s.load = fx::add(s.load, fx::rescale<W>(in.load_n[i].q(), st), st);
      ++s.wheels;
    }
  }
  return s;
}

}  // namespace

TractionMonitor::TractionMonitor() noexcept = default;

void TractionMonitor::clear_stop() noexcept { *this = TractionMonitor(); }

void TractionMonitor::restart() noexcept {
  recent_count_ = 0U;
  recent_next_ = 0U;
  mark_count_ = 0U;
  since_mark_m_ = LengthM::zero();
  settled_ = false;
}

TractionSample TractionMonitor::resistance_of(const TractionInput& in, std::uint8_t wheels, LengthM radius,
                                              Ratio& rho) noexcept {
  if (!in.loads_valid) {
    return TractionSample::no_loads;
  }
  if (in.pull_assumed) {
    return TractionSample::pull_assumed;
  }
  fx::Status st;
  const WheelSums s = sum_wheels(in, wheels, st);
  if ((static_cast<std::uint32_t>(s.wheels) * 2U) < static_cast<std::uint32_t>(wheels)) {
    return TractionSample::too_few_wheels;
  }
  if (s.mixed) {
    return TractionSample::mixed_direction;
  }
  // rho = (sum T / r - sum DP) / sum W: each wheel's thrust less its share
  // of the pull, over the weight those wheels carry.
  const W thrust = fx::div<W>(s.torque, radius.q(), st);
  const W resistance = fx::sub(thrust, s.pull, st);
  rho = Ratio(fx::div<RatioQ>(resistance, s.load, st));
  return st.ok() ? TractionSample::ok : TractionSample::overflow;
}

Ratio TractionMonitor::push_median(Ratio rho) noexcept {
  recent_[recent_next_] = rho;
  recent_next_ = static_cast<std::uint8_t>((recent_next_ + 1U) % kTractionMedianSamples);
  if (recent_count_ < kTractionMedianSamples) {
    ++recent_count_;
  }
  return detail::median_of(recent_, recent_count_);
}

void TractionMonitor::advance(const TractionInput& in, Ratio rho_med, const TractionParams& params) noexcept {
  const std::uint32_t dt_ms = have_time_ ? elapsed_ms(last_time_, in.time) : 0U;
  have_time_ = true;
  last_time_ = in.time;
  if (!in.speed_valid || (dt_ms > kMaxGapMs)) {
    return;
  }
  fx::Status st;
  const W dt_s = fx::mul(W::from_int(static_cast<std::int64_t>(dt_ms), st), kSecondsPerMs, st);
  const W step_m = fx::mul(fx::abs(fx::rescale<W>(in.speed_mps.q(), st), st), dt_s, st);
  const LengthM travelled{fx::add(since_mark_m_.q(), fx::rescale<LengthQ>(step_m, st), st)};
  if (!st.ok()) {
    return;  // GCOVR_EXCL_LINE defensive: |v| <= 128 m/s for <= 2 s fits Q7.24 (docs/traction.md)
  }
  since_mark_m_ = travelled;
  if (!settled_) {
    // The start's acceleration: the first span sets no baseline (the
    // distance so far counts towards it, and no mark is kept).
    settled_ = since_mark_m_ >= params.trend_span_m;
    if (settled_) {
      since_mark_m_ = LengthM::zero();
    }
    return;
  }
  // span / 8 (validate(): the span is positive, so the quotient truncates
  // towards zero by less than one LSB).
  const LengthM spacing = LengthM::from_raw(params.trend_span_m.raw() / kMarksPerSpan);
  if (since_mark_m_ < spacing) {
    return;
  }
  mark_newest_ = static_cast<std::uint8_t>((mark_newest_ + 1U) % kTractionTrendMarks);
  mark_rho_[mark_newest_] = rho_med;
  mark_gap_m_[mark_newest_] = since_mark_m_;
  since_mark_m_ = LengthM::zero();
  if (mark_count_ < kTractionTrendMarks) {
    ++mark_count_;
  }
}

bool TractionMonitor::ahead_of(Ratio rho_med, const TractionParams& params, Ratio& ahead,
                               fx::Status& st) const noexcept {
  ahead = rho_med;
  // Walk back from the newest mark until the marks span trend_span_m; the
  // first mark's own gap reaches to before the history and is never used.
  W distance = fx::rescale<W>(since_mark_m_.q(), st);
  const W span = fx::rescale<W>(params.trend_span_m.q(), st);
  std::uint8_t index = mark_newest_;
  for (std::uint8_t k = 0U; k < mark_count_; ++k) {
    if ((k > 0U) && (distance >= span)) {
      const W rise = fx::sub(fx::rescale<W>(rho_med.q(), st), fx::rescale<W>(mark_rho_[index].q(), st), st);
      if (rise > W::zero()) {
        const W carried = fx::div<W>(fx::mul(fx::rescale<W>(params.lookahead_m.q(), st), rise, st), distance, st);
        ahead = Ratio(fx::rescale<RatioQ>(fx::add(fx::rescale<W>(rho_med.q(), st), carried, st), st));
      }
      return true;
    }
    distance = fx::add(distance, fx::rescale<W>(mark_gap_m_[index].q(), st), st);
    index = static_cast<std::uint8_t>((index + kTractionTrendMarks - 1U) % kTractionTrendMarks);
  }
  return false;
}

void TractionMonitor::push_history(bool caution, bool stop, bool clear) noexcept {
  caution_history_ = shift_in(caution_history_, caution);
  stop_history_ = shift_in(stop_history_, stop);
  clear_history_ = shift_in(clear_history_, clear);
}

void TractionMonitor::transition(const MonitorParams& monitor, TractionOutput& out) noexcept {
  if (state_ == TractionState::stop) {
    return;  // latched until clear_stop()
  }
  if (count_bits(stop_history_, monitor.window_m) >= monitor.trip_n) {
    state_ = TractionState::stop;
    out.stop_tripped = true;
  } else if ((state_ == TractionState::nominal) && (count_bits(caution_history_, monitor.window_m) >= monitor.trip_n)) {
    state_ = TractionState::caution;
  } else if ((state_ == TractionState::caution) && (count_bits(clear_history_, monitor.window_m) >= monitor.clear_n)) {
    state_ = TractionState::nominal;
  } else {
    // No change.
  }
}

TractionSample TractionMonitor::evaluate(const TractionInput& input, const TractionParams& params, Ratio rho,
                                         TractionOutput& out) noexcept {
  fx::Status st;
  const bool standing =
      input.speed_valid && (fx::abs(input.speed_mps.q(), st) < kTractionStandingSpeed.q());
  if (standing || !st.ok()) {
    restart();
    have_time_ = true;
    last_time_ = input.time;
    return TractionSample::standing;
  }
  const Ratio rho_med = push_median(rho);
  advance(input, rho_med, params);
  Ratio ahead{};
  out.trend_known = ahead_of(rho_med, params, ahead, st);
  if (!st.ok()) {
    out.trend_known = false;
    return TractionSample::overflow;
  }
  out.rho_valid = true;
  out.resistance = rho;
  out.resistance_median = rho_med;
  out.resistance_ahead = ahead;
  return (recent_count_ < kTractionMedianSamples) ? TractionSample::filling : TractionSample::ok;
}

TractionOutput TractionMonitor::step(const TractionInput& input, const TractionParams& params,
                                     const MonitorParams& monitor, LengthM wheel_radius_m) noexcept {
  TractionOutput out{};
  if (!traction_check_on(params)) {
    out.state = TractionState::off;
    out.sample = TractionSample::check_off;
    return out;
  }
  Ratio rho{};
  out.sample = resistance_of(input, monitor.wheel_count, wheel_radius_m, rho);
  if (out.sample == TractionSample::ok) {
    out.sample = evaluate(input, params, rho, out);
  }
  bool caution = false;
  bool stop = false;
  bool clear = false;
  if (out.sample == TractionSample::ok) {
    fx::Status st;
    stop = out.resistance_ahead >= params.stop_coefficient;
    caution = out.resistance_ahead >= params.caution_coefficient;
    // validate(): hysteresis < caution, so the difference cannot overflow.
    clear = out.resistance_ahead.q() < fx::sub(params.caution_coefficient.q(), params.hysteresis.q(), st);
  }
  push_history(caution, stop, clear);
  transition(monitor, out);
  out.state = state_;
  return out;
}

}  // namespace flight
}  // namespace sinkwatch
