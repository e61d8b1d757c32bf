// The health of each telemetry channel over time (sensor_health.hpp,
// docs/fault-tolerance.md).
#include "sinkwatch/flight/sensor_health.hpp"

#include <limits>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using detail::CurrentHistory;
using detail::HealthTrack;

constexpr std::uint8_t kRunMax = 0xFFU;
/// A run length no 8-bit run reaches: the threshold of a check that is off.
constexpr std::uint32_t kNeverReached = 0x100U;
/// 2^32 - 1, the largest difference of two raw 32-bit values: the step
/// tolerance of an angle check that is off (no difference is beyond it).
constexpr std::uint32_t kNoAngleSpike = 0xFFFFFFFFU;

constexpr std::uint8_t kImu = static_cast<std::uint8_t>(SensorChannel::imu);
constexpr std::uint8_t kJoints = static_cast<std::uint8_t>(SensorChannel::joints);
constexpr std::uint8_t kClock = static_cast<std::uint8_t>(SensorChannel::clock);

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

/// The run length at which a check of `cycles` samples trips (0: never).
std::uint32_t trip_at(std::uint8_t cycles) noexcept { return (cycles > 0U) ? cycles : kNeverReached; }

/// A channel that is absent this sample: no comparison with the next one.
void forget(HealthTrack& t) noexcept {
  t.have_last = false;
  t.same_run = 0U;
  t.spike_run = 0U;
}

/// A fault (any verdict but ok) restarts the recovery; good samples count
/// it down from recover_cycles. The channel's health this sample.
SensorHealth settle(HealthTrack& t, SensorHealth raw_verdict, std::uint8_t recover_cycles) noexcept {
  if (raw_verdict != SensorHealth::ok) {
    t.faulted = true;
    t.good_run = 0U;
    t.health = raw_verdict;
    return raw_verdict;
  }
  if (t.faulted) {
    t.good_run = bump(t.good_run);
    t.faulted = t.good_run < recover_cycles;
  }
  t.health = t.faulted ? SensorHealth::recovering : SensorHealth::ok;
  return t.health;
}

/// settle() with its usual case, an ok sample of a channel with no fault
/// to recover from, answered without the call.
SW_FX_INLINE SensorHealth settled(HealthTrack& t, SensorHealth raw_verdict, std::uint8_t recover_cycles) noexcept {
  return ((raw_verdict == SensorHealth::ok) && !t.faulted) ? SensorHealth::ok
                                                           : settle(t, raw_verdict, recover_cycles);
}

/// A spike, and spikes in a row a noise burst.
SensorHealth spike_verdict(std::uint8_t spike_run) noexcept {
  return (spike_run >= 2U) ? SensorHealth::noisy : SensorHealth::spike;
}

/// An angle's step limit as the tolerance the distance() of two raw angles
/// may reach without a spike; a zero or negative limit switches it off.
std::uint32_t angle_tolerance(AngleRad limit) noexcept {
  return (limit.raw() > 0) ? static_cast<std::uint32_t>(limit.raw()) : kNoAngleSpike;
}

/// |a - b| of two raw 32-bit values, exactly, in 32 bits: the larger less
/// the smaller lies in [0, 2^32), so the unsigned difference (mod 2^32) is it.
std::uint32_t distance(std::int32_t a, std::int32_t b) noexcept {
  const auto ua = static_cast<std::uint32_t>(a);
  const auto ub = static_cast<std::uint32_t>(b);
  return (a >= b) ? (ua - ub) : (ub - ua);
}

/// More than `tolerance` from `reference`.
bool angle_beyond(AngleRad a, AngleRad reference, std::uint32_t tolerance) noexcept {
  return distance(a.raw(), reference.raw()) > tolerance;
}

// A spike is a jump from the previous raw value that is also a jump from
// the last value that was not a spike: one wild sample, or the first of a
// burst. A sample back near the last good value (the spike has passed) or
// near the previous one (a level change, e.g. a bias step) is not a spike.

bool attitude_equal(const RoverAttitude& a, const RoverAttitude& b) noexcept {
  return (a.pitch_rad == b.pitch_rad) && (a.roll_rad == b.roll_rad);
}

/// Any one joint identical to its previous sample (a frozen encoder).
bool any_joint_equal(const JointAnglesRad& a, const JointAnglesRad& b) noexcept {
  bool equal = false;
  for (std::uint32_t side = 0U; side < kSideCount; ++side) {
    equal = equal || (a.rocker_rad[side] == b.rocker_rad[side]) || (a.bogie_rad[side] == b.bogie_rad[side]);
  }
  return equal;
}

/// One joint's spike: beyond the previous sample and the last good one (the
/// second distance only for a joint beyond the first).
bool joint_spike(AngleRad a, AngleRad previous, AngleRad good, std::uint32_t tolerance) noexcept {
  return angle_beyond(a, previous, tolerance) && angle_beyond(a, good, tolerance);
}

bool joints_spike(const JointAnglesRad& a, const JointAnglesRad& previous, const JointAnglesRad& good,
                  std::uint32_t tolerance) noexcept {
  bool spike = false;
  for (std::uint32_t side = 0U; side < kSideCount; ++side) {
    spike = spike || joint_spike(a.rocker_rad[side], previous.rocker_rad[side], good.rocker_rad[side], tolerance) ||
            joint_spike(a.bogie_rad[side], previous.bogie_rad[side], good.bogie_rad[side], tolerance);
  }
  return spike;
}

/// The current along the commanded direction, in raw Q11.20 widened to 64
/// bits (the negation of INT32_MIN stays exact).
std::int64_t directed_raw(CurrentA current_a, DriveDirection direction) noexcept {
  const std::int64_t raw = static_cast<std::int64_t>(current_a.raw());
  return (direction == DriveDirection::reverse) ? -raw : raw;
}

/// A current's step limit as the tolerances |D_a - D_b| may reach without a
/// spike (D = reading or -reading in reverse, in [-2^31, 2^31]): with one
/// direction (at most 2^32 - 1, so 2^32 - 1 switches the check off) and
/// across a reversal (at most 2^32, so 2^32 switches it off).
struct CurrentTolerance {
  std::uint32_t one_way;
  std::uint64_t reversed;
};

CurrentTolerance current_tolerance(CurrentA limit) noexcept {
  if (limit.raw() > 0) {
    const auto t = static_cast<std::uint32_t>(limit.raw());
    return CurrentTolerance{t, t};
  }
  return CurrentTolerance{0xFFFFFFFFU, std::uint64_t{1U} << 32U};
}

/// |D_a - D_b| > tolerance for two currents along their directions: with
/// one direction the difference is +-(r_a - r_b), whose magnitude distance()
/// gives exactly in 32 bits (the usual case); across a reversal it is
/// +-(r_a + r_b), up to 2^32, in 64 bits.
bool current_beyond(std::int32_t reading_a, bool reverse_a, std::int32_t reading_b, bool reverse_b,
                    const CurrentTolerance& tolerance) noexcept {
  if (reverse_a == reverse_b) {
    return distance(reading_a, reading_b) > tolerance.one_way;
  }
  const std::int64_t sum = static_cast<std::int64_t>(reading_a) + static_cast<std::int64_t>(reading_b);
  return fx::detail::magnitude(sum) > tolerance.reversed;
}

/// D >= level for a current along its direction (D as in current_beyond):
/// a 32-bit comparison forward, the negation widened in reverse.
bool directed_at_least(std::int32_t reading, bool reverse, std::int32_t level) noexcept {
  if (!reverse) {
    return reading >= level;
  }
  return -static_cast<std::int64_t>(reading) >= static_cast<std::int64_t>(level);
}

/// At least three of the other five wheels draw more than twice the
/// no-load current: the rover is pulling, so a wheel that draws less than
/// the no-load current transmits no torque. Asked only about a wheel below
/// the no-load current while driving, which a healthy drive never has: the
/// six wheels' count is not made every sample.
bool others_pull(const HealthSample& s, std::int32_t no_load_raw, std::uint32_t wheel) noexcept {
  const std::int64_t twice = 2 * static_cast<std::int64_t>(no_load_raw);
  std::uint32_t drawing = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if ((i != wheel) && !s.presence.current_missing[i] && (directed_raw(s.current_a[i], s.direction[i]) > twice)) {
      ++drawing;
    }
  }
  return drawing >= 3U;
}

/// The current checks' parameters, prepared once per sample for the six
/// wheels (a zero run or step limit as a threshold never reached).
struct CurrentChecks {
  CurrentTolerance step_tolerance;
  std::int32_t no_load_raw;
  std::int32_t range_raw;
  std::uint32_t stuck_at;
  std::uint32_t implausible_at;
  bool driving;
};

/// A jump from the previous sample and from the last one that was not a spike.
bool current_spike(const CurrentHistory& h, std::int32_t reading, bool reverse, const CurrentChecks& k) noexcept {
  return current_beyond(reading, reverse, h.last_reading, h.last_reverse, k.step_tolerance) &&
         current_beyond(reading, reverse, h.good_reading, h.good_reverse, k.step_tolerance);
}

/// One wheel's current this sample, before settle(): its runs in `t`, its
/// previous values in `h`.
SensorHealth current_verdict(HealthTrack& t, CurrentHistory& h, const HealthSample& s, std::uint32_t wheel,
                             const CurrentChecks& k) noexcept {
  if (s.presence.current_missing[wheel]) {
    forget(t);
    t.bad_run = 0U;
    return SensorHealth::missing;
  }
  // Compared along the commanded direction, so that a reversal (the escape)
  // is no jump.
  // Stuck compares the register as read (a held value stays held when the
  // direction reverses).
  const std::int32_t reading = s.current_a[wheel].raw();
  const bool reverse = s.direction[wheel] == DriveDirection::reverse;
  bool spike = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, reading == h.last_reading, k.driving);
    spike = current_spike(h, reading, reverse, k);
  }
  t.spike_run = spike ? bump(t.spike_run) : 0U;
  t.have_last = true;
  h.last_reading = reading;
  h.last_reverse = reverse;
  if (spike) {
    return spike_verdict(t.spike_run);
  }
  h.good_reading = reading;
  h.good_reverse = reverse;
  // Stuck: the value repeated stuck_cycles times, identical to the bit.
  if (t.same_run >= k.stuck_at) {
    return SensorHealth::stuck;
  }
  const bool stalled = directed_at_least(reading, reverse, k.range_raw);
  const bool free_wheel =
      k.driving && !directed_at_least(reading, reverse, k.no_load_raw) && others_pull(s, k.no_load_raw, wheel);
  t.bad_run = (free_wheel || stalled) ? bump(t.bad_run) : 0U;
  return (t.bad_run >= k.implausible_at) ? SensorHealth::implausible : SensorHealth::ok;
}

/// A current channel whose next steady sample changes nothing but its last
/// value: compared before, no run under way (so its last good value is its
/// last one), no fault to recover from, read forward.
bool quiet_after(const HealthTrack& t, const CurrentHistory& h) noexcept {
  return t.have_last && (t.same_run == 0U) && (t.spike_run == 0U) && (t.bad_run == 0U) && !t.faulted &&
         !h.last_reverse;
}

/// What makes a quiet channel's forward sample steady, prepared once per
/// sample for the six wheels: the step tolerance, and the readings that are
/// neither at the range (stalled) nor, while driving, below the no-load
/// current, as low <= reading < low + width (width 0: none).
struct SteadyWindow {
  std::uint32_t step_tolerance;
  std::int32_t low;
  std::uint32_t width;
  bool driving;
};

SteadyWindow steady_window(const HealthParams& p, CurrentA no_load_a, CurrentA current_range_a,
                           bool driving) noexcept {
  const std::int32_t range = current_range_a.raw();
  const std::int32_t low = driving ? no_load_a.raw() : std::numeric_limits<std::int32_t>::min();
  // range - low < 2^32 when low < range: exact in 32 unsigned bits.
  const std::uint32_t width =
      (low < range) ? (static_cast<std::uint32_t>(range) - static_cast<std::uint32_t>(low)) : 0U;
  return SteadyWindow{current_tolerance(p.current_step_a).one_way, low, width, driving};
}

/// A quiet channel's forward sample that current_verdict() finds ok with
/// every run still 0: no repeat while driving, no jump from the last value,
/// below the range, and not below the no-load current while driving (the
/// other wheels are then not asked). The window's test: reading - low
/// wraps to at least 2^32 - (low - reading) > width below low.
SW_FX_INLINE bool steady_forward(const CurrentHistory& h, std::int32_t reading, const SteadyWindow& w) noexcept {
  return ((reading != h.last_reading) || !w.driving) &&
         (distance(reading, h.last_reading) <= w.step_tolerance) &&
         ((static_cast<std::uint32_t>(reading) - static_cast<std::uint32_t>(w.low)) < w.width);
}

/// One more sample in a saturating counter, inline (the call cost as much
/// again as the count): the increment kept unless it wrapped to zero, the
/// monitor's count_sample() form (round 17: one instruction fewer per
/// count than adding the comparison's result). cppcheck's value flow
/// assumes that an unsigned increment does not wrap, which is the case
/// tested here (0xFFFFFFFF + 1 is 0): its "always true" is a false
/// positive (docs/assurance.md).
SW_FX_INLINE void tally(std::uint32_t& n) noexcept {
  const std::uint32_t next = n + 1U;
  // cppcheck-suppress knownConditionTrueFalse
  if (next != 0U) {
    n = next;
  }
}

/// Wheel i's sample, when its bit in `steady` is set and it is steady
/// (present, forward and steady_forward()), taken as current_verdict() and
/// settle() would: its value last and good, every run 0, one more ok;
/// otherwise its bit cleared.
SW_FX_INLINE void steady_wheel(CurrentHistory& h, std::uint32_t& ok_count, const HealthSample& s, std::uint32_t i,
                               const SteadyWindow& w, std::uint32_t& steady) noexcept {
  const std::uint32_t bit = 1U << i;
  const std::int32_t reading = s.current_a[i].raw();
  // Present (false is 0) and forward (0): both tested at once.
  const bool present_forward = (static_cast<std::uint32_t>(s.presence.current_missing[i]) |
                                static_cast<std::uint32_t>(s.direction[i])) == 0U;
  if (((steady & bit) != 0U) && present_forward && steady_forward(h, reading, w)) {
    h.last_reading = reading;
    h.good_reading = reading;
    tally(ok_count);
  } else {
    steady &= ~bit;
  }
}

/// The quiet wheels (bit i of `quiet`) whose sample is steady
/// (steady_wheel()); those wheels' bits. Out of line: in currents() the
/// monitor's, the sample's and the report's pointers, live across the
/// wheels for the calls after them, made them spill their own. The wheels
/// one by one, not in a loop (round 17): each wheel's offsets are
/// constants, with no index, bit or counter carried from wheel to wheel.
[[gnu::noinline]] std::uint32_t steady_samples(CurrentHistory (&history)[kWheelCount],
                                               std::uint32_t (&by_health)[kSensorChannelCount][kSensorHealthCount],
                                               const HealthSample& s, const SteadyWindow window,
                                               std::uint32_t quiet) noexcept {
  // A local copy, which the word stores cannot alias: kept in registers
  // (through a reference it was read again after every store).
  const SteadyWindow w = window;
  constexpr auto kOk = static_cast<std::uint8_t>(SensorHealth::ok);
  std::uint32_t steady = quiet;  ///< cleared for a wheel that is not steady
  static_assert(kWheelCount == 6U, "one call per wheel below");
  steady_wheel(history[0], by_health[0][kOk], s, 0U, w, steady);
  steady_wheel(history[1], by_health[1][kOk], s, 1U, w, steady);
  steady_wheel(history[2], by_health[2][kOk], s, 2U, w, steady);
  steady_wheel(history[3], by_health[3][kOk], s, 3U, w, steady);
  steady_wheel(history[4], by_health[4][kOk], s, 4U, w, steady);
  steady_wheel(history[5], by_health[5][kOk], s, 5U, w, steady);
  return steady;
}

}  // namespace

void SensorHealthMonitor::count(SensorChannel c, SensorHealth h) noexcept {
  tally(counters_.by_health[static_cast<std::uint8_t>(c)][static_cast<std::uint8_t>(h)]);
}

bool SensorHealthMonitor::current_sample(const HealthSample& s, const HealthParams& p, CurrentA no_load_a,
                                         CurrentA current_range_a, std::uint32_t wheel,
                                         SensorHealthReport& r) noexcept {
  const CurrentChecks k{current_tolerance(p.current_step_a),
                        no_load_a.raw(),
                        current_range_a.raw(),
                        trip_at(p.stuck_cycles),
                        trip_at(p.implausible_cycles),
                        s.driving};
  HealthTrack& t = track_[wheel];
  CurrentHistory& h = current_history_[wheel];
  const SensorHealth verdict = current_verdict(t, h, s, wheel, k);
  const SensorHealth health = settled(t, verdict, p.recover_cycles);
  t.health = health;
  r.channel[wheel] = health;
  r.current_usable[wheel] = usable(health);
  tally(counters_.by_health[wheel][static_cast<std::uint8_t>(health)]);
  return quiet_after(t, h);
}

void SensorHealthMonitor::currents(const HealthSample& s, const HealthParams& p, CurrentA no_load_a,
                                   CurrentA current_range_a, SensorHealthReport& r) noexcept {
  // Every wheel's report as a steady sample leaves it, stored first as
  // constants (no pointer into the report walked in the loop);
  // current_sample() overwrites a wheel that is not steady.
  static_assert(kWheelCount == 6U, "six wheels' report fields spelled out");
  r.channel[0] = SensorHealth::ok;
  r.channel[1] = SensorHealth::ok;
  r.channel[2] = SensorHealth::ok;
  r.channel[3] = SensorHealth::ok;
  r.channel[4] = SensorHealth::ok;
  r.channel[5] = SensorHealth::ok;
  r.current_usable[0] = true;
  r.current_usable[1] = true;
  r.current_usable[2] = true;
  r.current_usable[3] = true;
  r.current_usable[4] = true;
  r.current_usable[5] = true;
  // The steady samples first (steady_samples()); the others after, each by
  // the general checks. A wheel's checks read its own state and the sample
  // only, so the order of the wheels changes nothing.
  const std::uint32_t steady =
      steady_samples(current_history_, counters_.by_health, s, steady_window(p, no_load_a, current_range_a, s.driving),
                     quiet_currents_);
  constexpr std::uint32_t kAllWheels = (1U << kWheelCount) - 1U;
  if (steady != kAllWheels) {
    // A steady wheel stays quiet (its bit is set); the others are quiet as
    // current_sample() leaves them.
    std::uint32_t next_quiet = steady;
    std::uint32_t bit = 1U;
    for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
      if (((steady & bit) == 0U) && current_sample(s, p, no_load_a, current_range_a, i, r)) {
        next_quiet |= bit;
      }
      bit <<= 1U;
    }
    quiet_currents_ = static_cast<std::uint8_t>(next_quiet);
  }
}

// The IMU, joint and bridge stages are each called once per sample: inline
// into update() (SW_FX_INLINE), without a call and its saved registers.
// currents() stays a call: inline, its six-wheel loop spills.
SW_FX_INLINE SensorHealth SensorHealthMonitor::imu_channel(const HealthSample& s, const HealthParams& p) noexcept {
  HealthTrack& t = track_[kImu];
  if (s.presence.attitude_missing) {
    forget(t);
    return SensorHealth::missing;
  }
  const std::uint32_t tolerance = angle_tolerance(p.attitude_step_rad);
  bool spike = false;
  bool off_good = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, attitude_equal(s.attitude, last_attitude_), s.driving);
    const bool pitch_off_good = angle_beyond(s.attitude.pitch_rad, step_attitude_.pitch_rad, tolerance);
    const bool roll_off_good = angle_beyond(s.attitude.roll_rad, step_attitude_.roll_rad, tolerance);
    // A spike is beyond the previous sample too (that distance only for an
    // angle beyond the last good one).
    spike = (pitch_off_good && angle_beyond(s.attitude.pitch_rad, last_attitude_.pitch_rad, tolerance)) ||
            (roll_off_good && angle_beyond(s.attitude.roll_rad, last_attitude_.roll_rad, tolerance));
    off_good = pitch_off_good || roll_off_good;
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
  return (t.same_run >= trip_at(p.stuck_cycles)) ? SensorHealth::stuck : SensorHealth::ok;
}

SW_FX_INLINE SensorHealth SensorHealthMonitor::joints_channel(const HealthSample& s, const HealthParams& p) noexcept {
  HealthTrack& t = track_[kJoints];
  if (s.presence.joints_missing) {
    forget(t);
    return SensorHealth::missing;
  }
  bool spike = false;
  if (t.have_last) {
    t.same_run = repeat_run(t.same_run, any_joint_equal(s.joints, last_joints_), s.driving);
    spike = joints_spike(s.joints, last_joints_, step_joints_, angle_tolerance(p.joint_step_rad));
  }
  t.spike_run = spike ? bump(t.spike_run) : 0U;
  t.have_last = true;
  last_joints_ = s.joints;
  if (spike) {
    return spike_verdict(t.spike_run);
  }
  step_joints_ = s.joints;
  return (t.same_run >= trip_at(p.stuck_cycles)) ? SensorHealth::stuck : SensorHealth::ok;
}

SW_FX_INLINE void SensorHealthMonitor::bridge(const HealthSample& s, const HealthParams& p, SensorHealth imu,
                                              SensorHealth joints, SensorHealthReport& r) noexcept {
  r.attitude_usable =
      good_attitude_.take(usable(imu), s.attitude, s.time, p.bridge_ms, r.attitude_bridged, r.attitude);
  r.joints_usable = good_joints_.take(usable(joints), s.joints, s.time, p.bridge_ms, r.joints_bridged, r.joints);
}

// A quiet IMU or joint channel (ok, so not faulted, its last sample no
// spike and its last good value that sample; no repeat run) whose next
// sample is present and within the step limit of its last one, and while
// driving not a repeat, is what imu_channel() or joints_channel() and
// settle() find ok with nothing changed but the last and last good values:
// no distance to the last good value (it is the last one) and no run.
SW_FX_INLINE SensorHealth SensorHealthMonitor::imu_health(const HealthSample& s, const HealthParams& p) noexcept {
  if (quiet_imu_ && !s.presence.attitude_missing) {
    const std::uint32_t tolerance = angle_tolerance(p.attitude_step_rad);
    const std::uint32_t pitch_step = distance(s.attitude.pitch_rad.raw(), last_attitude_.pitch_rad.raw());
    const std::uint32_t roll_step = distance(s.attitude.roll_rad.raw(), last_attitude_.roll_rad.raw());
    // The attitude repeats when both angles do.
    if ((pitch_step <= tolerance) && (roll_step <= tolerance) && (((pitch_step | roll_step) != 0U) || !s.driving)) {
      const RoverAttitude sample = s.attitude;
      last_attitude_ = sample;
      step_attitude_ = sample;
      return SensorHealth::ok;
    }
  }
  const SensorHealth health = settled(track_[kImu], imu_channel(s, p), p.recover_cycles);
  quiet_imu_ = (health == SensorHealth::ok) && (track_[kImu].same_run == 0U);
  return health;
}

/// A joint's step from its last sample within `tolerance` and at least
/// `at_least` (1 while driving: a frozen encoder repeats; else 0), in one
/// comparison: step - at_least wraps to 2^32 - 1 for a repeat while
/// driving, and tolerance >= 1 (angle_tolerance()).
SW_FX_INLINE bool steady_joint(AngleRad a, AngleRad last, std::uint32_t at_least, std::uint32_t tolerance) noexcept {
  return (distance(a.raw(), last.raw()) - at_least) <= (tolerance - at_least);
}

SW_FX_INLINE SensorHealth SensorHealthMonitor::joints_health(const HealthSample& s, const HealthParams& p) noexcept {
  if (quiet_joints_ && !s.presence.joints_missing) {
    const std::uint32_t tolerance = angle_tolerance(p.joint_step_rad);
    const std::uint32_t at_least = s.driving ? 1U : 0U;
    static_assert(kSideCount == 2U, "two sides: a rocker and a bogie each");
    const JointAnglesRad& j = s.joints;
    const bool steady = steady_joint(j.rocker_rad[0], last_joints_.rocker_rad[0], at_least, tolerance) &&
                        steady_joint(j.rocker_rad[1], last_joints_.rocker_rad[1], at_least, tolerance) &&
                        steady_joint(j.bogie_rad[0], last_joints_.bogie_rad[0], at_least, tolerance) &&
                        steady_joint(j.bogie_rad[1], last_joints_.bogie_rad[1], at_least, tolerance);
    if (steady) {
      // One read of the sample for both stores, angle by angle: a copy of
      // the whole record (arrays) was kept in the frame as well, a store
      // that nothing read (round 17).
      const AngleRad rocker0 = j.rocker_rad[0];
      const AngleRad rocker1 = j.rocker_rad[1];
      const AngleRad bogie0 = j.bogie_rad[0];
      const AngleRad bogie1 = j.bogie_rad[1];
      last_joints_ = JointAnglesRad{{rocker0, rocker1}, {bogie0, bogie1}};
      step_joints_ = JointAnglesRad{{rocker0, rocker1}, {bogie0, bogie1}};
      return SensorHealth::ok;
    }
  }
  const SensorHealth health = settled(track_[kJoints], joints_channel(s, p), p.recover_cycles);
  quiet_joints_ = (health == SensorHealth::ok) && (track_[kJoints].same_run == 0U);
  return health;
}

void SensorHealthMonitor::update(const HealthSample& s, const HealthParams& p, CurrentA no_load_a,
                                 CurrentA current_range_a, SensorHealthReport& report) noexcept {
  currents(s, p, no_load_a, current_range_a, report);
  const SensorHealth imu = imu_health(s, p);
  const SensorHealth joints = joints_health(s, p);
  repeated_run_ = 0U;
  const SensorHealth clock =
      settled(track_[kClock], s.clock_jump ? SensorHealth::spike : SensorHealth::ok, p.recover_cycles);
  report.channel[kImu] = imu;
  report.channel[kJoints] = joints;
  report.channel[kClock] = clock;
  bridge(s, p, imu, joints, report);
  // The three channels' counts spelled out: no loop, no call per channel.
  tally(counters_.by_health[kImu][static_cast<std::uint8_t>(imu)]);
  tally(counters_.by_health[kJoints][static_cast<std::uint8_t>(joints)]);
  tally(counters_.by_health[kClock][static_cast<std::uint8_t>(clock)]);
}

void SensorHealthMonitor::accept_levels() noexcept {
  // The next sample of every channel is its own reference: no comparison
  // with the values from before the ground's acknowledgement.
  for (HealthTrack& t : track_) {
    t.have_last = false;
  }
  quiet_currents_ = 0U;
  quiet_imu_ = false;
  quiet_joints_ = false;
  imu_after_noise_ = false;
}

SensorHealth SensorHealthMonitor::clock_refused(bool repeated, const HealthParams& p) noexcept {
  // A repeated stamp is a frozen clock only after stuck_cycles of them (one
  // repeat is a telemetry hiccup the step already refuses); any other
  // refused stamp (stale, from the future) is a jump.
  repeated_run_ = repeated ? bump(repeated_run_) : 0U;
  const bool stuck = repeated && (repeated_run_ >= trip_at(p.stuck_cycles));
  const SensorHealth verdict = stuck ? SensorHealth::stuck : (repeated ? SensorHealth::ok : SensorHealth::spike);
  const SensorHealth h = settle(track_[kClock], verdict, p.recover_cycles);
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
