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
// division, 0.5 LSB): this one trades the last bit for one reciprocal per
// run-time divisor and a product per quotient. Where the exact quotient is
// needed (flight's corrections, correction.cpp), the product is corrected
// against the remainder.
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

/// floor((2^63 - 1) / v) for v in [2^31, 2^32): the quotient of the exact
/// 64 / 32-bit division (2^63 - 1 < v 2^32, so it fits 32 bits), which on a
/// core without a divide instruction takes no division either
/// (wide::divide_64_by_32_by_reciprocal: a seed, one Newton step and 16-bit
/// products, docs/fixedpoint.md 5.8). Until session 18 this was a second
/// Newton step at full width and a correction against the remainder (about
/// 150 instructions on the Cortex-M0 and 57 on the M4, against about 110
/// and 50 after it), the same floor. Where the core divides words, the two
/// digits are corrected against their exact remainders since round 16
/// (wide::detail::digit_by_remainder: about 26 instructions on the M4
/// against 31).
constexpr std::uint32_t floor_two_to_63_less_1_over(std::uint32_t v) noexcept {
  constexpr std::uint64_t kNumerator = (std::uint64_t{1U} << 63U) - 1U;
  return wide::divide_64_by_32(kNumerator, v).quotient;
}

/// True where a 64-bit shift by a run-time count is a library call
/// (__aeabi_llsr, about 12 instructions and the call): ARMv6-M, the cores
/// wide::kMul32x32BySoftware names. ARMv7-M (the Cortex-M4), ARMv7-A and
/// x86-64 shift inline, and there the word form below measured slower.
constexpr bool kShift64BySoftware = wide::kMul32x32BySoftware;

/// value / 2^s rounded to nearest, ties up, for s in [1, 63]: with
/// x = floor(value / 2^(s-1)), floor(x / 2) + (x mod 2) (the same integer as
/// (value + 2^(s-1)) >> s, without its carry). x is formed on 32-bit words
/// (high >> t; low >> t joined by high << (32 - t), written as two shifts so
/// that t = 0 needs no case). The form for kShift64BySoftware; the host tests
/// call it directly (test_reciprocal: against the 64-bit shift for every s).
SW_FX_INLINE constexpr std::uint64_t shift_right_rounded_by_words(std::uint64_t value, std::uint32_t s) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(value / kWord);
  const auto low = static_cast<std::uint32_t>(value);
  const std::uint32_t t = s - 1U;  // 0..62
  if (t >= 32U) {
    const std::uint32_t x = high >> (t - 32U);
    return std::uint64_t{(x >> 1U) + (x & 1U)};
  }
  const std::uint64_t x =
      (std::uint64_t{high >> t} * kWord) | std::uint64_t{(low >> t) | ((high << 1U) << (31U - t))};
  return (x >> 1U) + (x & 1U);
}

/// value / 2^s rounded to nearest, ties up, for value < 2^63 and s in
/// [1, 63], in the core's cheaper form: one 64-bit shift by s - 1
/// ((value + 2^(s-1)) >> s as ((value >> (s-1)) + 1) >> 1, the same integer),
/// or the word form above. The same integer either way.
SW_FX_INLINE constexpr std::uint64_t shift_right_rounded(std::uint64_t value, std::uint32_t s) noexcept {
  if constexpr (kShift64BySoftware) {
    return shift_right_rounded_by_words(value, s);
  } else {
    return ((value >> (s - 1U)) + 1U) >> 1U;
  }
}

/// |x| / d on magnitudes, times_reciprocal's core: |x| times the mantissa
/// (one 32 x 32-bit product, below 2^63) rounded by `shift` = Fx + scale -
/// Fout; a shift >= 64 rounds to zero, and a shift <= 0 gives 0 here: there
/// a non-zero product would only grow, beyond every format
/// (times_mantissa_grows, the caller's overflow). A caller that goes on with
/// the magnitude (the flight code's current limit adds I0 to it in 64 bits,
/// where it cannot overflow) takes these two; times_reciprocal puts the sign
/// back and saturates.
SW_FX_INLINE constexpr std::uint64_t times_mantissa(std::uint32_t x_magnitude, std::uint32_t mantissa,
                                                    std::int32_t shift) noexcept {
  const std::uint64_t product = wide::mul_32x32_64(x_magnitude, mantissa);  // < 2^63
  std::uint64_t rounded = 0U;
  if ((shift > 0) && (shift < 64)) {
    // (product + 2^(s-1)) >> s without a 64-bit shift by a run-time count.
    rounded = shift_right_rounded(product, static_cast<std::uint32_t>(shift));
  }
  return rounded;
}

/// Whether times_mantissa's product is one a shift <= 0 would grow (the
/// same product: inline beside times_mantissa, it is formed once).
SW_FX_INLINE constexpr bool times_mantissa_grows(std::uint32_t x_magnitude, std::uint32_t mantissa,
                                                 std::int32_t shift) noexcept {
  return (shift <= 0) && (wide::mul_32x32_64(x_magnitude, mantissa) != 0U);
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
  // A divisor of one word (every 32-bit Q value) shifts as a word: a 64-bit
  // shift by a variable count is a library call on 32-bit cores.
  const std::uint32_t normalised = (n <= 32U) ? (static_cast<std::uint32_t>(d_raw) << (32U - n))
                                             : static_cast<std::uint32_t>(wide::shr(d_raw, n - 32U));
  // normalised is in [2^31, 2^32).
  const std::uint32_t mantissa = detail::floor_two_to_63_less_1_over(normalised);
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
  // A product that a shift <= 0 would grow saturates (overflow).
  const auto x_magnitude = static_cast<std::uint32_t>(detail::magnitude(x.raw()));
  const std::int32_t shift = (Fx + r.scale) - Out::frac_bits;
  const std::uint64_t mag = detail::times_mantissa_grows(x_magnitude, r.mantissa, shift)
                                ? ~std::uint64_t{0U}
                                : detail::times_mantissa(x_magnitude, r.mantissa, shift);
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_RECIPROCAL_HPP
