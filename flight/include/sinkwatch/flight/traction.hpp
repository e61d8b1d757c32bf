// traction.hpp: the rover's motion-resistance check, a stop rule that does
// not need Table 2 to match the soil (issue 14; docs/traction.md).
//
// The paper's section 7 stops near the maximum drive current; Eq. 15 turns
// the current into a sinkage only through C1..C3 fitted on one soil. What
// embeds a rover, whatever the soil, is that the wheels' torque goes more
// and more into the soil's resistance (compaction, bulldozing, slip sinkage)
// and less into pull. The rover measures that share directly: its torques
// from the motor currents (motor.hpp), its weight on the wheels from the
// statics (wheel_load.hpp) and the pull its slope and acceleration need
// from the force balance (drawbar_pull.hpp). Each usable cycle:
//
//   rho       = (sum_i T_i / r - sum_i DP_i) / sum_i W_i    the motion-resistance coefficient
//   rho_med   = median of the last kMedianSamples rho       (one noisy sample cannot trip)
//   rise      = rho_med now - rho_med >= trend_span_m back  (travelled distance, odometry)
//   rho_ahead = rho_med + lookahead_m * max(0, rise / distance)
//
// rho_ahead at or above stop_coefficient is STOP evidence, at or above
// caution_coefficient CAUTION evidence; the state moves on the monitor's
// N-of-M window (section 4's trip_n of window_m; clear_n below caution), and
// STOP is latched until clear_stop(), like a wheel's. T_i and W_i are the
// wheels' directed torques and loads (reverse drive: the torque that drives
// the rover backwards, and the pulls' sign flipped).
//
// The history restarts whenever the rover stands (odometry below
// kTractionStandingSpeed): a trend across a halt would compare two drives,
// and the first trend_span_m of a drive (the start's acceleration) sets no
// baseline. Evidence needs a full median (kTractionMedianSamples samples).
//
// A cycle is unusable for this check (no evidence, never clear) when fewer
// than half the monitored wheels have a torque, when the pulls are assumed
// (DP_max at high slip: table numbers, and the wheel monitor's slip rule
// stops then), when the wheels do not all drive one way, or when the
// arithmetic overflows. Section 8 of the table holds the levels; a table
// without it leaves the check off (TractionState::off).
#ifndef SINKWATCH_FLIGHT_TRACTION_HPP
#define SINKWATCH_FLIGHT_TRACTION_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

/// Samples of the running median (odd).
constexpr std::uint8_t kTractionMedianSamples = 5U;
/// Distance marks of the trend's history; one every trend_span_m / 8, so
/// the history reaches back two spans.
constexpr std::uint8_t kTractionTrendMarks = 16U;

/// Below this ground speed the rover stands (Yutu drives at 0.055 m/s).
constexpr SpeedMps kTractionStandingSpeed{fx::constant<SpeedQ>(0.005)};

/// 1/r of the table's wheel radius, the thrust per unit of drive torque, in
/// Q7.24 (1/m): round(2^24 / r), prepared once per parameter load
/// (PreparedParameters::traction_inverse_radius()) so that the check
/// multiplies the torque sum instead of dividing it every cycle. Zero for a
/// radius outside [kMinRadiusM, kMaxRadiusM] (then every sample is overflow).
struct InverseRadius {
  std::uint32_t per_m_q24{0U};
};

/// The table's 1/r for the check (the radius must lie in [kMinRadiusM,
/// kMaxRadiusM], which validate() enforces; else zero).
[[nodiscard]] InverseRadius inverse_radius(LengthM wheel_radius_m) noexcept;

/// rho_ahead = rho_med + lookahead * max(0, (rho_med - rho_back) / distance),
/// the trend carried ahead (docs/traction.md): `distance_m_q24` is the
/// travelled distance in raw LengthM units (a sum of Q7.24 gaps, 2^-24 m),
/// positive. One rounding (the carried term, half away from zero, 2^-25);
/// false when the distance is not positive or rho_ahead leaves Q7.24.
[[nodiscard]] bool carried_ahead(Ratio rho_med, Ratio rho_back, std::int64_t distance_m_q24, LengthM lookahead_m,
                                 Ratio& ahead) noexcept;

namespace detail {

/// n / d rounded half up, exactly (d > 0): the quotient rho = resistance /
/// sum W before its sign, from the library's fx::wide::divmod (without a
/// divide instruction a one-word divisor, every load sum below 65,536 N,
/// takes its normalising 64 / 32-bit long division, not __aeabi_uldivmod)
/// rounded on the exact remainder (test_traction.cpp compares it with the
/// plain form).
[[nodiscard]] std::uint64_t rounded_quotient(std::uint64_t n, std::uint64_t d) noexcept;

/// 2^32: one word.
constexpr std::uint64_t kTwoTo32 = std::uint64_t{1U} << 32U;

/// A divisor of one word (every load sum below 65,536 N) and a quotient
/// below 2^32 (n / 2^32 < d: every rho in Q7.24, and more).
[[nodiscard]] constexpr bool one_word_quotient(std::uint64_t n, std::uint64_t d) noexcept {
  return (d < kTwoTo32) && ((n / kTwoTo32) < d);
}

/// rounded_quotient(n, d) for one_word_quotient(n, d), forced inline into
/// the check (a header function, so that the library holds no second copy
/// and the tests reach it): the divisor and the dividend shifted left by the
/// same s until the divisor's top bit is set, then the library's two
/// base-2^16 digits (fx::wide::detail::quotient_digits; on the Cortex-M4
/// two UDIVs, no __aeabi_uldivmod call). (n 2^s) / (d 2^s) has n / d's
/// quotient and 2^s times its remainder, and the rounding compares the
/// remainder with the divisor less it, both scaled alike: the same verdict.
/// The check takes it where the core divides words
/// (fx::wide::kDivideInstruction); elsewhere each 32-bit `/` would be a
/// library call.
[[nodiscard]] SW_FX_INLINE std::uint64_t rounded_quotient_one_word(std::uint64_t n, std::uint64_t d) noexcept {
  const auto den = static_cast<std::uint32_t>(d);
  const std::uint32_t s = 32U - fx::wide::bit_length32(den);  // 0..31: d > n / 2^32 >= 0
  const std::uint32_t v = den << s;
  const auto n_high = static_cast<std::uint32_t>(n / kTwoTo32);
  const auto n_low = static_cast<std::uint32_t>(n);
  // n 2^s < v 2^32 <= 2^64: its high word from both of n's words.
  const std::uint32_t u_high = (s == 0U) ? n_high : ((n_high << s) | (n_low >> (32U - s)));
  const std::uint32_t u_low = n_low << s;
  const fx::wide::detail::QuotientDigits q =
      fx::wide::detail::quotient_digits((std::uint64_t{u_high} * kTwoTo32) | u_low, v);
  const std::uint32_t remainder = ((q.partial * fx::wide::detail::kDigitBase) + (u_low & 0xFFFFU)) - (q.low * v);
  const std::uint32_t round_up = (remainder >= (v - remainder)) ? 1U : 0U;
  return static_cast<std::uint64_t>((q.high * fx::wide::detail::kDigitBase) + q.low) + round_up;
}

/// |v| dt / 1000 rounded half up, in raw LengthM units (2^-24 m), for a
/// speed magnitude `speed_q24` (raw 2^-24 m/s, at most 2^31) and dt_ms <=
/// 2000: the distance of one cycle, exactly, with no 64-bit division (the
/// speed split at 1000, each part's thousandths by a multiplication).
[[nodiscard]] std::uint64_t travelled_q24(std::uint32_t speed_q24, std::uint32_t dt_ms) noexcept;

}  // namespace detail

enum class TractionState : std::uint8_t { off = 0U, nominal = 1U, caution = 2U, stop = 3U };

/// What became of this cycle's sample.
enum class TractionSample : std::uint8_t {
  ok = 0U,
  check_off = 1U,        ///< the table has no section 8
  too_few_wheels = 2U,   ///< fewer than half the monitored wheels have a torque
  pull_assumed = 3U,     ///< the pulls are DP_max at high slip, not a force balance
  mixed_direction = 4U,  ///< the wheels do not all drive the same way
  overflow = 5U,         ///< an intermediate overflowed: no number
  no_loads = 6U,         ///< the cycle has no loads or pulls (the step's status was not ok)
  standing = 7U,         ///< the rover stands: the history restarts
  filling = 8U,          ///< fewer than kTractionMedianSamples samples since the restart
};

/// One cycle's input, from the rover step's stages.
struct TractionInput {
  TimeMs time;
  bool loads_valid{false};           ///< load_n and drawbar_pull_n hold this cycle's numbers
  bool pull_assumed{false};          ///< drawbar pulls are DP_max at high slip
  WheelLoadN load_n[kWheelCount];
  DrawbarPullN drawbar_pull_n[kWheelCount];
  bool torque_valid[kWheelCount]{};  ///< the wheel monitor's estimate_valid
  TorqueNm torque_nm[kWheelCount];   ///< directed (motor.hpp)
  DriveDirection direction[kWheelCount]{};
  bool speed_valid{false};           ///< speed_mps is a measurement (odometry / VO)
  SpeedMps speed_mps;                ///< signed; the distance travelled is |v| dt
};

/// The directed sums of the wheels with a torque: T, DP and W, as raw
/// Q15.16 integers (2^-16 N m, 2^-16 N): at most six values below 2^31 in
/// magnitude, so every sum is exact in 64 bits. The pulls are summed as read
/// and turned once (resistance_of): a sum that is used has every wheel
/// driving one way, so its directed sum is the sum, negated in reverse. The
/// wheels drive one way when every bit of their directions is the same in
/// all of them: their OR equals their AND.
struct TractionSums {
  /// One wheel in wheels_and_any: the count lies above the directions' byte.
  static constexpr std::uint32_t kOneWheel = 0x100U;

  std::int64_t torque_q16{0};
  std::int64_t pull_q16{0};  ///< as read: not yet along the drive direction
  std::int64_t load_q16{0};
  /// The wheels summed times kOneWheel plus the OR of their directions
  /// (uint8, so below kOneWheel): one register for both in the loop.
  std::uint32_t wheels_and_any{0U};
  std::uint32_t all_bits{0xFFU};  ///< the AND of the directions

  /// One wheel with a torque, in wheel order (forced inline: the rover step
  /// sums its own arrays with it, so that no input record is copied).
  SW_FX_INLINE void add(TorqueNm torque_nm, DrawbarPullN pull_n, WheelLoadN load_n, DriveDirection d) noexcept {
    const auto direction = static_cast<std::uint32_t>(d);
    wheels_and_any = (wheels_and_any | direction) + kOneWheel;
    all_bits &= direction;
    pull_q16 += pull_n.raw();
    torque_q16 += torque_nm.raw();
    load_q16 += load_n.raw();
  }
  [[nodiscard]] std::uint32_t wheels() const noexcept { return wheels_and_any / kOneWheel; }
  [[nodiscard]] std::uint32_t any_bits() const noexcept { return wheels_and_any % kOneWheel; }
};

/// One cycle's input as the check reads it: TractionInput with its wheels
/// summed. The rover step builds it from its own arrays (RoverStep::
/// traction_stage), not from a copy of them.
struct TractionCycle {
  TimeMs time;
  bool loads_valid{false};   ///< `sums` hold this cycle's wheels (else unread)
  bool pull_assumed{false};  ///< drawbar pulls are DP_max at high slip
  TractionSums sums;         ///< the monitored wheels (the first wheel_count) whose torque_valid
  bool speed_valid{false};
  SpeedMps speed_mps;
};

struct TractionOutput {
  TractionState state{TractionState::off};
  TractionSample sample{TractionSample::check_off};
  bool stop_tripped{false};    ///< entered STOP in this cycle
  bool rho_valid{false};       ///< resistance and resistance_median hold this cycle's numbers
  Ratio resistance;            ///< rho of this cycle
  Ratio resistance_median;     ///< rho_med
  bool trend_known{false};     ///< the history reaches trend_span_m back
  Ratio resistance_ahead;      ///< rho_ahead (rho_med without a known trend)
};

class TractionMonitor {
 public:
  TractionMonitor() noexcept;

  /// One cycle into `out`, every field written (the record may be the
  /// previous cycle's: the rover step keeps it in its output, so no output
  /// is built and copied); `params` is the table's section 8 and `monitor`
  /// its section 4 (the N-of-M window). `per_radius` is the table's 1/r
  /// (inverse_radius()).
  /// Inline (below): the rover step does not call it (it sums its own
  /// arrays into a TractionCycle), so the flight library carries no copy.
  inline void step(const TractionInput& input, const TractionParams& params, const MonitorParams& monitor,
                   InverseRadius per_radius, TractionOutput& out) noexcept;
  /// The same with the wheels already summed (TractionCycle).
  void step(const TractionCycle& input, const TractionParams& params, const MonitorParams& monitor,
            InverseRadius per_radius, TractionOutput& out) noexcept;

  /// Back to NOMINAL with empty histories (the ground's re-plan).
  void clear_stop() noexcept;

  [[nodiscard]] TractionState state() const noexcept { return state_; }

 private:
  /// rho of this cycle into `rho`; the sample's verdict.
  [[nodiscard]] static inline TractionSample resistance_of(const TractionCycle& in, std::uint8_t wheels,
                                                           InverseRadius per_radius, Ratio& rho) noexcept;
  // resistance_of, push_median, evaluate, advance, ahead_of, push_history
  // and transition are step()'s stages, inline (defined and used only in traction.cpp,
  // forced inline there): a call each per cycle less.
  /// rho_med after pushing `rho`.
  [[nodiscard]] inline Ratio push_median(Ratio rho) noexcept;
  /// A sample with a resistance: the restart when standing, else the
  /// median, the distance and rho_ahead into `out`; the sample's verdict.
  inline TractionSample evaluate(const TractionCycle& input, const TractionParams& params, Ratio rho,
                                 TractionOutput& out) noexcept;
  /// Empties the median and the trend's history (the rover stands).
  void restart() noexcept;
  /// Adds |v| dt to the distance and, every trend_span_m / 8 after the
  /// first trend_span_m, a mark.
  inline void advance(const TractionCycle& in, Ratio rho_med, const TractionParams& params) noexcept;
  /// rho_ahead from the marks; false when the history is shorter than the span.
  inline bool ahead_of(Ratio rho_med, const TractionParams& params, Ratio& ahead, bool& overflow) const noexcept;
  inline void push_history(bool caution, bool stop, bool clear) noexcept;
  inline void transition(const MonitorParams& monitor, TractionOutput& out) noexcept;

  TractionState state_{TractionState::nominal};
  Ratio recent_[kTractionMedianSamples];  ///< the last rho, oldest overwritten
  /// The first recent_count_ of them, ascending: kept sorted as each sample
  /// replaces the oldest, so that the median is read, not sorted for.
  Ratio sorted_[kTractionMedianSamples];
  std::uint8_t recent_count_{0U};
  std::uint8_t recent_next_{0U};
  /// The trend's history: rho_med at each mark and the distance from the
  /// previous mark to it (relative, so that no odometer can overflow).
  Ratio mark_rho_[kTractionTrendMarks];
  LengthM mark_gap_m_[kTractionTrendMarks];
  std::uint8_t mark_count_{0U};
  std::uint8_t mark_newest_{0U};
  LengthM since_mark_m_;        ///< travelled since the newest mark (since the restart, until settled)
  bool settled_{false};         ///< the first trend_span_m since the restart is behind
  bool have_time_{false};
  TimeMs last_time_{0U};
  std::uint16_t caution_history_{0U};  ///< bit 0 is the newest sample
  std::uint16_t stop_history_{0U};
  std::uint16_t clear_history_{0U};
};

/// The first `wheels` (at most six) wheels' sums over those with a torque
/// (every wheel asked, so that the loop's bound is a constant: with the
/// bound min(wheels, 6) cppcheck, reading the header alone, took it for 0).
[[nodiscard]] inline TractionSums traction_sums(const TractionInput& in, std::uint8_t wheels) noexcept {
  TractionSums sums{};
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if ((i < wheels) && in.torque_valid[i]) {
      sums.add(in.torque_nm[i], in.drawbar_pull_n[i], in.load_n[i], in.direction[i]);
    }
  }
  return sums;
}

inline void TractionMonitor::step(const TractionInput& input, const TractionParams& params,
                                  const MonitorParams& monitor, InverseRadius per_radius,
                                  TractionOutput& out) noexcept {
  const TractionCycle cycle{input.time,
                            input.loads_valid,
                            input.pull_assumed,
                            traction_sums(input, monitor.wheel_count),
                            input.speed_valid,
                            input.speed_mps};
  step(cycle, params, monitor, per_radius, out);
}

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_TRACTION_HPP
