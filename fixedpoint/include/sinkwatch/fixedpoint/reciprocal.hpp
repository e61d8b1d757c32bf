// reciprocal.hpp: 1/d of a positive fixed-point value as a normalised 32-bit
// mantissa and a power of two, and quotients x/d as one 32 x 32 -> 64-bit
// product with it.
//
// Where one divisor serves several quotients (a lever and the forces on it,
// the wheel-load statics of docs/rover-loads.md, section 7.4), one division
// per divisor and a product per quotient replace a division per quotient. A
// fixed-format reciprocal loses relative precision as d grows (1/d of a lever
// of 30 m in Q10.21 keeps 16 bits); the mantissa here keeps 32 bits whatever
// d is, the shift carries the magnitude.
//
// Definition (every target computes exactly these integers):
//   D > 0 the divisor's magnitude (raw) with Fd fraction bits, n = bit_length(D);
//   Dn = D * 2^(32-n) for n <= 32, floor(D / 2^(n-32)) for n > 32: Dn in [2^31, 2^32);
//   mantissa = floor((2^63 - 1) / Dn), in [2^31, 2^32);
//   1/d ~ mantissa * 2^-scale, scale = 31 + n - Fd.
// Truncating D and flooring the quotient each err by less than 2^-31
// relative, so mantissa * 2^-scale is within 2^-30 of 1/d, relative.
//
// times_reciprocal<Out>(x, r) = x * mantissa * 2^-(Fx + scale - Fout), rounded to
// nearest (ties away from zero) on the magnitude: within 0.5 LSB of Out plus
// |x/d| * 2^-30. It saturates and raises overflow when the quotient leaves Out.
// host_tests/fixedpoint/test_reciprocal.cpp checks the definition and the
// bound against the exact quotient.
//
// Not to be confused with fx::reciprocal (sqrt.hpp: 1/x as a Q value, one
// division, 0.5 LSB) or flight's ConstantDivisor (constant_divisor.hpp:
// exact quotients by a table constant, fx::div's bits): this one trades the
// last bit for one division per run-time divisor and a product per quotient.
#ifndef SINKWATCH_FIXEDPOINT_RECIPROCAL_HPP
#define SINKWATCH_FIXEDPOINT_RECIPROCAL_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace fx {

/// 1/d ~ mantissa * 2^-scale; mantissa == 0 marks "no reciprocal" (d == 0).
struct NormalisedReciprocal {
  std::uint32_t mantissa{0U};
  std::int32_t scale{0};
};

namespace detail {

/// The mantissa floor((2^63 - 1) / v), v in [2^31, 2^32), and the quotients of
/// normalised_quotient.hpp come from one long division: the two-digit long
/// division of Hacker's Delight (2nd ed., figure 9-3, divlu) in base 2^16 with
/// 32-bit words only. Each digit's estimate from the divisor's high half is at most
/// two too large and is corrected at most twice, so both loops are bounded by
/// two. The result is the exact floor (test_reciprocal checks it against its
/// definition): the bits of a 64-bit library division at the cost of two
/// 32 / 16-bit divisions, which a core without a divide instruction does in
/// a fraction of __udivmoddi4's time (docs/performance.md, session 12).
constexpr std::uint32_t kDigitBase = 0x10000U;

/// One quotient digit of that division: the estimate of `partial` over the
/// divisor's high digit, corrected at most twice against its low digit (one
/// correction stops once the remainder leaves the digit: then
/// kDigitBase * rhat would not fit, and the estimate is right). Both counted
/// loops are simple (MISRA C++:2023 rule 9.5.1: no break).
constexpr std::uint32_t quotient_digit(std::uint32_t partial, std::uint32_t v_high, std::uint32_t v_low,
                                       std::uint32_t next_digit) noexcept {
  std::uint32_t q = partial / v_high;
  std::uint32_t rhat = partial - (q * v_high);
  bool correcting = true;
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    correcting = correcting && ((q >= kDigitBase) || ((q * v_low) > ((kDigitBase * rhat) + next_digit)));
    if (correcting) {
      --q;
      rhat += v_high;
      correcting = rhat < kDigitBase;
    }
  }
  return q;
}

/// floor(u / v) and u mod v for v in [2^31, 2^32) and u < v * 2^32 (the
/// quotient fits 32 bits; the caller normalises): two digits in base 2^16,
/// each from quotient_digit. The partial remainders fit 32 bits, and the
/// wrapping 32-bit arithmetic gives them exactly (Hacker's Delight's divlu).
constexpr wide::DivMod<std::uint32_t> divide_64_by_32(std::uint64_t u, std::uint32_t v) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  // v >= 2^31, so the high digit is at least 2^15: the OR changes nothing
  // but shows the static analyser a divisor that cannot be zero.
  const std::uint32_t v_high = (v >> 16U) | 0x8000U;
  const std::uint32_t v_low = v & 0xFFFFU;
  const auto u_high = static_cast<std::uint32_t>(u / kWord);  // u >> 32 without a library shift
  const auto u_low = static_cast<std::uint32_t>(u);
  const std::uint32_t u_high_digit = u_low >> 16U;
  const std::uint32_t u_low_digit = u_low & 0xFFFFU;
  const std::uint32_t q1 = quotient_digit(u_high, v_high, v_low, u_high_digit);
  const std::uint32_t partial = ((u_high * kDigitBase) + u_high_digit) - (q1 * v);
  const std::uint32_t q0 = quotient_digit(partial, v_high, v_low, u_low_digit);
  const std::uint32_t remainder = ((partial * kDigitBase) + u_low_digit) - (q0 * v);
  return wide::DivMod<std::uint32_t>{(q1 * kDigitBase) + q0, remainder};
}

}  // namespace detail

/// The reciprocal of the positive magnitude `d_raw` with `d_frac_bits`
/// fraction bits; d_raw == 0 gives mantissa 0 (times_reciprocal() then reports
/// div_by_zero).
[[nodiscard]] constexpr NormalisedReciprocal normalised_reciprocal(std::uint64_t d_raw, std::int32_t d_frac_bits) noexcept {
  if (d_raw == 0U) {
    return NormalisedReciprocal{};
  }
  const std::uint32_t n = wide::bit_length(d_raw);
  const std::uint64_t normalised = (n <= 32U) ? wide::shl(d_raw, 32U - n) : wide::shr(d_raw, n - 32U);
  // normalised is in [2^31, 2^32): the high half of the divisor is at least
  // 2^15, never zero.
  constexpr std::uint64_t kTwoTo63Less1 = ~std::uint64_t{0U} >> 1U;
  const std::uint32_t mantissa =
      detail::divide_64_by_32(kTwoTo63Less1, static_cast<std::uint32_t>(normalised)).quotient;
  return NormalisedReciprocal{mantissa, (31 + static_cast<std::int32_t>(n)) - d_frac_bits};
}

/// The reciprocal of a positive Q value (a non-positive one gives no
/// reciprocal: divisors here are lengths and weights checked positive).
template <typename S, std::int32_t F>
[[nodiscard]] constexpr NormalisedReciprocal normalised_reciprocal(Q<S, F> d) noexcept {
  return (d.raw() > 0) ? normalised_reciprocal(static_cast<std::uint64_t>(d.raw()), F) : NormalisedReciprocal{};
}

/// x / d in the format Out from d's reciprocal r. Out may have 64-bit
/// storage, to keep a quotient that only a later sum brings into range.
template <typename Out, std::int32_t Fx>
[[nodiscard]] constexpr Out times_reciprocal(Q<std::int32_t, Fx> x, NormalisedReciprocal r, Status& status) noexcept {
  using OutS = typename Out::storage_type;
  const bool negative = detail::is_negative(x.raw());
  if (r.mantissa == 0U) {
    status.raise(Flag::div_by_zero);
    if (x.raw() == 0) {
      return Out::zero();
    }
    return negative ? Out::min() : Out::max();
  }
  const std::uint64_t product =
      wide::mul_32x32_64(static_cast<std::uint32_t>(detail::magnitude(x.raw())), r.mantissa);  // < 2^63
  const std::int32_t shift = (Fx + r.scale) - Out::frac_bits;
  // shift <= 0: a non-zero product is >= 2^31 and would only grow, beyond
  // Out. shift >= 64: product / 2^shift < 1/2 rounds to zero.
  const bool grows = shift <= 0;
  const bool rounds = (shift > 0) && (shift < 64);
  std::uint64_t mag = (grows && (product != 0U)) ? ~std::uint64_t{0U} : 0U;
  if (rounds) {
    const auto s = static_cast<std::uint32_t>(shift);
    mag = (product + (std::uint64_t{1U} << (s - 1U))) >> s;  // no carry out: product < 2^63
  }
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_RECIPROCAL_HPP
