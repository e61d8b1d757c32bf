// Sensor faults on a traverse (docs/fault-tolerance.md): each fault class is
// detected and reported, a wheel without usable evidence never stays NOMINAL
// beside embedding, one spike never stops the rover, a lasting loss leads to
// the table's loss policy, and a returning sensor recovers. Every class is
// also run with the handling switched off (section 7 all zero, and the
// telemetry's absence flags not set, as before issue 18: a dropout then
// reads as the 0 A the converter gives), to show the bad outcome the
// handling prevents: each test can fail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>

#include "rover_test_support.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/sensor_health.hpp"

namespace sinkwatch {
namespace {

using flight::RoverStepOutput;
using flight::RoverStepStatus;
using flight::SensorChannel;
using flight::SensorHealth;
using flight::WheelState;
using rover_test::q;

constexpr std::uint32_t kPeriodMs = 200U;  // 5 Hz
constexpr std::uint32_t kFaultWheel = 1U;  // left middle

/// Deterministic noise in [-1, 1] for cycle k and channel c.
double noise(std::uint32_t k, std::uint32_t c) {
  std::uint32_t h = (k * 2654435761U) ^ (c * 40503U + 0x9E3779B9U);
  h ^= h >> 15U;
  h *= 2246822519U;
  h ^= h >> 13U;
  return static_cast<double>(h % 20001U) / 10000.0 - 1.0;
}

/// A drive at 5 Hz: 0.35 A per wheel with 4 mA of sensor noise, level
/// ground with 0.03 deg of IMU and joint noise, 10 % slip. From cycle
/// `embed_from` on, every wheel but `spared` draws 0.05 A more per cycle
/// (the soil softening under it) up to 1.5 A, past the limit.
struct Drive {
  std::uint32_t embed_from = 1000U;
  std::uint32_t spared = kFaultWheel;

  flight::RoverTelemetry at(std::uint32_t k) const {
    flight::RoverTelemetry t{};
    t.time = flight::TimeMs{10000U + kPeriodMs * k};
    t.valid = true;
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      double a = 0.35 + 0.004 * noise(k, i);
      if ((k >= embed_from) && (i != spared)) {
        a += std::fmin(0.05 * static_cast<double>(k - embed_from), 1.15);
      }
      t.current_a[i] = q<flight::CurrentA>(a);
      t.direction[i] = flight::DriveDirection::forward;
    }
    t.attitude = rover_test::attitude(0.0005 * noise(k, 6U), 0.0005 * noise(k, 7U));
    t.joints = rover_test::joints(0.0005 * noise(k, 8U), 0.0005 * noise(k, 9U), 0.0005 * noise(k, 10U),
                                  0.0005 * noise(k, 11U));
    t.accel_valid = true;
    t.accel_mps2 = flight::AccelMps2::zero();
    t.speed_valid = true;
    t.speed_mps = q<flight::SpeedMps>(0.045);
    t.rim_speed_valid = true;
    t.rim_speed_mps = q<flight::SpeedMps>(0.05);
    return t;
  }
};

/// A fault applied to cycle k's telemetry.
using Fault = std::function<void(std::uint32_t k, flight::RoverTelemetry&)>;

/// Handling on (the default table) or off (section 7 all zero and the
/// absence flags dropped: a missing current reads 0 A).
enum class Handling : std::uint8_t { on, off };

class SensorFaults : public ::testing::Test {
 public:
  flight::ParameterTable table = flight::default_parameter_table();
  flight::RoverParams rover = flight::yutu_like_rover_params(flight::kGravityMoon);

  /// Runs `cycles` cycles of `drive` with `fault`; calls `check` on each.
  void run(const Drive& drive, const Fault& fault, Handling handling, std::uint32_t cycles,
           const std::function<void(std::uint32_t, const RoverStepOutput&)>& check) {
    flight::ParameterTable used = table;
    if (handling == Handling::off) {
      used.health = flight::HealthParams{};
    }
    flight::PreparedParameters prepared{};
    ASSERT_EQ(flight::prepare(used, rover, prepared), flight::PrepareStatus::ok);
    flight::RoverStep step;
    for (std::uint32_t k = 0U; k < cycles; ++k) {
      flight::RoverTelemetry t = drive.at(k);
      fault(k, t);
      if (handling == Handling::off) {
        strip_presence(t);
      }
      RoverStepOutput out{};
      step.step(t, t.time, prepared, out);
      check(k, out);
    }
  }

  static void strip_presence(flight::RoverTelemetry& t) {
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      if (t.presence.current_missing[i]) {
        t.current_a[i] = flight::CurrentA::zero();
      }
    }
    t.presence = flight::SensorPresence{};
  }
};

SensorHealth channel(const RoverStepOutput& out, std::uint32_t c) { return out.health.channel[c]; }

bool another_wheel_points_to_embedding(const RoverStepOutput& out, std::uint32_t self) {
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    if ((i != self) && (out.monitor.wheels[i].state != WheelState::nominal)) {
      return true;
    }
  }
  return false;
}

/// The fault wheel's current held from cycle `from` on at `value_a`, or at
/// its value in that cycle when value_a is NaN.
Fault held_current(std::uint32_t from, double value_a) {
  auto held = std::make_shared<flight::CurrentA>();
  return [from, value_a, held](std::uint32_t k, flight::RoverTelemetry& t) {
    if (k == from) {
      *held = std::isnan(value_a) ? t.current_a[kFaultWheel] : q<flight::CurrentA>(value_a);
    }
    if (k >= from) {
      t.current_a[kFaultWheel] = *held;
    }
  };
}

struct NominalBesideEmbedding {
  std::uint32_t detected_at = 0U;  ///< first cycle the channel was not usable (0: never)
  std::uint32_t nominal_beside = 0U;  ///< cycles after detection NOMINAL beside embedding
  bool rover_stopped = false;
};

NominalBesideEmbedding watch_fault_wheel(SensorFaults& f, const Drive& drive, const Fault& fault,
                                         Handling handling) {
  NominalBesideEmbedding seen;
  f.run(drive, fault, handling, 60U, [&](std::uint32_t k, const RoverStepOutput& out) {
    if ((seen.detected_at == 0U) && !flight::usable(channel(out, kFaultWheel))) {
      seen.detected_at = k;
    }
    const bool after_detection = (handling == Handling::off) || (seen.detected_at != 0U);
    if (after_detection && another_wheel_points_to_embedding(out, kFaultWheel) &&
        (out.monitor.wheels[kFaultWheel].state == WheelState::nominal)) {
      ++seen.nominal_beside;
    }
    seen.rover_stopped = seen.rover_stopped || (out.decision == flight::RoverDecision::stop_and_replan);
  });
  return seen;
}

TEST_F(SensorFaults, StuckCurrentIsNamedAndItsWheelNeverStaysNominalBesideEmbedding) {
  const Drive drive{25U, kFaultWheel};
  const Fault stuck = held_current(10U, std::nan(""));
  const NominalBesideEmbedding on = watch_fault_wheel(*this, drive, stuck, Handling::on);
  // Identical for stuck_cycles samples after the first held one.
  EXPECT_EQ(on.detected_at, 10U + table.health.stuck_cycles);
  EXPECT_EQ(on.nominal_beside, 0U);
  EXPECT_TRUE(on.rover_stopped);
  const NominalBesideEmbedding off = watch_fault_wheel(*this, drive, stuck, Handling::off);
  EXPECT_GT(off.nominal_beside, 0U) << "without the handling the stuck wheel reads NOMINAL";
}

TEST_F(SensorFaults, CurrentStuckAtZeroOrFreeWheelingIsImplausibleOnAPullingRover) {
  const Drive drive{25U, kFaultWheel};
  const Fault zero = held_current(10U, 0.0);
  const Fault free_wheel = [](std::uint32_t k, flight::RoverTelemetry& t) {
    if (k >= 10U) {
      t.current_a[kFaultWheel] = q<flight::CurrentA>(0.02 + 0.004 * noise(k, 99U));
    }
  };
  for (const Fault& fault : {zero, free_wheel}) {
    const NominalBesideEmbedding on = watch_fault_wheel(*this, drive, fault, Handling::on);
    EXPECT_EQ(on.detected_at, 10U + table.health.implausible_cycles - 1U);
    EXPECT_EQ(on.nominal_beside, 0U);
    const NominalBesideEmbedding off = watch_fault_wheel(*this, drive, fault, Handling::off);
    EXPECT_GT(off.nominal_beside, 0U);
  }
}

/// The fault wheel's current missing in cycles [from, until).
Fault dropout(std::uint32_t from, std::uint32_t until, std::uint32_t first_wheel = kFaultWheel,
              std::uint32_t wheels = 1U) {
  return [=](std::uint32_t k, flight::RoverTelemetry& t) {
    for (std::uint32_t i = first_wheel; (k >= from) && (k < until) && (i < first_wheel + wheels); ++i) {
      t.presence.current_missing[i] = true;
      t.current_a[i] = flight::CurrentA::from_raw(0x12345);  // whatever the converter held
    }
  };
}

TEST_F(SensorFaults, LastingDropoutStopsUnderTheStopPolicy) {
  table.health.policy = flight::LossPolicy::stop;
  std::uint32_t stopped_at = 0U;
  flight::StopReason reason = flight::StopReason::none;
  run(Drive{}, dropout(10U, 40U), Handling::on, 40U, [&](std::uint32_t k, const RoverStepOutput& out) {
    if (k >= 10U) {
      EXPECT_EQ(channel(out, kFaultWheel), SensorHealth::missing);
      EXPECT_EQ(out.monitor.wheels[kFaultWheel].sample_status, flight::SampleStatus::sensor_fault);
    }
    if ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) {
      stopped_at = k;
      reason = out.monitor.wheels[kFaultWheel].stop_reason;
    }
  });
  EXPECT_EQ(stopped_at, 10U + table.monitor.invalid_to_stop - 1U);
  EXPECT_EQ(reason, flight::StopReason::telemetry);
  // Off: the 0 A the converter gives is taken for a measurement; the rover
  // drives on with a wheel it cannot see.
  bool stopped_off = false;
  run(Drive{}, dropout(10U, 40U), Handling::off, 40U, [&](std::uint32_t, const RoverStepOutput& out) {
    stopped_off = stopped_off || (out.decision == flight::RoverDecision::stop_and_replan);
  });
  EXPECT_FALSE(stopped_off);
}

TEST_F(SensorFaults, DropoutRunsDegradedUnderTheContinuePolicyAndRecovers) {
  table.health.policy = flight::LossPolicy::continue_degraded;
  bool stopped = false;
  std::uint32_t ok_again_at = 0U;
  std::uint32_t nominal_again_at = 0U;
  run(Drive{}, dropout(10U, 40U), Handling::on, 70U, [&](std::uint32_t k, const RoverStepOutput& out) {
    stopped = stopped || (out.decision == flight::RoverDecision::stop_and_replan);
    if ((k >= 10U) && (k < 40U)) {
      EXPECT_TRUE(out.monitor.degraded) << k;
      EXPECT_EQ(out.monitor.wheels_blind, 1U) << k;
    }
    // Unusable samples are CAUTION evidence: trip_n of them and the blind
    // wheel is in CAUTION, where it stays until it sees again.
    if ((k >= 10U + table.monitor.trip_n - 1U) && (k < 40U)) {
      EXPECT_EQ(out.monitor.wheels[kFaultWheel].state, WheelState::caution) << k << " (blind, not clear)";
    }
    if ((k >= 40U) && (ok_again_at == 0U) && (channel(out, kFaultWheel) == SensorHealth::ok)) {
      ok_again_at = k;
    }
    if ((k >= 40U) && (nominal_again_at == 0U) && (out.monitor.wheels[kFaultWheel].state == WheelState::nominal)) {
      nominal_again_at = k;
    }
  });
  EXPECT_FALSE(stopped);
  EXPECT_EQ(ok_again_at, 40U + table.health.recover_cycles - 1U);
  EXPECT_GT(nominal_again_at, 0U) << "the wheel's own clear samples bring it back";
}

TEST_F(SensorFaults, WholeSideDropoutStopsUnderEitherPolicy) {
  for (const flight::LossPolicy policy : {flight::LossPolicy::stop, flight::LossPolicy::continue_degraded}) {
    table.health.policy = policy;
    std::uint32_t stopped_at = 0U;
    run(Drive{}, dropout(10U, 60U, 0U, 3U), Handling::on, 40U, [&](std::uint32_t k, const RoverStepOutput& out) {
      if ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) {
        stopped_at = k;
      }
    });
    // Three blind wheels exceed max_blind_wheels at once; under the stop
    // policy each blind wheel stops after invalid_to_stop samples.
    const std::uint32_t expected =
        (policy == flight::LossPolicy::continue_degraded) ? 10U : 10U + table.monitor.invalid_to_stop - 1U;
    EXPECT_EQ(stopped_at, expected);
  }
  bool stopped_off = false;
  run(Drive{}, dropout(10U, 60U, 0U, 3U), Handling::off, 40U, [&](std::uint32_t, const RoverStepOutput& out) {
    stopped_off = stopped_off || (out.decision == flight::RoverDecision::stop_and_replan);
  });
  EXPECT_FALSE(stopped_off) << "without the handling half the rover is driven blind";
}

Fault spike_at(std::uint32_t at, double add_a) {
  return [=](std::uint32_t k, flight::RoverTelemetry& t) {
    if (k == at) {
      t.current_a[2] = q<flight::CurrentA>(rover_test::d(t.current_a[2]) + add_a);
    }
  };
}

bool stops(SensorFaults& f, const Fault& fault, Handling handling, std::uint32_t& spike_cycles) {
  bool stopped = false;
  spike_cycles = 0U;
  f.run(Drive{}, fault, handling, 30U, [&](std::uint32_t, const RoverStepOutput& out) {
    stopped = stopped || (out.decision == flight::RoverDecision::stop_and_replan);
    spike_cycles += (channel(out, 2U) == SensorHealth::spike) ? 1U : 0U;
  });
  return stopped;
}

TEST_F(SensorFaults, OneSpikeNeverStopsTheRover) {
  std::uint32_t spikes = 0U;
  // N-of-M alone (the default trip_n = 3) absorbs one spike ...
  EXPECT_FALSE(stops(*this, spike_at(15U, 5.0), Handling::off, spikes));
  // ... and so does the spike check where N-of-M is set to one sample.
  table.monitor.trip_n = 1U;
  table.monitor.clear_n = 1U;
  EXPECT_FALSE(stops(*this, spike_at(15U, 5.0), Handling::on, spikes));
  EXPECT_EQ(spikes, 1U);
  // Both off: the spike stops the rover.
  EXPECT_TRUE(stops(*this, spike_at(15U, 5.0), Handling::off, spikes));
}

/// Largest change of any wheel's load from one cycle to the next, in N.
double largest_load_jump(SensorFaults& f, const Fault& fault, Handling handling, std::uint32_t& noisy_or_spike,
                         std::uint32_t& lost) {
  double largest = 0.0;
  double previous[flight::kWheelCount] = {};
  bool have_previous = false;
  noisy_or_spike = 0U;
  lost = 0U;
  f.run(Drive{}, fault, handling, 50U, [&](std::uint32_t, const RoverStepOutput& out) {
    const SensorHealth imu = channel(out, static_cast<std::uint32_t>(SensorChannel::imu));
    noisy_or_spike += ((imu == SensorHealth::noisy) || (imu == SensorHealth::spike)) ? 1U : 0U;
    lost += (out.status == RoverStepStatus::sensor_lost) ? 1U : 0U;
    if (!out.loads_valid) {
      have_previous = false;
      return;
    }
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      const double w = rover_test::d(out.load_n[i]);
      largest = have_previous ? std::fmax(largest, std::fabs(w - previous[i])) : largest;
      previous[i] = w;
    }
    have_previous = true;
  });
  return largest;
}

TEST_F(SensorFaults, ImuNoiseBurstIsBridgedThenLeavesTheRoverWithoutLoads) {
  // 4 s of +-8 deg alternating pitch noise from cycle 10.
  const Fault burst = [](std::uint32_t k, flight::RoverTelemetry& t) {
    if ((k >= 10U) && (k < 30U)) {
      const double sign = ((k % 2U) == 0U) ? 1.0 : -1.0;
      t.attitude.pitch_rad = q<flight::AngleRad>(sign * 0.14);
    }
  };
  std::uint32_t flagged = 0U;
  std::uint32_t lost = 0U;
  // The healthy drive's own cycle-to-cycle change (its 0.03 deg of noise).
  const double jump_healthy =
      largest_load_jump(*this, [](std::uint32_t, flight::RoverTelemetry&) {}, Handling::on, flagged, lost);
  EXPECT_EQ(flagged, 0U);
  const double jump_on = largest_load_jump(*this, burst, Handling::on, flagged, lost);
  EXPECT_EQ(flagged, 20U);
  // Bridged for bridge_ms (10 samples), then no loads until the burst ends.
  EXPECT_EQ(lost, 20U - table.health.bridge_ms / kPeriodMs);
  EXPECT_LE(jump_on, 1.5 * jump_healthy) << "the bridged loads keep the last good attitude";
  const double jump_off = largest_load_jump(*this, burst, Handling::off, flagged, lost);
  EXPECT_EQ(flagged, 0U);
  EXPECT_EQ(lost, 0U);
  EXPECT_GT(jump_off, 1.0) << "without the handling the noise reaches the loads";
}

TEST_F(SensorFaults, AfterANoiseBurstTheImuIsBelievedAgainWhereverTheRoverNowStands) {
  // During a 4 s burst the rover pitches 3 deg nose-up (it climbs on); after
  // the burst the attitude is calm but 3 deg from the last good one. Not a
  // bias step: two calm samples make the new reference.
  const Fault burst_and_climb = [](std::uint32_t k, flight::RoverTelemetry& t) {
    const double climb = (k >= 10U) ? std::fmin(0.0026 * static_cast<double>(k - 10U), 0.0524) : 0.0;
    t.attitude.pitch_rad = q<flight::AngleRad>(rover_test::d(t.attitude.pitch_rad) + climb);
    if ((k >= 10U) && (k < 30U)) {
      const double sign = ((k % 2U) == 0U) ? 1.0 : -1.0;
      t.attitude.pitch_rad = q<flight::AngleRad>(climb + sign * 0.14);
    }
  };
  constexpr std::uint32_t kImu = static_cast<std::uint32_t>(SensorChannel::imu);
  std::uint32_t usable_again_at = 0U;
  run(Drive{}, burst_and_climb, Handling::on, 50U, [&](std::uint32_t k, const RoverStepOutput& out) {
    if ((k >= 30U) && (usable_again_at == 0U) && flight::usable(channel(out, kImu))) {
      usable_again_at = k;
    }
  });
  EXPECT_EQ(usable_again_at, 31U) << "the first calm sample is a jump from the last noisy one";
}

TEST_F(SensorFaults, ImuBiasStepIsNamedBridgedThenFailsSafeUntilTheGroundAcceptsIt) {
  // Pitch 0.1 rad (5.7 deg) high from cycle 10 on: a spike, then a level the
  // rover cannot have reached in a sample (implausible), bridged for
  // bridge_ms, then no loads and STOP.
  const Fault bias = [](std::uint32_t k, flight::RoverTelemetry& t) {
    if (k >= 10U) {
      t.attitude.pitch_rad = q<flight::AngleRad>(rover_test::d(t.attitude.pitch_rad) + 0.1);
    }
  };
  constexpr std::uint32_t kImu = static_cast<std::uint32_t>(SensorChannel::imu);
  std::uint32_t implausible_at = 0U;
  std::uint32_t lost_at = 0U;
  std::uint32_t stopped_at = 0U;
  run(Drive{}, bias, Handling::on, 40U, [&](std::uint32_t k, const RoverStepOutput& out) {
    if (k == 10U) {
      EXPECT_EQ(channel(out, kImu), SensorHealth::spike);
    }
    implausible_at = ((implausible_at == 0U) && (channel(out, kImu) == SensorHealth::implausible)) ? k : implausible_at;
    lost_at = ((lost_at == 0U) && (out.status == RoverStepStatus::sensor_lost)) ? k : lost_at;
    stopped_at = ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) ? k : stopped_at;
  });
  EXPECT_EQ(implausible_at, 11U);
  EXPECT_EQ(lost_at, 10U + table.health.bridge_ms / kPeriodMs);
  EXPECT_EQ(stopped_at, lost_at + table.monitor.invalid_to_stop - 1U);
  // Off: the biased attitude goes into the loads unnoticed.
  std::uint32_t named_off = 0U;
  bool stopped_off = false;
  run(Drive{}, bias, Handling::off, 40U, [&](std::uint32_t, const RoverStepOutput& out) {
    named_off += (channel(out, kImu) != SensorHealth::ok) ? 1U : 0U;
    stopped_off = stopped_off || (out.decision == flight::RoverDecision::stop_and_replan);
  });
  EXPECT_EQ(named_off, 0U);
  EXPECT_FALSE(stopped_off);
}

TEST_F(SensorFaults, TheGroundsClearStopAcceptsABiasedAttitude) {
  flight::PreparedParameters prepared{};
  ASSERT_EQ(flight::prepare(table, rover, prepared), flight::PrepareStatus::ok);
  flight::RoverStep step;
  const Drive drive{};
  constexpr std::uint32_t kImu = static_cast<std::uint32_t>(SensorChannel::imu);
  RoverStepOutput out{};
  for (std::uint32_t k = 0U; k < 40U; ++k) {
    flight::RoverTelemetry t = drive.at(k);
    if (k >= 10U) {
      t.attitude.pitch_rad = q<flight::AngleRad>(rover_test::d(t.attitude.pitch_rad) + 0.1);
    }
    if (k == 30U) {
      step.clear_stop();  // the ground looked and accepts the new attitude
    }
    step.step(t, t.time, prepared, out);
    if (k >= 31U) {
      EXPECT_TRUE(flight::usable(channel(out, kImu))) << k;
      EXPECT_EQ(out.status, RoverStepStatus::ok) << k;
    }
  }
  EXPECT_EQ(out.decision, flight::RoverDecision::continue_drive);
}

TEST_F(SensorFaults, FrozenJointSensorIsStuckThenBridgedThenFailsSafe) {
  const Fault freeze = [](std::uint32_t k, flight::RoverTelemetry& t) {
    if (k >= 10U) {
      t.joints.bogie_rad[0] = q<flight::AngleRad>(0.01);
    }
  };
  std::uint32_t stuck_at = 0U;
  std::uint32_t lost_at = 0U;
  std::uint32_t stopped_at = 0U;
  run(Drive{}, freeze, Handling::on, 60U, [&](std::uint32_t k, const RoverStepOutput& out) {
    const SensorHealth joints = channel(out, static_cast<std::uint32_t>(SensorChannel::joints));
    stuck_at = ((stuck_at == 0U) && (joints == SensorHealth::stuck)) ? k : stuck_at;
    lost_at = ((lost_at == 0U) && (out.status == RoverStepStatus::sensor_lost)) ? k : lost_at;
    stopped_at = ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) ? k : stopped_at;
  });
  EXPECT_EQ(stuck_at, 10U + table.health.stuck_cycles);
  // The last good sample is the one before the detection.
  EXPECT_EQ(lost_at, stuck_at + table.health.bridge_ms / kPeriodMs);
  EXPECT_EQ(stopped_at, lost_at + table.monitor.invalid_to_stop - 1U);
  bool stopped_off = false;
  run(Drive{}, freeze, Handling::off, 60U, [&](std::uint32_t, const RoverStepOutput& out) {
    stopped_off = stopped_off || (out.decision == flight::RoverDecision::stop_and_replan);
  });
  EXPECT_FALSE(stopped_off) << "without the handling the loads rest on a frozen joint";
}

TEST_F(SensorFaults, StalledMotorAtTheSensorRangeIsNamedAndStopsByTheCurrentRule) {
  // The jump to the stall current is a spike in its first sample; from the
  // next on it is a new level: a current far above I_max, STOP evidence.
  const Fault stall = held_current(10U, 10.0);
  std::uint32_t implausible_at = 0U;
  std::uint32_t stopped_at = 0U;
  flight::StopReason reason = flight::StopReason::none;
  run(Drive{}, stall, Handling::on, 40U, [&](std::uint32_t k, const RoverStepOutput& out) {
    implausible_at =
        ((implausible_at == 0U) && (channel(out, kFaultWheel) == SensorHealth::implausible)) ? k : implausible_at;
    if ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) {
      stopped_at = k;
      reason = out.monitor.wheels[kFaultWheel].stop_reason;
    }
  });
  EXPECT_EQ(implausible_at, 11U + table.health.implausible_cycles - 1U);
  EXPECT_EQ(stopped_at, 11U + table.monitor.trip_n - 1U);
  EXPECT_EQ(reason, flight::StopReason::current);
  // Off: the current rule stops the rover as it did before issue 18, one
  // sample earlier (no spike check), and nobody names the motor.
  std::uint32_t named_off = 0U;
  std::uint32_t stopped_off = 0U;
  run(Drive{}, stall, Handling::off, 40U, [&](std::uint32_t k, const RoverStepOutput& out) {
    named_off += (channel(out, kFaultWheel) == SensorHealth::implausible) ? 1U : 0U;
    stopped_off = ((stopped_off == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) ? k : stopped_off;
  });
  EXPECT_EQ(named_off, 0U);
  EXPECT_EQ(stopped_off, 10U + table.monitor.trip_n - 1U);
}

TEST_F(SensorFaults, ClockRepeatsAndJumpsAreNamed) {
  // Cycles 10..21 repeat cycle 9's stamp (cycle 22 then comes 2.6 s after
  // the last fresh one: a gap); from 30 on the clock is 10 s ahead.
  const Fault clock = [](std::uint32_t k, flight::RoverTelemetry& t) {
    if ((k >= 10U) && (k < 22U)) {
      t.time = flight::TimeMs{10000U + kPeriodMs * 9U};
    }
    if (k >= 30U) {
      t.time = flight::TimeMs{t.time.ms + 10000U};
    }
  };
  constexpr std::uint32_t kClock = static_cast<std::uint32_t>(SensorChannel::clock);
  std::uint32_t stuck_at = 0U;
  std::uint32_t jumps[2] = {0U, 0U};
  std::uint32_t ok_after_jump = 0U;
  run(Drive{}, clock, Handling::on, 45U, [&](std::uint32_t k, const RoverStepOutput& out) {
    const SensorHealth h = channel(out, kClock);
    stuck_at = ((stuck_at == 0U) && (h == SensorHealth::stuck)) ? k : stuck_at;
    if (h == SensorHealth::spike) {
      jumps[(jumps[0] == 0U) ? 0U : 1U] = k;
    }
    ok_after_jump = ((k > 30U) && (ok_after_jump == 0U) && (h == SensorHealth::ok)) ? k : ok_after_jump;
  });
  EXPECT_EQ(stuck_at, 10U + table.health.stuck_cycles - 1U);
  EXPECT_EQ(jumps[0], 22U);
  EXPECT_EQ(jumps[1], 30U);
  EXPECT_EQ(ok_after_jump, 30U + table.health.recover_cycles);
  // Off: the repeats are refused as before issue 18, but never named stuck.
  std::uint32_t stuck_off = 0U;
  run(Drive{}, clock, Handling::off, 45U, [&](std::uint32_t, const RoverStepOutput& out) {
    stuck_off += (channel(out, kClock) == SensorHealth::stuck) ? 1U : 0U;
  });
  EXPECT_EQ(stuck_off, 0U);
}

TEST_F(SensorFaults, HealthyDriveReportsEveryChannelOk) {
  std::uint32_t not_ok = 0U;
  run(Drive{}, [](std::uint32_t, flight::RoverTelemetry&) {}, Handling::on, 200U,
      [&](std::uint32_t, const RoverStepOutput& out) {
        for (std::uint32_t c = 0U; c < flight::kSensorChannelCount; ++c) {
          not_ok += (out.health.channel[c] != SensorHealth::ok) ? 1U : 0U;
        }
        EXPECT_EQ(out.decision, flight::RoverDecision::continue_drive);
      });
  EXPECT_EQ(not_ok, 0U);
}

TEST_F(SensorFaults, ImuAndJointDropoutsAreBridgedThenFailSafeAndRecover) {
  for (const bool imu : {true, false}) {
    const Fault gone = [imu](std::uint32_t k, flight::RoverTelemetry& t) {
      if ((k >= 10U) && (k < 40U)) {
        (imu ? t.presence.attitude_missing : t.presence.joints_missing) = true;
      }
    };
    const std::uint32_t c = static_cast<std::uint32_t>(imu ? SensorChannel::imu : SensorChannel::joints);
    std::uint32_t bridged = 0U;
    std::uint32_t lost_at = 0U;
    std::uint32_t stopped_at = 0U;
    std::uint32_t ok_again_at = 0U;
    run(Drive{}, gone, Handling::on, 60U, [&](std::uint32_t k, const RoverStepOutput& out) {
      if ((k >= 10U) && (k < 40U)) {
        EXPECT_EQ(channel(out, c), SensorHealth::missing) << k;
      }
      bridged += (imu ? out.health.attitude_bridged : out.health.joints_bridged) ? 1U : 0U;
      lost_at = ((lost_at == 0U) && (out.status == RoverStepStatus::sensor_lost)) ? k : lost_at;
      stopped_at = ((stopped_at == 0U) && (out.decision == flight::RoverDecision::stop_and_replan)) ? k : stopped_at;
      ok_again_at = ((k >= 40U) && (ok_again_at == 0U) && (channel(out, c) == SensorHealth::ok)) ? k : ok_again_at;
    });
    // The last good sample is cycle 9: bridged while at most bridge_ms old
    // (cycles 10..19), then lost.
    EXPECT_EQ(bridged, table.health.bridge_ms / kPeriodMs) << imu;
    EXPECT_EQ(lost_at, 10U + table.health.bridge_ms / kPeriodMs) << imu;
    EXPECT_EQ(stopped_at, lost_at + table.monitor.invalid_to_stop - 1U) << imu;
    EXPECT_EQ(ok_again_at, 40U + table.health.recover_cycles - 1U) << imu;
  }
}

TEST(SensorHealthMonitor, BeforeTheFirstSampleEveryChannelIsMissing) {
  const flight::SensorHealthReport r{};
  for (const SensorHealth h : r.channel) {
    EXPECT_EQ(h, SensorHealth::missing);
  }
  for (const bool usable : r.current_usable) {
    EXPECT_FALSE(usable);
  }
  EXPECT_FALSE(r.attitude_usable);
  EXPECT_FALSE(r.joints_usable);
}

TEST(SensorHealthMonitor, CountersSaturateAndCountEveryHealth) {
  flight::SensorHealthMonitor m;
  flight::HealthParams p{};
  p.stuck_cycles = 2U;
  for (int k = 0; k < 5; ++k) {
    static_cast<void>(m.clock_refused(true, p));
  }
  static_cast<void>(m.clock_refused(false, p));
  const flight::SensorHealthCounters& c = m.counters();
  constexpr std::uint32_t kClock = static_cast<std::uint32_t>(SensorChannel::clock);
  EXPECT_EQ(c.by_health[kClock][static_cast<std::uint32_t>(SensorHealth::stuck)], 4U);
  EXPECT_EQ(c.by_health[kClock][static_cast<std::uint32_t>(SensorHealth::spike)], 1U);
}

TEST(SensorHealthNames, EveryChannelAndHealthHasItsNameAndNothingElseDoes) {
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_lf), "LF_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_lm), "LM_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_lr), "LR_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_rf), "RF_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_rm), "RM_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::current_rr), "RR_current");
  EXPECT_STREQ(flight::channel_name(SensorChannel::imu), "imu");
  EXPECT_STREQ(flight::channel_name(SensorChannel::joints), "joints");
  EXPECT_STREQ(flight::channel_name(SensorChannel::clock), "clock");
  EXPECT_STREQ(flight::channel_name(static_cast<SensorChannel>(flight::kSensorChannelCount)), "unknown");
  EXPECT_STREQ(flight::health_name(SensorHealth::ok), "ok");
  EXPECT_STREQ(flight::health_name(SensorHealth::missing), "missing");
  EXPECT_STREQ(flight::health_name(SensorHealth::stuck), "stuck");
  EXPECT_STREQ(flight::health_name(SensorHealth::spike), "spike");
  EXPECT_STREQ(flight::health_name(SensorHealth::noisy), "noisy");
  EXPECT_STREQ(flight::health_name(SensorHealth::implausible), "implausible");
  EXPECT_STREQ(flight::health_name(SensorHealth::recovering), "recovering");
  EXPECT_STREQ(flight::health_name(static_cast<SensorHealth>(flight::kSensorHealthCount)), "unknown");
}

}  // namespace
}  // namespace sinkwatch
