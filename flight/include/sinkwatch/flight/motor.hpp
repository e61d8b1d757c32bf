// motor.hpp: drive torque from motor current and back (the paper's key
// technology 3, "the relationship between motor current and driving torque").
//
//     T = N * eta * Kt * (I - d * I0),   d = +1 forward, -1 reverse
//
// N is the gear ratio, eta the gear efficiency, Kt the motor's torque
// constant, I0 the no-load current. I0 is the current the motor draws to
// overcome its own friction, which opposes the direction of rotation: driving
// forward it is subtracted from a positive current, in reverse it is added to
// a negative one, so the torque keeps its sign convention (positive drives the
// rover forward) in both directions. The model is the motoring quadrant: when
// the wheel is back-driven (|I| < I0) the friction term dominates and the
// returned torque is the linear model's value, which docs/flight.md flags as
// outside the calibrated range.
//
// The current is valid when |I| <= the sensor's range (the parameter table's
// current_abs_max); beyond it the sensor is saturated and no torque is given.
#ifndef SINKWATCH_FLIGHT_MOTOR_HPP
#define SINKWATCH_FLIGHT_MOTOR_HPP

#include <cstdint>

#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"

namespace sinkwatch {
namespace flight {

/// One drive motor and its gearbox (all six wheels share the type).
struct MotorParams {
  GearRatio gear_ratio;              ///< N, motor turns per wheel turn (torque multiplier)
  Efficiency efficiency;             ///< eta in (0, 1]
  TorqueConstantNmPerA kt_nm_per_a;  ///< Kt at the motor shaft
  CurrentA no_load_current_a;        ///< I0 >= 0
  CurrentA current_abs_max_a;        ///< valid range of the current sensor, > I0
};

struct TorqueResult {
  TorqueNm torque_nm;  ///< zero unless status == ok
  EstimateStatus status{EstimateStatus::ok};
};

struct CurrentResult {
  CurrentA current_a;  ///< zero unless status == ok
  EstimateStatus status{EstimateStatus::ok};
};

/// The wheel torque for the measured current and the commanded direction.
[[nodiscard]] TorqueResult torque_from_current(const MotorParams& motor, CurrentA current_a,
                                               DriveDirection direction) noexcept;

struct DriveTorques;  // wheel_load.hpp (which includes this header)

namespace detail {

/// torque_from_current() of each wheel, current_a[i] and direction[i] into
/// torque[i], for a motor check_motor() accepts (the validated table's: no
/// check per wheel). The per-cycle step computes its six torques in one
/// call, written in place: no result record returned through memory and
/// copied per wheel (round 14). Defined for N = 1 (torque_of_valid_motor,
/// of_valid.hpp, is its one-element case) and N = limits::kWheelCount.
template <std::uint32_t N>
void torques_of_valid_motor(const MotorParams& motor, const CurrentA (&current_a)[N],
                            const DriveDirection (&direction)[N], TorqueResult (&torque)[N]) noexcept;

extern template void torques_of_valid_motor<1U>(const MotorParams& motor, const CurrentA (&current_a)[1U],
                                                const DriveDirection (&direction)[1U],
                                                TorqueResult (&torque)[1U]) noexcept;
extern template void torques_of_valid_motor<limits::kWheelCount>(
    const MotorParams& motor, const CurrentA (&current_a)[limits::kWheelCount],
    const DriveDirection (&direction)[limits::kWheelCount], TorqueResult (&torque)[limits::kWheelCount]) noexcept;

/// torques_of_valid_motor<kWheelCount>'s bits for a motor validate()
/// accepted (the per-cycle step's, rover_step.cpp): without its tests that
/// such a motor cannot fail (I -+ I0 leaving Q11.20; a torque beyond
/// Q15.16 other than +2^31 raw), motor.cpp says why. In the same loop, the
/// torques the wheel loads may use: wheel i's is usable when
/// current_usable[i] (the health monitor passed its current) and its
/// torque is ok (drive.usable[i]); drive.torque_nm[i] is then that torque,
/// else zero (round 17: a second loop over the stored results before; one
/// record for both arrays, one pointer fewer in the loop).
void torques_of_validated_motor(const MotorParams& motor, const CurrentA (&current_a)[limits::kWheelCount],
                                const DriveDirection (&direction)[limits::kWheelCount],
                                const bool (&current_usable)[limits::kWheelCount],
                                TorqueResult (&torque)[limits::kWheelCount], DriveTorques& drive) noexcept;

}  // namespace detail

/// The motor's gain N eta Kt prepared once per parameter load as its
/// normalised reciprocal (fixedpoint/reciprocal.hpp): current_from_torque is
/// then one 32 x 32 -> 64-bit product per call instead of three divisions
/// (issue 15; docs/flight.md, "Current from torque").
struct MotorDivisors {
  fx::NormalisedReciprocal inverse_gain;  ///< 1 / (N eta Kt), within 2^-29 relative
  /// The torque-to-current shift s = 16 + scale - 20 of inverse_gain as
  /// its rounding constant 2^(s-1) and four counts in [0, 31], prepared for
  /// detail::current_raw_from_validated_torque (round 17): (sum >> s) on
  /// 32-bit words is low' = ((low >> a) >> b) | ((high << c) >> d) and
  /// high' = (high >> a) >> b, with (a, b, c, d) = (s, 0, 32 - s, 0) for s
  /// below 32 and (31, 1, 0, s - 32) from 32 on: no 64-bit shift by a
  /// run-time count and no case per call. All 0 where s is outside [1, 63]
  /// (validate() accepts no such motor: s lies in [8, 43]).
  std::uint64_t current_rounding_raw{0U};
  std::uint32_t current_low_shift{0U};    ///< a
  std::uint32_t current_clear_shift{0U};  ///< b
  std::uint32_t current_join_shift{0U};   ///< c
  std::uint32_t current_high_shift{0U};   ///< d
};

/// MotorDivisors for the reciprocal `inverse_gain`: its prepared shift and
/// rounding constant beside it.
[[nodiscard]] MotorDivisors motor_divisors_of(fx::NormalisedReciprocal inverse_gain) noexcept;

[[nodiscard]] MotorDivisors make_motor_divisors(const MotorParams& motor) noexcept;

/// The inverse of torque_from_current: the current that produces `torque_nm`
/// in `direction`,
///     I = T / (N eta Kt) + d * I0,
/// T / (N eta Kt) as one product with `divisors` (made from `motor`), within
/// 0.5 LSB + |T / (N eta Kt)| 2^-29 of the exact quotient (docs/flight.md;
/// host_tests/flight/dividing_oracle.hpp keeps the three divisions as the
/// oracle it is checked against).
/// Not checked against the sensor's range: a limit beyond it is a limit the
/// current cannot reach, which the caller may want to know (status overflow
/// only when the result leaves Q11.20).
[[nodiscard]] CurrentResult current_from_torque(const MotorParams& motor, const MotorDivisors& divisors,
                                                TorqueNm torque_nm, DriveDirection direction) noexcept;

/// ok when the motor parameters are usable (N, eta, Kt > 0, eta <= 1,
/// 0 <= I0 < current_abs_max).
[[nodiscard]] EstimateStatus check_motor(const MotorParams& motor) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_MOTOR_HPP
