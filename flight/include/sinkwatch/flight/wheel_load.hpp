// wheel_load.hpp: each wheel's normal load W from a quasi-static model of a
// six-wheel rocker-bogie rover with a differential (Yutu's suspension).
//
// The paper's Eq. 15 needs W per wheel, and section 7 says it comes from "the
// vehicle's kinematic and dynamic model and a force analysis". A rocker-bogie
// with a differential is statically determinate; docs/rover-loads.md derives
// the solution this function evaluates:
//
//   contact points  from the link geometry and the rocker/bogie angles;
//   projection      x~ = x - z tan(pitch)/cos(roll), y~ = y - z tan(roll)
//                   (contact forces parallel to gravity, section 2);
//   differential    M = m g x~_com / 2 about each rocker pivot;
//   roll balance    S_left = (m g y~_com - M (Z_L + Z_R) - m g Y_R) / (Y_L - Y_R);
//   rocker          F_front = (M + b S) / (a + b), F_bogie = S - F_front;
//   bogie           F_middle = beta F_bogie, F_rear = F_bogie - F_middle;
//   normal load     W_i = F_i cos(pitch) cos(roll).
//
// The six loads sum to m g cos(pitch) cos(roll). An attitude at which any
// wheel would need a negative load is beyond the stability (tip-over or
// wheel-lift) limit: the result is a status, never a number.
//
// Fixed point: trigonometry from fx (Q1.30, within 1 LSB), every intermediate
// in Q31.32, loads rounded once to Q15.16. docs/rover-loads.md, section 7,
// bounds the error; props/rover/prop_wheel_load.cpp asserts the bound against
// the double-precision twin (ground/reference rover_loads.hpp).
#ifndef SINKWATCH_FLIGHT_WHEEL_LOAD_HPP
#define SINKWATCH_FLIGHT_WHEEL_LOAD_HPP

#include <cstdint>

#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace flight {

/// IMU attitude. Pitch positive nose up, roll positive right side down.
struct RoverAttitude {
  AngleRad pitch_rad;
  AngleRad roll_rad;
};

/// Suspension joint angles, index 0 = left, 1 = right. Rocker relative to the
/// body, bogie relative to its rocker; positive raises the link's front end.
struct JointAnglesRad {
  AngleRad rocker_rad[kSideCount];
  AngleRad bogie_rad[kSideCount];
};

enum class WheelLoadStatus : std::uint8_t {
  ok = 0U,
  invalid_params = 1U,         ///< validate_rover_params() failed
  attitude_out_of_range = 2U,  ///< |pitch| or |roll| beyond the attitude limit
  joint_out_of_range = 3U,     ///< a joint angle beyond its limit
  degenerate = 4U,             ///< a projected lever shorter than 1 mm
  tip_over = 5U,               ///< a wheel would need a negative load
  overflow = 6U,               ///< an intermediate left its format
};

struct WheelLoadResult {
  WheelLoadN load_n[kWheelCount];  ///< all zero unless status == ok
  WheelLoadN weight_normal_n;      ///< m g cos(pitch) cos(roll), zero unless ok
  /// With tip_over: the wheel with the most negative load (the one lifting);
  /// else kWheelCount.
  std::uint32_t lifting_wheel{kWheelCount};
  /// The pitch the loads were computed at and its sine (fx::sin's bits), both
  /// zero unless ok: drawbar_pulls() takes the sine from here when its own
  /// pitch is this one, so sin(pitch) is computed once per cycle. Set them
  /// together or not at all.
  AngleRad pitch_rad;
  fx::Q1_30 sin_pitch;
  WheelLoadStatus status{WheelLoadStatus::invalid_params};  ///< a default result is never usable
};

/// The quasi-static wheel loads; bounded, no allocation, every input checked.
[[nodiscard]] WheelLoadResult wheel_loads(const RoverParams& params, const RoverAttitude& attitude,
                                          const JointAnglesRad& joints) noexcept;

/// The same for parameters checked once per load (prepared_params.hpp):
/// invalid_params unless prepared.ready(), and no validation per call.
[[nodiscard]] WheelLoadResult wheel_loads(const PreparedParameters& prepared, const RoverAttitude& attitude,
                                          const JointAnglesRad& joints) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_WHEEL_LOAD_HPP
