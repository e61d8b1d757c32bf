// The motor model (motor.hpp). The gain N * eta * Kt is never formed as one
// number: multiplying (and dividing) step by step keeps each rounding relative
// to a quantity of the output's size, which docs/flight.md bounds.
#include "sinkwatch/flight/motor.hpp"

namespace sinkwatch {
namespace flight {

namespace {

bool direction_is_valid(DriveDirection d) noexcept {
  return (d == DriveDirection::forward) || (d == DriveDirection::reverse);
}

}  // namespace

EstimateStatus check_motor(const MotorParams& motor) noexcept {
  if ((motor.gear_ratio <= GearRatio::zero()) || (motor.efficiency <= Efficiency::zero()) ||
      (motor.efficiency.q() > EfficiencyQ::from_raw(std::int32_t{0x40000000})) ||  // 1.0 in Q1.30
      (motor.kt_nm_per_a <= TorqueConstantNmPerA::zero()) || (motor.no_load_current_a < CurrentA::zero()) ||
      (motor.current_abs_max_a <= motor.no_load_current_a)) {
    return EstimateStatus::invalid_motor;
  }
  return EstimateStatus::ok;
}

TorqueResult torque_from_current(const MotorParams& motor, CurrentA current_a, DriveDirection direction) noexcept {
  const EstimateStatus motor_status = check_motor(motor);
  if (motor_status != EstimateStatus::ok) {
    return TorqueResult{TorqueNm::zero(), motor_status};
  }
  if (!direction_is_valid(direction)) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::invalid_direction};
  }
  fx::Status st;
  const CurrentQ magnitude = fx::abs(current_a.q(), st);
  if ((!st.ok()) || (magnitude > motor.current_abs_max_a.q())) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::invalid_current};
  }
  // I0 opposes the rotation: subtract it driving forward, add it in reverse.
  // Both operands are within +-current_abs_max < 2048 A, so this is exact.
  const CurrentQ effective = (direction == DriveDirection::forward)
                                 ? fx::sub(current_a.q(), motor.no_load_current_a.q(), st)
                                 : fx::add(current_a.q(), motor.no_load_current_a.q(), st);
  const WideQ motor_torque = fx::mul<WideQ>(motor.kt_nm_per_a.q(), effective, st);
  const WideQ after_gear_loss = fx::mul<WideQ>(motor.efficiency.q(), motor_torque, st);
  const LoadQ wheel_torque = fx::mul<LoadQ>(motor.gear_ratio.q(), after_gear_loss, st);
  if (!st.ok()) {
    return TorqueResult{TorqueNm::zero(), EstimateStatus::overflow};
  }
  return TorqueResult{TorqueNm(wheel_torque), EstimateStatus::ok};
}

namespace {

/// T / (N eta Kt), one division at a time (each rounding relative to the
/// quantity it produces).
WideQ driving_current(const MotorDivisors& divisors, TorqueNm torque_nm, fx::Status& st) noexcept {
  const WideQ per_gear = div_by_constant<WideQ>(torque_nm.q(), divisors.gear_ratio, st);
  const WideQ before_loss = div_by_constant<WideQ>(per_gear, divisors.efficiency, st);
  return div_by_constant<WideQ>(before_loss, divisors.kt, st);
}

}  // namespace

CurrentResult current_from_torque(const MotorParams& motor, const MotorDivisors& divisors, TorqueNm torque_nm,
                                  DriveDirection direction) noexcept {
  const EstimateStatus motor_status = check_motor(motor);
  if (motor_status != EstimateStatus::ok) {
    return CurrentResult{CurrentA::zero(), motor_status};
  }
  if (!direction_is_valid(direction)) {
    return CurrentResult{CurrentA::zero(), EstimateStatus::invalid_direction};
  }
  fx::Status st;
  const WideQ driving = driving_current(divisors, torque_nm, st);
  const WideQ i0 = fx::rescale<WideQ>(motor.no_load_current_a.q(), st);
  const WideQ total =
      (direction == DriveDirection::forward) ? fx::add(driving, i0, st) : fx::sub(driving, i0, st);
  const CurrentQ current = fx::rescale<CurrentQ>(total, st);
  if (!st.ok()) {
    return CurrentResult{CurrentA::zero(), EstimateStatus::overflow};
  }
  return CurrentResult{CurrentA(current), EstimateStatus::ok};
}

MotorDivisors make_motor_divisors(const MotorParams& motor) noexcept {
  return MotorDivisors{make_divisor(motor.gear_ratio.q()), make_divisor(motor.efficiency.q()),
                       make_divisor(motor.kt_nm_per_a.q())};
}

}  // namespace flight
}  // namespace sinkwatch
