// The motor model (motor.hpp). From current to torque the gain N * eta * Kt
// is applied step by step, each rounding relative to a quantity of the
// output's size; from torque to current it is one product with the gain's
// normalised reciprocal, whose error is relative (docs/flight.md bounds both).
#include "sinkwatch/flight/motor.hpp"

#include "sinkwatch/flight/wheel_load.hpp"

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

#include "of_valid.hpp"

namespace sinkwatch {
namespace flight {

namespace {

bool direction_is_valid(DriveDirection d) noexcept {
  return (d == DriveDirection::forward) || (d == DriveDirection::reverse);
}

// The three steps of torque_from_current on magnitudes: each is fx::mul's
// product of two magnitudes rounded half up, with the same bits as the
// checked chain (fx::mul into Q31.32, Q31.32, Q15.16) it replaced, which
// could not saturate before the last step (|Kt I| <= 2^62 raw, eta <= 1).
// A Q31.32 magnitude w = hi 2^32 + lo times a 32-bit v, shifted right by
// s <= 32: round(w v / 2^s) = hi v 2^(32 - s) + round(lo v / 2^s) exactly
// (2^s divides hi v 2^32), so each step is one 32 x 32 -> 64-bit product,
// and a second one only for a magnitude of 2^32 raw or more (above 1 A of
// driving current with the default motor's Kt of 0.025 N m/A: rare).

/// |Kt (I - I0)| in Q31.32 (raw): Q3.28 x Q11.20, 16 bits dropped, below
/// 2^46 + 1.
std::uint64_t kt_times(std::int32_t kt_raw, std::int32_t effective_raw) noexcept {
  const std::uint64_t product =
      fx::wide::mul_32x32_64(static_cast<std::uint32_t>(kt_raw), fx::detail::magnitude32(effective_raw));
  // (product + 2^15) >> 16 as the quotient plus the dropped half bit: the
  // same value (product < 2^62), without the rounding constant's two
  // registers, which pushed the six-wheel loop's parameters onto the stack.
  return (product >> 16U) + ((product >> 15U) & 1U);
}

/// The magnitude w (below 2^47) times the 32-bit v, shifted right by
/// 32 - kLeft and rounded half up, as the high word's part is shifted left
/// by kLeft (above).
template <std::uint32_t kLeft>
std::uint64_t times_wide_rounded(std::uint64_t w, std::uint32_t v) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  constexpr std::uint32_t kShift = 32U - kLeft;
  const auto high = static_cast<std::uint32_t>(w / kWord);
  const std::uint64_t low_part = (fx::wide::mul_32x32_64(static_cast<std::uint32_t>(w), v) +
                                  (std::uint64_t{1U} << (kShift - 1U))) >> kShift;
  return (high == 0U) ? low_part : (low_part + (fx::wide::mul_32x32_64(high, v) << kLeft));
}

/// |eta x| in Q31.32: Q1.30 x Q31.32, 30 bits dropped; eta <= 1, so at most |x|.
std::uint64_t efficiency_times(std::int32_t efficiency_raw, std::uint64_t x) noexcept {
  return times_wide_rounded<2U>(x, static_cast<std::uint32_t>(efficiency_raw));
}

/// |N x| in Q15.16: Q15.16 x Q31.32, 32 bits dropped; below 2^46.
std::uint64_t gear_times(std::int32_t gear_raw, std::uint64_t x) noexcept {
  return times_wide_rounded<0U>(x, static_cast<std::uint32_t>(gear_raw));
}

/// Both fields of `out` (a record assigned whole is a memcpy call on the M0).
SW_FX_INLINE void put(TorqueResult& out, TorqueNm torque_nm, EstimateStatus status) noexcept {
  out.torque_nm = torque_nm;
  out.status = status;
}

/// The refusals of a wheel's inputs that every motor form makes: ok, or
/// the refusal. An invalid direction; |I| beyond the sensor's range, as
/// fx::abs and a comparison gave it (the magnitude 2^31 of the most
/// negative current, where fx::abs overflowed, exceeds every range:
/// check_motor, 0 <= I0 < current_abs_max < 2^31).
SW_FX_INLINE EstimateStatus input_refusal(const MotorParams& motor, CurrentA current_a,
                                          DriveDirection direction) noexcept {
  if (!direction_is_valid(direction)) {
    return EstimateStatus::invalid_direction;
  }
  if (fx::detail::magnitude32(current_a.raw()) > static_cast<std::uint32_t>(motor.current_abs_max_a.raw())) {
    return EstimateStatus::invalid_current;
  }
  return EstimateStatus::ok;
}

/// input_refusal's refusal stored in `out`: true when there was one.
SW_FX_INLINE bool refused_input(const MotorParams& motor, CurrentA current_a, DriveDirection direction,
                                TorqueResult& out) noexcept {
  const EstimateStatus refusal = input_refusal(motor, current_a, direction);
  if (refusal != EstimateStatus::ok) {
    put(out, TorqueNm::zero(), refusal);
    return true;
  }
  return false;
}

/// One wheel's torque (torque_from_current() for a valid motor) into `out`,
/// inline into the loop of torques_of_valid_motor: each outcome stored
/// where it is known, not merged into a record first.
SW_FX_INLINE void torque_into(const MotorParams& motor, CurrentA current_a, DriveDirection direction,
                              TorqueResult& out) noexcept {
  if (refused_input(motor, current_a, direction, out)) {
    return;
  }
  fx::Status st;
  // I0 opposes the rotation: subtract it driving forward, add it in reverse.
  // Both operands are within +-current_abs_max < 2048 A, so this is exact.
  const CurrentQ effective = (direction == DriveDirection::forward)
                                 ? fx::sub(current_a.q(), motor.no_load_current_a.q(), st)
                                 : fx::add(current_a.q(), motor.no_load_current_a.q(), st);
  if (!st.ok()) {
    put(out, TorqueNm::zero(), EstimateStatus::overflow);
    return;
  }
  // Kt, eta and N are positive (check_motor), so the chain works on |I - I0|
  // and puts the sign back at the end, as fx::mul does (ties away from zero).
  const std::uint64_t wheel_torque = gear_times(
      motor.gear_ratio.raw(), efficiency_times(motor.efficiency.raw(),
                                               kt_times(motor.kt_nm_per_a.raw(), effective.raw())));
  const bool negative = effective.raw() < 0;
  constexpr std::uint64_t kMaxPositive = 0x7FFFFFFFU;
  if (wheel_torque > (kMaxPositive + (negative ? 1U : 0U))) {
    put(out, TorqueNm::zero(), EstimateStatus::overflow);
    return;
  }
  const auto t = static_cast<std::int64_t>(wheel_torque);  // <= 2^31
  put(out, TorqueNm(LoadQ::from_raw(static_cast<std::int32_t>(negative ? -t : t))), EstimateStatus::ok);
}

/// One wheel's torque for a motor validate() accepted (torque_into's bits;
/// the validated motor's bounds make two of its refusals impossible):
/// |I| <= current_abs_max <= 1000 A and 0 <= I0 < current_abs_max, so
/// I -+ I0 is within 2000 A and cannot leave Q11.20; and the chain is
/// monotone in |I -+ I0| <= current_abs_max + I0, whose torque
/// validate_envelope() found within 2^31 raw (forward at -current_abs_max),
/// so only +2^31 (reverse at +current_abs_max, which it does not test) can
/// leave Q15.16, and the test is on the low word alone. The status is
/// returned and the torque (zero unless ok) put in `torque_raw`, not in a
/// record: the caller stores both and tests the status in a register
/// (round 17; a record written through a reference stayed in memory).
SW_FX_INLINE EstimateStatus torque_of_validated(const MotorParams& motor, CurrentA current_a,
                                                DriveDirection direction, std::int32_t& torque_raw) noexcept {
  torque_raw = 0;
  const EstimateStatus refusal = input_refusal(motor, current_a, direction);
  if (refusal != EstimateStatus::ok) {
    return refusal;
  }
  const std::int32_t i0_raw = motor.no_load_current_a.raw();
  const std::int32_t effective_raw =
      (direction == DriveDirection::forward) ? (current_a.raw() - i0_raw) : (current_a.raw() + i0_raw);
  const auto wheel_torque = static_cast<std::uint32_t>(gear_times(
      motor.gear_ratio.raw(),
      efficiency_times(motor.efficiency.raw(), kt_times(motor.kt_nm_per_a.raw(), effective_raw))));  // <= 2^31
  const bool negative = effective_raw < 0;
  constexpr std::uint32_t kMaxPositive = 0x7FFFFFFFU;
  if ((!negative) && (wheel_torque > kMaxPositive)) {
    return EstimateStatus::overflow;
  }
  const auto t = static_cast<std::int64_t>(wheel_torque);
  torque_raw = static_cast<std::int32_t>(negative ? -t : t);
  return EstimateStatus::ok;
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

template <std::uint32_t N>
void detail::torques_of_valid_motor(const MotorParams& motor, const CurrentA (&current_a)[N],
                                    const DriveDirection (&direction)[N], TorqueResult (&torque)[N]) noexcept {
  // A copy: the stores into `torque` could otherwise alias the parameters,
  // which would be read again for every wheel.
  const MotorParams m = motor;
  for (std::uint32_t i = 0U; i < N; ++i) {
    torque_into(m, current_a[i], direction[i], torque[i]);
  }
}

template void detail::torques_of_valid_motor<1U>(const MotorParams& motor, const CurrentA (&current_a)[1U],
                                                 const DriveDirection (&direction)[1U],
                                                 TorqueResult (&torque)[1U]) noexcept;
template void detail::torques_of_valid_motor<limits::kWheelCount>(
    const MotorParams& motor, const CurrentA (&current_a)[limits::kWheelCount],
    const DriveDirection (&direction)[limits::kWheelCount], TorqueResult (&torque)[limits::kWheelCount]) noexcept;

void detail::torques_of_validated_motor(const MotorParams& motor, const CurrentA (&current_a)[limits::kWheelCount],
                                        const DriveDirection (&direction)[limits::kWheelCount],
                                        const bool (&current_usable)[limits::kWheelCount],
                                        TorqueResult (&torque)[limits::kWheelCount], DriveTorques& drive) noexcept {
  const MotorParams m = motor;  // as in torques_of_valid_motor
  for (std::uint32_t i = 0U; i < limits::kWheelCount; ++i) {
    std::int32_t torque_raw = 0;
    const EstimateStatus status = torque_of_validated(m, current_a[i], direction[i], torque_raw);
    put(torque[i], TorqueNm::from_raw(torque_raw), status);
    const bool usable = current_usable[i] && (status == EstimateStatus::ok);
    drive.usable[i] = usable;
    drive.torque_nm[i] = TorqueNm::from_raw(usable ? torque_raw : 0);
  }
}

TorqueResult detail::torque_of_valid_motor(const MotorParams& motor, CurrentA current_a,
                                           DriveDirection direction) noexcept {
  const CurrentA currents[1U]{current_a};
  const DriveDirection directions[1U]{direction};
  TorqueResult torque[1U]{};
  torques_of_valid_motor<1U>(motor, currents, directions, torque);
  return torque[0U];
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

MotorDivisors motor_divisors_of(fx::NormalisedReciprocal inverse_gain) noexcept {
  const std::int32_t shift = (LoadQ::frac_bits + inverse_gain.scale) - CurrentQ::frac_bits;
  if ((shift < 1) || (shift > 63)) {
    return MotorDivisors{inverse_gain, 0U, 0U, 0U, 0U, 0U};
  }
  const auto s = static_cast<std::uint32_t>(shift);
  const std::uint64_t rounding = std::uint64_t{1U} << (s - 1U);
  if (s < 32U) {
    return MotorDivisors{inverse_gain, rounding, s, 0U, 32U - s, 0U};
  }
  return MotorDivisors{inverse_gain, rounding, 31U, 1U, 0U, s - 32U};
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
  return motor_divisors_of(fx::normalised_reciprocal(gain, kGainFracBits - static_cast<std::int32_t>(dropped)));
}

}  // namespace flight
}  // namespace sinkwatch
