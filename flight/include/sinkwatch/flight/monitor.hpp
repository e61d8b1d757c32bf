// monitor.hpp: the sinkage monitor of section 7: per wheel NOMINAL -> CAUTION
// -> STOP, and the rover's decision to continue or to stop and re-plan.
//
// Each cycle, for each wheel, from its motor current I, load W, drawbar pull
// DP and direction:
//   T     = torque_from_current(I)   given by the caller (motor.hpp; RoverStep
//                                    computes it once for the loads and here)
//   C(W)  = corrections_at(W)                            (Table 2)
//   z     = sinkage_from_pull(C, r, W, T, DP)            (Eq. 11)
//   I_max = current_limit(W) at z = allowed sinkage      (section 7)
// A sample is STOP evidence when d*I >= I_max or z >= stop level, CAUTION
// evidence when d*I >= f*I_max or z >= caution level, and "clear" when both
// are below the caution levels minus their hysteresis. States move only on
// N of the last M samples (the paper's "close to the maximum current" made
// robust to one noisy sample):
//   NOMINAL -> CAUTION  trip_n of the last window_m samples caution or worse
//   any     -> STOP     trip_n of the last window_m samples stop evidence,
//                       or invalid_to_stop unusable samples in a row
//   CAUTION -> NOMINAL  clear_n of the last window_m samples clear
//   STOP    latched until clear_stop() (the ground's re-plan acknowledges it)
// Unusable telemetry (flagged invalid, stale, repeated time stamp, current or
// load out of range, an estimate that overflows) is counted per reason, never
// turned into a sinkage number, counts as CAUTION evidence and never as clear:
// a blind wheel cannot return to NOMINAL.
//
// On entering STOP the wheel writes an EventRecord: the time, the reason, the
// peak current of the episode (since the wheel was last NOMINAL) and, as
// section 7 proposes for ground reproduction, the sinkage that Eq. 11 gives
// for that peak current with DP = DP_max.
#ifndef SINKWATCH_FLIGHT_MONITOR_HPP
#define SINKWATCH_FLIGHT_MONITOR_HPP

#include <cstdint>

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

enum class WheelState : std::uint8_t { nominal = 0U, caution = 1U, stop = 2U };

/// What became of this cycle's sample.
enum class SampleStatus : std::uint8_t {
  ok = 0U,
  flagged_invalid = 1U,       ///< the telemetry's own validity flag was false
  stale = 2U,                 ///< older than stale_timeout_ms, or from the future
  repeated_time = 3U,         ///< same time stamp as the previous sample: not refreshed
  current_out_of_range = 4U,  ///< |I| beyond the sensor range
  load_out_of_range = 5U,     ///< W outside [load_min, load_max]
  direction_invalid = 6U,     ///< direction is not forward/reverse
  estimate_failed = 7U,       ///< an intermediate overflowed: no number
  sensor_fault = 8U,          ///< the wheel's current sensor is faulty (sensor_health.hpp)
};
constexpr std::uint8_t kSampleStatusCount = 9U;

/// Why a wheel entered STOP. `slip`: its samples came at or above the rover's
/// high-slip level, where the drawbar pull is assumed (DP_max), not measured.
/// `traction`: never a wheel's; the rover's motion-resistance check
/// (traction.hpp) stopped it, reported by the ground beside the wheels'.
enum class StopReason : std::uint8_t { none = 0U, current = 1U, sinkage = 2U, telemetry = 3U, slip = 4U, traction = 5U };

/// One wheel's telemetry for one cycle.
struct WheelInput {
  TimeMs time;                  ///< when the sample was taken
  CurrentA current_a;           ///< signed; positive drives the rover forward
  WheelLoadN load_n;            ///< from the rover's statics (issue 4)
  DrawbarPullN drawbar_pull_n;  ///< from the rover's behaviour (issue 4)
  DriveDirection direction{DriveDirection::forward};  ///< commanded direction
  bool valid{false};            ///< the telemetry source's own validity flag
  /// drawbar_pull_n is DP_max assumed at or above the high-slip level
  /// (DrawbarStatus::saturated), not a measurement. With DP at its maximum,
  /// Eq. 11 gives the smallest sinkage the current allows, so the number
  /// cannot clear the wheel; and a wheel slipping that much makes no headway:
  /// the sample is STOP evidence (StopReason::slip), as a MER-style slip check
  /// would have it (docs/flight.md, docs/scenarios.md finding 3).
  bool drawbar_assumed{false};
  /// The sensor health monitor named this wheel's current channel faulty
  /// (missing, stuck, spiking, implausible): the sample is unusable. Under
  /// LossPolicy::continue_degraded such samples hold the wheel in CAUTION
  /// but do not count towards invalid_to_stop (the wheel is blind, not the
  /// rover); under LossPolicy::stop they count like any unusable sample.
  bool sensor_fault{false};
  /// corrections_at(table.correction, load_n) when the caller has already
  /// evaluated it (RoverStep does, for DP_max/W), else null: the monitor then
  /// reads it instead of evaluating the table again. Must be for this load_n
  /// and live for the duration of the step() call.
  const CorrectionResult* corrections{nullptr};
  /// The wheel's drive torque from this sample's current and direction,
  /// torque_from_current(table.motor, current_a, direction) (motor.hpp),
  /// computed once per cycle by the caller: RoverStep feeds the same torque
  /// to the wheel loads. The monitor does not compute it again. The default
  /// is "no torque" (invalid_current): a usable sample without one gives no
  /// estimate (SampleStatus::estimate_failed), never a sinkage from a zero.
  TorqueResult drive_torque{TorqueNm::zero(), EstimateStatus::invalid_current};
};

/// One cycle's samples of every wheel, read in place from the caller's
/// arrays (RoverStep's telemetry, output and per-wheel terms) instead of
/// six WheelInput records built and read again each cycle. Wheel i's sample
/// is the WheelInput {time, (*current_a)[i], (*load_n)[i],
/// (*drawbar_pull_n)[i], (*direction)[i], valid, drawbar_assumed,
/// sensor_fault = !(*current_usable)[i], corrections = &(*corrections)[i]
/// (null when `corrections` is null), drive_torque = (*drive_torque)[i]},
/// and the monitor's result is the one that WheelInput gives, bit for bit.
/// Every pointer is to the caller's array, which lives for the step() call.
struct WheelSamples {
  TimeMs time{0U};
  bool valid{false};
  bool drawbar_assumed{false};
  const CurrentA (*current_a)[kMaxWheels]{nullptr};
  const DriveDirection (*direction)[kMaxWheels]{nullptr};
  const WheelLoadN (*load_n)[kMaxWheels]{nullptr};
  const DrawbarPullN (*drawbar_pull_n)[kMaxWheels]{nullptr};
  const bool (*current_usable)[kMaxWheels]{nullptr};
  const CorrectionResult (*corrections)[kMaxWheels]{nullptr};  ///< null: the monitor evaluates C(W)
  const TorqueResult (*drive_torque)[kMaxWheels]{nullptr};
};

/// One wheel's result for one cycle.
struct WheelOutput {
  WheelState state{WheelState::nominal};
  SampleStatus sample_status{SampleStatus::ok};
  StopReason stop_reason{StopReason::none};  ///< why the wheel is in STOP (none otherwise)
  bool stop_tripped{false};    ///< entered STOP in this cycle; last_event() is new
  bool estimate_valid{false};  ///< torque_nm and sinkage_m hold this cycle's numbers
  TorqueNm torque_nm;
  SinkageM sinkage_m;
  bool limit_valid{false};     ///< current_limit_a holds this cycle's I_max
  CurrentA current_limit_a;
  LoadClamp clamp{LoadClamp::none};  ///< the load outside Table 2's range: corrections held
};

/// Written when a wheel enters STOP (section 7: for ground reproduction).
struct EventRecord {
  std::uint8_t wheel{0U};
  TimeMs time{0U};
  StopReason reason{StopReason::none};
  CurrentA peak_current_a;            ///< largest d*I of the episode
  WheelLoadN load_at_peak_n;          ///< the load at that sample
  bool peak_sinkage_valid{false};
  SinkageM peak_sinkage_m;            ///< Eq. 11 at the peak current with DP = DP_max
  bool max_estimate_valid{false};
  SinkageM max_estimated_sinkage_m;   ///< largest per-cycle estimate of the episode
};

/// Unusable samples per reason (saturating counters).
struct WheelCounters {
  std::uint32_t samples{0U};
  std::uint32_t by_status[kSampleStatusCount]{};  ///< index: SampleStatus; [0] counts good samples
};

class WheelMonitor {
 public:
  explicit WheelMonitor(std::uint8_t wheel_index = 0U) noexcept;

  /// One cycle. `now` is the monitor's clock, used for staleness. The
  /// parameters are prepared once per load (prepared_params.hpp): the
  /// corrections' and the motor model's divisions by table constants go
  /// through their prepared reciprocals. Parameters without a valid table
  /// make the sample unusable (fail-safe). The result is written whole into
  /// `out` (RoverMonitor passes its own record's entry: no copy per wheel).
  void step(const WheelInput& input, TimeMs now, const PreparedParameters& prepared, WheelOutput& out) noexcept;

  /// Back to NOMINAL with empty histories and peaks (counters are kept).
  void clear_stop() noexcept;

  /// NOMINAL -> CAUTION without evidence of its own: the rover monitor's
  /// rule for a wheel without usable evidence while another wheel points to
  /// embedding. No effect in CAUTION or STOP.
  void hold_in_caution() noexcept;

  [[nodiscard]] WheelState state() const noexcept { return state_; }
  [[nodiscard]] bool has_event() const noexcept { return has_event_; }
  [[nodiscard]] const EventRecord& last_event() const& noexcept { return event_; }
  const EventRecord& last_event() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  [[nodiscard]] const WheelCounters& counters() const& noexcept { return counters_; }
  const WheelCounters& counters() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary

 private:
  // track_episode and transition are step()'s stages, inline (defined and
  // used only in monitor.cpp, forced inline there): a call each per wheel
  // and cycle less (round 13: M0 -141, M4 -109 instructions per step).
  /// The episode's peak current (and its load) and largest estimate.
  inline void track_episode(CurrentA directed, WheelLoadN load_n, SinkageM sinkage_m) noexcept;
  /// This cycle's N-of-M histories as words: the members before their cut
  /// to 16 bits (n_of_m::shifted_in in monitor.cpp; the windows count the same).
  struct Histories {
    std::uint32_t caution;
    std::uint32_t stop;
    std::uint32_t clear;
  };
  /// Stage 4: NOMINAL -> CAUTION -> STOP and back (STOP latched), on the
  /// cycle's histories `h`.
  /// `current_stop`, `slip_stop`: what the last usable sample was stop
  /// evidence of (current, slip, else sinkage); it names a STOP the window
  /// trips. `kValidTable`: the parameters passed validate() (monitor.cpp).
  template <bool kValidTable>
  inline void transition(bool current_stop, bool slip_stop, const Histories& h, TimeMs now,
                         const PreparedParameters& prepared, WheelOutput& out) noexcept;
  // RoverMonitor steps its wheels on their samples of a WheelSamples in
  // place (step_body), which no WheelMonitor outside it can index.
  friend class RoverMonitor;

  /// One cycle on a sample read through `Sample`'s accessors (monitor.cpp:
  /// a WheelInput, or one wheel of a WheelSamples whose cycle's flag and
  /// age RoverMonitor found ok, asked once per cycle): the one body of
  /// step() and of RoverMonitor's step on WheelSamples. Forced inline
  /// (monitor.cpp): RoverMonitor's loop over a WheelSamples' wheels, its
  /// only caller on that sample, takes it in place (round 16: no call, no
  /// argument records and no reload of the wheel's state per wheel; M4
  /// -54, M0 -69 instructions per step); the WheelInput paths call it
  /// through step_sample, out of line, one copy for their three callers.
  /// `blind_wheels`: RoverMonitor's count of blind wheels, one more on a
  /// sensor fault's sample.
  template <typename Sample>
  inline void step_body(Sample input, TimeMs now, const PreparedParameters& prepared, WheelOutput& out,
                        std::uint8_t& blind_wheels) noexcept;
  /// step_body out of line (monitor.cpp).
  template <typename Sample>
  void step_sample(Sample input, TimeMs now, const PreparedParameters& prepared, WheelOutput& out,
                   std::uint8_t& blind_wheels) noexcept;
  /// The record written on entering STOP (out of line: its records are not
  /// in step()'s frame on the cycles without a STOP).
  [[nodiscard]] EventRecord stop_event(TimeMs now, StopReason reason,
                                       const PreparedParameters& prepared) const noexcept;

  std::uint8_t wheel_{0U};
  WheelState state_{WheelState::nominal};
  StopReason stop_reason_{StopReason::none};
  std::uint16_t caution_history_{0U};  ///< bit 0 is the newest sample
  std::uint16_t stop_history_{0U};
  std::uint16_t clear_history_{0U};
  std::uint8_t consecutive_unusable_{0U};
  bool have_last_time_{false};
  TimeMs last_time_{0U};
  /// The episode has had a usable sample: peak_current_a_, load_at_peak_n_
  /// and max_estimate_m_ hold its numbers (they start and end together).
  bool have_peak_{false};
  CurrentA peak_current_a_{};
  WheelLoadN load_at_peak_n_{};
  SinkageM max_estimate_m_{};
  bool has_event_{false};
  EventRecord event_{};
  WheelCounters counters_{};
};

enum class RoverDecision : std::uint8_t { continue_drive = 0U, stop_and_replan = 1U };

struct RoverOutput {
  RoverDecision decision{RoverDecision::continue_drive};
  std::uint8_t wheels_in_stop{0U};
  std::uint8_t wheels_in_caution{0U};
  std::uint8_t wheels_blind{0U};  ///< wheels whose sample was a sensor fault this cycle
  /// Driving on with blind wheels (LossPolicy::continue_degraded, at most
  /// max_blind_wheels of them): the decision rests on the other wheels.
  bool degraded{false};
  WheelOutput wheels[kMaxWheels];  ///< the first monitor.wheel_count are meaningful
};

class RoverMonitor {
 public:
  RoverMonitor() noexcept;

  /// One cycle for every wheel; inputs beyond monitor.wheel_count are ignored.
  /// The decision is stop_and_replan when at least rover_stop_k wheels are in
  /// STOP, or (LossPolicy::continue_degraded) more than max_blind_wheels are
  /// blind. A wheel without usable evidence is held in CAUTION while any
  /// other wheel is in CAUTION or STOP: never NOMINAL beside embedding.
  /// Without a valid table the decision is stop_and_replan and no wheel is
  /// stepped. The result is written into `out` (every field: wheels beyond
  /// monitor.wheel_count get a default WheelOutput), so that a caller that
  /// keeps it in a larger record (RoverStepOutput) needs no copy of the six
  /// wheels' outputs.
  void step(const WheelInput (&inputs)[kMaxWheels], TimeMs now, const PreparedParameters& prepared,
            RoverOutput& out) noexcept;
  /// The same cycle on the samples of `samples` (WheelSamples), read in
  /// place: the result of the WheelInput records they stand for.
  void step(const WheelSamples& samples, TimeMs now, const PreparedParameters& prepared, RoverOutput& out) noexcept;

  /// The ground's acknowledgement after a re-plan: every wheel back to NOMINAL.
  void clear_stop() noexcept;

  [[nodiscard]] const WheelMonitor& wheel(std::uint8_t index) const& noexcept;
  const WheelMonitor& wheel(std::uint8_t index) const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary

 private:
  /// The unusable-evidence rule and the decision after every wheel's step
  /// (the first `count` wheels monitored; `out`'s tallies of them made).
  void rover_rules(const ParameterTable& table, std::uint8_t count, RoverOutput& out) noexcept;
  /// Every monitored wheel on parameters whose table is valid, into `out`;
  /// `Wheels` steps wheel i (monitor.cpp: from a WheelInput or a WheelSamples).
  template <typename Wheels>
  void step_all(const Wheels& wheels, TimeMs now, const PreparedParameters& prepared, RoverOutput& out) noexcept;
  /// step_all on a WheelSamples cycle whose flag or age is not ok (out of
  /// line: the rare cycle's records stay out of the usual cycle's frame).
  void step_unfresh(const WheelSamples& samples, TimeMs now, const PreparedParameters& prepared,
                    RoverOutput& out) noexcept;

  WheelMonitor wheels_[kMaxWheels];
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_MONITOR_HPP
