// The motor model (motor.hpp). From current to torque the gain N * eta * Kt
// is applied step by step, each rounding relative to a quantity of the
// output's size; from torque to current it is one product with the gain's
// normalised reciprocal, whose error is relative (docs/flight.md bounds both).
#include "sinkwatch/flight/motor.hpp"

#include "of_valid.hpp"

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
  return detail::torque_of_valid_motor(motor, current_a, direction);
}

TorqueResult detail::torque_of_valid_motor(const MotorParams& motor, CurrentA current_a,
                                           DriveDirection direction) noexcept {
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

CurrentResult current_from_torque(const MotorParams& motor, const MotorDivisors& divisors, TorqueNm torque_nm,
                                  DriveDirection direction) noexcept {
  const EstimateStatus motor_status = check_motor(motor);
  if (motor_status != EstimateStatus::ok) {
    return CurrentResult{CurrentA::zero(), motor_status};
  }
  return detail::current_of_valid_motor(motor, divisors, torque_nm, direction);
}

CurrentResult detail::current_of_valid_motor(const MotorParams& motor, const MotorDivisors& divisors,
                                             TorqueNm torque_nm, DriveDirection direction) noexcept {
  if (!direction_is_valid(direction)) {
    return CurrentResult{CurrentA::zero(), EstimateStatus::invalid_direction};
  }
  fx::Status st;
  // The driving part in Q43.20 (int64): beyond Q11.20 it may still be brought
  // back into range by I0; the sum goes into Q11.20 exactly (same fraction bits).
  using WideCurrentQ = fx::Q<std::int64_t, CurrentQ::frac_bits>;
  const WideCurrentQ driving = fx::times_reciprocal<WideCurrentQ>(torque_nm.q(), divisors.inverse_gain, st);
  const WideCurrentQ i0 = fx::rescale<WideCurrentQ>(motor.no_load_current_a.q(), st);
  const WideCurrentQ total =
      (direction == DriveDirection::forward) ? fx::add(driving, i0, st) : fx::sub(driving, i0, st);
  const CurrentQ current = fx::rescale<CurrentQ>(total, st);
  if (!st.ok()) {
    return CurrentResult{CurrentA::zero(), EstimateStatus::overflow};
  }
  return CurrentResult{CurrentA(current), EstimateStatus::ok};
}

MotorDivisors make_motor_divisors(const MotorParams& motor) noexcept {
  // N eta exactly (46 fraction bits, below 2^61), its leading 32 bits times
  // Kt (below 2^63): the gain within 2^-31 relative, whatever the formats'
  // magnitudes. A motor check_motor() refuses gets no reciprocal (every
  // current_from_torque call refuses it before using one).
  if ((motor.gear_ratio.raw() <= 0) || (motor.efficiency.raw() <= 0) || (motor.kt_nm_per_a.raw() <= 0)) {
    return MotorDivisors{};
  }
  const std::uint64_t n_eta =
      static_cast<std::uint64_t>(motor.gear_ratio.raw()) * static_cast<std::uint64_t>(motor.efficiency.raw());
  const std::uint32_t length = fx::wide::bit_length(n_eta);
  const std::uint32_t dropped = (length > 32U) ? (length - 32U) : 0U;
  const std::uint64_t gain = (n_eta >> dropped) * static_cast<std::uint64_t>(motor.kt_nm_per_a.raw());
  constexpr std::int32_t kGainFracBits = GearQ::frac_bits + EfficiencyQ::frac_bits + KtQ::frac_bits;
  return MotorDivisors{fx::normalised_reciprocal(gain, kGainFracBits - static_cast<std::int32_t>(dropped))};
}

}  // namespace flight
}  // namespace sinkwatch
