// The health of each telemetry channel over time (sensor_health.hpp,
// docs/fault-tolerance.md).
#include "sinkwatch/flight/sensor_health.hpp"

namespace sinkwatch {
namespace flight {
namespace {

constexpr std::uint8_t kRunMax = 0xFFU;

std::uint8_t bump(std::uint8_t run) noexcept { return (run < kRunMax) ? static_cast<std::uint8_t>(run + 1U) : run; }

/// Samples identical to the previous one while driving. A change ends the
/// run; a parked rover's samples neither lengthen nor end it (a live sensor
/// on a parked rover may repeat itself, a stuck one stays stuck).
std::uint8_t repeat_run(std::uint8_t run, bool same, bool driving) noexcept {
  if (!same) {
    return 0U;
  }
  return driving ? bump(run) : run;
}

/// |a - b| > limit, in 64 bits so that no difference of two raw values
/// overflows. A zero limit switches the check off.
bool beyond(std::int64_t a, std::int64_t b, std::int32_t limit) noexcept {
  if (limit <= 0) {
    return false;
  }
  // Both operands are raw 32-bit values or their negations: |a - b| < 2^33.
  const std::int64_t d = a - b;
  const std::int64_t magnitude = (d < 0) ? -d : d;
  return magnitude > static_cast<std::int64_t>(limit);
}

/// A jump from the previous raw value that is also a jump from the last
/// value that was not a spike: one wild sample, or the first of a burst. A
/// sample back near the last good value (the spike has passed) or near the
/// previous one (a level change, e.g. a bias step) is not a spike.
bool is_spike(std::int64_t value, std::int64_t previous, std::int64_t last_good, std::int32_t limit) noexcept {
  return beyond(value, previous, limit) && beyond(value, last_good, limit);
}

bool attitude_equal(const RoverAttitude& a, const RoverAttitude& b) noexcept {
  return (a.pitch_rad == b.pitch_rad) && (a.roll_rad == b.roll_rad);
}

/// Pitch or roll more than `limit` from `reference`.
bool attitude_beyond(const RoverAttitude& a, const RoverAttitude& reference, AngleRad limit) noexcept {
  return beyond(a.pitch_rad.raw(), reference.pitch_rad.raw(), limit.raw()) ||
         beyond(a.roll_rad.raw(), reference.roll_rad.raw(), limit.raw());
}

bool attitude_spike(const RoverAttitude& a, const RoverAttitude& previous, const RoverAttitude& good,
                    AngleRad limit) noexcept {
  return is_spike(a.pitch_rad.raw(), previous.pitch_rad.raw(), good.pitch_rad.raw(), limit.raw()) ||
         is_spike(a.roll_rad.raw(), previous.roll_rad.raw(), good.roll_rad.raw(), limit.raw());
}

/// Any one joint identical to its previous sample (a frozen encoder).
bool any_joint_equal(const JointAnglesRad& a, const JointAnglesRad& b) noexcept {
  bool equal = false;
  for (std::uint32_t side = 0U; side < kSideCount; ++side) {
    equal = equal || (a.rocker_rad[side] == b.rocker_rad[side]) || (a.bogie_rad[side] == b.bogie_rad[side]);
  }
  return equal;
}

bool joints_spike(const JointAnglesRad& a, const JointAnglesRad& previous, const JointAnglesRad& good,
                  AngleRad limit) noexcept {
  bool spike = false;
  for (std::uint32_t side = 0U; side < kSideCount; ++side) {
    spike = spike ||
            is_spike(a.rocker_rad[side].raw(), previous.rocker_rad[side].raw(), good.rocker_rad[side].raw(),
                     limit.raw()) ||
            is_spike(a.bogie_rad[side].raw(), previous.bogie_rad[side].raw(), good.bogie_rad[side].raw(),
                     limit.raw());
  }
  return spike;
}

/// The current along the commanded direction, in raw Q11.20 widened to 64
/// bits (the negation of INT32_MIN stays exact).
std::int64_t directed_raw(CurrentA current_a, DriveDirection direction) noexcept {
  const std::int64_t raw = static_cast<std::int64_t>(current_a.raw());
  return (direction == DriveDirection::reverse) ? -raw : raw;
}

/// A spike, and spikes in a row a noise burst.
SensorHealth spike_verdict(std::uint8_t spike_run) noexcept {
  return (spike_run >= 2U) ? SensorHealth::noisy : SensorHealth::spike;
}

/// The wheels that draw more than twice the no-load current (bit i: wheel
/// i), counted once per sample for all six wheels' "others pulling" test.
std::uint32_t drawing_mask(const HealthSample& s, CurrentA no_load_a) noexcept {
  const std::int64_t twice = 2 * static_cast<std::int64_t>(no_load_a.raw());
  std::uint32_t mask = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if (!s.presence.current_missing[i] && (directed_raw(s.current_a[i], s.direction[i]) > twice)) {
      mask |= (1U << i);
    }
  }
  return mask;
}

/// At least three of the other five wheels draw more than twice the
/// no-load current (`drawing`: drawing_mask(), `drawing_count` its bits):
/// the rover is pulling, so a wheel that draws less than the no-load
/// current transmits no torque.
bool others_draw(std::uint32_t drawing, std::uint32_t drawing_count, std::uint32_t wheel) noexcept {
  const std::uint32_t self = (drawing >> wheel) & 1U;
  return (drawing_count - self) >= 3U;
}

/// The number of set bits of a wheel mask.
std::uint32_t wheel_count_of(std::uint32_t mask) noexcept {
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    n += (mask >> i) & 1U;
  }
  return n;
}

}  // namespace

void SensorHealthMonitor::count(SensorChannel c, SensorHealth h) noexcept {
  std::uint32_t& n = counters_.by_health[static_cast<std::uint8_t>(c)][static_cast<std::uint8_t>(h)];
  if (n < 0xFFFFFFFFU) {
    ++n;
  }
}

SensorHealth SensorHealthMonitor::settle(Track& t, SensorHealth raw_verdict, const HealthParams& p) noexcept {
  if (raw_verdict != SensorHealth::ok) {
    t.faulted = true;
    t.good_run = 0U;
    t.health = raw_verdict;
    return raw_verdict;
  }
  if (t.faulted) {
    t.good_run = bump(t.good_run);
    t.faulted = t.good_run < p.recover_cycles;
  }
  t.health = t.faulted ? SensorHealth::recovering : SensorHealth::ok;
  return t.health;
}

SensorHealth SensorHealthMonitor::current_channel(std::uint32_t wheel, const HealthSample& s, const HealthParams& p,
                                                  CurrentA no_load_a, CurrentA current_range_a,
                                                  bool pulling) noexcept {
  Track& t = track_[wheel];
  if (s.presence.current_missing[wheel]) {
    t.have_last = false;
    t.same_run = 0U;
    t.spike_run = 0U;
    t.bad_run = 0U;
    return SensorHealth::missing;
  }
  // Compared along the commanded direction, so that a reversal (the escape)
  // is no jump.
  // Stuck compares the register as read (a held value stays held when the
  // direction reverses).
  const std::int64_t raw = directed_raw(s.current_a[wheel], s.direction[wheel]);
  const std::int32_t reading = s.current_a[wheel].raw();
  bool spike = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, reading == last_reading_[wheel], s.driving);
    spike = is_spike(raw, last_current_raw_[wheel], good_current_raw_[wheel], p.current_step_a.raw());
  }
  t.spike_run = spike ? bump(t.spike_run) : 0U;
  t.have_last = true;
  last_current_raw_[wheel] = raw;
  last_reading_[wheel] = reading;
  if (spike) {
    return spike_verdict(t.spike_run);
  }
  good_current_raw_[wheel] = raw;
  // Stuck: the value repeated stuck_cycles times, identical to the bit.
  if ((p.stuck_cycles > 0U) && (t.same_run >= p.stuck_cycles)) {
    return SensorHealth::stuck;
  }
  const bool free_wheel = s.driving && pulling && (raw < static_cast<std::int64_t>(no_load_a.raw()));
  const bool stalled = (raw >= static_cast<std::int64_t>(current_range_a.raw()));
  t.bad_run = (free_wheel || stalled) ? bump(t.bad_run) : 0U;
  if ((p.implausible_cycles > 0U) && (t.bad_run >= p.implausible_cycles)) {
    return SensorHealth::implausible;
  }
  return SensorHealth::ok;
}

SensorHealth SensorHealthMonitor::imu_channel(const HealthSample& s, const HealthParams& p) noexcept {
  Track& t = track_[static_cast<std::uint8_t>(SensorChannel::imu)];
  if (s.presence.attitude_missing) {
    t.have_last = false;
    t.same_run = 0U;
    t.spike_run = 0U;
    return SensorHealth::missing;
  }
  bool spike = false;
  bool off_good = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, attitude_equal(s.attitude, last_attitude_), s.driving);
    spike = attitude_spike(s.attitude, last_attitude_, step_attitude_, p.attitude_step_rad);
    off_good = attitude_beyond(s.attitude, step_attitude_, p.attitude_step_rad);
  }
  t.spike_run = spike ? bump(t.spike_run) : 0U;
  t.have_last = true;
  last_attitude_ = s.attitude;
  if (spike) {
    const SensorHealth verdict = spike_verdict(t.spike_run);
    imu_after_noise_ = imu_after_noise_ || (verdict == SensorHealth::noisy);
    return verdict;
  }
  // Unlike a current, the attitude of a rover at walking pace cannot settle
  // at a new level one step limit away within a sample: a level that stays
  // there after one clean jump is a bias step. It is not believed until the
  // IMU comes back to the last good attitude, or the ground's clear_stop()
  // accepts it. After a noise burst the last good attitude is old (the rover
  // drove on meanwhile): two calm samples in a row make the new reference.
  if (off_good && !imu_after_noise_) {
    return SensorHealth::implausible;
  }
  imu_after_noise_ = false;
  step_attitude_ = s.attitude;
  return ((p.stuck_cycles > 0U) && (t.same_run >= p.stuck_cycles)) ? SensorHealth::stuck : SensorHealth::ok;
}

SensorHealth SensorHealthMonitor::joints_channel(const HealthSample& s, const HealthParams& p) noexcept {
  Track& t = track_[static_cast<std::uint8_t>(SensorChannel::joints)];
  if (s.presence.joints_missing) {
    t.have_last = false;
    t.same_run = 0U;
    t.spike_run = 0U;
    return SensorHealth::missing;
  }
  bool spike = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, any_joint_equal(s.joints, last_joints_), s.driving);
    spike = joints_spike(s.joints, last_joints_, step_joints_, p.joint_step_rad);
  }
  t.spike_run = spike ? bump(t.spike_run) : 0U;
  t.have_last = true;
  last_joints_ = s.joints;
  if (spike) {
    return spike_verdict(t.spike_run);
  }
  step_joints_ = s.joints;
  return ((p.stuck_cycles > 0U) && (t.same_run >= p.stuck_cycles)) ? SensorHealth::stuck : SensorHealth::ok;
}

void SensorHealthMonitor::bridge(const HealthSample& s, const HealthParams& p, SensorHealthReport& r) noexcept {
  r.attitude_usable = good_attitude_.take(usable(r.channel[static_cast<std::uint8_t>(SensorChannel::imu)]),
                                          s.attitude, s.time, p.bridge_ms, r.attitude_bridged);
  r.attitude = good_attitude_.value;
  r.joints_usable = good_joints_.take(usable(r.channel[static_cast<std::uint8_t>(SensorChannel::joints)]), s.joints,
                                      s.time, p.bridge_ms, r.joints_bridged);
  r.joints = good_joints_.value;
}

SensorHealthReport SensorHealthMonitor::update(const HealthSample& s, const HealthParams& p, CurrentA no_load_a,
                                               CurrentA current_range_a) noexcept {
  SensorHealthReport r{};
  const std::uint32_t drawing = drawing_mask(s, no_load_a);
  const std::uint32_t drawing_count = wheel_count_of(drawing);
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    const SensorHealth raw =
        current_channel(i, s, p, no_load_a, current_range_a, others_draw(drawing, drawing_count, i));
    r.channel[i] = settle(track_[i], raw, p);
    r.current_usable[i] = usable(r.channel[i]);
  }
  constexpr std::uint8_t kImu = static_cast<std::uint8_t>(SensorChannel::imu);
  constexpr std::uint8_t kJoints = static_cast<std::uint8_t>(SensorChannel::joints);
  constexpr std::uint8_t kClock = static_cast<std::uint8_t>(SensorChannel::clock);
  r.channel[kImu] = settle(track_[kImu], imu_channel(s, p), p);
  r.channel[kJoints] = settle(track_[kJoints], joints_channel(s, p), p);
  repeated_run_ = 0U;
  r.channel[kClock] = settle(track_[kClock], s.clock_jump ? SensorHealth::spike : SensorHealth::ok, p);
  bridge(s, p, r);
  for (std::uint8_t c = 0U; c < kSensorChannelCount; ++c) {
    count(static_cast<SensorChannel>(c), r.channel[c]);
  }
  return r;
}

void SensorHealthMonitor::accept_levels() noexcept {
  // The next sample of every channel is its own reference: no comparison
  // with the values from before the ground's acknowledgement.
  for (Track& t : track_) {
    t.have_last = false;
  }
  imu_after_noise_ = false;
}

SensorHealth SensorHealthMonitor::clock_refused(bool repeated, const HealthParams& p) noexcept {
  // A repeated stamp is a frozen clock only after stuck_cycles of them (one
  // repeat is a telemetry hiccup the step already refuses); any other
  // refused stamp (stale, from the future) is a jump.
  repeated_run_ = repeated ? bump(repeated_run_) : 0U;
  const bool stuck = repeated && (p.stuck_cycles > 0U) && (repeated_run_ >= p.stuck_cycles);
  const SensorHealth verdict = stuck ? SensorHealth::stuck : (repeated ? SensorHealth::ok : SensorHealth::spike);
  constexpr std::uint8_t kClock = static_cast<std::uint8_t>(SensorChannel::clock);
  const SensorHealth h = settle(track_[kClock], verdict, p);
  count(SensorChannel::clock, h);
  return h;
}

const char* channel_name(SensorChannel c) noexcept {
  switch (c) {
    case SensorChannel::current_lf:
      return "LF_current";
    case SensorChannel::current_lm:
      return "LM_current";
    case SensorChannel::current_lr:
      return "LR_current";
    case SensorChannel::current_rf:
      return "RF_current";
    case SensorChannel::current_rm:
      return "RM_current";
    case SensorChannel::current_rr:
      return "RR_current";
    case SensorChannel::imu:
      return "imu";
    case SensorChannel::joints:
      return "joints";
    case SensorChannel::clock:
      return "clock";
    default:
      return "unknown";
  }
}

const char* health_name(SensorHealth h) noexcept {
  switch (h) {
    case SensorHealth::ok:
      return "ok";
    case SensorHealth::missing:
      return "missing";
    case SensorHealth::stuck:
      return "stuck";
    case SensorHealth::spike:
      return "spike";
    case SensorHealth::noisy:
      return "noisy";
    case SensorHealth::implausible:
      return "implausible";
    case SensorHealth::recovering:
      return "recovering";
    default:
      return "unknown";
  }
}

}  // namespace flight
}  // namespace sinkwatch
