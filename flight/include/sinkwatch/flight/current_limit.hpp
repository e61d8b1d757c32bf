// current_limit.hpp: the maximum drive current of section 7.
//
// At high slip the drawbar pull saturates at DP_max (Fig. 10). Putting
// DP = DP_max and the allowed sinkage z = z_max into Eq. 11 and solving for
// the torque gives the torque at which the wheel would sit at z_max:
//
//     T_max = (W / C1) * (r * (DP_max/W + C3) + C2 * z_max)
//
// and the motor model (motor.hpp) turns it into the current limit
//
//     I_max = T_max / (N eta Kt) + I0     (magnitude, in the driving direction).
//
// Recomputed every cycle from the current load, because W moves the limit
// both directly and through C(W). The monitor compares the measured current
// in the direction of motion with it. Section 7's inverse, the sinkage at the
// peak current (for the event record), is sinkage_from_pull() on the torque
// of that current with DP = DP_max.
#ifndef SINKWATCH_FLIGHT_CURRENT_LIMIT_HPP
#define SINKWATCH_FLIGHT_CURRENT_LIMIT_HPP

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

struct TorqueLimitResult {
  TorqueNm torque_nm;  ///< T_max >= 0 or zero with a status
  EstimateStatus status{EstimateStatus::ok};
};

struct CurrentLimitResult {
  CurrentA current_limit_a;  ///< |I_max|, zero unless status == ok
  TorqueNm torque_limit_nm;  ///< T_max behind it
  LoadClamp clamp{LoadClamp::none};  ///< the load's position in the correction table
  EstimateStatus status{EstimateStatus::ok};
};

/// T_max from Eq. 11 at DP = DP_max, z = z_max. A negative T_max (the soil
/// cannot carry the load at all at z_max) is returned as computed.
[[nodiscard]] TorqueLimitResult torque_limit(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m,
                                             WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept;

/// I_max for one wheel from the corrections already evaluated at `load_n`
/// (corrections_at(table, divisors, load_n): the per-cycle step evaluates
/// them once per wheel and shares them between DP_max/W, Eq. 15 and this
/// limit): T_max, then the motor model in the forward direction, its
/// divisions through the divisors prepared once per load
/// (make_motor_divisors(motor)). The limit is a magnitude; it is the same for
/// both directions because I0 always adds to the current needed.
[[nodiscard]] CurrentLimitResult current_limit(const CorrectionResult& corrections, const MotorParams& motor,
                                               const MotorDivisors& divisors, LengthM radius_m,
                                               WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_CURRENT_LIMIT_HPP
