// correction.hpp: the corrections C1, C2, C3 of Eq. 11 as functions of the
// wheel load (the paper's Table 2), and the soil-bin drawbar-pull maximum
// DP_max/W (section 7, Fig. 10) over the same load breakpoints.
//
// Each is piecewise linear between the breakpoints and held constant beyond
// the first and the last; a load outside the breakpoints is reported
// (LoadClamp), because the fit says nothing about loads it was not made at.
// Default: Table 2's five soil-bin loads 3, 7, 10, 15, 20 kg times
// 9.81 N/kg, C1 = C2 = 1, C3 = 0.20, 0.15, 0.13, 0.13, 0.13 (param_table.hpp).
//
// DP_max is stored as the traction coefficient DP_max/W, not in newtons:
// Table 1 and Fig. 10 give it as a coefficient, and a coefficient carries over
// between loads where a force does not.
#ifndef SINKWATCH_FLIGHT_CORRECTION_HPP
#define SINKWATCH_FLIGHT_CORRECTION_HPP

#include <cstdint>

#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace flight {

constexpr std::uint8_t kMaxCorrectionRows = 8U;

/// One soil-bin load and its fitted corrections.
struct CorrectionRow {
  WheelLoadN load_n;   ///< breakpoint; strictly increasing along the table
  Ratio c1;
  Ratio c2;
  Ratio c3;
  Ratio dp_max_ratio;  ///< DP_max / W at high slip for this load
};

struct CorrectionTable {
  std::uint8_t count{0U};  ///< rows in use, 1..kMaxCorrectionRows
  CorrectionRow rows[kMaxCorrectionRows];
};

/// Where the load fell relative to the breakpoints.
enum class LoadClamp : std::uint8_t {
  none = 0U,         ///< within [first, last]: interpolated
  below_first = 1U,  ///< below the first breakpoint: the first row's values
  above_last = 2U,   ///< above the last breakpoint: the last row's values
};

struct CorrectionResult {
  Coefficients coefficients;
  Ratio dp_max_ratio;
  LoadClamp clamp{LoadClamp::none};
  EstimateStatus status{EstimateStatus::ok};  ///< invalid_load for W <= 0, invalid_coefficient for a malformed table
};

/// A segment width W_k+1 - W_k (raw Q15.16, positive) shifted left until its
/// top bit is bit 31, and its reciprocal's mantissa (fixedpoint/reciprocal.hpp).
/// The interpolation fraction (W - W_k) / width is then one product with the
/// mantissa, at most two below the quotient, and a remainder that corrects
/// it: the exact quotient, so the fraction has fx::div's bits without a
/// division per cycle (correction.cpp, fraction_of).
struct SegmentWidth {
  std::uint32_t normalised{0U};  ///< width * 2^shift, in [2^31, 2^32); 0: no segment
  std::uint32_t shift{0U};
  std::uint32_t mantissa{0U};  ///< floor((2^63 - 1) / normalised)
};

/// The segment widths of a table, prepared once per table load, and the
/// reciprocal of its first row's C1, the divisor of the current limit
/// (T_max = W L / C1) for every load where C1 takes that value: Table 2's
/// C1 is the same in every row, so all six wheels divide by it each cycle.
/// The monitor (of_valid.hpp, torque_limit_raw_of_valid) finds the limit's
/// quotient from it for a C1 equal to c1_raw, the long division's quotient
/// (fx::detail::quotient_of_leading_words_by_reciprocal), and divides
/// otherwise (round 17).
struct CorrectionDivisors {
  SegmentWidth width[kMaxCorrectionRows];  ///< [k]: rows k..k+1; unused entries: zero
  std::int32_t c1_raw{0};                  ///< rows[0].c1 raw where positive; 0: none (no C1 in range is 0)
  std::uint32_t c1_mantissa{0U};           ///< fx::normalised_reciprocal(C1).mantissa; 0: none
};

namespace detail {
// The interpolation of corrections_at() on raw integers. Here, not in the
// source, so that host_tests/flight/test_correction_paths.cpp can compare it
// with the 64-bit form it replaced (session 19) on random and edge inputs.

/// An interpolation fraction f (raw Q0.32) in its two 16-bit halves: split
/// once per load and used for all four coefficients of the row pair.
struct FractionHalves {
  std::uint32_t low;   ///< f mod 2^16
  std::uint32_t high;  ///< floor(f / 2^16)
};

[[nodiscard]] SW_FX_INLINE constexpr FractionHalves halves_of(std::uint32_t fraction) noexcept {
  return FractionHalves{fraction & 0xFFFFU, fraction >> 16U};
}

/// The top of P = f s for a 32-bit span s: P's high word floor(P / 2^32) and
/// its bits 16 to 31, all the interpolation's rounding reads (the bias added
/// to P is a multiple of 2^16, so P's low 16 bits never carry into it).
struct ProductTop {
  std::uint32_t high;    ///< floor(P / 2^32)
  std::uint32_t bits16;  ///< floor(P / 2^16) mod 2^16
};

/// P's top from fx::wide::mul_32x32_64 (on ARMv6-M its carry-free 16-bit
/// columns, whose low-word instructions the compiler drops here, where only
/// bits 16 to 63 are read; elsewhere the widening multiply).
[[nodiscard]] SW_FX_INLINE constexpr ProductTop product_top(FractionHalves f, std::uint32_t span) noexcept {
  const std::uint64_t p = fx::wide::mul_32x32_64((f.high << 16U) | f.low, span);
  return ProductTop{static_cast<std::uint32_t>(p >> 32U), static_cast<std::uint32_t>(p >> 16U) & 0xFFFFU};
}

/// P = a b as its two 32-bit words.
struct ProductWords {
  std::uint32_t high;
  std::uint32_t low;
};

/// a b's words (fx::wide::mul_32x32_64).
[[nodiscard]] SW_FX_INLINE constexpr ProductWords product_words(std::uint32_t a, std::uint32_t b) noexcept {
  const std::uint64_t p = fx::wide::mul_32x32_64(a, b);
  return ProductWords{static_cast<std::uint32_t>(p >> 32U), static_cast<std::uint32_t>(p)};
}

/// floor((P + 2^31 +- 2^23) / 2^32) from P's top: the bias is (2^15 +- 2^7)
/// 2^16, so the carry into the high word is that of bits16 + 2^15 +- 2^7.
/// `down`: the smaller bias (the value crossed zero; see interpolate_raw).
[[nodiscard]] SW_FX_INLINE constexpr std::uint32_t rounded_step(ProductTop p, bool down) noexcept {
  return p.high + ((p.bits16 + (down ? 0x7F80U : 0x8080U)) >> 16U);
}

/// One coefficient's interpolation from a to b (raw Q7.24), made once per
/// segment and call and then applied to each load's fraction
/// (interpolated_value): the ends' comparisons are not repeated per load
/// (round 16).
struct Interpolant {
  std::int32_t start;   ///< a
  std::uint32_t span;   ///< |b - a|, the modular 32-bit difference (exact: below 2^32); 0 when b = a
  std::uint32_t limit;  ///< |a| where a lies against d = b - a's sign (the value may cross zero), else 0
  std::int32_t sign;    ///< d's: -1 where b < a (the step is subtracted), else 1
};

[[nodiscard]] SW_FX_INLINE constexpr Interpolant interpolant_of(std::int32_t a_raw, std::int32_t b_raw) noexcept {
  const auto a_bits = static_cast<std::uint32_t>(a_raw);
  const auto b_bits = static_cast<std::uint32_t>(b_raw);
  if (b_raw < a_raw) {
    // Against d's sign: a > 0, |a| = a.
    return Interpolant{a_raw, a_bits - b_bits, (a_raw > 0) ? a_bits : 0U, -1};
  }
  // Against d's sign: a < 0, |a| = 0 - a modulo 2^32 (2^31 for INT32_MIN).
  return Interpolant{a_raw, b_bits - a_bits, (a_raw < 0) ? (0U - a_bits) : 0U, 1};
}

/// a + f (b - a) (raw Q7.24) for the fraction f in [0, 1), bit for bit the
/// Q31.32 interpolation (the dividing oracle's, host_tests/flight): with
/// d = b - a (|d| < 2^32) and P = f |d| < 2^64, that interpolation rounds
/// the step m = round(P / 2^24) (half up) into Q31.32 as a 2^8 +- m, and the
/// value v = a 2^8 +- m into Q7.24, half away from zero. Since a 2^8 is a
/// multiple of 2^8, v's rounding is a +- one of two roundings of m / 2^8:
///   up   = floor((m + 128) / 2^8) = floor((P + 2^31 + 2^23) / 2^32)
///            when v has d's sign (v rounds away from a),
///   down = floor((m + 127) / 2^8) = floor((P + 2^31 - 2^23) / 2^32)
///            when it has not (v crossed zero: it rounds back towards a)
/// (floor(floor(x) / k) = floor(x / k) for integer k). The value lies
/// between a and b, so the result fits Q7.24 and no status is needed (docs/performance.md, session 16).
///
/// v has d's sign when a has it too, or when m > |a| 2^8, that is (m an
/// integer) P >= |a| 2^32 + 2^23. The two roundings differ only where P's
/// low word is in [2^31 - 2^23, 2^31 + 2^23), and there that comparison is
/// P's high word >= |a| (session 18): down where P's high word is below
/// c.limit, which is 0 (never) where a has d's sign.
///
/// b = a gives P = 0 and a step of floor((2^31 +- 2^23) / 2^32) = 0: a
/// itself. The paper's Table 2 keeps C1, C2 and DP_max/W constant over the
/// loads; corrections_at stores a for such a coefficient without this
/// (round 14: per load; round 16: one test per call).
[[nodiscard]] SW_FX_INLINE constexpr std::int32_t interpolated_value(const Interpolant& c, FractionHalves f) noexcept {
  const ProductTop p = product_top(f, c.span);
  const std::uint32_t step = rounded_step(p, p.high < c.limit);
  // The step times d's sign, not a branch on it per load: one multiply-
  // accumulate (round 17). |step| < 2^32, so the sum is exact in 64 bits.
  const auto signed_step = static_cast<std::int64_t>(step);
  return static_cast<std::int32_t>(std::int64_t{c.start} + (signed_step * std::int64_t{c.sign}));
}

/// The interpolation above of the pair (a, b) at f in one call (the tests',
/// and correction_of's for a load beyond the first segment); b = a is a,
/// returned without the product.
[[nodiscard]] SW_FX_INLINE constexpr std::int32_t interpolate_raw(std::int32_t a_raw, std::int32_t b_raw,
                                                                   FractionHalves f) noexcept {
  if (b_raw == a_raw) {
    return a_raw;
  }
  return interpolated_value(interpolant_of(a_raw, b_raw), f);
}

}  // namespace detail

/// Once per table load. Widths that are not positive (a table validate()
/// refuses) stay zero, and corrections_at below then fails with a status,
/// never a number.
[[nodiscard]] CorrectionDivisors make_correction_divisors(const CorrectionTable& table) noexcept;

/// C1..C3 and DP_max/W at each load `load_n[i]` into `out[i]`, the
/// interpolation fraction's division by the segment width done with
/// `divisors` (made from this table); true when every `out[i].status` is ok.
/// A table that passed validate() never gives a status other than ok or
/// invalid_load. The per-cycle step passes its six loads in one call and
/// reads the results in place: the table's row count, first and last
/// breakpoints are read once per call, and no result record is returned
/// and copied per wheel (round 14). A load of the first segment (where a
/// lunar rover's loads lie with Table 2's breakpoints) is found by one
/// comparison of W - W_0 with a span worked out once per call, the same
/// outcome as the four load tests it passes (round 15; correction.cpp,
/// first_segment_span). Every load's first-segment fraction is worked out
/// first, then each coefficient for all N loads, its pair compared once per
/// call (a constant one stored as it is), and a load outside the first
/// segment is then overwritten by the search of its own segment (round 16).
/// Defined for N = 1 (the single-load form
/// below) and N = limits::kWheelCount. host_tests/flight/dividing_oracle.hpp
/// keeps the same function with a plain fx::div as the oracle it is
/// checked against bit for bit.
template <std::uint32_t N>
[[nodiscard]] bool corrections_at(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                  const WheelLoadN (&load_n)[N], CorrectionResult (&out)[N]) noexcept;

extern template bool corrections_at<1U>(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                          const WheelLoadN (&load_n)[1U], CorrectionResult (&out)[1U]) noexcept;
extern template bool corrections_at<limits::kWheelCount>(
    const CorrectionTable& table, const CorrectionDivisors& divisors, const WheelLoadN (&load_n)[limits::kWheelCount],
    CorrectionResult (&out)[limits::kWheelCount]) noexcept;

/// C1..C3 and DP_max/W at the one load `load_n`: the batch form's
/// one-element case (the monitor's own evaluation, the table's checks).
[[nodiscard]] inline CorrectionResult corrections_at(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                                     WheelLoadN load_n) noexcept {
  const WheelLoadN loads[1U]{load_n};
  CorrectionResult result[1U]{};
  static_cast<void>(corrections_at<1U>(table, divisors, loads, result));  // the status is in the result
  return result[0U];
}

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_CORRECTION_HPP
