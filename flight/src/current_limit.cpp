// Section 7's maximum drive current (current_limit.hpp).
#include "sinkwatch/flight/current_limit.hpp"

#include "of_valid.hpp"

namespace sinkwatch {
namespace flight {

TorqueLimitResult torque_limit(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m, WheelLoadN load_n,
                               SinkageM allowed_sinkage_m) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return TorqueLimitResult{TorqueNm::zero(), input_status};
  }
  return detail::torque_limit_of_valid(c, dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
}

CurrentLimitResult current_limit(const CorrectionResult& corr, const MotorParams& motor,
                                 const MotorDivisors& divisors, LengthM radius_m, WheelLoadN load_n,
                                 SinkageM allowed_sinkage_m) noexcept {
  if (corr.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, corr.status};
  }
  const EstimateStatus input_status = check_estimator_inputs(corr.coefficients, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, input_status};
  }
  // The motor is checked after T_max, as current_from_torque() would: a
  // T_max beyond its format is overflow whatever the motor. T_max through
  // torque_limit() (its input check passes again): one expansion of the
  // inline core in this file, not two.
  const TorqueLimitResult t = torque_limit(corr.coefficients, corr.dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
  const EstimateStatus motor_status = check_motor(motor);
  if ((t.status == EstimateStatus::ok) && (motor_status != EstimateStatus::ok)) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, motor_status};
  }
  return detail::limit_from_torque(corr, motor, divisors, t);
}

}  // namespace flight
}  // namespace sinkwatch
