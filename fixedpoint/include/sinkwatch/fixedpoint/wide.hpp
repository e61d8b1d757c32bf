// wide.hpp: unsigned double-width integers for exact intermediate results.
//
// A product or a shifted dividend of two N-bit magnitudes needs 2N bits. For
// 32-bit storage that is uint64_t. For 64-bit storage it is U128 below: GCC's
// __int128 does not exist on 32-bit ARM, and the results must be bit-exact on
// every target, so the 128-bit arithmetic is written out in two uint64_t
// halves. Every function here is overloaded for uint64_t and U128 so the Q
// operations are written once for both.
//
// The small helpers (compare, add, subtract, shift, bit length, the 32x32
// and 64x64-bit products) are SW_FX_INLINE (inline.hpp): forced inline in
// the -Os firmware builds, where GCC otherwise keeps them as calls and a
// shift by a constant becomes a call plus a library shift; plain inline in
// the coverage build. The long divisions (divmod) stay calls: inlined at
// every use they would grow the code for about 2 % of the cycle.
//
// All shifts are on unsigned operands (MISRA C++:2023 rule 7.0.4) and every
// shift count is checked against the width before it is used.
#ifndef SINKWATCH_FIXEDPOINT_WIDE_HPP
#define SINKWATCH_FIXEDPOINT_WIDE_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/inline.hpp"

namespace sinkwatch {
namespace fx {
namespace wide {

/// 128-bit unsigned integer as two 64-bit halves.
struct U128 {
  std::uint64_t hi;
  std::uint64_t lo;
};

SW_FX_INLINE constexpr std::uint32_t width(std::uint64_t) noexcept { return 64U; }
SW_FX_INLINE constexpr std::uint32_t width(const U128&) noexcept { return 128U; }

SW_FX_INLINE constexpr U128 make_u128(std::uint64_t value) noexcept { return U128{0U, value}; }

SW_FX_INLINE constexpr bool equal(std::uint64_t a, std::uint64_t b) noexcept { return a == b; }
SW_FX_INLINE constexpr bool equal(const U128& a, const U128& b) noexcept { return (a.hi == b.hi) && (a.lo == b.lo); }

SW_FX_INLINE constexpr bool less(std::uint64_t a, std::uint64_t b) noexcept { return a < b; }
SW_FX_INLINE constexpr bool less(const U128& a, const U128& b) noexcept {
  return (a.hi < b.hi) || ((a.hi == b.hi) && (a.lo < b.lo));
}

SW_FX_INLINE constexpr bool is_zero(std::uint64_t a) noexcept { return a == 0U; }
SW_FX_INLINE constexpr bool is_zero(const U128& a) noexcept { return (a.hi == 0U) && (a.lo == 0U); }

/// a + b; the caller guarantees no carry out of the top bit.
SW_FX_INLINE constexpr std::uint64_t add(std::uint64_t a, std::uint64_t b) noexcept { return a + b; }
SW_FX_INLINE constexpr U128 add(const U128& a, const U128& b) noexcept {
  const std::uint64_t lo = a.lo + b.lo;
  const std::uint64_t carry = (lo < a.lo) ? 1U : 0U;
  return U128{a.hi + b.hi + carry, lo};
}

/// a - b; the caller guarantees a >= b.
SW_FX_INLINE constexpr std::uint64_t sub(std::uint64_t a, std::uint64_t b) noexcept { return a - b; }
SW_FX_INLINE constexpr U128 sub(const U128& a, const U128& b) noexcept {
  const std::uint64_t borrow = (a.lo < b.lo) ? 1U : 0U;
  return U128{a.hi - b.hi - borrow, a.lo - b.lo};
}

/// a >> n; n >= width gives 0.
SW_FX_INLINE constexpr std::uint64_t shr(std::uint64_t a, std::uint32_t n) noexcept { return (n >= 64U) ? 0U : (a >> n); }
SW_FX_INLINE constexpr U128 shr(const U128& a, std::uint32_t n) noexcept {
  if (n >= 128U) {
    return U128{0U, 0U};
  }
  if (n >= 64U) {
    return U128{0U, shr(a.hi, n - 64U)};
  }
  if (n == 0U) {
    return a;
  }
  return U128{a.hi >> n, (a.lo >> n) | (a.hi << (64U - n))};
}

/// a << n, bits shifted out are lost; n >= width gives 0.
SW_FX_INLINE constexpr std::uint64_t shl(std::uint64_t a, std::uint32_t n) noexcept { return (n >= 64U) ? 0U : (a << n); }
SW_FX_INLINE constexpr U128 shl(const U128& a, std::uint32_t n) noexcept {
  if (n >= 128U) {
    return U128{0U, 0U};
  }
  if (n >= 64U) {
    return U128{shl(a.lo, n - 64U), 0U};
  }
  if (n == 0U) {
    return a;
  }
  return U128{(a.hi << n) | (a.lo >> (64U - n)), a.lo << n};
}

/// Bit n of a (0 = least significant); n >= width gives false.
SW_FX_INLINE constexpr bool bit(std::uint64_t a, std::uint32_t n) noexcept { return (shr(a, n) & 1U) != 0U; }
SW_FX_INLINE constexpr bool bit(const U128& a, std::uint32_t n) noexcept { return (shr(a, n).lo & 1U) != 0U; }

/// Number of significant bits of a 32-bit value (0 for a == 0), by halving
/// the range five times: 16, 8, 4, 2 and 1 bits. The bit-at-a-time loop it
/// replaces was not turned into a count-leading-zeros instruction by GCC at
/// -Os (Cortex-M0 and M4) nor at -O2 (x86-64): up to 32 rounds
/// (docs/performance.md, session 13). Each halving is a branch around a
/// shift and an add: on the Cortex-M0 (no conditional execution) about 14
/// instructions, where the same halvings as selects (s = (v >= 2^16) ? 16 :
/// 0, ...) took about 36 (session 18). The ARMv6-M build of bit_length32
/// uses it; test_wide.cpp checks it against the bit-by-bit count on every
/// target, as it checks bit_length32.
SW_FX_INLINE constexpr std::uint32_t bit_length32_by_halves(std::uint32_t a) noexcept {
  std::uint32_t v = a;
  std::uint32_t bits = 0U;
  if ((v >> 16U) != 0U) {
    v >>= 16U;
    bits += 16U;
  }
  if ((v >> 8U) != 0U) {
    v >>= 8U;
    bits += 8U;
  }
  if ((v >> 4U) != 0U) {
    v >>= 4U;
    bits += 4U;
  }
  if ((v >> 2U) != 0U) {
    v >>= 2U;
    bits += 2U;
  }
  if ((v >> 1U) != 0U) {
    v >>= 1U;
    bits += 1U;
  }
  return bits + v;  // v is now 0 (a == 0) or 1
}

/// True where the core counts leading zeros in one instruction (ARMv7-M's
/// CLZ: __ARM_FEATURE_CLZ; x86-64's BSR or LZCNT), so GCC's and clang's
/// __builtin_clz is that instruction; on ARMv6-M it would be a library call
/// (__clzsi2), and there the halving above is used (docs/misra.md, D-07).
#if (defined(__ARM_FEATURE_CLZ) || defined(__x86_64__)) && defined(__GNUC__)
constexpr bool kClzInstruction = true;
#else
constexpr bool kClzInstruction = false;
#endif

/// Number of significant bits of a 32-bit value (0 for a == 0): 32 less the
/// leading zeros where the core counts them, else by halves. The same count
/// either way.
SW_FX_INLINE constexpr std::uint32_t bit_length32(std::uint32_t a) noexcept {
  if constexpr (kClzInstruction) {
    // __builtin_clz(0) is undefined: zero is answered first.
    return (a == 0U) ? 0U : (32U - static_cast<std::uint32_t>(__builtin_clz(a)));
  } else {
    return bit_length32_by_halves(a);
  }
}

/// Number of significant bits (0 for a == 0), a 32-bit half at a time: a
/// 64-bit shift by a variable count is a library call on 32-bit cores.
SW_FX_INLINE constexpr std::uint32_t bit_length(std::uint64_t a) noexcept {
  // a / 2^32 is the high word: the compilers emit the same shift (no library
  // call, checked with arm-none-eabi-g++ at -O0 and -Os). Written as a
  // division because clang's static analyser, which does not follow the
  // widening of a 32-bit argument, reads "a >> 32" as a shift past the width.
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  return (high != 0U) ? (32U + bit_length32(high)) : bit_length32(static_cast<std::uint32_t>(a));
}

SW_FX_INLINE constexpr std::uint32_t bit_length(const U128& a) noexcept {
  return (a.hi != 0U) ? (64U + bit_length(a.hi)) : bit_length(a.lo);
}

/// The 32 bits of a > 0 from its leading one down (a's bit_length is
/// `bits`): a * 2^(32 - bits), truncated when bits > 32. Shifts by a run-time
/// count on 32-bit words only (a 64-bit one is a library call on 32-bit cores).
SW_FX_INLINE constexpr std::uint32_t leading_word(std::uint64_t a, std::uint32_t bits) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto high = static_cast<std::uint32_t>(a / kWord);
  const auto low = static_cast<std::uint32_t>(a);
  if (bits <= 32U) {
    return (bits == 0U) ? 0U : (low << (32U - bits));
  }
  const std::uint32_t s = bits - 32U;  // 1..32
  return (s < 32U) ? ((high << (32U - s)) | (low >> s)) : high;
}

/// True where a 32 x 32 -> 64-bit product has no instruction: ARMv6-M
/// (Cortex-M0/M0+/M1) has only the 32-bit MULS, and GCC calls __aeabi_lmul
/// (about 41 instructions plus the call) for every 64-bit product.
#if defined(__ARM_ARCH_6M__) || (defined(__ARM_ARCH) && (__ARM_ARCH == 6) && !defined(__ARM_ARCH_ISA_ARM))
constexpr bool kMul32x32BySoftware = true;
#else
constexpr bool kMul32x32BySoftware = false;
#endif

/// The columns of a 32 x 32-bit product from four 16 x 16 -> 32-bit
/// products (each a MULS on ARMv6-M), summed so that no 32-bit sum can carry
/// out: each partial product is at most (2^16 - 1)^2 and each column part
/// added to it below 2^16, so every sum is at most (2^16 - 1) 2^16 + 2^16 - 1
/// < 2^32 (Hacker's Delight's mulhu, with the low word kept). a b = high 2^32
/// + (cross mod 2^16) 2^16 + (low mod 2^16).
struct ProductColumns {
  std::uint32_t high;   ///< floor(a b / 2^32)
  std::uint32_t cross;  ///< its low half: bits 16..31 of a b
  std::uint32_t low;    ///< its low half: bits 0..15 of a b
};

SW_FX_INLINE constexpr ProductColumns product_columns(std::uint32_t a, std::uint32_t b) noexcept {
  const std::uint32_t half_mask = 0xFFFFU;
  const std::uint32_t a_lo = a & half_mask;
  const std::uint32_t a_hi = a >> 16U;
  const std::uint32_t b_lo = b & half_mask;
  const std::uint32_t b_hi = b >> 16U;
  const std::uint32_t low = a_lo * b_lo;
  // Weight 2^16: a_lo b_hi plus the low product's top half, then a_hi b_lo
  // plus the low half of that sum; the high halves go up to weight 2^32.
  const std::uint32_t column_16 = (a_lo * b_hi) + (low >> 16U);
  const std::uint32_t column_16_cross = (a_hi * b_lo) + (column_16 & half_mask);
  const std::uint32_t high = (a_hi * b_hi) + (column_16 >> 16U) + (column_16_cross >> 16U);
  return ProductColumns{high, column_16_cross, low};
}

/// a * b exactly from its columns. With no carry to test it is about five
/// instructions shorter than the form with carries it replaced (session
/// 19), and a caller that keeps only the high word lets the compiler drop
/// the low word's instructions. Plain integer arithmetic, so the same 64
/// bits as the widening multiply on every target. The ARMv6-M build of
/// mul_32x32_64 uses it; the host tests call it directly (test_wide_mul)
/// because there it is not on the product's path.
SW_FX_INLINE constexpr std::uint64_t mul_32x32_64_halves(std::uint32_t a, std::uint32_t b) noexcept {
  const ProductColumns c = product_columns(a, b);
  return (static_cast<std::uint64_t>(c.high) << 32U) | ((c.low & 0xFFFFU) | (c.cross << 16U));
}

/// Full product of two unsigned 32-bit values: one widening multiply
/// (UMULL, MUL) where the core has it, four MULS on ARMv6-M. The same bits
/// either way.
SW_FX_INLINE constexpr std::uint64_t mul_32x32_64(std::uint32_t a, std::uint32_t b) noexcept {
  if constexpr (kMul32x32BySoftware) {
    return mul_32x32_64_halves(a, b);
  } else {
    return static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b);
  }
}

/// round(a b / 2^32), half up (at most 2^32 - 1, as a b <= (2^32 - 1)^2),
/// on ARMv6-M from the product's columns without its low word: the rounding
/// half 2^31 = 2^15 2^16 carries into the high word exactly when bits 16 to
/// 31 of a b plus 2^15 do, since bits 0 to 15 cannot carry (they are the low
/// product's low half, added to nothing). The host tests call it directly
/// against the built-in product (test_wide_mul).
SW_FX_INLINE constexpr std::uint32_t mul_32x32_rounded_high_by_columns(std::uint32_t a, std::uint32_t b) noexcept {
  const ProductColumns c = product_columns(a, b);
  return c.high + (((c.cross & 0xFFFFU) + 0x8000U) >> 16U);
}

/// round(a b / 2^32), half up, on every target: the columns on ARMv6-M,
/// else the widening multiply and one 64-bit add. The same integer.
SW_FX_INLINE constexpr std::uint32_t mul_32x32_rounded_high(std::uint32_t a, std::uint32_t b) noexcept {
  if constexpr (kMul32x32BySoftware) {
    return mul_32x32_rounded_high_by_columns(a, b);
  } else {
    return static_cast<std::uint32_t>((mul_32x32_64(a, b) + (std::uint64_t{1U} << 31U)) >> 32U);
  }
}

/// Full product of two signed 32-bit values, through the magnitudes: |a b| <=
/// 2^62 fits int64_t, so the sign is put back without any wrap.
SW_FX_INLINE constexpr std::int64_t mul_32x32_64(std::int32_t a, std::int32_t b) noexcept {
  // 0 - a in unsigned arithmetic is |a| for every a, INT32_MIN included.
  const auto mag_a = (a < 0) ? (0U - static_cast<std::uint32_t>(a)) : static_cast<std::uint32_t>(a);
  const auto mag_b = (b < 0) ? (0U - static_cast<std::uint32_t>(b)) : static_cast<std::uint32_t>(b);
  const auto product = static_cast<std::int64_t>(mul_32x32_64(mag_a, mag_b));
  return ((a < 0) != (b < 0)) ? -product : product;
}

/// a * b mod 2^64, the built-in uint64_t product, from one full 32 x 32 ->
/// 64-bit product of the low words and the low 32 bits of the two cross
/// products (the high words' product falls off the top): on ARMv6-M one
/// mul_32x32_64_halves and two MULS instead of a call to __aeabi_lmul. The
/// host tests call it directly (test_wide_mul).
SW_FX_INLINE constexpr std::uint64_t mul_64x64_low_by_words(std::uint64_t a, std::uint64_t b) noexcept {
  const std::uint64_t mask = 0xFFFFFFFFU;
  const auto a_lo = static_cast<std::uint32_t>(a & mask);
  const auto a_hi = static_cast<std::uint32_t>(a >> 32U);
  const auto b_lo = static_cast<std::uint32_t>(b & mask);
  const auto b_hi = static_cast<std::uint32_t>(b >> 32U);
  // Unsigned 32-bit products wrap mod 2^32: exactly the bits that land below
  // 2^64 after the shift by 32.
  const std::uint32_t cross = (a_lo * b_hi) + (a_hi * b_lo);
  return mul_32x32_64_halves(a_lo, b_lo) + (static_cast<std::uint64_t>(cross) << 32U);
}

/// a * b mod 2^64 (the built-in product's bits) on every target, without
/// __aeabi_lmul on ARMv6-M.
SW_FX_INLINE constexpr std::uint64_t mul_64x64_low(std::uint64_t a, std::uint64_t b) noexcept {
  if constexpr (kMul32x32BySoftware) {
    return mul_64x64_low_by_words(a, b);
  } else {
    return a * b;
  }
}

/// Full product of two 32-bit values.
SW_FX_INLINE constexpr std::uint64_t mul_full(std::uint32_t a, std::uint32_t b) noexcept {
  return mul_32x32_64(a, b);
}
/// The 128-bit sum of the four 32 x 32-bit partial products of a 64 x 64-bit
/// product (ll = a_lo b_lo, lh = a_lo b_hi, hl = a_hi b_lo, hh = a_hi b_hi).
SW_FX_INLINE constexpr U128 sum_partial_products(std::uint64_t ll, std::uint64_t lh, std::uint64_t hl,
                                                 std::uint64_t hh) noexcept {
  const std::uint64_t mask = 0xFFFFFFFFU;
  // Middle column: at most 3 * (2^32 - 1) summands' worth, fits in 64 bits.
  const std::uint64_t mid = (ll >> 32U) + (lh & mask) + (hl & mask);
  const std::uint64_t lo = (ll & mask) | (mid << 32U);
  const std::uint64_t hi = hh + (lh >> 32U) + (hl >> 32U) + (mid >> 32U);
  return U128{hi, lo};
}

/// a * b in 128 bits from the 16-bit-halves products (mul_32x32_64_halves),
/// skipping the partial products of a zero high word (most Q31.32 operands
/// are below 2^32 in magnitude): mul_full on ARMv6-M, where each partial
/// product costs about 25 instructions. The host tests call it directly.
SW_FX_INLINE constexpr U128 mul_full_skipping_zero_words(std::uint64_t a, std::uint64_t b) noexcept {
  const std::uint64_t mask = 0xFFFFFFFFU;
  const auto a_lo = static_cast<std::uint32_t>(a & mask);
  const auto a_hi = static_cast<std::uint32_t>(a >> 32U);
  const auto b_lo = static_cast<std::uint32_t>(b & mask);
  const auto b_hi = static_cast<std::uint32_t>(b >> 32U);
  const std::uint64_t ll = mul_32x32_64_halves(a_lo, b_lo);
  const std::uint64_t lh = (b_hi != 0U) ? mul_32x32_64_halves(a_lo, b_hi) : 0U;
  std::uint64_t hl = 0U;
  std::uint64_t hh = 0U;
  if (a_hi != 0U) {
    hl = mul_32x32_64_halves(a_hi, b_lo);
    hh = (b_hi != 0U) ? mul_32x32_64_halves(a_hi, b_hi) : 0U;
  }
  return sum_partial_products(ll, lh, hl, hh);
}

/// Full product of two 64-bit values, by 32-bit limbs (schoolbook). Where a
/// 32 x 32 -> 64-bit product is one instruction, all four are formed (the
/// branches of the skipping form would cost more than they save).
SW_FX_INLINE constexpr U128 mul_full(std::uint64_t a, std::uint64_t b) noexcept {
  if constexpr (kMul32x32BySoftware) {
    return mul_full_skipping_zero_words(a, b);
  } else {
    const std::uint64_t mask = 0xFFFFFFFFU;
    const auto a_lo = static_cast<std::uint32_t>(a & mask);
    const auto a_hi = static_cast<std::uint32_t>(a >> 32U);
    const auto b_lo = static_cast<std::uint32_t>(b & mask);
    const auto b_hi = static_cast<std::uint32_t>(b >> 32U);
    return sum_partial_products(mul_32x32_64(a_lo, b_lo), mul_32x32_64(a_lo, b_hi), mul_32x32_64(a_hi, b_lo),
                                mul_32x32_64(a_hi, b_hi));
  }
}

/// Quotient and remainder of an unsigned division.
template <typename W>
struct DivMod {
  W quotient;
  W remainder;
};

/// True where the core divides 32-bit words in one instruction: ARMv7-M's
/// and ARMv8-M's UDIV (__ARM_FEATURE_IDIV), x86-64's DIV. Elsewhere (ARMv6-M,
/// ARMv7-A without the division extension) every `/` on 32 or 64 bits is a
/// library call (on the Cortex-M0 __aeabi_uidiv about 97 instructions for a
/// 16-bit quotient, __aeabi_uldivmod 500 to 1,100), and the divisions below
/// are formed from a reciprocal and 16 x 16-bit products instead
/// (docs/misra.md, D-07; docs/fixedpoint.md 5.8). The same quotient and
/// remainder either way.
#if defined(__ARM_FEATURE_IDIV) || defined(__x86_64__)
constexpr bool kDivideInstruction = true;
#else
constexpr bool kDivideInstruction = false;
#endif

namespace detail {

/// The seeds of the reciprocals below and in reciprocal.hpp.
struct ReciprocalSeeds {
  std::uint16_t y0[128];
};

/// y0[i] = floor(2^24 / (2 (128 + i) + 1)): 2^47 / v at the middle of the
/// interval v / 2^24 in [128 + i, 129 + i).
constexpr ReciprocalSeeds make_reciprocal_seeds() noexcept {
  ReciprocalSeeds t{};
  for (std::uint32_t i = 0U; i < 128U; ++i) {
    t.y0[i] = static_cast<std::uint16_t>(0x1000000U / ((2U * (128U + i)) + 1U));
  }
  return t;
}
/// One table for the program (inline: not one per translation unit).
inline constexpr ReciprocalSeeds kReciprocalSeeds = make_reciprocal_seeds();

/// One Newton step from the seed y0 ~ 2^47 / v (v in [2^31, 2^32)):
/// p = v y0 / 2^16 ~ 2^31 (below 2^32), c = 2^32 - p,
/// z1 = y0 c / 2^16 = y0 (2 - v y0 / 2^47) 2^15 ~ 2^62 / v, each product
/// below 2^32. With y0 = (1 - e) 2^47 / v, z1 = (1 - e^2) 2^62 / v less its
/// floor (below 1) plus at most y0 / 2^16 < 1 from p's: so z1 < 2^62 / v + 1
/// for every v (docs/fixedpoint.md 5.8).
SW_FX_INLINE constexpr std::uint32_t first_newton_step(std::uint32_t v, std::uint32_t y0) noexcept {
  const std::uint32_t p = ((v >> 16U) * y0) + (((v & 0xFFFFU) * y0) >> 16U);
  const std::uint32_t c = 0U - p;  // 2^32 - p: wraps by design
  return (y0 * (c >> 16U)) + ((y0 * (c & 0xFFFFU)) >> 16U);
}

/// The base of the long divisions below: two 16-bit digits per quotient.
constexpr std::uint32_t kDigitBase = 0x10000U;

/// A quotient digit and the remainder after it.
struct DigitStep {
  std::uint32_t digit;
  std::uint32_t remainder;
};

/// floor(x / v) and x mod v for x = partial 2^16 + next (partial < v, next <
/// 2^16, so the digit is below 2^16) and v in [2^31, 2^32) with v_high =
/// floor(v / 2^16): the estimate partial / v_high (one 32-bit division) is
/// never below the digit and at most two above it (v_high >= 2^15; the
/// bound also holds for the estimates 2^16 and 2^16 + 1 that no digit
/// reaches: docs/fixedpoint.md 5.8), so at most two corrections against the
/// exact remainder x - estimate v, a signed 64-bit value in [-2v, v) (one
/// UMULL and a 64-bit subtraction on ARMv7-M), finish it. Nested, not
/// counted: a digit found right on the first try tests nothing more. Since
/// round 16 (before it, Hacker's Delight's divlu test against v's low half,
/// more instructions per digit on the Cortex-M4); the same digit.
/// The partial dividend x is the caller's where it forms it more cheaply than
/// from partial and next (digit_of, for x div 2^16 == partial).
SW_FX_INLINE constexpr DigitStep digit_of(std::uint32_t partial, std::uint64_t x, std::uint32_t v,
                                          std::uint32_t v_high) noexcept {
  std::uint32_t digit = partial / v_high;
  // x < 2^48 and digit v < 2^49: both fit int64, so the difference is exact.
  std::int64_t rest = static_cast<std::int64_t>(x) - static_cast<std::int64_t>(std::uint64_t{digit} * v);
  if (rest < 0) {
    --digit;
    rest += static_cast<std::int64_t>(v);
    if (rest < 0) {
      --digit;
      rest += static_cast<std::int64_t>(v);
    }
  }
  return DigitStep{digit, static_cast<std::uint32_t>(rest)};
}

SW_FX_INLINE constexpr DigitStep digit_by_remainder(std::uint32_t partial, std::uint32_t next, std::uint32_t v,
                                                    std::uint32_t v_high) noexcept {
  return digit_of(partial, (std::uint64_t{partial} * kDigitBase) | next, v, v_high);
}

/// r = floor((z1 - 1) / 2^14) ~ 2^48 / v from below, for v in [2^31, 2^32):
/// r v < 2^48 (z1 - 1 < 2^62 / v) and 2^48 - r v <= 1.5 * 2^32 (the
/// largest at v = 2^31; docs/fixedpoint.md 5.8), so r < 2^17.
SW_FX_INLINE constexpr std::uint32_t digit_reciprocal(std::uint32_t v) noexcept {
  return (first_newton_step(v, kReciprocalSeeds.y0[(v >> 24U) & 0x7FU]) - 1U) >> 14U;
}

/// floor(x / v) and x mod v for x = partial 2^16 + next (partial < v, next <
/// 2^16, so the digit is below 2^16), v in [2^31, 2^32) and r =
/// digit_reciprocal(v). The estimate floor(partial r / 2^32), from a 16 x
/// 17-bit and a 16 x 16-bit product, is the digit or one or two below it
/// (docs/fixedpoint.md 5.8), so two counted corrections against the exact
/// remainder finish it. That remainder, below 3 v < 2^34 before them, is
/// kept as two words: the low one by the wrapping product (as divlu's), the
/// high one (0, 1 or 2) from digit v's high word and the borrow.
SW_FX_INLINE constexpr DigitStep digit_by_reciprocal(std::uint32_t partial, std::uint32_t next, std::uint32_t v,
                                                     std::uint32_t r) noexcept {
  // partial r / 2^16 without the 17-bit r on 16 bits: the low half takes
  // r / 2, losing under 2^-15 of the unit; the sum is below 2^32.
  const std::uint32_t scaled = ((partial >> 16U) * r) + (((partial & 0xFFFFU) * (r >> 1U)) >> 15U);
  std::uint32_t digit = scaled >> 16U;
  const std::uint32_t dividend_low = (partial << 16U) | next;
  std::uint32_t low = dividend_low - (digit * v);  // wraps by design: the low word of x - digit v
  // floor(digit v / 2^32): digit v / 2^16 = digit (v / 2^16) + digit (v mod 2^16) / 2^16 < 2^32.
  const std::uint32_t product_high = ((digit * (v >> 16U)) + ((digit * (v & 0xFFFFU)) >> 16U)) >> 16U;
  std::uint32_t high = (partial >> 16U) - product_high - ((low > dividend_low) ? 1U : 0U);
  // MISRA C++:2023 9.5.1: a simple counted loop, no break.
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if ((high != 0U) || (low >= v)) {
      high -= (low < v) ? 1U : 0U;
      low -= v;
      ++digit;
    }
  }
  return DigitStep{digit, low};
}

}  // namespace detail

namespace detail {
/// The two base-2^16 digits of floor(u / v) (v in [2^31, 2^32), u < v
/// 2^32) and the partial remainder between them, written once for the
/// division with its remainder (packed_by_digits) and for the quotient alone
/// (quotient_64_by_32).
struct QuotientDigits {
  std::uint32_t high;
  std::uint32_t partial;  ///< (u div 2^16) - high v, below v
  std::uint32_t low;
  std::uint32_t remainder;  ///< u mod v
};

SW_FX_INLINE constexpr QuotientDigits quotient_digits(std::uint64_t u, std::uint32_t v) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  // v >= 2^31, so the high digit is at least 2^15: the OR changes nothing
  // but shows the static analyser a divisor that cannot be zero.
  const std::uint32_t v_high = (v >> 16U) | 0x8000U;
  const auto u_high = static_cast<std::uint32_t>(u / kWord);  // u >> 32 without a library shift
  const auto u_low = static_cast<std::uint32_t>(u);
  const DigitStep high = digit_by_remainder(u_high, u_low >> 16U, v, v_high);
  const DigitStep low = digit_by_remainder(high.remainder, u_low & 0xFFFFU, v, v_high);
  return QuotientDigits{high.digit, high.remainder, low.digit, low.remainder};
}

/// divide_64_by_32_by_digits's quotient (low word) and remainder (high
/// word), packed as packed_by_reciprocal's below (two registers, no frame
/// for the result).
constexpr std::uint64_t packed_by_digits(std::uint64_t u, std::uint32_t v) noexcept {
  const QuotientDigits d = quotient_digits(u, v);
  return (static_cast<std::uint64_t>(d.remainder) << 32U) | ((d.high * kDigitBase) + d.low);
}
}  // namespace detail

/// floor(u / v) and u mod v for v in [2^31, 2^32) and u < v * 2^32 (the
/// quotient fits 32 bits; the caller normalises): two base-2^16 digits, each
/// from a 32-bit division by the divisor's high half, corrected against the
/// exact remainder (detail::digit_by_remainder). The form for cores with a
/// divide instruction.
SW_FX_INLINE constexpr DivMod<std::uint32_t> divide_64_by_32_by_digits(std::uint64_t u, std::uint32_t v) noexcept {
  const std::uint64_t packed = detail::packed_by_digits(u, v);
  return DivMod<std::uint32_t>{static_cast<std::uint32_t>(packed), static_cast<std::uint32_t>(packed >> 32U)};
}

namespace detail {
/// divide_64_by_32_by_reciprocal's quotient (low word) and remainder (high
/// word) as one 64-bit value: AAPCS returns it in two registers, where a
/// two-word struct goes through the caller's memory (16 more bytes of frame
/// on the step's deepest path on the Cortex-M0, through normalised_reciprocal).
constexpr std::uint64_t packed_by_reciprocal(std::uint64_t u, std::uint32_t v) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const std::uint32_t r = digit_reciprocal(v);
  const auto u_high = static_cast<std::uint32_t>(u / kWord);
  const auto u_low = static_cast<std::uint32_t>(u);
  const DigitStep high = digit_by_reciprocal(u_high, u_low >> 16U, v, r);
  const DigitStep low = digit_by_reciprocal(high.remainder, u_low & 0xFFFFU, v, r);
  return (static_cast<std::uint64_t>(low.remainder) << 32U) | ((high.digit << 16U) | low.digit);
}
}  // namespace detail

/// The same quotient and remainder with no division: a reciprocal of v to
/// 17 bits (a seed and one Newton step, four 16 x 16-bit products), then the
/// same two base-2^16 digits, each estimated from it and corrected at most
/// twice against the exact remainder (detail::digit_by_reciprocal). The form
/// for cores without a divide instruction: about 100 instructions on the
/// Cortex-M0 against about 280 for the digits' two library divisions.
SW_FX_INLINE constexpr DivMod<std::uint32_t> divide_64_by_32_by_reciprocal(std::uint64_t u, std::uint32_t v) noexcept {
  const std::uint64_t packed = detail::packed_by_reciprocal(u, v);
  return DivMod<std::uint32_t>{static_cast<std::uint32_t>(packed), static_cast<std::uint32_t>(packed >> 32U)};
}

/// floor(u / v) and u mod v for v in [2^31, 2^32) and u < v * 2^32, in the
/// core's cheaper form (kDivideInstruction); both are exact.
constexpr DivMod<std::uint32_t> divide_64_by_32(std::uint64_t u, std::uint32_t v) noexcept {
  if constexpr (kDivideInstruction) {
    return divide_64_by_32_by_digits(u, v);
  } else {
    return divide_64_by_32_by_reciprocal(u, v);
  }
}

/// floor(u / v) alone, for v in [2^31, 2^32) and u < v * 2^32, forced
/// inline: on a core with a divide instruction the two digits without the
/// remainder (no call and no packed result), else the reciprocal form's
/// quotient. For a caller that divides in its own code (Eq. 11 and the
/// limit, flight/src/of_valid.hpp: round 14 took the twelve calls per step
/// of packed_by_digits off the Cortex-M4).
SW_FX_INLINE constexpr std::uint32_t quotient_64_by_32(std::uint64_t u, std::uint32_t v) noexcept {
  if constexpr (kDivideInstruction) {
    const detail::QuotientDigits d = detail::quotient_digits(u, v);
    return (d.high * detail::kDigitBase) + d.low;
  } else {
    return divide_64_by_32_by_reciprocal(u, v).quotient;
  }
}

/// floor(n 2^31 / d) for n and d in [2^31, 2^32) (n 2^31 < d 2^32: the
/// quotient fits 32 bits), the normalised quotients' division
/// (normalised_quotient.hpp): quotient_64_by_32(n 2^31, d). Where the core
/// divides words, its first partial dividend, (n 2^31) div 2^16, is formed
/// as n 2^15 (one 64-bit shift of n, not the join of two words) and the
/// second's next digit is 0 (round 16). test_normalised_quotient checks it
/// against the built-in division.
SW_FX_INLINE constexpr std::uint32_t quotient_of_leading_words(std::uint32_t n, std::uint32_t d) noexcept {
  if constexpr (kDivideInstruction) {
    // d >= 2^31: the OR changes nothing but shows the analyser a non-zero divisor.
    const std::uint32_t v_high = (d >> 16U) | 0x8000U;
    const detail::DigitStep high = detail::digit_of(n >> 1U, std::uint64_t{n} << 15U, d, v_high);
    const detail::DigitStep low =
        detail::digit_of(high.remainder, std::uint64_t{high.remainder} << 16U, d, v_high);
    return (high.digit << 16U) | low.digit;
  } else {
    return quotient_64_by_32(std::uint64_t{n} << 31U, d);
  }
}

/// num / den and num mod den for a one-word divisor (den != 0) and any
/// 64-bit dividend, with no library division: den shifted left by s until
/// its top bit is set, the dividend by the same s into three words, then two
/// divide_64_by_32_by_reciprocal (the high two words, then the remainder and
/// the low word: each partial dividend's high word is below the divisor), the
/// remainder shifted back. Exact: (num 2^s) / (den 2^s) has num / den's
/// quotient and 2^s times its remainder.
constexpr DivMod<std::uint64_t> divmod_by_word_normalising(std::uint64_t num, std::uint32_t den) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const std::uint32_t s = 32U - bit_length32(den);  // 0..31: den != 0
  const std::uint32_t v = den << s;
  const auto high = static_cast<std::uint32_t>(num / kWord);
  const auto low = static_cast<std::uint32_t>(num);
  // The dividend times 2^s, 96 bits: top < 2^s <= v.
  const std::uint32_t top = (s == 0U) ? 0U : (high >> (32U - s));
  const std::uint32_t middle = (s == 0U) ? high : ((high << s) | (low >> (32U - s)));
  // A quotient below 2^32 (top == 0, middle < v) needs the second division only.
  const bool one_word = (top == 0U) && (middle < v);
  const DivMod<std::uint32_t> upper = one_word ? DivMod<std::uint32_t>{0U, middle}
                                               : divide_64_by_32_by_reciprocal((std::uint64_t{top} << 32U) | middle, v);
  const DivMod<std::uint32_t> lower =
      divide_64_by_32_by_reciprocal((std::uint64_t{upper.remainder} << 32U) | (low << s), v);
  return DivMod<std::uint64_t>{(std::uint64_t{upper.quotient} << 32U) | lower.quotient, lower.remainder >> s};
}

/// num / den (den != 0 is the caller's duty). By the built-in operator where
/// the core divides (a library call on 32-bit ARM, one instruction on
/// x86-64); without a divide instruction a one-word divisor takes
/// divmod_by_word_normalising (on the Cortex-M0 about 160 instructions for
/// the step's slip ratio and 190 for random operands, against 520 and 1,080
/// for __aeabi_uldivmod). The same quotient and remainder.
constexpr DivMod<std::uint64_t> divmod(std::uint64_t num, std::uint64_t den) noexcept {
  if constexpr (!kDivideInstruction) {
    if (den < (std::uint64_t{1U} << 32U)) {
      return divmod_by_word_normalising(num, static_cast<std::uint32_t>(den));
    }
  }
  return DivMod<std::uint64_t>{num / den, num % den};
}

/// Bit i of a (i < 128) by 32-bit shifts only: a 64-bit shift by a variable
/// count is a library call on 32-bit cores.
constexpr std::uint32_t bit_at(const U128& a, std::uint32_t i) noexcept {
  const std::uint64_t half = (i >= 64U) ? a.hi : a.lo;
  const std::uint32_t j = i & 63U;
  const auto word = static_cast<std::uint32_t>((j >= 32U) ? (half >> 32U) : half);
  return (word >> (j & 31U)) & 1U;
}

/// num / den by restoring long division, one bit per step: at most 128 steps.
/// den != 0 is the caller's duty. When den < 2^64 (every Q31.32 divisor) the
/// remainder, always below den, is kept in 64 bits plus the bit shifted out,
/// and the steps whose quotient bit must be zero are skipped.
constexpr DivMod<U128> divmod(const U128& num, const U128& den) noexcept {
  if (num.hi == 0U && den.hi == 0U) {
    return DivMod<U128>{U128{0U, num.lo / den.lo}, U128{0U, num.lo % den.lo}};
  }
  const std::uint32_t n_bits = bit_length(num);
  U128 quotient{0U, 0U};
  if (den.hi == 0U) {
    // The top bit_length(den) - 1 bits of num are below den: their quotient
    // bits are zero and they are the remainder after them, so the loop
    // starts past them (the same quotient and remainder in n_bits -
    // bit_length(den) + 1 steps instead of n_bits). num.hi != 0 here, so
    // n_bits >= 65 > bit_length(den) >= 1.
    const std::uint32_t skipped = bit_length(den.lo) - 1U;
    std::uint64_t remainder = shr(num, n_bits - skipped).lo;
    for (std::uint32_t step = skipped; step < n_bits; ++step) {
      const std::uint32_t i = n_bits - 1U - step;
      // 2 remainder + bit < 2 den <= 2^65: `carry` is its bit 64. With it set
      // the value exceeds den, and the difference, below den, is exact
      // modulo 2^64.
      const bool carry = (remainder >> 63U) != 0U;
      remainder = (remainder << 1U) | bit_at(num, i);
      quotient = U128{(quotient.hi << 1U) | (quotient.lo >> 63U), quotient.lo << 1U};
      if (carry || (remainder >= den.lo)) {
        remainder -= den.lo;
        quotient.lo |= 1U;
      }
    }
    return DivMod<U128>{quotient, U128{0U, remainder}};
  }
  U128 remainder{0U, 0U};
  for (std::uint32_t step = 0U; step < n_bits; ++step) {
    const std::uint32_t i = n_bits - 1U - step;
    remainder = U128{(remainder.hi << 1U) | (remainder.lo >> 63U), (remainder.lo << 1U) | bit_at(num, i)};
    quotient = U128{(quotient.hi << 1U) | (quotient.lo >> 63U), quotient.lo << 1U};
    if (!less(remainder, den)) {
      remainder = sub(remainder, den);
      quotient.lo |= 1U;
    }
  }
  return DivMod<U128>{quotient, remainder};
}

namespace detail {
// One conversion per wide type, as a specialised class template: MISRA
// C++:2023 17.8.1 forbids explicit specialisations of function templates.
template <typename W>
struct FromU64;
template <>
struct FromU64<std::uint64_t> {
  SW_FX_INLINE static constexpr std::uint64_t of(std::uint64_t value) noexcept { return value; }
};
template <>
struct FromU64<U128> {
  SW_FX_INLINE static constexpr U128 of(std::uint64_t value) noexcept { return make_u128(value); }
};
}  // namespace detail

/// Converts a uint64_t into the wide type W.
template <typename W>
SW_FX_INLINE constexpr W from_u64(std::uint64_t value) noexcept {
  return detail::FromU64<W>::of(value);
}

/// Low 64 bits of a wide value (the caller has checked that it fits).
SW_FX_INLINE constexpr std::uint64_t low_u64(std::uint64_t a) noexcept { return a; }
SW_FX_INLINE constexpr std::uint64_t low_u64(const U128& a) noexcept { return a.lo; }

}  // namespace wide
}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_WIDE_HPP
