// Section 7's maximum drive current (current_limit.hpp).
#include "sinkwatch/flight/current_limit.hpp"

#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

#include "of_valid.hpp"

namespace sinkwatch {
namespace flight {

namespace {

/// W L from L's leading 32 bits (truncated: < 2^-31 relative) times W > 0:
/// one 32 x 32 -> 64-bit product whose scale is known only at run time.
fx::ScaledMagnitude load_times(fx::Q<std::int64_t, 48> lever, WheelLoadN load_n) noexcept {
  const std::uint64_t magnitude = fx::detail::magnitude(lever.raw());
  const std::uint32_t bits = fx::wide::bit_length(magnitude);
  const std::uint32_t leading = fx::wide::leading_word(magnitude, bits);  // magnitude 2^(32 - bits)
  const std::uint64_t product =
      fx::wide::mul_32x32_64(leading, static_cast<std::uint32_t>(load_n.raw()));  // < 2^63
  return fx::ScaledMagnitude{lever.raw() < 0, product,
                             ((16 + 48) + 32) - static_cast<std::int32_t>(bits)};
}

/// r (DP_max/W + C3) exactly (Q15.48 raw) for inputs check_estimator_inputs()
/// accepts: r > 0 and |C3| <= 1 (2^24 raw), so the sum of the two ratios is
/// below 2^31 + 2^24 < 2^32 in magnitude and r times it is one 32 x 32 ->
/// 64-bit product (below 2^57). r DP_max/W + r C3, the same integer, took two.
std::int64_t radius_times_ratios(std::int32_t r, Ratio dp_max_ratio, Ratio c3) noexcept {
  const std::int64_t sum = static_cast<std::int64_t>(dp_max_ratio.raw()) + static_cast<std::int64_t>(c3.raw());
  const auto sum_magnitude = static_cast<std::uint32_t>(fx::detail::magnitude(sum));  // < 2^32
  return detail::with_sign(sum < 0, fx::wide::mul_32x32_64(sum_magnitude, static_cast<std::uint32_t>(r)));
}

/// torque_limit() for inputs check_estimator_inputs() accepts.
TorqueLimitResult torque_limit_of_valid(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m,
                                        WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept {
  // T_max = W L / C1 with the lever L = r (DP_max/W + C3) + C2 z_max, one
  // division (docs/flight.md, "Current limit"). L is exact in Q15.48: for
  // accepted inputs (0 < r <= 2 m, 0 < C1, C2 <= 4, |C3| <= 1, W > 0) and
  // any 32-bit DP_max/W and z_max its products are below 2^57 (r times a
  // sum below 2^32) and at most 2^57 raw and their sum below 2^58, so the sum
  // is plain 64-bit arithmetic: the bits of the saturating sum it replaced,
  // which could not saturate either. r, C1 and C2 are positive: only the
  // other factors have a sign to take off and put back.
  const std::int32_t z = allowed_sinkage_m.raw();
  const std::int64_t lever =
      radius_times_ratios(radius_m.raw(), dp_max_ratio, c.c3) +
      detail::with_sign(z < 0, fx::wide::mul_32x32_64(fx::detail::magnitude32(z), static_cast<std::uint32_t>(c.c2.raw())));
  fx::Status st;
  const fx::ScaledMagnitude c1{false, static_cast<std::uint32_t>(c.c1.raw()), RatioQ::frac_bits};
  const LoadQ t_max = fx::divide_normalised<LoadQ>(load_times(fx::Q<std::int64_t, 48>::from_raw(lever), load_n), c1, st);
  if (!st.ok()) {
    return TorqueLimitResult{TorqueNm::zero(), EstimateStatus::overflow};
  }
  return TorqueLimitResult{TorqueNm(t_max), EstimateStatus::ok};
}

/// The limit from T_max: the motor model in the forward direction (a
/// magnitude in the direction of motion: I0 adds), current_from_torque()'s
/// bits for a motor check_motor() accepts. T_max times the prepared
/// reciprocal of the gain is below 2^62 raw (a 32 x 32-bit product shifted
/// right), I0 below 2^31, so their sum is exact in 64 bits; only a current
/// beyond Q11.20 is refused, as rescaling the sum would refuse it.
CurrentLimitResult limit_from_torque(const CorrectionResult& corr, const MotorParams& motor,
                                     const MotorDivisors& divisors, const TorqueLimitResult& t) noexcept {
  // Each return builds the whole result (no zeroed result overwritten
  // field by field: the Cortex-M0 build cleared it with a memset per wheel).
  if (t.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, t.status};
  }
  using WideCurrentQ = fx::Q<std::int64_t, CurrentQ::frac_bits>;
  fx::Status st;  // div_by_zero only for a motor without a reciprocal
  const WideCurrentQ driving = fx::times_reciprocal<WideCurrentQ>(t.torque_nm.q(), divisors.inverse_gain, st);
  const std::int64_t total = driving.raw() + static_cast<std::int64_t>(motor.no_load_current_a.raw());
  constexpr std::int64_t kMin = std::numeric_limits<std::int32_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
  if ((!st.ok()) || (total < kMin) || (total > kMax)) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, EstimateStatus::overflow};
  }
  const CurrentA limit(CurrentQ::from_raw(static_cast<std::int32_t>(total)));
  return CurrentLimitResult{limit, t.torque_nm, corr.clamp, EstimateStatus::ok};
}

}  // namespace

TorqueLimitResult torque_limit(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m, WheelLoadN load_n,
                               SinkageM allowed_sinkage_m) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return TorqueLimitResult{TorqueNm::zero(), input_status};
  }
  return torque_limit_of_valid(c, dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
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
  // T_max beyond its format is overflow whatever the motor.
  const EstimateStatus motor_status = check_motor(motor);
  if (motor_status != EstimateStatus::ok) {
    const TorqueLimitResult t =
        torque_limit_of_valid(corr.coefficients, corr.dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
    const EstimateStatus status = (t.status != EstimateStatus::ok) ? t.status : motor_status;
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, status};
  }
  return detail::current_limit_of_valid(corr, motor, divisors, radius_m, load_n, allowed_sinkage_m);
}

CurrentLimitResult detail::current_limit_of_valid(const CorrectionResult& corr, const MotorParams& motor,
                                                  const MotorDivisors& divisors, LengthM radius_m,
                                                  WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept {
  // By reference, built in place: passed by value, the 8-byte result was a
  // memcpy per wheel on the Cortex-M0. limit_from_torque has this one
  // caller (current_limit() comes here once its checks pass), so GCC
  // inlines it: a call per wheel and cycle less (session 18).
  const TorqueLimitResult t =
      torque_limit_of_valid(corr.coefficients, corr.dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
  return limit_from_torque(corr, motor, divisors, t);
}

}  // namespace flight
}  // namespace sinkwatch
