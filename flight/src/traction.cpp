// The motion-resistance check (traction.hpp; docs/traction.md).
#include "sinkwatch/flight/traction.hpp"

#include "median.hpp"
#include "n_of_m.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/estimator.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using fx::wide::mul_32x32_64;
using n_of_m::count_bits;
using n_of_m::shift_in;

/// |sum T| below 2^31 raw (2^-16 N m, so 32768 N m): the bound that keeps the
/// thrust product in 64 bits (docs/traction.md, "Arithmetic and error").
constexpr std::uint64_t kMaxTorqueSumQ16 = (std::uint64_t{1U} << 31U) - 1U;
/// 2^24: a Q15.16 force in units of 2^-40 N (the thrust's units).
constexpr std::int64_t kQ16ToQ40 = static_cast<std::int64_t>(std::uint64_t{1U} << 24U);
/// A gap between usable samples longer than this is not integrated: the
/// odometry cannot say where the rover was in between.
constexpr std::uint32_t kMaxGapMs = 2000U;
/// Marks per trend span (kTractionTrendMarks / 2: the history reaches back
/// two spans).
constexpr std::int32_t kMarksPerSpan = 8;

/// n / d rounded half away from zero, as a raw Q7.24 ratio (d > 0), by
/// detail::rounded_quotient_one_word or detail::rounded_quotient. Beyond Q7.24 it saturates and raises overflow.
Ratio rounded_ratio(std::int64_t n, std::uint64_t d, fx::Status& st) noexcept {
  const bool negative = n < 0;
  const std::uint64_t magnitude = fx::detail::magnitude(n);
  // The usual quotient in the check's own code on a core that divides
  // words (round 15 of issue 15); otherwise, and for the rest, the call.
  const std::uint64_t quotient =
      (fx::wide::kDivideInstruction && detail::one_word_quotient(magnitude, d))
          ? detail::rounded_quotient_one_word(magnitude, d)
          : detail::rounded_quotient(magnitude, d);
  return Ratio::from_raw(
      fx::detail::from_sign_magnitude<RatioQ::storage_type>(negative && (quotient != 0U), quotient, st));
}

/// ceil(2^41 / 1000): x * kPerThousand / 2^41 is floor(x / 1000) for every
/// 32-bit x. It exceeds 2^41 / 1000 by e / 1000 with e = 1000 kPerThousand -
/// 2^41 = 448, so x kPerThousand / 2^41 = x / 1000 + x e / (1000 2^41), and
/// with x = 1000 q + r (r <= 999) the fraction r / 1000 + x e / (1000 2^41)
/// stays below 1 because x e < 2^32 * 2^9 = 2^41 (Granlund and Montgomery,
/// "Division by invariant integers using multiplication", 1994, Theorem 4.2).
constexpr std::uint32_t kPerThousand = 2199023256U;
constexpr std::uint32_t kPerThousandShift = 41U;

/// floor(x / 1000) without a division: a library call of about 100
/// instructions on the Cortex-M0, which has no divide instruction.
std::uint32_t thousandths(std::uint32_t x) noexcept {
  return static_cast<std::uint32_t>(mul_32x32_64(x, kPerThousand) >> kPerThousandShift);
}

/// detail::travelled_q24, forced inline into advance() (its one use in the
/// check: the call cost a third of its instructions).
SW_FX_INLINE std::uint64_t travelled_inline(std::uint32_t speed_q24, std::uint32_t dt_ms) noexcept {
  // |v| = 1000 a + b: |v| dt + 500 = 1000 a dt + (b dt + 500), so the
  // quotient by 1000 is a dt plus that of b dt + 500 (< 2^21), exactly.
  // a <= 2^31 / 1000, so a dt <= 2,147,483 * 2000 < 2^32.
  const std::uint32_t a = thousandths(speed_q24);
  const std::uint32_t b = speed_q24 - (a * 1000U);
  return static_cast<std::uint64_t>(a * dt_ms) + thousandths((b * dt_ms) + 500U);
}

}  // namespace

namespace detail {

std::uint64_t rounded_quotient(std::uint64_t n, std::uint64_t d) noexcept {
  // The library's 64-bit division (fixedpoint/wide.hpp): on a core without
  // a divide instruction a one-word divisor (every load sum below 65,536 N)
  // takes the normalising 64 / 32-bit long division, not __aeabi_uldivmod.
  const fx::wide::DivMod<std::uint64_t> qr = fx::wide::divmod(n, d);
  return qr.quotient + ((qr.remainder >= (d - qr.remainder)) ? 1U : 0U);
}

std::uint64_t travelled_q24(std::uint32_t speed_q24, std::uint32_t dt_ms) noexcept {
  return travelled_inline(speed_q24, dt_ms);
}

}  // namespace detail

InverseRadius inverse_radius(LengthM wheel_radius_m) noexcept {
  if ((wheel_radius_m < kMinRadiusM) || (wheel_radius_m > kMaxRadiusM)) {
    return InverseRadius{};
  }
  // 1/r in Q7.24 is 2^24 / (r_raw 2^-24) = 2^48 / r_raw, rounded half up;
  // below 2^31 for r >= kMinRadiusM (167772 raw).
  const std::uint64_t r = static_cast<std::uint64_t>(wheel_radius_m.raw());
  constexpr std::uint64_t kTwoTo48 = std::uint64_t{1U} << 48U;
  return InverseRadius{static_cast<std::uint32_t>((kTwoTo48 + (r / 2U)) / r)};
}

bool carried_ahead(Ratio rho_med, Ratio rho_back, std::int64_t distance_m_q24, LengthM lookahead_m,
                   Ratio& ahead) noexcept {
  ahead = rho_med;
  if (distance_m_q24 <= 0) {
    return false;
  }
  // Two Q7.24 values differ by less than 2^32 raw.
  const std::int64_t rise = static_cast<std::int64_t>(rho_med.raw()) - static_cast<std::int64_t>(rho_back.raw());
  if (rise <= 0) {
    return true;  // nothing to carry: rho_ahead = rho_med
  }
  // lookahead (|L| <= 2^31, 2^-24 m) times the rise (< 2^32, 2^-24) is below
  // 2^63 in units of 2^-48 m; over the distance (2^-24 m) the quotient is the
  // carried term in 2^-24, its raw Q7.24 value: one rounding.
  const bool backwards = lookahead_m.raw() < 0;
  const std::uint64_t lever = mul_32x32_64(static_cast<std::uint32_t>(fx::detail::magnitude(lookahead_m.raw())),
                                           static_cast<std::uint32_t>(rise));
  const std::uint64_t d = static_cast<std::uint64_t>(distance_m_q24);
  std::uint64_t carried = lever / d;
  const std::uint64_t remainder = lever - (carried * d);
  if (remainder >= (d - remainder)) {
    ++carried;
  }
  // carried < 2^63: the sum is exact in 64 bits, and must fit Q7.24.
  const std::int64_t signed_carried = backwards ? -static_cast<std::int64_t>(carried) : static_cast<std::int64_t>(carried);
  const std::int64_t sum = static_cast<std::int64_t>(rho_med.raw()) + signed_carried;
  if ((sum > static_cast<std::int64_t>(RatioQ::max().raw())) || (sum < static_cast<std::int64_t>(RatioQ::min().raw()))) {
    return false;
  }
  ahead = Ratio::from_raw(static_cast<RatioQ::storage_type>(sum));
  return true;
}

TractionMonitor::TractionMonitor() noexcept = default;

void TractionMonitor::clear_stop() noexcept { *this = TractionMonitor(); }

void TractionMonitor::restart() noexcept {
  recent_count_ = 0U;
  recent_next_ = 0U;
  mark_count_ = 0U;
  since_mark_m_ = LengthM::zero();
  settled_ = false;
}

SW_FX_INLINE TractionSample TractionMonitor::resistance_of(const TractionCycle& in, std::uint8_t wheels,
                                                           InverseRadius per_radius, Ratio& rho) noexcept {
  if (!in.loads_valid) {
    return TractionSample::no_loads;
  }
  if (in.pull_assumed) {
    return TractionSample::pull_assumed;
  }
  const TractionSums& s = in.sums;
  const std::uint32_t summed = s.wheels();
  if ((summed * 2U) < static_cast<std::uint32_t>(wheels)) {
    return TractionSample::too_few_wheels;
  }
  const std::uint32_t any_bits = s.any_bits();
  if ((summed > 0U) && (any_bits != s.all_bits)) {
    return TractionSample::mixed_direction;
  }
  // Reverse (every wheel, as just checked): the pull that drives the rover
  // backwards is -DP.
  const bool reverse = any_bits == static_cast<std::uint32_t>(DriveDirection::reverse);
  const std::int64_t pull_q16 = reverse ? -s.pull_q16 : s.pull_q16;
  // rho = (sum T / r - sum DP) / sum W: each wheel's thrust less its share
  // of the pull, over the weight those wheels carry (docs/traction.md,
  // "Arithmetic and error"). Out of the products' range: no number.
  const std::uint64_t torque = fx::detail::magnitude(s.torque_q16);
  if ((per_radius.per_m_q24 == 0U) || (torque > kMaxTorqueSumQ16) || (s.load_q16 <= 0)) {
    return TractionSample::overflow;
  }
  // sum T (< 2^31, 2^-16 N m) times 1/r (< 2^31, 2^-24 1/m): the thrust in
  // 2^-40 N, exact and below 2^62; the pull in the same units is below 2^59.
  const std::uint64_t thrust = mul_32x32_64(static_cast<std::uint32_t>(torque), per_radius.per_m_q24);
  const std::int64_t signed_thrust =
      (s.torque_q16 < 0) ? -static_cast<std::int64_t>(thrust) : static_cast<std::int64_t>(thrust);
  const std::int64_t resistance = signed_thrust - (pull_q16 * kQ16ToQ40);
  // resistance (2^-40 N) / sum W (2^-16 N) is rho in units of 2^-24: the
  // quotient is rho's raw Q7.24 value, rounded once.
  fx::Status st;
  rho = rounded_ratio(resistance, static_cast<std::uint64_t>(s.load_q16), st);
  return st.ok() ? TractionSample::ok : TractionSample::overflow;
}

// The stages of a usable sample (push_median, advance, ahead_of, evaluate)
// and of the state (push_history, transition) are each called once per
// cycle: inline into step() (SW_FX_INLINE), without a call, its saved
// registers and its arguments (about 45 Cortex-M4 instructions per cycle).
// resistance_of is inline too (above) since its wheels come summed
// (TractionCycle, round 16): it no longer spills a six-wheel loop.
SW_FX_INLINE Ratio TractionMonitor::push_median(Ratio rho) noexcept {
  // The window's values stay sorted: the oldest value leaves (any copy of
  // it: equal ratios are the same bits), the new one is inserted in order.
  // The median of the multiset is the same as that of a sorted copy
  // (median_of), without the copy, its zeroing and the sort.
  std::uint8_t kept = recent_count_;
  if (kept == kTractionMedianSamples) {
    const Ratio oldest = recent_[recent_next_];
    bool found = false;
    for (std::uint8_t i = 0U; i < kTractionMedianSamples; ++i) {
      found = found || (sorted_[i] == oldest);
      if (found && ((i + 1U) < kTractionMedianSamples)) {
        sorted_[i] = sorted_[i + 1U];
      }
    }
    --kept;
  }
  std::uint8_t slot = kept;
  while ((slot > 0U) && (rho < sorted_[slot - 1U])) {
    sorted_[slot] = sorted_[slot - 1U];
    --slot;
  }
  sorted_[slot] = rho;
  recent_[recent_next_] = rho;
  recent_next_ = detail::next_slot<kTractionMedianSamples>(recent_next_);
  recent_count_ = static_cast<std::uint8_t>(kept + 1U);
  // The lower middle of an even count, as median_of.
  return sorted_[static_cast<std::uint8_t>(kept / 2U)];
}

SW_FX_INLINE void TractionMonitor::advance(const TractionCycle& in, Ratio rho_med,
                                           const TractionParams& params) noexcept {
  const std::uint32_t dt_ms = have_time_ ? elapsed_ms(last_time_, in.time) : 0U;
  have_time_ = true;
  last_time_ = in.time;
  if (!in.speed_valid || (dt_ms > kMaxGapMs)) {
    return;
  }
  // |v| dt / 1000: |v| (<= 2^31, 2^-24 m/s) times dt (<= 2000 ms) is below
  // 2^42; the division by 1000 rounds once (half up) into 2^-24 m.
  const std::uint32_t speed = fx::detail::magnitude32(in.speed_mps.raw());
  const std::uint64_t step_q24 = travelled_inline(speed, dt_ms);
  fx::Status st;
  const LengthM step_m = LengthM::from_raw(fx::detail::from_sign_magnitude<LengthQ::storage_type>(false, step_q24, st));
  const LengthM travelled{fx::add(since_mark_m_.q(), step_m.q(), st)};
  if (!st.ok()) {
    return;  // GCOVR_EXCL_LINE defensive: beyond 64 m/s for 2 s (the step refuses |v| > 5 m/s; docs/traction.md)
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

SW_FX_INLINE bool TractionMonitor::ahead_of(Ratio rho_med, const TractionParams& params, Ratio& ahead,
                               bool& overflow) const noexcept {
  ahead = rho_med;
  overflow = false;
  // Walk back from the newest mark until the marks span trend_span_m; the
  // first mark's own gap reaches to before the history and is never used.
  // The distance in raw LengthM units: at most 17 values below 2^31, exact.
  std::int64_t distance = since_mark_m_.raw();
  const std::int64_t span = params.trend_span_m.raw();
  std::uint8_t index = mark_newest_;
  for (std::uint8_t k = 0U; k < mark_count_; ++k) {
    if ((k > 0U) && (distance >= span)) {
      overflow = !carried_ahead(rho_med, mark_rho_[index], distance, params.lookahead_m, ahead);
      return true;
    }
    distance += mark_gap_m_[index].raw();
    index = static_cast<std::uint8_t>((index + kTractionTrendMarks - 1U) % kTractionTrendMarks);
  }
  return false;
}

SW_FX_INLINE void TractionMonitor::push_history(bool caution, bool stop, bool clear) noexcept {
  caution_history_ = shift_in(caution_history_, caution);
  stop_history_ = shift_in(stop_history_, stop);
  clear_history_ = shift_in(clear_history_, clear);
}

namespace {

/// Set bits among the newest `window` of `history`: none when the history
/// is empty (the usual case of the stop and caution histories), without the
/// count.
SW_FX_INLINE std::uint8_t evidence(std::uint16_t history, std::uint8_t window) noexcept {
  return (history == 0U) ? std::uint8_t{0U} : count_bits(history, window);
}

}  // namespace

SW_FX_INLINE void TractionMonitor::transition(const MonitorParams& monitor, TractionOutput& out) noexcept {
  if (state_ == TractionState::stop) {
    return;  // latched until clear_stop()
  }
  if (evidence(stop_history_, monitor.window_m) >= monitor.trip_n) {
    state_ = TractionState::stop;
    out.stop_tripped = true;
  } else if ((state_ == TractionState::nominal) && (evidence(caution_history_, monitor.window_m) >= monitor.trip_n)) {
    state_ = TractionState::caution;
  } else if ((state_ == TractionState::caution) && (evidence(clear_history_, monitor.window_m) >= monitor.clear_n)) {
    state_ = TractionState::nominal;
  } else {
    // No change.
  }
}

SW_FX_INLINE TractionSample TractionMonitor::evaluate(const TractionCycle& input, const TractionParams& params,
                                                      Ratio rho, TractionOutput& out) noexcept {
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
  bool overflow = false;
  out.trend_known = ahead_of(rho_med, params, ahead, overflow);
  if (overflow) {
    out.trend_known = false;
    return TractionSample::overflow;
  }
  out.rho_valid = true;
  out.resistance = rho;
  out.resistance_median = rho_med;
  out.resistance_ahead = ahead;
  return (recent_count_ < kTractionMedianSamples) ? TractionSample::filling : TractionSample::ok;
}

void TractionMonitor::step(const TractionCycle& input, const TractionParams& params, const MonitorParams& monitor,
                           InverseRadius per_radius, TractionOutput& out) noexcept {
  // Every field, as TractionOutput{} has them (the record is the previous
  // cycle's).
  out.stop_tripped = false;
  out.rho_valid = false;
  out.resistance = Ratio::zero();
  out.resistance_median = Ratio::zero();
  out.trend_known = false;
  out.resistance_ahead = Ratio::zero();
  if (!traction_check_on(params)) {
    out.state = TractionState::off;
    out.sample = TractionSample::check_off;
    return;
  }
  Ratio rho{};
  // The sample's verdict in a local, stored once.
  TractionSample sample = resistance_of(input, monitor.wheel_count, per_radius, rho);
  if (sample == TractionSample::ok) {
    sample = evaluate(input, params, rho, out);
  }
  out.sample = sample;
  bool caution = false;
  bool stop = false;
  bool clear = false;
  if (sample == TractionSample::ok) {
    fx::Status st;
    stop = out.resistance_ahead >= params.stop_coefficient;
    caution = out.resistance_ahead >= params.caution_coefficient;
    // validate(): hysteresis < caution, so the difference cannot overflow.
    clear = out.resistance_ahead.q() < fx::sub(params.caution_coefficient.q(), params.hysteresis.q(), st);
  }
  push_history(caution, stop, clear);
  transition(monitor, out);
  out.state = state_;
}

}  // namespace flight
}  // namespace sinkwatch
