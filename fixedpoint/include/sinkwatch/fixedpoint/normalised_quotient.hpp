// normalised_quotient.hpp: n / d for operands of any scale, from one 64 / 32-bit
// long division of their leading bits, rounded into a Q format.
//
// Where a quotient's operands are products of inputs (Eq. 11's sinkage
// (C1 T - r (C3 W + DP)) / (C2 W), the section 7 torque limit W L / C1), an
// exact quotient needs a 128-bit dividend; the flight code's chains took one
// per division through the Q31.32 path. Here both operands are normalised to
// their leading 32 bits (wide::leading_word, truncated: < 2^-31 relative
// each),
//
//   |n| ~ N * 2^a,  |d| ~ D * 2^b,  N, D in [2^31, 2^32),
//   q = floor(N 2^31 / D), in (2^30, 2^32)  (wide::divide_64_by_32, exact:
//         two base-2^16 digits, each from a 32-bit division where the core
//         has a divide instruction, else from a reciprocal of D and 16-bit
//         products with at most two corrections; docs/fixedpoint.md 5.8),
//
// and n / d ~ q * 2^(a - b - 31). The floor loses < 2^-30 relative, the
// truncations < 2^-31 each (in opposite directions for n and d), so
// q * 2^(a - b - 31) is within |n/d| * 2^-29 of n/d. Rounding into Out (to
// nearest, ties away from zero, on the magnitude) adds 0.5 LSB:
//
//   |divide_normalised<Out>(n, d) - n/d| <= 0.5 LSB(Out) + |n/d| * 2^-29.
//
// Every shift by a run-time count is on 32-bit words (a 64-bit one is a
// library call on 32-bit cores).
// A quotient beyond Out saturates and raises overflow; d == 0 raises
// div_by_zero and gives 0 for n == 0, else the saturated value of n's sign.
// host_tests/fixedpoint/test_normalised_quotient.cpp checks the bound against
// the exact quotient over random and edge operands.
#ifndef SINKWATCH_FIXEDPOINT_NORMALISED_QUOTIENT_HPP
#define SINKWATCH_FIXEDPOINT_NORMALISED_QUOTIENT_HPP

#include <cstdint>
#include <limits>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace fx {

/// A signed value with a run-time scale: (negative ? -1 : 1) * magnitude * 2^-frac_bits.
/// For operands whose scale is only known at run time (a product whose
/// leading bits were kept, flight/src/current_limit.cpp).
struct ScaledMagnitude {
  bool negative{false};
  std::uint64_t magnitude{0U};
  std::int32_t frac_bits{0};
};

/// The Q value as a ScaledMagnitude (exact; INT64_MIN's magnitude is 2^63).
template <typename S, std::int32_t F>
[[nodiscard]] constexpr ScaledMagnitude to_scaled(Q<S, F> x) noexcept {
  return ScaledMagnitude{detail::is_negative(x.raw()), detail::magnitude(x.raw()), F};
}

namespace detail {

/// q * 2^exponent rounded to an integer (to nearest, ties up) for q < 2^32;
/// all ones when it needs more than 64 bits (every format then saturates).
/// Inline: in a file with two divisions GCC -Os made it a call (session 19:
/// M0 -27, M4 -92 per step).
SW_FX_INLINE constexpr std::uint64_t scale_quotient(std::uint32_t q, std::int32_t exponent) noexcept {
  if (exponent > 32) {
    return ~std::uint64_t{0U};
  }
  if (exponent >= 0) {
    return wide::shl(std::uint64_t{q}, static_cast<std::uint32_t>(exponent));  // < 2^64
  }
  if (exponent < -32) {
    return 0U;  // q * 2^exponent < 2^32 * 2^-33 = 1/2
  }
  // x = floor(q / 2^(s-1)), then floor(x / 2) + (x mod 2): q / 2^s rounded
  // half up, all in one 32-bit word (x + 1 would need 33 bits for x =
  // 2^32 - 1; a 64-bit shift by a variable count is a library call on
  // 32-bit cores).
  const std::uint32_t x = q >> (static_cast<std::uint32_t>(-exponent) - 1U);
  return std::uint64_t{(x >> 1U) + (x & 1U)};
}

/// A magnitude's leading 32 bits and its bit length.
struct LeadingBits {
  std::uint32_t word;  ///< a 2^(32 - bits), truncated when bits > 32: in [2^31, 2^32)
  std::uint32_t bits;  ///< wide::bit_length(a)
};

/// For a > 0: wide::leading_word and wide::bit_length in one pass, by halving
/// steps that shift the word left (16, 8, 4, 2 and 1 bits) until its top bit
/// is set and count the bits it lacked; a high word then takes the low
/// word's top bits. The form for cores without a count of leading zeros
/// (ARMv6-M: about 22 instructions where the two helpers took about 30);
/// the host tests call it directly (test_normalised_quotient).
SW_FX_INLINE constexpr LeadingBits leading_bits_by_halves(std::uint64_t a) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  const auto low = static_cast<std::uint32_t>(a);
  std::uint32_t word = (high != 0U) ? high : low;
  std::uint32_t bits = (high != 0U) ? 64U : 32U;
  if ((word >> 16U) == 0U) {
    word <<= 16U;
    bits -= 16U;
  }
  if ((word >> 24U) == 0U) {
    word <<= 8U;
    bits -= 8U;
  }
  if ((word >> 28U) == 0U) {
    word <<= 4U;
    bits -= 4U;
  }
  if ((word >> 30U) == 0U) {
    word <<= 2U;
    bits -= 2U;
  }
  if ((word >> 31U) == 0U) {
    word <<= 1U;
    bits -= 1U;
  }
  // A high word shifted left by 64 - bits (1 to 31) takes as many of the
  // low word's top bits.
  if ((high != 0U) && (bits < 64U)) {
    word |= low >> (bits - 32U);
  }
  return LeadingBits{word, bits};
}

/// The leading bits of a = high 2^32 + low with high != 0, by one count of
/// leading zeros of high (s, 0 to 31): high shifted left by s takes low's
/// top s bits as (low >> 1) >> (31 - s), the shift by 32 - s (32, no C++
/// shift, at s == 0) split so that neither part reaches 32. The one form
/// of the three callers below.
SW_FX_INLINE constexpr LeadingBits leading_bits_of_high_word(std::uint32_t high, std::uint32_t low) noexcept {
  const auto s = static_cast<std::uint32_t>(__builtin_clz(high));
  return LeadingBits{(high << s) | ((low >> 1U) >> (31U - s)), 64U - s};
}

/// The leading bits of a = low (high word zero), counted on `counted`, a
/// non-zero word with low's leading one (low itself, or low | 1 where low
/// may be zero: __builtin_clz(0) is undefined).
SW_FX_INLINE constexpr LeadingBits leading_bits_of_low_word(std::uint32_t low, std::uint32_t counted) noexcept {
  const auto s = static_cast<std::uint32_t>(__builtin_clz(counted));
  return LeadingBits{low << s, 32U - s};
}

/// For a > 0: the same two integers from one count of leading zeros of the
/// word that holds a's leading one, without a branch on the count. A high
/// word shifted left by s (0 to 31) takes the low word's top s bits as
/// (low >> 1) >> (31 - s): the shift by 32 - s, which is 32 (no C++ shift)
/// at s == 0, split so that neither part reaches 32. The count of `low | 1`
/// is low's for low != 0, and keeps __builtin_clz away from 0 (undefined)
/// at a == 0, where it gives the halving form's word 0 and bit length 1.
/// Only where the core counts leading zeros in one instruction (round 15:
/// the two-helper form branched on the high word's count and again on a
/// count of 0). The host tests call it directly against the halving form
/// and the two helpers (test_normalised_quotient).
SW_FX_INLINE constexpr LeadingBits leading_bits_by_clz(std::uint64_t a) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  const auto low = static_cast<std::uint32_t>(a);
  if (high != 0U) {
    return leading_bits_of_high_word(high, low);
  }
  return leading_bits_of_low_word(low, low | 1U);
}

/// For a > 0, a's leading 32 bits and bit length in the core's cheaper form:
/// a count of leading zeros where the core has one (wide::kClzInstruction),
/// else the halving steps above. The same two integers either way. For
/// a == 0 the word is 0 and the bit length has no meaning (1): a zero
/// operand is answered before its scale is looked at.
SW_FX_INLINE constexpr LeadingBits leading_bits(std::uint64_t a) noexcept {
  if constexpr (wide::kClzInstruction) {
    return leading_bits_by_clz(a);
  } else {
    return leading_bits_by_halves(a);
  }
}

/// For a != 0: true and a's leading bits (leading_bits_by_clz's two
/// integers) in `out`; for a == 0: false, `out` untouched. A non-zero high
/// word answers the test for zero by itself, so a == 0 is tested only on
/// the path where the high word is 0 (round 16: the quotient's test of its
/// leading word, after either path, was a comparison and a branch more per
/// division). The host tests call it directly (test_normalised_quotient).
SW_FX_INLINE constexpr bool leading_bits_unless_zero_by_clz(std::uint64_t a, LeadingBits& out) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  const auto low = static_cast<std::uint32_t>(a);
  if (high != 0U) {
    out = leading_bits_of_high_word(high, low);
    return true;
  }
  if (low == 0U) {
    return false;
  }
  out = leading_bits_of_low_word(low, low);
  return true;
}

/// For a > 0: leading_bits_by_clz's two integers without its guard of the
/// count against a zero low word (`low | 1`): a > 0 with a zero high word
/// has a non-zero low word. For the quotient's divisor, positive by its
/// contract (round 16: one instruction fewer per division, where the
/// divisor's high word is zero). The host tests call it directly.
SW_FX_INLINE constexpr LeadingBits leading_bits_of_positive_by_clz(std::uint64_t a) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  const auto low = static_cast<std::uint32_t>(a);
  if (high != 0U) {
    return leading_bits_of_high_word(high, low);
  }
  return leading_bits_of_low_word(low, low);
}

/// For a > 0, leading_bits(a) in the core's cheaper form (the same two
/// integers).
SW_FX_INLINE constexpr LeadingBits leading_bits_of_positive(std::uint64_t a) noexcept {
  if constexpr (wide::kClzInstruction) {
    return leading_bits_of_positive_by_clz(a);
  } else {
    return leading_bits_by_halves(a);
  }
}

/// a != 0, and a's leading bits in `out` when it is, in the core's cheaper
/// form: the count of leading zeros above, else the halving steps and a
/// test of their word (0 only for a == 0). The same answer either way.
SW_FX_INLINE constexpr bool leading_bits_unless_zero(std::uint64_t a, LeadingBits& out) noexcept {
  if constexpr (wide::kClzInstruction) {
    return leading_bits_unless_zero_by_clz(a, out);
  } else {
    out = leading_bits_by_halves(a);
    return out.word != 0U;
  }
}

/// floor(n 2^31 / d) for n and d in [2^31, 2^32), wide::quotient_of_leading_words'
/// integer, from m = floor((2^63 - 1) / d) (reciprocal.hpp's
/// floor_two_to_63_less_1_over, prepared once for a divisor that recurs):
/// 2^63 - m d is in [1, d], so n 2^31 / d exceeds n m / 2^32 by
/// n (2^63 - m d) / (d 2^32), in (0, n / 2^32] and so in (0, 1): the quotient
/// is e = floor(n m / 2^32) or e + 1, and the remainder n 2^31 - e d, in
/// [0, 2 d), says which. Two 32 x 32-bit products and a 64-bit comparison
/// in place of the long division (round 17). test_normalised_quotient checks
/// it against the built-in division.
SW_FX_INLINE constexpr std::uint32_t quotient_of_leading_words_by_reciprocal(std::uint32_t n, std::uint32_t d,
                                                                             std::uint32_t m) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto estimate = static_cast<std::uint32_t>(wide::mul_32x32_64(n, m) / kWord);
  const std::uint64_t rest = (std::uint64_t{n} << 31U) - wide::mul_32x32_64(estimate, d);  // in [0, 2 d)
  return estimate + ((rest >= d) ? 1U : 0U);
}

}  // namespace detail

/// n / d rounded into Out, within 0.5 LSB + |n/d| 2^-29 (above).
template <typename Out>
[[nodiscard]] constexpr Out divide_normalised(ScaledMagnitude n, ScaledMagnitude d, Status& status) noexcept {
  using OutS = typename Out::storage_type;
  const bool negative = n.negative != d.negative;
  if (d.magnitude == 0U) {
    status.raise(Flag::div_by_zero);
    if (n.magnitude == 0U) {
      return Out::zero();
    }
    return n.negative ? Out::min() : Out::max();
  }
  if (n.magnitude == 0U) {
    return Out::zero();
  }
  // Both leading words in [2^31, 2^32); n's times 2^31 has a high word below
  // d's, so the quotient fits 32 bits.
  const detail::LeadingBits n_leading = detail::leading_bits(n.magnitude);
  const detail::LeadingBits d_leading = detail::leading_bits(d.magnitude);
  const std::uint32_t q = wide::divide_64_by_32(std::uint64_t{n_leading.word} << 31U, d_leading.word).quotient;
  // n/d ~ q * 2^(n_bits - d_bits - 31 - n.frac + d.frac); in Out's raw units
  // q * 2^exponent with:
  const std::int32_t exponent =
      ((static_cast<std::int32_t>(n_leading.bits) - static_cast<std::int32_t>(d_leading.bits)) - 31) -
      ((n.frac_bits - d.frac_bits) - Out::frac_bits);
  const std::uint64_t mag = detail::scale_quotient(q, exponent);
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

/// n / d for Q operands (the common case: both scales known when compiled).
template <typename Out, typename SN, std::int32_t FN, typename SD, std::int32_t FD>
[[nodiscard]] constexpr Out divide_normalised(Q<SN, FN> n, Q<SD, FD> d, Status& status) noexcept {
  return divide_normalised<Out>(to_scaled(n), to_scaled(d), status);
}

/// A divisor's reciprocal prepared by the caller for quotient_by_positive:
/// `mantissa` = fx::normalised_reciprocal(d).mantissa where `prepared`.
struct PreparedReciprocal {
  bool prepared{false};
  std::uint32_t mantissa{0U};
};

/// divide_normalised<Out>(n, d, st) for a 32-bit Out (kOutFrac fraction
/// bits) and a divisor d > 0, as its raw quotient (`raw`) and whether st
/// stayed ok (the return): the same leading words, the same quotient
/// q = floor(N 2^31 / D), the same rounding and so the same error bound;
/// only what a caller with a divisor known positive does not need is left
/// out: d == 0, the 64-bit scaling of q and the saturated value of an
/// overflow (`raw` is 0 then). The flight code's Eq. 11 and section 7
/// limit (flight/src/of_valid.hpp: C2 W and C1 are positive) divide with it. The
/// overflow decision on 32-bit words: q >= 2^30 (N >= 2^31, D < 2^32), so
/// for an exponent e >= 1 q 2^e >= 2^31 fits only as -2^31 (e == 1, q ==
/// 2^30); for e <= 0 the rounded magnitude is below 2^32 and is compared
/// with 2^31 - 1 or 2^31 as from_sign_magnitude compares it. Both forms
/// over random and edge operands: host_tests/fixedpoint/
/// test_normalised_quotient.cpp (QuotientByPositive).
///
/// With `reciprocal.prepared`, its mantissa is floor((2^63 - 1) / D) for
/// d's leading word D (fx::normalised_reciprocal(d).mantissa), prepared
/// once for a divisor that recurs, and q is found from it
/// (detail::quotient_of_leading_words_by_reciprocal: the same q without the
/// long division); else (PreparedReciprocal{}, a divisor that does not
/// recur) the mantissa is not read.
template <std::int32_t kOutFrac>
SW_FX_INLINE bool quotient_by_positive(bool negative, std::uint64_t n_magnitude, std::int32_t n_frac,
                                       std::uint64_t d_magnitude, std::int32_t d_frac,
                                       PreparedReciprocal reciprocal, std::int32_t& raw) noexcept {
  raw = 0;
  detail::LeadingBits n_leading{0U, 0U};
  if (!detail::leading_bits_unless_zero(n_magnitude, n_leading)) {
    return true;  // n == 0
  }
  const detail::LeadingBits d_leading = detail::leading_bits_of_positive(d_magnitude);
  const std::int32_t exponent =
      ((static_cast<std::int32_t>(n_leading.bits) - static_cast<std::int32_t>(d_leading.bits)) - 31) -
      ((n_frac - d_frac) - kOutFrac);
  const std::uint32_t q =
      reciprocal.prepared
          ? detail::quotient_of_leading_words_by_reciprocal(n_leading.word, d_leading.word, reciprocal.mantissa)
          : wide::quotient_of_leading_words(n_leading.word, d_leading.word);
  constexpr std::uint32_t kTop = 0x80000000U;  // 2^31: -2^31's magnitude
  // e in [-32, -1] (the quotients that fit, but for the largest at e == 0)
  // is tested first, in one unsigned comparison of -e - 1 (a negative value
  // wraps beyond 31): q 2^e rounded half up on the word as
  // floor(q / 2^(-e - 1)) halved plus its last bit, at most 2^31.
  const auto shift_less_one = static_cast<std::uint32_t>(-1 - exponent);
  std::uint32_t magnitude = q;  // e == 0: q itself
  if (shift_less_one < 32U) {
    const std::uint32_t x = q >> shift_less_one;
    magnitude = (x >> 1U) + (x & 1U);
  } else if (exponent > 0) {
    const bool minimum = negative && (exponent == 1) && (q == (kTop >> 1U));
    raw = minimum ? std::numeric_limits<std::int32_t>::min() : 0;
    return minimum;
  } else if (exponent < 0) {
    magnitude = 0U;  // e < -32: q 2^e < 2^32 2^-33 = 1/2
  } else {
    // e == 0: q itself
  }
  if (magnitude > (negative ? kTop : (kTop - 1U))) {
    return false;
  }
  // -m for m <= 2^31 through m - 1 (which fits) keeps the conversion in range.
  raw = (negative && (magnitude != 0U)) ? (-static_cast<std::int32_t>(magnitude - 1U) - 1)
                                        : static_cast<std::int32_t>(magnitude);
  return true;
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_NORMALISED_QUOTIENT_HPP
