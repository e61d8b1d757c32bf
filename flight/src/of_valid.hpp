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
//
// The input check, Eq. 11's and the limit's cores are defined here, forced
// inline (SW_FX_INLINE): the monitor's one per-wheel function
// (monitor.cpp, estimate_from) computes the sinkage and the limit without a
// call, an argument record or a result record between them, and the public
// functions (estimator.cpp, current_limit.cpp) expand the same code, so
// there is still one definition of each (round 13: M0 -526, M4 -262
// instructions per six-wheel step, the bits unchanged).
#ifndef SINKWATCH_FLIGHT_OF_VALID_HPP
#define SINKWATCH_FLIGHT_OF_VALID_HPP

#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/correction.hpp"
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

/// a b exactly for any a and a b the caller has checked positive (so |a b|
/// < 2^62): with_sign(a < 0, |a| b)'s integer. Where the core has a 32 x 32
/// -> 64-bit signed product (SMULL) it is that one instruction, with no
/// branch on a's sign (round 15); on ARMv6-M, where every 64-bit product is
/// built from 16-bit ones, the magnitudes' product with the sign put back
/// (no __aeabi_lmul), as before. host_tests/flight/test_estimator.cpp
/// (TimesPositive) checks both forms against the exact product.
SW_FX_INLINE std::int64_t times_positive(std::int32_t a, std::int32_t b_positive) noexcept {
  if constexpr (fx::wide::kMul32x32BySoftware) {
    return with_sign(a < 0, fx::wide::mul_32x32_64(fx::detail::magnitude32(a), static_cast<std::uint32_t>(b_positive)));
  } else {
    return static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b_positive);
  }
}

/// a b for two factors the caller has checked non-negative: the unsigned
/// product's bits on every target. Where the core has SMULL, the signed
/// product (GCC turned the unsigned one of a value it knew non-negative
/// from a range check into a 64 x 32-bit product, two instructions more);
/// on ARMv6-M the unsigned 16-bit products, as before.
SW_FX_INLINE std::uint64_t product_of_non_negative(std::int32_t a, std::int32_t b) noexcept {
  if constexpr (fx::wide::kMul32x32BySoftware) {
    return fx::wide::mul_32x32_64(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
  } else {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b));
  }
}

/// torque_from_current() for a motor check_motor() accepts.
[[nodiscard]] TorqueResult torque_of_valid_motor(const MotorParams& motor, CurrentA current_a,
                                                 DriveDirection direction) noexcept;

/// current_from_torque() for a motor check_motor() accepts.
[[nodiscard]] CurrentResult current_of_valid_motor(const MotorParams& motor, const MotorDivisors& divisors,
                                                   TorqueNm torque_nm, DriveDirection direction) noexcept;

/// The coefficients' part of check_estimator_inputs(): C1 and C2 in
/// [kMinC12, kMaxC12], C3 in [kMinC3, kMaxC3].
SW_FX_INLINE bool coefficients_in_range(const Coefficients& c) noexcept {
  return (c.c1 >= kMinC12) && (c.c1 <= kMaxC12) && (c.c2 >= kMinC12) && (c.c2 <= kMaxC12) && (c.c3 >= kMinC3) &&
         (c.c3 <= kMaxC3);
}

/// check_estimator_inputs(), inline.
SW_FX_INLINE EstimateStatus estimator_inputs_status(const Coefficients& c, LengthM radius_m,
                                                    WheelLoadN load_n) noexcept {
  if ((radius_m < kMinRadiusM) || (radius_m > kMaxRadiusM)) {
    return EstimateStatus::invalid_radius;
  }
  if (load_n <= WheelLoadN::zero()) {
    return EstimateStatus::invalid_load;
  }
  if (!coefficients_in_range(c)) {
    return EstimateStatus::invalid_coefficient;
  }
  return EstimateStatus::ok;
}

/// sinkage_from_pull()'s raw sinkage (Q?.24) for inputs
/// check_estimator_inputs() accepts, into `z_raw`; false (z_raw 0) where it
/// overflows.
SW_FX_INLINE bool sinkage_raw_of_valid(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                       TorqueNm torque_nm, DrawbarPullN drawbar_pull_n, std::int32_t& z_raw) noexcept {
  // z = (C1 T - r C3 W - r DP) / (C2 W): one division, its operands in
  // Q23.40 on 64 bits (docs/flight.md, "Sinkage"). C1 T, r DP and C2 W are
  // exact products; r C3 is rounded to Q2.29 before it meets W, so r C3 W is
  // one product rounded to Q23.40. For inputs check_estimator_inputs()
  // accepts (0 < C1, C2 <= 4, |C3| <= 1, 0 < r <= 2 m, W > 0; T and DP any
  // 32-bit value) the terms are at most 2^57, 2^56 and 2^56 + 1 raw
  // (|r C3| <= 2, 2^30 in Q2.29), their sum below 2^58: no intermediate can
  // overflow, so the sum is plain 64-bit arithmetic without saturation
  // tests, and each product is fx::mul's rounding of the exact product
  // (ties away from zero), bit for bit the checked chain it replaced. r, W,
  // C1 and C2 are positive, so only T, DP and C3 have a sign (r |C3| and
  // its product with W as magnitudes, C3's sign put back once).
  const std::int32_t r = radius_m.raw();
  const std::int32_t w = load_n.raw();
  const std::int64_t drive = times_positive(torque_nm.raw(), c.c1.raw());
  const std::int64_t pull_moment = times_positive(drawbar_pull_n.raw(), r);
  const auto r_c3 = static_cast<std::uint32_t>(fx::detail::round_shift_const<(2 * LengthQ::frac_bits) - 29>(
      fx::wide::mul_32x32_64(static_cast<std::uint32_t>(r), fx::detail::magnitude32(c.c3.raw()))));  // <= 2^30
  const std::int64_t offset_moment =
      with_sign(c.c3.raw() < 0, fx::detail::round_shift_const<(29 + LoadQ::frac_bits) - 40>(
                                    fx::wide::mul_32x32_64(r_c3, static_cast<std::uint32_t>(w))));  // < 2^56

  using Moment = fx::Q<std::int64_t, 40>;
  const Moment numerator = Moment::from_raw((drive - pull_moment) - offset_moment);
  const std::uint64_t denominator = product_of_non_negative(c.c2.raw(), w);  // > 0
  // C2 W changes with each wheel's load: no prepared reciprocal.
  return fx::quotient_by_positive<LengthQ::frac_bits>(numerator.raw() < 0, fx::detail::magnitude(numerator.raw()),
                                                       Moment::frac_bits, denominator, 40, fx::PreparedReciprocal{},
                                                       z_raw);
}

/// sinkage_from_pull() for inputs check_estimator_inputs() accepts.
SW_FX_INLINE SinkageResult sinkage_of_valid(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                             TorqueNm torque_nm, DrawbarPullN drawbar_pull_n) noexcept {
  std::int32_t z = 0;
  if (!sinkage_raw_of_valid(c, radius_m, load_n, torque_nm, drawbar_pull_n, z)) {
    return SinkageResult{SinkageM::zero(), EstimateStatus::overflow};
  }
  return SinkageResult{SinkageM(LengthQ::from_raw(z)), EstimateStatus::ok};
}

/// W L from L's leading 32 bits (truncated: < 2^-31 relative) times W > 0:
/// one 32 x 32 -> 64-bit product whose scale is known only at run time.
/// The leading word and bit length in one pass (fx::detail::leading_bits,
/// the quotient's own normalisation: the same integers as wide::bit_length
/// and wide::leading_word for L != 0; L == 0 gives the product 0, a zero
/// numerator whatever its scale).
SW_FX_INLINE fx::ScaledMagnitude load_times(fx::Q<std::int64_t, 48> lever, WheelLoadN load_n) noexcept {
  const fx::detail::LeadingBits leading = fx::detail::leading_bits(fx::detail::magnitude(lever.raw()));
  const std::uint64_t product =
      fx::wide::mul_32x32_64(leading.word, static_cast<std::uint32_t>(load_n.raw()));  // < 2^63
  return fx::ScaledMagnitude{lever.raw() < 0, product,
                             ((16 + 48) + 32) - static_cast<std::int32_t>(leading.bits)};
}

/// r (DP_max/W + C3) exactly (Q15.48 raw) for inputs check_estimator_inputs()
/// accepts: r > 0 and |C3| <= 1 (2^24 raw), so the sum of the two ratios is
/// below 2^31 + 2^24 < 2^32 in magnitude and r times it is one 32 x 32 ->
/// 64-bit product (below 2^57). r DP_max/W + r C3, the same integer, took two.
/// The form for ARMv6-M, where a 64-bit product is four 16-bit ones.
SW_FX_INLINE std::int64_t radius_times_ratios_by_magnitude(std::int32_t r, Ratio dp_max_ratio, Ratio c3) noexcept {
  // |sum| < 2^32 is its low word taken modulo 2^32 (the wrapping 32-bit sum
  // or its negation): no 64-bit negation. The sum is negative exactly when
  // DP_max/W < -C3 (-C3 fits: |C3| <= 2^24 raw).
  const std::uint32_t low = static_cast<std::uint32_t>(dp_max_ratio.raw()) + static_cast<std::uint32_t>(c3.raw());
  const bool negative = dp_max_ratio.raw() < -c3.raw();
  const std::uint32_t sum_magnitude = negative ? (0U - low) : low;
  return with_sign(negative, fx::wide::mul_32x32_64(sum_magnitude, static_cast<std::uint32_t>(r)));
}

/// The same integer on every target: where the core has a 32 x 32 -> 64-bit
/// signed product, r DP_max/W + r C3 as one product and one multiply-
/// accumulate (SMULL, SMLAL: both terms and their sum below 2^62), with no
/// sign to take off and put back (round 15); else the magnitude form above.
/// host_tests/flight/test_estimator.cpp (RadiusTimesRatios) checks both
/// against the exact product.
SW_FX_INLINE std::int64_t radius_times_ratios(std::int32_t r, Ratio dp_max_ratio, Ratio c3) noexcept {
  if constexpr (fx::wide::kMul32x32BySoftware) {
    return radius_times_ratios_by_magnitude(r, dp_max_ratio, c3);
  } else {
    return (static_cast<std::int64_t>(dp_max_ratio.raw()) * static_cast<std::int64_t>(r)) +
           (static_cast<std::int64_t>(c3.raw()) * static_cast<std::int64_t>(r));
  }
}

/// torque_limit()'s raw T_max (Q?.16) for inputs check_estimator_inputs()
/// accepts, into `t_max_raw`; false (t_max_raw 0) where it overflows. A
/// prepared `c1_reciprocal` (fx::normalised_reciprocal(C1).mantissa) finds
/// the quotient from it (fx::quotient_by_positive: the same integer).
SW_FX_INLINE bool torque_limit_raw_core(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m,
                                        WheelLoadN load_n, SinkageM allowed_sinkage_m,
                                        fx::PreparedReciprocal c1_reciprocal, std::int32_t& t_max_raw) noexcept {
  // T_max = W L / C1 with the lever L = r (DP_max/W + C3) + C2 z_max, one
  // division (docs/flight.md, "Current limit"). L is exact in Q15.48: for
  // accepted inputs (0 < r <= 2 m, 0 < C1, C2 <= 4, |C3| <= 1, W > 0) and
  // any 32-bit DP_max/W and z_max its products are below 2^57 (r times a
  // sum below 2^32) and at most 2^57 raw and their sum below 2^58, so the sum
  // is plain 64-bit arithmetic: the bits of the saturating sum it replaced,
  // which could not saturate either. r, C1 and C2 are positive: only the
  // other factors have a sign.
  const std::int64_t lever = radius_times_ratios(radius_m.raw(), dp_max_ratio, c.c3) +
                             times_positive(allowed_sinkage_m.raw(), c.c2.raw());
  const fx::ScaledMagnitude w_lever = load_times(fx::Q<std::int64_t, 48>::from_raw(lever), load_n);
  return fx::quotient_by_positive<LoadQ::frac_bits>(w_lever.negative, w_lever.magnitude, w_lever.frac_bits,
                                                     static_cast<std::uint32_t>(c.c1.raw()), RatioQ::frac_bits,
                                                     c1_reciprocal, t_max_raw);
}

/// torque_limit_raw_core for the monitor: where C1 is `divisors`'
/// (CorrectionDivisors::c1_raw, Table 2's C1 at every load) the quotient
/// comes from its prepared reciprocal, for all six wheels, instead of a
/// long division each (round 17). Divisors of any table keep the bits: only
/// an equal C1 takes the reciprocal.
SW_FX_INLINE bool torque_limit_raw_of_valid(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m,
                                            WheelLoadN load_n, SinkageM allowed_sinkage_m,
                                            const CorrectionDivisors& divisors, std::int32_t& t_max_raw) noexcept {
  return torque_limit_raw_core(c, dp_max_ratio, radius_m, load_n, allowed_sinkage_m,
                               fx::PreparedReciprocal{c.c1.raw() == divisors.c1_raw, divisors.c1_mantissa}, t_max_raw);
}

/// torque_limit() for inputs check_estimator_inputs() accepts.
SW_FX_INLINE TorqueLimitResult torque_limit_of_valid(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m,
                                                     WheelLoadN load_n, SinkageM allowed_sinkage_m) noexcept {
  std::int32_t t_max = 0;
  if (!torque_limit_raw_core(c, dp_max_ratio, radius_m, load_n, allowed_sinkage_m, fx::PreparedReciprocal{}, t_max)) {
    return TorqueLimitResult{TorqueNm::zero(), EstimateStatus::overflow};
  }
  return TorqueLimitResult{TorqueNm(LoadQ::from_raw(t_max)), EstimateStatus::ok};
}

/// The limit's raw current (Q?.20) from a raw T_max (Q?.16) into
/// `current_raw`: the motor model in the forward direction (a magnitude in
/// the direction of motion: I0 adds), current_from_torque()'s bits for a
/// motor check_motor() accepts; false where it is refused. T_max times the
/// prepared reciprocal of the gain is below 2^62 raw (a 32 x 32-bit product
/// shifted right), I0 below 2^31, so their sum is exact in 64 bits; only a
/// current beyond Q11.20 is refused, as rescaling the sum would refuse it.
SW_FX_INLINE bool current_raw_from_torque(const MotorParams& motor, const MotorDivisors& divisors,
                                          std::int32_t t_max_raw, std::int32_t& current_raw) noexcept {
  // fx::times_reciprocal<Q43.20>(T_max, 1/gain)'s core on magnitudes
  // (fx::detail::times_mantissa: below 2^63, so the 64-bit quotient cannot
  // overflow), the sign put back and I0 added; only the quotient's refusals
  // are kept: no reciprocal (div_by_zero) and a product that a shift <= 0
  // would only grow (overflow). The same integer and the same refusals.
  const fx::NormalisedReciprocal inverse = divisors.inverse_gain;
  const std::uint32_t t_magnitude = fx::detail::magnitude32(t_max_raw);
  const std::int32_t shift = (LoadQ::frac_bits + inverse.scale) - CurrentQ::frac_bits;
  const std::uint64_t driving = fx::detail::times_mantissa(t_magnitude, inverse.mantissa, shift);
  const std::int64_t total =
      with_sign(t_max_raw < 0, driving) + static_cast<std::int64_t>(motor.no_load_current_a.raw());
  constexpr std::int64_t kMin = std::numeric_limits<std::int32_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
  const bool refused =
      (inverse.mantissa == 0U) || fx::detail::times_mantissa_grows(t_magnitude, inverse.mantissa, shift);
  if (refused || (total < kMin) || (total > kMax)) {
    current_raw = 0;
    return false;
  }
  current_raw = static_cast<std::int32_t>(total);
  return true;
}

/// round(t_magnitude / gain) in Q?.20: (product + 2^(s-1)) >> s with the
/// prepared 2^(s-1) and counts (MotorDivisors; round 17: no 64-bit shift by
/// a run-time count, 1 instruction fewer per wheel on the Cortex-M4). The
/// sum is below 2^63 + 2^62, so it does not wrap. The same integer as
/// shift_right_rounded for every s in [1, 63] (test_estimator.cpp,
/// PreparedWordsShiftIsTheRoundedShift).
SW_FX_INLINE std::uint64_t shifted_by_prepared_words(const MotorDivisors& divisors,
                                                     std::uint32_t t_magnitude) noexcept {
  const std::uint64_t sum =
      fx::wide::mul_32x32_64(t_magnitude, divisors.inverse_gain.mantissa) + divisors.current_rounding_raw;
  const auto high = static_cast<std::uint32_t>(sum >> 32U);
  const auto low = static_cast<std::uint32_t>(sum);
  const std::uint32_t a = divisors.current_low_shift;
  const std::uint32_t b = divisors.current_clear_shift;
  const std::uint32_t low_shifted =
      ((low >> a) >> b) | ((high << divisors.current_join_shift) >> divisors.current_high_shift);
  return (std::uint64_t{(high >> a) >> b} << 32U) | std::uint64_t{low_shifted};
}

/// current_raw_from_torque() for a motor validate() accepted (the prepared
/// table's, estimate_from's): the same integer and the same refusals, less
/// the two such a motor cannot meet. Its gain N eta Kt lies in about
/// [10^-6, 4 10^4] (param_table.cpp: N in [1, 10^4], eta in [0.01, 1], Kt in
/// [10^-4, 4]), so 1/gain has a mantissa (not 0) and the scale 32 +
/// floor(log2 gain), and the shift 16 + scale - 20 = 28 + floor(log2 gain)
/// lies in [8, 43]: within (0, 64), where times_mantissa rounds the product
/// and no product grows (round 16: one test of the mantissa and one of the
/// shift fewer per wheel). test_estimator.cpp
/// (ValidatedMotorsShiftIsWithinItsRange) checks the ends of the ranges.
SW_FX_INLINE bool current_raw_from_validated_torque(const MotorParams& motor, const MotorDivisors& divisors,
                                                    std::int32_t t_max_raw, std::int32_t& current_raw) noexcept {
  std::uint64_t driving = 0U;
  if constexpr (fx::detail::kShift64BySoftware) {
    // ARMv6-M: shift_right_rounded's word form (the prepared form below
    // measured 1 instruction per wheel more there).
    const fx::NormalisedReciprocal inverse = divisors.inverse_gain;
    const auto shift = static_cast<std::uint32_t>((LoadQ::frac_bits + inverse.scale) - CurrentQ::frac_bits);
    driving = fx::detail::shift_right_rounded(
        fx::wide::mul_32x32_64(fx::detail::magnitude32(t_max_raw), inverse.mantissa), shift);
  } else {
    driving = shifted_by_prepared_words(divisors, fx::detail::magnitude32(t_max_raw));
  }
  const std::int64_t total =
      with_sign(t_max_raw < 0, driving) + static_cast<std::int64_t>(motor.no_load_current_a.raw());
  constexpr std::int64_t kMin = std::numeric_limits<std::int32_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
  if ((total < kMin) || (total > kMax)) {
    current_raw = 0;
    return false;
  }
  current_raw = static_cast<std::int32_t>(total);
  return true;
}

/// The limit from T_max (current_raw_from_torque) as current_limit()'s
/// result, for a motor check_motor() accepts.
SW_FX_INLINE CurrentLimitResult limit_from_torque(const CorrectionResult& corr, const MotorParams& motor,
                                                  const MotorDivisors& divisors, const TorqueLimitResult& t) noexcept {
  // Each return builds the whole result (no zeroed result overwritten
  // field by field: the Cortex-M0 build cleared it with a memset per wheel).
  if (t.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, t.status};
  }
  std::int32_t current = 0;
  if (!current_raw_from_torque(motor, divisors, t.torque_nm.raw(), current)) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, EstimateStatus::overflow};
  }
  return CurrentLimitResult{CurrentA(CurrentQ::from_raw(current)), t.torque_nm, corr.clamp, EstimateStatus::ok};
}

}  // namespace detail
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_OF_VALID_HPP
