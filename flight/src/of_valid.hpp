// of_valid.hpp: the motor model (motor.hpp), Eq. 11 (estimator.hpp) and the
// section 7 limit (current_limit.hpp) for inputs that are already known to
// pass check_motor() and check_estimator_inputs().
//
// Each public function checks its parameters and then calls its core here.
// The per-cycle callers reach the cores directly where the check has
// already been made: the motor comes from a table that validate() accepted
// (validate_motor implies check_motor), and the monitor checks the
// coefficients, radius and load of a wheel once for both Eq. 11 and the
// limit instead of once in each. Per step that is 12 motor checks and six
// input checks fewer (docs/performance.md, session 16). The cores differ
// from the public functions only in the checks they leave out: the same
// arithmetic, the same statuses for every other input.
#ifndef SINKWATCH_FLIGHT_OF_VALID_HPP
#define SINKWATCH_FLIGHT_OF_VALID_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"

namespace sinkwatch {
namespace flight {
namespace detail {

/// The magnitude (below 2^63) with the sign `negative`: a product of a
/// signed value and a factor the caller has checked positive (the radius, the
/// load, C1 or C2 of inputs check_estimator_inputs() accepts) is formed as
/// the product of the magnitudes with the signed value's sign put back, one
/// magnitude fewer than fx::wide::mul_32x32_64 takes for two signed values.
inline std::int64_t with_sign(bool negative, std::uint64_t magnitude) noexcept {
  const auto m = static_cast<std::int64_t>(magnitude);
  return negative ? -m : m;
}

/// torque_from_current() for a motor check_motor() accepts.
[[nodiscard]] TorqueResult torque_of_valid_motor(const MotorParams& motor, CurrentA current_a,
                                                 DriveDirection direction) noexcept;

/// current_from_torque() for a motor check_motor() accepts.
[[nodiscard]] CurrentResult current_of_valid_motor(const MotorParams& motor, const MotorDivisors& divisors,
                                                   TorqueNm torque_nm, DriveDirection direction) noexcept;

/// sinkage_from_pull() for inputs check_estimator_inputs() accepts.
[[nodiscard]] SinkageResult sinkage_of_valid(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                             TorqueNm torque_nm, DrawbarPullN drawbar_pull_n) noexcept;

/// current_limit() for corrections whose status is ok, with coefficients,
/// radius and load that check_estimator_inputs() accepts, and a motor
/// check_motor() accepts.
[[nodiscard]] CurrentLimitResult current_limit_of_valid(const CorrectionResult& corrections, const MotorParams& motor,
                                                        const MotorDivisors& divisors, LengthM radius_m,
                                                        WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept;

}  // namespace detail
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_OF_VALID_HPP
