// sensor_health.hpp: the health of each telemetry channel over time, so that
// a faulty sensor is named as such and its numbers never become evidence
// (docs/fault-tolerance.md; not in the paper, whose soil bin had no faults).
//
// Channels: the six motor currents, the IMU attitude, the suspension joint
// angles and the time stamp. Each fresh sample moves every channel through:
//
//   missing      the source marks the value absent (a dropout)
//   stuck        the raw value identical for stuck_cycles samples while the
//                rover drives (a live sensor's noise moves its last bit);
//                the clock: stuck_cycles repeated time stamps
//   spike        a jump beyond the channel's step limit from the previous raw
//                value: this sample is not used. A lasting level change of a
//                current or a joint is one spike, then the new level
//   noisy        spikes in two or more samples in a row (a noise burst)
//   implausible  a driven wheel's current below the motor's no-load current
//                while the other wheels draw more than twice it (a free-
//                wheeling motor or a broken gear: no torque reaches the soil);
//                a current at the sensor's range (a stalled motor); an
//                attitude that stays a step limit away from the last good one
//                after one clean jump (an IMU bias step), until it returns or
//                the ground's clear_stop() accepts it (after a noise burst
//                two calm samples make the new reference instead)
//   recovering   good again, for fewer than recover_cycles samples
//   ok
//
// A current channel that is not ok or recovering makes its wheel's sample
// unusable (SampleStatus::sensor_fault); an IMU or joint channel that is not
// usable is bridged with its last good value for up to bridge_ms (reported),
// after which no wheel has loads. What a lasting loss leads to is the table's
// LossPolicy (param_table.hpp, section 7): stop, or continue on the wheels
// that still have evidence while at most max_blind_wheels are blind.
//
// Bounded per call: one loop over the six wheels' steady samples and one
// over those that are not (and, for a wheel below the no-load current while
// driving, one over the other five), two over the two sides' joints; no
// allocation, no division.
#ifndef SINKWATCH_FLIGHT_SENSOR_HEALTH_HPP
#define SINKWATCH_FLIGHT_SENSOR_HEALTH_HPP

#include <cstdint>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace flight {

/// Telemetry channels, in this order in SensorHealthReport::channel.
enum class SensorChannel : std::uint8_t {
  current_lf = 0U,
  current_lm = 1U,
  current_lr = 2U,
  current_rf = 3U,
  current_rm = 4U,
  current_rr = 5U,
  imu = 6U,
  joints = 7U,
  clock = 8U,
};
constexpr std::uint8_t kSensorChannelCount = 9U;

enum class SensorHealth : std::uint8_t {
  ok = 0U,
  missing = 1U,
  stuck = 2U,
  spike = 3U,
  noisy = 4U,
  implausible = 5U,
  recovering = 6U,
};
constexpr std::uint8_t kSensorHealthCount = 7U;

/// The telemetry's per-sensor absence flags (RoverTelemetry): false is present.
struct SensorPresence {
  bool current_missing[kWheelCount]{};
  bool attitude_missing{false};
  bool joints_missing{false};
};

/// Saturating count of samples per channel and health.
struct SensorHealthCounters {
  std::uint32_t by_health[kSensorChannelCount][kSensorHealthCount]{};
};

/// This cycle's health of every channel, and what the step may use.
struct SensorHealthReport {
  /// Before the first fresh sample nothing has been measured: missing.
  SensorHealth channel[kSensorChannelCount]{SensorHealth::missing, SensorHealth::missing, SensorHealth::missing,
                                            SensorHealth::missing, SensorHealth::missing, SensorHealth::missing,
                                            SensorHealth::missing, SensorHealth::missing, SensorHealth::missing};
  bool current_usable[kWheelCount]{};  ///< the wheel's current is evidence this cycle
  bool attitude_usable{false};         ///< `attitude` holds a measured or bridged value
  bool attitude_bridged{false};        ///< ... the last good one, not this sample's
  RoverAttitude attitude{};
  bool joints_usable{false};
  bool joints_bridged{false};
  JointAnglesRad joints{};
};

/// One fresh sample's inputs to the health checks: a view of the telemetry
/// (references, so that the step does not copy the currents, directions,
/// attitude and joints into a record every cycle).
struct HealthSample {
  TimeMs time;
  const CurrentA (&current_a)[kWheelCount];
  const DriveDirection (&direction)[kWheelCount];
  const RoverAttitude& attitude;
  const JointAnglesRad& joints;
  const SensorPresence& presence;
  bool driving{false};     ///< the rim speed is known and at least kMinRimSpeedForSlip
  bool clock_jump{false};  ///< more than the stale timeout since the last fresh sample, or backwards
};

namespace detail {

/// One channel's runs (sensor_health.cpp keeps one per channel).
struct HealthTrack {
  SensorHealth health{SensorHealth::ok};
  bool have_last{false};
  std::uint8_t same_run{0U};   ///< samples identical to the previous raw value
  std::uint8_t spike_run{0U};  ///< consecutive spikes
  std::uint8_t bad_run{0U};    ///< consecutive implausible samples
  std::uint8_t good_run{0U};   ///< good samples since the last fault
  bool faulted{false};         ///< a fault since the channel was last ok
};

/// A motor current's previous samples: the raw register values, signed,
/// and whether each was read driving in reverse (the value along the
/// direction is then its negation).
struct CurrentHistory {
  std::int32_t last_reading{0};  ///< the previous sample
  std::int32_t good_reading{0};  ///< the last one not a spike
  bool last_reverse{false};
  bool good_reverse{false};
};

}  // namespace detail

class SensorHealthMonitor {
 public:
  SensorHealthMonitor() noexcept = default;

  /// One fresh sample (admitted by the step's clock checks) into `report`,
  /// every field written. `no_load_a` and `current_range_a` are the motor's
  /// (MotorParams).
  void update(const HealthSample& s, const HealthParams& p, CurrentA no_load_a, CurrentA current_range_a,
              SensorHealthReport& report) noexcept;

  /// The ground's acknowledgement (RoverStep::clear_stop): every channel's
  /// next sample is taken as its new reference, so an IMU bias the ground
  /// has accepted is no longer implausible. Health histories are kept.
  void accept_levels() noexcept;

  /// A sample the step refused on its time stamp: `repeated` counts towards
  /// the clock being stuck; otherwise a jump or stale stamp is a clock spike.
  SensorHealth clock_refused(bool repeated, const HealthParams& p) noexcept;

  [[nodiscard]] const SensorHealthCounters& counters() const& noexcept { return counters_; }
  const SensorHealthCounters& counters() const&& = delete;  // MISRA C++:2023 6.8.4

 private:
  void count(SensorChannel c, SensorHealth h) noexcept;
  void currents(const HealthSample& s, const HealthParams& p, CurrentA no_load_a, CurrentA current_range_a,
                SensorHealthReport& r) noexcept;
  /// One wheel's current by the general checks into `r` and the counters;
  /// whether the channel is then quiet.
  [[gnu::noinline]] bool current_sample(const HealthSample& s, const HealthParams& p, CurrentA no_load_a,
                                        CurrentA current_range_a, std::uint32_t wheel,
                                        SensorHealthReport& r) noexcept;
  // imu_channel, joints_channel and bridge are update()'s stages, inline
  // (defined and used only in sensor_health.cpp, forced inline there).
  inline SensorHealth imu_channel(const HealthSample& s, const HealthParams& p) noexcept;
  inline SensorHealth joints_channel(const HealthSample& s, const HealthParams& p) noexcept;
  inline void bridge(const HealthSample& s, const HealthParams& p, SensorHealth imu, SensorHealth joints,
                     SensorHealthReport& r) noexcept;
  /// The IMU's and the joints' health this sample: a quiet channel's steady
  /// sample without the general checks, else imu_channel() or
  /// joints_channel() settled (inline into update() too).
  inline SensorHealth imu_health(const HealthSample& s, const HealthParams& p) noexcept;
  inline SensorHealth joints_health(const HealthSample& s, const HealthParams& p) noexcept;

  detail::HealthTrack track_[kSensorChannelCount]{};
  detail::CurrentHistory current_history_[kWheelCount]{};
  /// Bit i: current channel i is quiet (sensor_health.cpp, quiet_after()):
  /// its next steady forward sample only replaces its last value.
  std::uint8_t quiet_currents_{0U};
  /// The IMU and the joints are quiet (sensor_health.cpp, imu_health() and
  /// joints_health()): ok with no repeat run, so that a steady sample only
  /// replaces their last values.
  bool quiet_imu_{false};
  bool quiet_joints_{false};
  RoverAttitude last_attitude_{};
  RoverAttitude step_attitude_{};  ///< the last good attitude: the bias check's reference
  bool imu_after_noise_{false};     ///< a noise burst since: the reference is old
  JointAnglesRad last_joints_{};
  JointAnglesRad step_joints_{};
  /// A channel's last usable value and when it was read: what bridges a
  /// fault of the IMU or the joints.
  template <typename Value>
  struct LastGood {
    bool have{false};
    TimeMs time{0U};
    Value value{};

    /// Keeps `sample` when it is usable; otherwise the last good value may
    /// stand in while at most `bridge_ms` old (`bridged` is then set; it is
    /// cleared otherwise). `out` gets `value` (the sample read once for
    /// both stores). Returns whether `value` may be used now.
    bool take(bool usable_now, const Value& sample, TimeMs now, std::uint32_t bridge_ms, bool& bridged,
              Value& out) noexcept {
      if (usable_now) {
        const Value kept = sample;
        have = true;
        time = now;
        value = kept;
        out = kept;
        bridged = false;
        return true;
      }
      out = value;
      bridged = have && (elapsed_ms(time, now) <= bridge_ms);
      return bridged;
    }
  };

  LastGood<RoverAttitude> good_attitude_{};
  LastGood<JointAnglesRad> good_joints_{};
  std::uint8_t repeated_run_{0U};
  SensorHealthCounters counters_{};
};

/// Whether a channel's sample counts: ok or recovering.
[[nodiscard]] constexpr bool usable(SensorHealth h) noexcept {
  return (h == SensorHealth::ok) || (h == SensorHealth::recovering);
}

/// The channel's and the health's names for reports ("LM_current", "stuck").
[[nodiscard]] const char* channel_name(SensorChannel c) noexcept;
[[nodiscard]] const char* health_name(SensorHealth h) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_SENSOR_HEALTH_HPP
