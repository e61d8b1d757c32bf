// libFuzzer harness: the flight per-cycle step (rover_step.hpp,
// RoverStep::step) fed arbitrary telemetry over many cycles.
//
// Input: one setup byte (bit 0: Eq. 15 table instead of the default; bits
// 1..2: gravity Moon, Mars, Earth, Moon), then one 75-byte record per cycle
// (a short last record is dropped):
//   u8 flags   bit 0 valid, 1 accel_valid, 2 speed_valid, 3 rim_speed_valid,
//              4 clear_stop() before the step, 5 physical mode,
//              6 attitude missing, 7 joints missing
//   u32 dt_ms  sample time = previous sample time + dt (wraps)
//   u32 lag_ms now = sample time + lag (wraps: a sample "from the future")
//   6 x i32 current (raw Q11.20), 6 x u8 direction (any byte; bit 7 also
//              marks that wheel's current missing, a dropout),
//   6 x i32 angle (raw Q3.28: pitch, roll, rocker L/R, bogie L/R),
//   3 x i32 acceleration, speed, rim speed (raw Q7.24).
// Raw mode passes every number as it is, so the range checks are fuzzed;
// physical mode shifts each number into a plausible range (and the
// direction to forward/reverse, the lag to under a second), so the estimator,
// the limits and the state machine are reached and driven through their
// transitions.
//
// Asserted every cycle (the ranges the headers document), besides "no crash,
// no sanitizer finding": every enum value is one of its enumerators; a valid
// estimate and limit only with an ok sample; loads non-negative when valid;
// pulls within +-DP_max <= 2 W when valid; slip in [-1, 1]; acceleration
// within kMaxAbsAccel; an unusable cycle reaches the monitor as an unusable
// sample; STOP latched until clear_stop(); the wheel counts and the decision
// agree with the wheel states (and the blind wheels, under the table's loss
// policy); every health value is an enumerator; a wheel whose current channel
// is unusable has no estimate; no wheel without usable evidence is NOMINAL
// while another is in CAUTION or STOP.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"

namespace sf = sinkwatch::flight;

namespace {

constexpr std::size_t kRecordBytes = 1U + 4U + 4U + (6U * 4U) + 6U + (6U * 4U) + (3U * 4U);
constexpr std::size_t kMaxCycles = 512U;  // keeps one input under a few ms

/// Aborts (a finding) naming the harness line whose assertion failed.
void check(bool condition, int line = __builtin_LINE()) {
  if (!condition) {
    std::fprintf(stderr, "fuzz_rover_step.cpp:%d: assertion failed\n", line);
    std::abort();
  }
}

class Reader {
 public:
  explicit Reader(const std::uint8_t* p) : p_(p) {}
  std::uint8_t u8() { return *p_++; }
  std::uint32_t u32() {
    std::uint32_t v = 0U;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(*p_++) << (8 * i);
    }
    return v;
  }
  std::int32_t i32(bool physical, int shift) {
    const auto v = static_cast<std::int32_t>(u32());
    return physical ? (v >> shift) : v;
  }

 private:
  const std::uint8_t* p_;
};

template <typename E>
std::uint32_t u(E e) {
  return static_cast<std::uint32_t>(e);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1U) {
    return 0;
  }
  const std::uint8_t setup = data[0];
  const sf::ParameterTable table =
      ((setup & 1U) != 0U) ? sf::eq15_parameter_table() : sf::default_parameter_table();
  const sf::AccelMps2 gravities[4] = {sf::kGravityMoon, sf::kGravityMars, sf::kGravityEarth, sf::kGravityMoon};
  const sf::RoverParams rover = sf::yutu_like_rover_params(gravities[(setup >> 1U) & 3U]);
  check(sf::validate(table) == sf::RejectReason::ok);
  check(sf::validate_rover_params(rover) == sf::RoverParamStatus::ok);
  // Prepared once, as the C interface does on a table load.
  sf::PreparedParameters prepared;
  check(sf::prepare(table, rover, prepared) == sf::PrepareStatus::ok);
  const std::uint8_t wheel_count = table.monitor.wheel_count;
  const std::uint8_t stop_k = (table.monitor.rover_stop_k == 0U) ? 1U : table.monitor.rover_stop_k;
  const sf::Ratio one_ratio = sf::Ratio::from_raw(std::int32_t{1} << 24);

  sf::RoverStep step;
  sf::WheelState previous[sf::kMaxWheels] = {};
  std::uint32_t time_ms = 0U;
  const std::size_t cycles = (size - 1U) / kRecordBytes;
  for (std::size_t c = 0U; c < cycles && c < kMaxCycles; ++c) {
    Reader r(data + 1U + (c * kRecordBytes));
    const std::uint8_t flags = r.u8();
    const bool physical = (flags & 32U) != 0U;
    sf::RoverTelemetry t{};
    t.valid = (flags & 1U) != 0U;
    t.accel_valid = (flags & 2U) != 0U;
    t.speed_valid = (flags & 4U) != 0U;
    t.rim_speed_valid = (flags & 8U) != 0U;
    const bool clear = (flags & 16U) != 0U;
    time_ms += r.u32();
    std::uint32_t lag = r.u32();
    if (physical) {
      lag &= 0x3FFU;
    }
    t.time = sf::TimeMs{time_ms};
    const sf::TimeMs now{time_ms + lag};
    for (sf::CurrentA& i : t.current_a) {
      i = sf::CurrentA::from_raw(r.i32(physical, 8));  // +-8 A (sensor range 10 A)
    }
    for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
      const std::uint8_t b = r.u8();
      t.direction[i] = static_cast<sf::DriveDirection>(physical ? (b & 1U) : b);
      t.presence.current_missing[i] = (b & 0x80U) != 0U;
    }
    t.presence.attitude_missing = (flags & 64U) != 0U;
    t.presence.joints_missing = (flags & 128U) != 0U;
    t.attitude.pitch_rad = sf::AngleRad::from_raw(r.i32(physical, 4));  // +-0.5 rad
    t.attitude.roll_rad = sf::AngleRad::from_raw(r.i32(physical, 4));
    for (std::uint32_t s = 0U; s < sf::kSideCount; ++s) {
      t.joints.rocker_rad[s] = sf::AngleRad::from_raw(r.i32(physical, 4));
    }
    for (std::uint32_t s = 0U; s < sf::kSideCount; ++s) {
      t.joints.bogie_rad[s] = sf::AngleRad::from_raw(r.i32(physical, 4));
    }
    t.accel_mps2 = sf::AccelMps2::from_raw(r.i32(physical, 8));     // +-0.5 m/s^2
    t.speed_mps = sf::SpeedMps::from_raw(r.i32(physical, 12));      // +-0.03 m/s
    t.rim_speed_mps = sf::SpeedMps::from_raw(r.i32(physical, 12));

    if (clear) {
      step.clear_stop();
      for (sf::WheelState& s : previous) {
        s = sf::WheelState::nominal;
      }
    }
    sf::RoverStepOutput o{};
    step.step(t, now, prepared, o);

    // Enumerations hold enumerators.
    check(u(o.status) <= u(sf::RoverStepStatus::sensor_lost));
    for (std::uint32_t c = 0U; c < sf::kSensorChannelCount; ++c) {
      check(u(o.health.channel[c]) < sf::kSensorHealthCount);
    }
    for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
      check(o.health.current_usable[i] == sf::usable(o.health.channel[i]));
    }
    check(u(o.load_status) <= u(sf::WheelLoadStatus::overflow));
    check(u(o.drawbar_status) <= u(sf::DrawbarStatus::overflow));
    check(u(o.decision) <= u(sf::RoverDecision::stop_and_replan));
    check(u(o.monitor.decision) <= u(sf::RoverDecision::stop_and_replan));
    check(o.status != sf::RoverStepStatus::invalid_table);         // the table is valid
    check(o.status != sf::RoverStepStatus::invalid_rover_params);  // and so are the params
    check(o.status != sf::RoverStepStatus::radius_mismatch);       // both say r = 0.15 m

    // What a valid flag promises.
    if (o.status == sf::RoverStepStatus::ok) {
      check(o.loads_valid && o.drawbar_valid && o.accel_valid);
    }
    if (o.loads_valid) {
      check(o.load_status == sf::WheelLoadStatus::ok);
      for (const sf::WheelLoadN& w : o.load_n) {
        check(w.raw() >= 0);
      }
    }
    if (o.drawbar_valid) {
      check(o.loads_valid && sf::usable(o.drawbar_status));
      for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
        // |DP| <= DP_max = (DP_max/W) W <= 2 W, plus rounding of the product.
        const std::int64_t limit = (2 * static_cast<std::int64_t>(o.load_n[i].raw())) + 4;
        const std::int64_t dp = o.drawbar_pull_n[i].raw();
        check(dp <= limit && -dp <= limit);
      }
    }
    if (o.accel_valid) {
      check(o.accel_mps2 <= sf::kMaxAbsAccel && o.accel_mps2.raw() >= -sf::kMaxAbsAccel.raw());
    }
    if (o.slip_known) {
      check(o.slip <= one_ratio && o.slip.raw() >= -one_ratio.raw());
    }
    if (o.status == sf::RoverStepStatus::tip_over) {
      check(o.lifting_wheel < sf::kWheelCount);
      check(o.decision == sf::RoverDecision::stop_and_replan);
    } else {
      check(o.lifting_wheel == sf::kWheelCount);
    }

    // Per wheel.
    std::uint8_t in_stop = 0U;
    std::uint8_t in_caution = 0U;
    for (std::uint8_t i = 0U; i < wheel_count; ++i) {
      const sf::WheelOutput& w = o.monitor.wheels[i];
      check(u(w.state) <= u(sf::WheelState::stop));
      check(u(w.sample_status) < sf::kSampleStatusCount);
      check(u(w.stop_reason) <= u(sf::StopReason::slip));
      check(u(w.clamp) <= u(sf::LoadClamp::above_last));
      const bool sample_ok = w.sample_status == sf::SampleStatus::ok;
      check(w.estimate_valid == sample_ok);
      check(w.limit_valid == sample_ok);
      if (w.limit_valid) {
        check(w.current_limit_a.raw() >= 0);  // |I_max|
      } else {
        check(w.current_limit_a.raw() == 0);
      }
      if (!w.estimate_valid) {
        check(w.sinkage_m.raw() == 0 && w.torque_nm.raw() == 0);
      }
      // A wheel without a usable current has no number of its own.
      if ((o.status == sf::RoverStepStatus::ok) && !o.health.current_usable[i]) {
        check(!sample_ok);
      }
      // A cycle the step could not use reaches the monitor as unusable.
      if (o.status == sf::RoverStepStatus::telemetry_stale) {
        check(w.sample_status == sf::SampleStatus::stale);
      } else if (o.status != sf::RoverStepStatus::ok) {
        check(w.sample_status == sf::SampleStatus::flagged_invalid);
      }
      check((w.state == sf::WheelState::stop) == (w.stop_reason != sf::StopReason::none));
      if (previous[i] == sf::WheelState::stop) {
        check(w.state == sf::WheelState::stop);  // latched
        check(!w.stop_tripped);
      }
      if (w.stop_tripped) {
        check(w.state == sf::WheelState::stop && step.monitor().wheel(i).has_event());
        check(step.monitor().wheel(i).last_event().wheel == i);
      }
      previous[i] = w.state;
      in_stop = static_cast<std::uint8_t>(in_stop + (w.state == sf::WheelState::stop ? 1U : 0U));
      in_caution = static_cast<std::uint8_t>(in_caution + (w.state == sf::WheelState::caution ? 1U : 0U));
    }
    check(o.monitor.wheels_in_stop == in_stop);
    check(o.monitor.wheels_in_caution == in_caution);
    std::uint8_t blind = 0U;
    for (std::uint8_t i = 0U; i < wheel_count; ++i) {
      const sf::WheelOutput& w = o.monitor.wheels[i];
      blind = static_cast<std::uint8_t>(blind + ((w.sample_status == sf::SampleStatus::sensor_fault) ? 1U : 0U));
      if ((in_stop + in_caution) > 0U) {
        check((w.sample_status == sf::SampleStatus::ok) || (w.state != sf::WheelState::nominal));
      }
    }
    check(o.monitor.wheels_blind == blind);
    const bool too_blind =
        (table.health.policy == sf::LossPolicy::continue_degraded) && (blind > table.health.max_blind_wheels);
    check((o.monitor.decision == sf::RoverDecision::stop_and_replan) == ((in_stop >= stop_k) || too_blind));
    // The rover stops on the wheels' decision, tip-over, or the
    // motion-resistance check in STOP (traction.hpp), and on nothing else.
    const bool traction_stop = o.traction.state == sf::TractionState::stop;
    check(u(o.traction.state) <= u(sf::TractionState::stop));
    if (o.status != sf::RoverStepStatus::invalid_table) {
      check((o.traction.state == sf::TractionState::off) == !sf::traction_check_on(table.traction));
    }
    if (o.status != sf::RoverStepStatus::tip_over) {
      check((o.decision == sf::RoverDecision::stop_and_replan) ==
            ((o.monitor.decision == sf::RoverDecision::stop_and_replan) || traction_stop));
    }
  }
  return 0;
}
