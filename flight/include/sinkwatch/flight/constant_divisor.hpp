// constant_divisor.hpp: division by a parameter-table constant through a
// reciprocal computed once per table load, with exactly the bits of fx::div.
//
// The per-cycle chain divides by numbers that change only with the table: the
// spacing W_k+1 - W_k of Table 2's load breakpoints (the interpolation
// fraction of the corrections C1..C3 and DP_max/W of Eq. 11) and the motor
// model's N, eta and Kt (I = T / (N eta Kt) + I0, the current limit of
// section 7). On a core without a divide instruction each fx::div there is a
// 64-bit library division (__udivmoddi4). Here the divisor d carries
// m = floor((2^64 - 1) / d), computed once; a division is then one 64x64-bit
// multiply, q' = floor(n m / 2^64), and one correction step:
//
//   m >= 2^64/d - 1  gives  n m / 2^64 > n/d - 1,  and  m <= 2^64/d  gives
//   n m / 2^64 <= n/d; so q' is q = floor(n/d) or q - 1, and r = n - q' d
//   (exact: q' d <= n < 2^64) is below d after at most one d is taken off.
//
// Quotient and remainder are therefore the exact ones, and the rounding (half
// away from zero, on the magnitude) and the saturation are fx::div's own: the
// result is bit-for-bit fx::div's (test_constant_divisor asserts it). When
// the shifted dividend does not fit in 64 bits the division falls back to
// fx::div itself.
#ifndef SINKWATCH_FLIGHT_CONSTANT_DIVISOR_HPP
#define SINKWATCH_FLIGHT_CONSTANT_DIVISOR_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace flight {

/// A 32-bit Q divisor and its reciprocal; reciprocal 0 means "divide by
/// fx::div" (a zero divisor, or one not prepared).
template <typename QB>
struct ConstantDivisor {
  QB value{};
  std::uint64_t reciprocal{0U};
};

/// Prepares `b` for repeated division (once per parameter load).
template <typename QB>
[[nodiscard]] constexpr ConstantDivisor<QB> make_divisor(QB b) noexcept {
  static_assert(QB::total_bits == 32U, "constant divisors are 32-bit formats");
  const std::uint64_t d = fx::detail::magnitude(b.raw());
  return ConstantDivisor<QB>{b, (d == 0U) ? 0U : (~std::uint64_t{0U} / d)};
}

namespace detail {

/// floor(n / d) and n mod d for d = |divisor|, m its reciprocal.
constexpr fx::wide::DivMod<std::uint64_t> divide_by_reciprocal(std::uint64_t n, std::uint64_t d,
                                                               std::uint64_t m) noexcept {
  std::uint64_t q = fx::wide::mul_full(n, m).hi;
  std::uint64_t r = n - fx::wide::mul_64x64_low(q, d);
  if (r >= d) {
    r -= d;
    ++q;
  }
  return fx::wide::DivMod<std::uint64_t>{q, r};
}

}  // namespace detail

/// m = floor((2^64 - 1) / d) for repeated division of 64-bit magnitudes by
/// d > 0 (d = 0 gives 0, which rounded_quotient must not be given).
[[nodiscard]] constexpr std::uint64_t reciprocal_of(std::uint64_t d) noexcept {
  return (d == 0U) ? 0U : (~std::uint64_t{0U} / d);
}

/// n / d rounded half up, fx::div's rounding of a magnitude, with m =
/// reciprocal_of(d), d > 0; exact for every n (the quotient is at most n).
[[nodiscard]] constexpr std::uint64_t rounded_quotient(std::uint64_t n, std::uint64_t d, std::uint64_t m) noexcept {
  const fx::wide::DivMod<std::uint64_t> qr = detail::divide_by_reciprocal(n, d, m);
  // Round half away from zero: up when remainder >= divisor - remainder.
  return (qr.remainder >= (d - qr.remainder)) ? (qr.quotient + 1U) : qr.quotient;
}

/// round(2^64 / d), half up, for 3 <= d: the raw Q31.32 reciprocal of a
/// Q31.32 value of raw d (one is 2^32 raw, so 1/v is 2^64/d raw), bit for bit
/// fx::div(one, v) for v >= 3 raw (smaller v leave Q31.32), from one 64-bit division of 2^64 - 1 and a
/// fix-up of its remainder (2^64 = q d + r with 1 <= r <= d) instead of the
/// 128-bit long division. Per cycle: the wheel-load statics' 1/lever.
/// d < 3 (never given by the statics, whose levers are >= 2^22 raw) returns
/// 2^63 - 1, the largest Q31.32 raw value, which fx::div saturates to.
[[nodiscard]] constexpr std::uint64_t rounded_reciprocal_q32(std::uint64_t d) noexcept {
  if (d < 3U) {
    return ~std::uint64_t{0U} >> 1U;
  }
  std::uint64_t q = ~std::uint64_t{0U} / d;
  std::uint64_t r = (~std::uint64_t{0U} % d) + 1U;
  if (r == d) {
    ++q;
    r = 0U;
  }
  return (r >= (d - r)) ? (q + 1U) : q;
}

/// a / b in the format Out, bit-for-bit fx::div<Out>(a, b.value).
template <typename Out, typename SA, std::int32_t FA, typename QB>
[[nodiscard]] constexpr Out div_by_constant(fx::Q<SA, FA> a, const ConstantDivisor<QB>& b,
                                            fx::Status& status) noexcept {
  constexpr std::int32_t k = (Out::frac_bits + QB::frac_bits) - FA;
  static_assert((k >= 0) && (k < 64), "the dividend is scaled up by 2^k, 0 <= k < 64");
  const std::uint64_t mag_a = fx::detail::magnitude(a.raw());
  if ((b.reciprocal == 0U) || (fx::wide::bit_length(mag_a) > static_cast<std::uint32_t>(64 - k))) {
    return fx::div<Out>(a, b.value, status);
  }
  const bool negative = fx::detail::is_negative(a.raw()) != fx::detail::is_negative(b.value.raw());
  const std::uint64_t den = fx::detail::magnitude(b.value.raw());
  const std::uint64_t mag =
      rounded_quotient(fx::wide::shl(mag_a, static_cast<std::uint32_t>(k)), den, b.reciprocal);
  using OutS = typename Out::storage_type;
  return Out::from_raw(fx::detail::from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_CONSTANT_DIVISOR_HPP
