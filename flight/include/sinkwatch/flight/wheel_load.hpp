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
//   drive torques   each wheel's tangential soil force is its share of the
//                   slope's pull, split by load (the drawbar-pull split), and
//                   its motor's torque T_i acts on its link as the couple
//                   -T_i; a wheel with a usable torque is projected from its
//                   axle and adds t_i = T_i / (cos(pitch) cos(roll)) to the
//                   moments, a wheel without one keeps the free-rolling couple
//                   (T = r F, the old statics: projected from its contact);
//   differential    M = m g x~_com / 2 about each rocker pivot;
//   roll balance    S_left = (m g y~_com - sum_s ((M - t_f,s) Z_s + q_s) - m g Y_R) / (Y_L - Y_R),
//                   q_s = (t_m + t_r)/span_s (y~_rear - y~_middle);
//   rocker          F_front = (M - t_front + b S) / (a + b), F_bogie = S - F_front;
//   bogie           F_middle = beta F_bogie - (t_m + t_r)/span, F_rear = F_bogie - F_middle;
//   normal load     W_i = F_i cos(pitch) cos(roll).
//
// docs/rover-loads.md, section 12 ("Drive torques in the flight statics"),
// derives this from the six equations of section 11.2.
//
// The six loads sum to m g cos(pitch) cos(roll). An attitude at which any
// wheel would need a negative load is beyond the stability (tip-over or
// wheel-lift) limit: the result is a status, never a number.
//
// Fixed point: trigonometry from fx (Q1.30, within 1 LSB); the balances in
// 32-bit Q6.25 with every force a share of the normal weight (so no 128-bit
// arithmetic and one format for every rover mass), quotients by a lever as
// products with its normalised reciprocal (fx/reciprocal.hpp), loads rounded
// once to Q15.16. A quotient by a lever of a few millimetres, far beyond the
// stability limit, can leave Q6.25: that evaluation is repeated in Q10.21 and
// then Q15.16 to decide the tip-over. docs/rover-loads.md, section 7.4,
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

/// Each wheel's drive torque from its motor current (torque_from_current,
/// positive driving the rover forward) and whether it may be used. A wheel
/// whose current is invalid or faulty is given `usable = false`: the statics
/// then take its couple as the free-rolling one (torque = radius x its share
/// of the pull, the statics without torques) and report it in
/// WheelLoadResult::torque_fallback_mask, never silently.
struct DriveTorques {
  TorqueNm torque_nm[kWheelCount];
  bool usable[kWheelCount]{};
};

/// WheelLoadResult::torque_fallback_mask when every wheel falls back.
inline constexpr std::uint8_t kEveryTorqueFallsBack{0x3FU};
static_assert(kEveryTorqueFallsBack == ((1U << kWheelCount) - 1U), "one bit per wheel");

/// No torque known for any wheel (every wheel falls back: kEveryTorqueFallsBack).
inline constexpr DriveTorques kNoDriveTorques{};

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
  /// Bit i set: wheel i's torque was not usable and the free-rolling couple
  /// was taken instead. Set whatever the status.
  std::uint8_t torque_fallback_mask{0U};
  /// The torques would lift a wheel that the weight alone keeps down: more
  /// than the links react quasi-statically (a stalled or spinning wheel). The
  /// loads are then those without torques (kEveryTorqueFallsBack); stability is decided
  /// by the weight alone (docs/rover-loads.md, section 12.4).
  bool torque_overload{false};
  WheelLoadStatus status{WheelLoadStatus::invalid_params};  ///< a default result is never usable
};

/// The quasi-static wheel loads with the drive torques' reactions; bounded,
/// no allocation, every input checked. The rover parameters are checked once
/// per load (prepare(), prepared_params.hpp): invalid_params unless
/// prepared.ready(), and no validation per call.
[[nodiscard]] WheelLoadResult wheel_loads(const PreparedParameters& prepared, const RoverAttitude& attitude,
                                          const JointAnglesRad& joints, const DriveTorques& torques) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_WHEEL_LOAD_HPP
