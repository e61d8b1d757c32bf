// The inputs of the rover golden vectors: a fixed, deterministic set of
// wheel-load and drawbar-pull cases (integer raw values only, so that the
// inputs are the same bits on every target). The expected output bits are in
// rover_golden.inc, written by make_rover_golden on the host; test_rover_golden
// checks them on the host and, under qemu, on 32-bit ARM.
#ifndef SINKWATCH_HOST_TESTS_ROVER_GOLDEN_CASES_HPP
#define SINKWATCH_HOST_TESTS_ROVER_GOLDEN_CASES_HPP

#include <cstdint>

#include "prepared_support.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace rover_golden {

constexpr std::uint32_t kCaseCount = 72U;
/// Cases from here on carry drive torques (the first 48 keep their inputs
/// and bits from before the statics took torques: none).
constexpr std::uint32_t kFirstTorqueCase = 48U;

struct Case {
  flight::RoverParams params;
  flight::RoverAttitude attitude;
  flight::JointAnglesRad joints;
  flight::DrawbarInput drawbar;
  flight::DriveTorques torques;
};

/// A small linear congruential generator: the same sequence everywhere.
inline std::uint32_t next(std::uint32_t& state) {
  state = state * 1664525U + 1013904223U;
  return state >> 8U;  // 24 bits
}

/// A raw value uniformly in [-limit, limit] (limit < 2^30).
inline std::int32_t spread(std::uint32_t& state, std::int32_t limit) {
  const std::uint32_t u = next(state);  // [0, 2^24)
  const std::int64_t span = 2 * static_cast<std::int64_t>(limit) + 1;
  return static_cast<std::int32_t>((static_cast<std::int64_t>(u) * span >> 24) - limit);
}

inline Case make_case(std::uint32_t index) {
  std::uint32_t state = 0x5EEDU + 7919U * index;
  const flight::AccelMps2 gravities[3] = {flight::kGravityMoon, flight::kGravityMars, flight::kGravityEarth};
  Case c{};
  c.params = flight::yutu_like_rover_params(gravities[index % 3U]);
  c.params.com_x_m = flight::LengthM::from_raw(spread(state, 1 << 19));  // +-3 cm
  c.params.com_y_m = flight::LengthM::from_raw(spread(state, 1 << 19));
  // Attitudes to +-0.75 rad: a part of the cases is beyond the stability limit.
  const std::int32_t att_limit = (3 << 28) / 4;
  c.attitude.pitch_rad = flight::AngleRad::from_raw(spread(state, att_limit));
  c.attitude.roll_rad = flight::AngleRad::from_raw(spread(state, att_limit));
  for (std::uint32_t s = 0U; s < flight::kSideCount; ++s) {
    c.joints.rocker_rad[s] = flight::AngleRad::from_raw(spread(state, c.params.rocker_limit_rad.raw()));
    c.joints.bogie_rad[s] = flight::AngleRad::from_raw(spread(state, c.params.bogie_limit_rad.raw()));
  }
  c.drawbar.accel_mps2 = flight::AccelMps2::from_raw(spread(state, 1 << 23));  // +-0.5 m/s^2
  c.drawbar.pitch_rad = c.attitude.pitch_rad;
  c.drawbar.slip_known = (index % 4U) == 0U;
  c.drawbar.slip = flight::Ratio::from_raw(spread(state, 1 << 24));
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    c.drawbar.dp_max_ratio[i] = flight::Ratio::from_raw((1 << 22) + static_cast<std::int32_t>(next(state) >> 1));
  }
  // Drawn last, so that the earlier cases' inputs do not move: each wheel's
  // torque usable with probability 5/6, within +-20 N m (beyond traction on
  // the Moon: the overload fallback is among the cases).
  if (index >= kFirstTorqueCase) {
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      c.torques.usable[i] = (next(state) % 6U) != 0U;
      c.torques.torque_nm[i] = flight::TorqueNm::from_raw(c.torques.usable[i] ? spread(state, 20 << 16) : 0);
    }
  }
  return c;
}

/// The output bits of one case.
struct Expected {
  std::uint8_t load_status;
  std::uint32_t lifting_wheel;
  std::int32_t load_raw[flight::kWheelCount];
  std::int32_t weight_normal_raw;
  std::uint8_t drawbar_status;
  std::uint8_t capped_mask;
  std::int32_t total_raw;
  std::int32_t dp_raw[flight::kWheelCount];
};

inline Expected evaluate(const Case& c) {
  const flight::WheelLoadResult loads = flight::wheel_loads(test::prepared_rover(c.params), c.attitude, c.joints, c.torques);
  const flight::DrawbarResult dp = flight::drawbar_pulls(test::prepared_rover(c.params), loads, c.drawbar);
  Expected e{};
  e.load_status = static_cast<std::uint8_t>(loads.status);
  e.lifting_wheel = loads.lifting_wheel;
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    e.load_raw[i] = static_cast<std::int32_t>(loads.load_n[i].raw());
    e.dp_raw[i] = static_cast<std::int32_t>(dp.dp_n[i].raw());
  }
  e.weight_normal_raw = static_cast<std::int32_t>(loads.weight_normal_n.raw());
  e.drawbar_status = static_cast<std::uint8_t>(dp.status);
  e.capped_mask = dp.capped_mask;
  e.total_raw = static_cast<std::int32_t>(dp.total_n.raw());
  return e;
}

}  // namespace rover_golden
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_ROVER_GOLDEN_CASES_HPP
