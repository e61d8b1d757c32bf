// trig.hpp: sin, cos, sincos, asin, acos, atan2 and the wheel entry angle in Q format.
//
// The entry angle is the paper's geometry cos theta1 = 1 - z/r (the angle at
// which the soil first touches a wheel of radius r sunk by z; the upper bound
// of the Wong-Reece stress integrals, Eqs. 1-8, and the term Eqs. 9-10
// approximate by z/r; docs/derivation.md). It is computed as
// 2 asin(sqrt(z / (2 r))): the same number, but accurate near zero sinkage,
// where 1 - z/r loses the significant bits of z. sin and cos serve the
// attitude (slope) terms and the trigonometric terms of Eqs. 7-8.
//
// Every function here runs on an FPU-less Cortex-M0 every control cycle for
// six wheels, so:
//  * integer arithmetic only, bit-exact on every target: 32-bit coefficients
//    and accumulators, 32 x 32 -> 64-bit products, no 128-bit arithmetic, no
//    tables computed in floating point, every loop bounded by a constant;
//  * polynomials are truncated Taylor series whose truncation error is proven
//    below one hundredth of an output LSB (docs/fixedpoint.md gives every
//    bound and its proof);
//  * results: sin and cos in Q1_30 within 1 LSB of the exact value of the
//    exact input angle, for every representable angle; asin, acos and
//    entry_angle and atan2 in Q3_28 (radians) within 1 LSB.
//
// Errors, in the caller's sticky Status:
//  * asin/acos of |x| > 1 raise Flag::domain and return zero. There is no
//    silent clamp to +-1: an argument past 1 means the caller's geometry is
//    wrong, and a clamp would hide it.
//  * entry_angle of z/r < 0 or z/r > 2 raises Flag::domain and returns zero.
//  * atan2(0, 0) raises Flag::domain and returns zero.
//  * sin and cos cannot fail: they take a Status only for uniformity.
//
// Range reduction for sin and cos multiplies the angle by 1/(2 pi) held to
// 128 bits (Payne-Hanek style, in 32-bit limbs), so the reduction is exact to
// 2^-60 turn even for an angle of 2^63 rad; the angle is never shifted by
// pi/2 in its own format, so there is no intermediate overflow (the classic
// cos(x) = sin(x + pi/2) bug near the top of the format is impossible).
#ifndef SINKWATCH_FIXEDPOINT_TRIG_HPP
#define SINKWATCH_FIXEDPOINT_TRIG_HPP

#include <cstdint>
#include <type_traits>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"
#include "sinkwatch/fixedpoint/status.hpp"

namespace sinkwatch {
namespace fx {
namespace detail {
namespace trig {

/// 1/(2 pi) = sum k_inv_two_pi[i] * 2^(-32 (i + 1)), truncated after 128
/// bits (error < 2^-128). Generated with mpmath at 80 digits; a host test
/// checks the leading limbs against long double.
constexpr std::uint32_t k_inv_two_pi[4] = {0x28BE60DBU, 0x9391054AU, 0x7F09D5F4U, 0x7D4D3770U};

/// pi/2 in units of 2^-32 rad, rounded to nearest (error 0.261 unit).
constexpr std::uint64_t k_half_pi_q32 = 6746518852U;

/// Taylor coefficients of sin(pi/4 v) = sum a_k v^k, k odd, a_k =
/// (pi/4)^k / k!, each in units of 2^-(32 + s_k) with s_k the largest shift
/// that keeps it below 2^32 (so each carries 32 significant bits).
constexpr std::uint32_t k_sin_a[6] = {3373259426U, 2774394673U, 2738217788U,
                                      2573821555U, 2822511172U, 4051937263U};
constexpr std::uint32_t k_sin_shift[6] = {0U, 3U, 8U, 14U, 21U, 29U};

/// Taylor coefficients b_k = (pi/4)^k / k! of cos(pi/4 v), k = 2, 4, ..., 12,
/// in units of 2^-(32 + s_k).
constexpr std::uint32_t k_cos_b[6] = {2649351758U, 2179004481U, 2867454962U,
                                      4042949445U, 3546872145U, 4243178780U};
constexpr std::uint32_t k_cos_shift[6] = {1U, 5U, 11U, 18U, 25U, 33U};

/// Taylor coefficients c_n = C(2n, n) / (4^n (2n + 1)) of
/// asin(s) = s + sum c_n s^(2n + 1), n = 1 .. 12, in units of 2^-32.
constexpr std::uint32_t k_asin_c[12] = {715827883U, 322122547U, 191739611U, 130489458U,
                                        96087692U,  74529556U,  59978547U,  49614607U,
                                        41925794U,  36036218U,  31407059U,  27690557U};

/// Taylor coefficients 1/(2n + 1) of atan(u) = u - u^3/3 + u^5/5 - ...,
/// n = 1 .. 11, in units of 2^-32.
constexpr std::uint32_t k_atan_c[11] = {1431655765U, 858993459U, 613566757U, 477218588U, 390451572U, 330382100U,
                                        286331153U,  252645135U, 226050910U, 204522252U, 186737709U};

/// tan(pi/8) in units of 2^-31; pi/4 and pi in units of 2^-32 rad (errors
/// 0.131 and 0.478 unit).
constexpr std::uint64_t k_tan_pi_8_q31 = 889516852U;
constexpr std::uint64_t k_quarter_pi_q32 = 3373259426U;
constexpr std::uint64_t k_pi_q32 = 13493037705U;

/// round(a * b / 2^shift) for 1 <= shift <= 63, a * b + 2^(shift-1) < 2^64.
constexpr std::uint64_t mul_round(std::uint64_t a, std::uint64_t b, std::uint32_t shift) noexcept {
  return (wide::mul_64x64_low(a, b) + (std::uint64_t{1U} << (shift - 1U))) >> shift;
}

/// a * b exactly: fx::wide::mul_32x32_64 (on ARMv6-M four MULS summed by
/// carry-free 16-bit columns, elsewhere the widening multiply).
SW_FX_INLINE constexpr std::uint64_t mul_wide(std::uint32_t a, std::uint32_t b) noexcept {
  return wide::mul_32x32_64(a, b);
}

/// floor(a b / 2^32), the product's high word: where only it is needed, the
/// compiler drops the low word's instructions.
SW_FX_INLINE constexpr std::uint32_t mul_high_word(std::uint32_t a, std::uint32_t b) noexcept {
  return static_cast<std::uint32_t>(mul_wide(a, b) >> 32U);
}

/// round(a b / 2^Shift) = (a b + 2^(Shift - 1)) >> Shift for a <= 2^31 and
/// a shift known at compile time of 33 to 63 bits (every product of the sine
/// and cosine kernels), from the product's high word alone: the rounding
/// half 2^(Shift - 1) lies wholly in the high word, so a b + 2^(Shift - 1) =
/// (hi + 2^(Shift - 33)) 2^32 + lo with lo < 2^32, which the shift by
/// Shift >= 32 drops whole. a <= 2^31 keeps hi < 2^31, so adding the half
/// (<= 2^30) cannot carry out. Exactly the bits of the 64-bit form.
template <std::uint32_t Shift>
SW_FX_INLINE constexpr std::uint32_t mul_round_high(std::uint32_t a, std::uint32_t b) noexcept {
  static_assert((Shift >= 33U) && (Shift <= 63U), "a rounding shift of 33 to 63 bits");
  return (mul_high_word(a, b) + (std::uint32_t{1U} << (Shift - 33U))) >> (Shift - 32U);
}

/// A value the kernels keep below 2^32 (w <= 2^31, every Horner bracket below
/// its coefficient, each limb of m), as the 32-bit operand of a product.
SW_FX_INLINE constexpr std::uint32_t word(std::uint64_t v) noexcept { return static_cast<std::uint32_t>(v); }

/// floor(limb c / 2^Shift), 1 <= Shift <= 63: from the product's high word
/// alone when Shift >= 32 (floor(p / 2^Shift) = floor(floor(p / 2^32) /
/// 2^(Shift - 32)), the same bits).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::uint64_t turn_part_shifted_right(std::uint32_t limb, std::uint32_t c) noexcept {
  if constexpr (Shift >= 32) {
    return static_cast<std::uint64_t>(mul_high_word(limb, c) >> static_cast<std::uint32_t>(Shift - 32));
  } else {
    return mul_wide(limb, c) >> static_cast<std::uint32_t>(Shift);
  }
}

/// Fraction of a turn of the angle m * 2^-F rad, in units of 2^-64 turn:
/// m * 2^-F / (2 pi) mod 1, computed limb by limb. Whole turns fall off the
/// top of the uint64_t (unsigned wrap, which is exactly "mod 1 turn").
/// Error: each of at most 8 truncated partial products loses < 1 unit and the
/// truncated constant < 2^-65 turn, so the result is low by less than 9 units.
/// One partial product of turns(): limb J of the angle times limb I of
/// 1/(2 pi), shifted to its weight 2^s in units of 2^-64 turn (s known at
/// compile time, so the shift is inline). Partial products of weight >= 2^64
/// are whole turns; those below 2^-64 are under one unit.
template <std::int32_t F, std::int32_t J, std::int32_t I>
SW_FX_INLINE constexpr std::uint64_t turn_part(std::uint32_t limb) noexcept {
  constexpr std::int32_t s = (32 + (32 * (J - I))) - F;
  if constexpr ((s < 64) && (s > -64)) {
    if constexpr (s >= 0) {
      return mul_wide(limb, k_inv_two_pi[I]) << static_cast<std::uint32_t>(s);
    } else {
      return turn_part_shifted_right<-s>(limb, k_inv_two_pi[I]);
    }
  } else {
    return 0U;
  }
}

/// The four partial products of one limb of the angle.
template <std::int32_t F, std::int32_t J>
SW_FX_INLINE constexpr std::uint64_t turn_parts(std::uint32_t limb) noexcept {
  return turn_part<F, J, 0>(limb) + turn_part<F, J, 1>(limb) + turn_part<F, J, 2>(limb) + turn_part<F, J, 3>(limb);
}

/// Fraction of a turn of the angle m * 2^-F rad, in units of 2^-64 turn:
/// m * 2^-F / (2 pi) mod 1, computed limb by limb. Whole turns fall off the
/// top of the uint64_t (unsigned wrap, which is exactly "mod 1 turn").
/// Error: each of at most 8 truncated partial products loses < 1 unit and the
/// truncated constant < 2^-65 turn, so the result is low by less than 9 units.
template <std::int32_t F>
constexpr std::uint64_t turns(std::uint64_t m) noexcept {
  const std::uint32_t low = word(m & 0xFFFFFFFFU);
  const std::uint32_t high = word(m >> 32U);
  // A zero high limb (always, for 32-bit storage) skips its products.
  const std::uint64_t from_high = (high != 0U) ? turn_parts<F, 1>(high) : 0U;
  return turn_parts<F, 0>(low) + from_high;
}

/// turns() of the magnitude of a raw angle of either storage. A 32-bit
/// angle's magnitude (<= 2^31) is one limb, taken as a word (magnitude32), so
/// its high limb is neither formed nor tested: the same value, since that
/// limb is zero.
template <std::int32_t F, typename S>
constexpr std::uint64_t angle_turns(S raw) noexcept {
  if constexpr (std::is_same<S, std::int32_t>::value) {
    return turn_parts<F, 0>(magnitude32(raw));
  } else {
    return turns<F>(magnitude(raw));
  }
}

/// angle_turns() of a 32-bit magnitude `limb` of F fractional bits (0 < F <
/// 32) whose product with k_inv_two_pi[2] is below 2^(32 + F) (at most
/// 2.015 rad for F = 28), from two products instead of three. With s = 32 -
/// F, the first two limbs of 1/(2 pi) shifted left by s bits are top 2^64 +
/// mid 2^32 + low, so floor(limb (k0 2^(32 + s) + k1 2^s) / 2^32) = limb top
/// 2^32 + limb mid + floor(limb low / 2^32): exactly turn_part<F, 0, 0> +
/// turn_part<F, 0, 1> (the first is limb k0 2^s, the second floor(limb k1 /
/// 2^(32 - s)) = limb (k1 >> (32 - s)) + floor(limb low / 2^32)), the sum
/// wrapping mod 1 turn as theirs does. turn_part<F, 0, 2> = floor(limb k2 /
/// 2^(32 + F)) is zero below the bound, turn_part<F, 0, 3> always.
template <std::int32_t F>
SW_FX_INLINE constexpr std::uint64_t near_turns(std::uint32_t limb) noexcept {
  static_assert((F > 0) && (F < 32), "a 32-bit angle with 1 to 31 fractional bits");
  constexpr std::uint32_t s = static_cast<std::uint32_t>(32 - F);
  constexpr std::uint32_t top = k_inv_two_pi[0] >> (32U - s);
  constexpr std::uint32_t mid = (k_inv_two_pi[0] << s) | (k_inv_two_pi[1] >> (32U - s));
  constexpr std::uint32_t low = k_inv_two_pi[1] << s;
  // limb top wraps mod 2^32: its whole turns fall off the top, as in turns().
  // Its low word is zero, so the high word of limb low joins it as an or.
  const std::uint64_t whole = (static_cast<std::uint64_t>(limb * top) << 32U) | mul_high_word(limb, low);
  return whole + mul_wide(limb, mid);
}

/// The largest raw magnitude near_turns<F> reduces exactly: limb k2 < 2^(32 + F).
template <std::int32_t F>
constexpr std::uint64_t k_near_limit = ((std::uint64_t{1U} << static_cast<std::uint32_t>(32 + F)) - 1U) / k_inv_two_pi[2];

/// An angle of magnitude below 3 pi/4 reduced as reduce() does, to q pi/2 +
/// r, q 0 or 1, |r| <= pi/4, r = m 2^-61 pi/4: the quadrant as whether sin
/// and cos swap kernels, and the one sign the reduction decides, cos's
/// beyond pi/2. reduce()'s other cases (q 2 and 3) cannot arise.
struct NearReduced {
  bool odd_quadrant;    ///< |angle| beyond pi/4: sin from cos(r), cos from sin(r)
  bool beyond_half_pi;  ///< |angle| at or beyond pi/2: cos negative
  std::uint64_t m;
};

/// reduce() below 3/8 turn: u < 1/8 is quadrant 0 with r = u; u in [1/8, 1/4)
/// quadrant 1 with r = -(1/4 - u) (reduce()'s negative residual, cos still
/// positive); u in [1/4, 3/8) quadrant 1 with r = u - 1/4 (cos negative).
/// The same m and signs as reduce(), sin_negative() and cos_negative().
constexpr NearReduced reduce_near(std::uint64_t turn_fraction) noexcept {
  // Whole eighths of a turn: 0, 1 or 2 below 3/8 turn.
  const std::uint32_t eighths = word(turn_fraction >> 61U);
  if (eighths == 0U) {
    return NearReduced{false, false, turn_fraction};
  }
  const std::uint64_t quarter = std::uint64_t{1U} << 62U;
  const bool beyond_half_pi = eighths > 1U;
  return NearReduced{true, beyond_half_pi, beyond_half_pi ? (turn_fraction - quarter) : (quarter - turn_fraction)};
}

/// An angle reduced to q * pi/2 + r with |r| <= pi/4. r = (negative ? -1 : 1)
/// * m * 2^-61 * pi/4, m <= 2^61.
struct Reduced {
  std::uint32_t quadrant;
  bool negative;
  std::uint64_t m;
};

constexpr Reduced reduce(std::uint64_t turn_fraction) noexcept {
  const std::uint64_t eighth = std::uint64_t{1U} << 61U;
  const std::uint64_t u = turn_fraction + eighth;  // wraps mod 1 turn: intended
  const std::uint32_t quadrant = static_cast<std::uint32_t>(u >> 62U);
  const std::uint64_t g = u & ((std::uint64_t{1U} << 62U) - 1U);
  if (g >= eighth) {
    return Reduced{quadrant, false, g - eighth};
  }
  return Reduced{quadrant, true, eighth - g};
}

/// v^2 in units of 2^-31 for v = m * 2^-61 <= 1, within 0.5 + 2^-30 units.
/// At most 2^31 (v <= 1), so it is returned as one word.
constexpr std::uint32_t square_q31(std::uint64_t m) noexcept {
  const std::uint32_t m_hi = word(m >> 30U);  // <= 2^31
  // m_lo 2^2 for m_lo = m mod 2^30: m's low word shifted, its top two bits
  // off the word (the same word sin_kernel takes).
  const std::uint32_t m_lo4 = word(m << 2U);
  // v^2 * 2^31 = m_hi^2 2^-31 + m_hi m_lo 2^-60 + m_lo^2 2^-91; the last term
  // is below 2^-31 units and dropped. floor(m_hi m_lo / 2^29) = floor(m_hi
  // m_lo4 / 2^31) < 2^32 (m_hi m_lo < 2^61): one word, the high word of
  // (2 m_hi) m_lo4. 2 m_hi wraps (to 0) only for m_hi = 2^31, that is m =
  // 2^61, whose m_lo4 is 0: the product is 0 either way.
  const std::uint32_t cross = mul_high_word(m_hi << 1U, m_lo4);
  const std::uint64_t sum = mul_wide(m_hi, m_hi) + cross;
  return word((sum + (std::uint64_t{1U} << 30U)) >> 31U);
}

/// c0 - w (c1 - w (c2 - w (c3 - w (c4 - w c5)))) for w <= 2^31 (v <= 1),
/// each c_k in units of 2^-(32 + S[k]) and the result in c0's: the Horner
/// steps of both kernels, each product rounded on its high word
/// (mul_round_high). For both coefficient sets every bracket is positive
/// (c_k exceeds the next term, w <= 1), so the steps stay unsigned, and each
/// is below its coefficient, so one word. Forced inline: one source for both
/// kernels, and the code GCC made of each before (sin_poly out of line,
/// cos_kernel's steps in place); as a plain template it cost the Cortex-M0
/// 67 instructions per step, out of line 39.
template <const std::uint32_t (&C)[6], const std::uint32_t (&S)[6]>
SW_FX_INLINE constexpr std::uint32_t alternating_horner(std::uint32_t w) noexcept {
  std::uint32_t b = C[5];
  b = C[4] - mul_round_high<(31U + S[5]) - S[4]>(w, b);
  b = C[3] - mul_round_high<(31U + S[4]) - S[3]>(w, b);
  b = C[2] - mul_round_high<(31U + S[3]) - S[2]>(w, b);
  b = C[1] - mul_round_high<(31U + S[2]) - S[1]>(w, b);
  return C[0] - mul_round_high<(31U + S[1]) - S[0]>(w, b);
}

/// P(w) = a1 - w (a3 - w (a5 - w (a7 - w (a9 - w a11)))) in units of 2^-32.
constexpr std::uint32_t sin_poly(std::uint32_t w) noexcept { return alternating_horner<k_sin_a, k_sin_shift>(w); }

/// |sin(pi/4 v)| * 2^30 rounded (<= 2^30, one word), for v = m * 2^-61 in
/// [0, 1] and w = square_q31(m) (computed once when cos_kernel needs it too).
constexpr std::uint32_t sin_kernel(std::uint64_t m, std::uint32_t w) noexcept {
  const std::uint32_t p = sin_poly(w);
  // sin = v P with v taken at full precision: m * P * 2^-93, in 2^-30 units
  // m * P * 2^-63. m = m_hi 2^30 + m_lo keeps both products below 2^63:
  // t = m_hi P + floor(m_lo P / 2^30), the second the high word of m_lo4 P
  // (m_lo4 = m_lo 2^2, square_q31's word).
  const std::uint32_t m_hi = word(m >> 30U);
  const std::uint32_t m_lo4 = word(m << 2U);
  // round(t / 2^33) = (floor(t / 2^32) + 1) >> 1, t < 2^63: from t's high
  // word alone.
  const std::uint32_t t_high = word((mul_wide(m_hi, p) + mul_high_word(m_lo4, p)) >> 32U);
  return (t_high + 1U) >> 1U;
}

/// cos(pi/4 v) * 2^30 rounded, for w = square_q31(m), v = m * 2^-61 in [0, 1].
constexpr std::uint64_t cos_kernel(std::uint32_t w) noexcept {
  const std::uint32_t b = alternating_horner<k_cos_b, k_cos_shift>(w);
  // cos = 1 - w Q, Q = b in units 2^-33: w Q in 2^-30 units is w b 2^-34.
  return (std::uint64_t{1U} << 30U) - mul_round_high<34U>(w, b);
}

/// |angle| = q pi/2 + r: sin is +-sin(r) in quadrants 0 and 2, +-cos(r) in
/// 1 and 3, and odd in the angle.
constexpr bool sin_negative(const Reduced& r, bool angle_negative) noexcept {
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  const bool negative = odd_quadrant ? (r.quadrant == 3U) : (r.negative != (r.quadrant == 2U));
  return negative != angle_negative;
}

/// cos is +-cos(r) in quadrants 0 and 2, -+sin(r) in 1 and 3, and even.
constexpr bool cos_negative(const Reduced& r) noexcept {
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  return odd_quadrant ? (r.negative != (r.quadrant == 1U)) : (r.quadrant == 2U);
}

/// Q1_30 from a sign and a magnitude <= 2^30.
constexpr Q1_30 signed_q1_30(bool negative, std::uint64_t mag) noexcept {
  const std::int32_t v = static_cast<std::int32_t>(mag);
  return Q1_30::from_raw(negative ? -v : v);
}

/// asin(s) in units of 2^-32 rad for s = s32 * 2^-32 in [0, 1/2].
constexpr std::uint64_t asin_poly(std::uint64_t s32) noexcept {
  const std::uint64_t w = mul_round(s32, s32, 32U);  // s^2 <= 1/4 in 2^-32 units
  // All terms of the series are positive: B_n = c_n + w B_(n+1).
  std::uint64_t b = k_asin_c[11];
  for (std::uint32_t step = 0U; step < 11U; ++step) {
    const std::uint32_t n = 10U - step;
    b = k_asin_c[n] + mul_round(w, b, 32U);
  }
  // asin(s) = s + s w B_1.
  return s32 + mul_round(s32, mul_round(w, b, 32U), 32U);
}

/// asin(|x|) in units of 2^-32 rad, |x| = m 2^-F <= 1, given also the exact
/// complement d = 2^F - m. Past 1/2 it uses asin(x) = pi/2 - 2 asin(sqrt((1 -
/// x) / 2)), with 1 - x exact (d), so the steep end near |x| = 1 is as
/// accurate as the flat middle.
template <std::int32_t F>
constexpr std::uint64_t asin_magnitude(std::uint64_t m, std::uint64_t d) noexcept {
  const std::uint64_t one = std::uint64_t{1U} << static_cast<std::uint32_t>(F);
  if ((2U * m) <= one) {
    std::uint64_t s32 = 0U;
    if constexpr (F <= 32) {
      s32 = m << static_cast<std::uint32_t>(32 - F);
    } else {
      const std::uint32_t sh = static_cast<std::uint32_t>(F - 32);
      s32 = (m + (std::uint64_t{1U} << (sh - 1U))) >> sh;
    }
    return asin_poly(s32);
  }
  // s = sqrt(d 2^-(F+1)) <= 1/2; s 2^32 = sqrt(d 2^(63-F)), radicand < 2^62.
  const std::uint64_t radicand = d << static_cast<std::uint32_t>(63 - F);
  const std::uint64_t root = isqrt_floor<std::uint64_t>(radicand);
  // Round to nearest: up when radicand - root^2 > root (no ties possible).
  const std::uint64_t s32 = ((radicand - wide::mul_64x64_low(root, root)) > root) ? (root + 1U) : root;
  return k_half_pi_q32 - (2U * asin_poly(s32));
}

/// atan(u) in units of 2^-32 rad for u = u32 * 2^-32 in [0, tan(pi/8)].
constexpr std::uint64_t atan_poly(std::uint64_t u32) noexcept {
  const std::uint64_t w = mul_round(u32, u32, 32U);  // u^2 <= 0.1716
  // atan(u) = u - u w B_1, B_n = c_n - w B_(n+1): every bracket is positive
  // (c_n > c_(n+1), w < 1), so the Horner steps stay unsigned.
  std::uint64_t b = k_atan_c[10];
  for (std::uint32_t step = 0U; step < 10U; ++step) {
    const std::uint32_t n = 9U - step;
    b = k_atan_c[n] - mul_round(w, b, 32U);
  }
  return u32 - mul_round(u32, mul_round(w, b, 32U), 32U);
}

/// Q3_28 from a sign and an angle in units of 2^-32 rad (< 4 pi).
constexpr Q3_28 q3_28_from_q32(bool negative, std::uint64_t angle_q32) noexcept {
  const std::int32_t v = static_cast<std::int32_t>((angle_q32 + 8U) >> 4U);
  return Q3_28::from_raw(negative ? -v : v);
}

}  // namespace trig
}  // namespace detail

/// sin(angle_rad) in Q1_30, within 1 LSB (2^-30) of the exact sine of the
/// exact angle, for every representable angle. Odd: sin(-x) == -sin(x) bit
/// for bit. Cannot fail.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q1_30 sin(Q<S, F> angle_rad, Status& status) noexcept {
  static_cast<void>(status);
  const detail::trig::Reduced r = detail::trig::reduce(detail::trig::angle_turns<F>(angle_rad.raw()));
  const std::uint32_t w = detail::trig::square_q31(r.m);
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  const std::uint64_t mag = odd_quadrant ? detail::trig::cos_kernel(w) : detail::trig::sin_kernel(r.m, w);
  return detail::trig::signed_q1_30(detail::trig::sin_negative(r, angle_rad.raw() < 0), mag);
}

/// cos(angle_rad) in Q1_30, within 1 LSB of the exact cosine of the exact
/// angle, for every representable angle. Even: cos(-x) == cos(x) bit for bit.
/// Cannot fail.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q1_30 cos(Q<S, F> angle_rad, Status& status) noexcept {
  static_cast<void>(status);
  const detail::trig::Reduced r = detail::trig::reduce(detail::trig::angle_turns<F>(angle_rad.raw()));
  const std::uint32_t w = detail::trig::square_q31(r.m);
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  const std::uint64_t mag = odd_quadrant ? detail::trig::sin_kernel(r.m, w) : detail::trig::cos_kernel(w);
  return detail::trig::signed_q1_30(detail::trig::cos_negative(r), mag);
}

/// The sine and cosine of one angle.
struct SinCos {
  Q1_30 sin;
  Q1_30 cos;
};

/// sin(angle_rad) and cos(angle_rad) together: one range reduction, one
/// square and one evaluation of each kernel, where sin() and cos() apart
/// reduce twice. Bit for bit the values of sin() and cos() (the same
/// reduction, kernels and signs), so within 1 LSB of the exact values for
/// every representable angle. Cannot fail.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr SinCos sincos(Q<S, F> angle_rad, Status& status) noexcept {
  static_cast<void>(status);
  const detail::trig::Reduced r = detail::trig::reduce(detail::trig::angle_turns<F>(angle_rad.raw()));
  const std::uint32_t w = detail::trig::square_q31(r.m);
  const std::uint64_t sin_r = detail::trig::sin_kernel(r.m, w);
  const std::uint64_t cos_r = detail::trig::cos_kernel(w);
  const bool odd_quadrant = (r.quadrant & 1U) != 0U;
  return SinCos{detail::trig::signed_q1_30(detail::trig::sin_negative(r, angle_rad.raw() < 0),
                                           odd_quadrant ? cos_r : sin_r),
                detail::trig::signed_q1_30(detail::trig::cos_negative(r), odd_quadrant ? sin_r : cos_r)};
}

namespace detail {
namespace trig {

/// The bounded sincos() of a raw angle within k_near_limit<F> and below 3
/// pi/4: one function per format, whatever the bounds of its callers (one
/// copy of the kernels).
template <std::int32_t F>
constexpr SinCos near_sincos(std::int32_t raw) noexcept {
  const NearReduced r = reduce_near(near_turns<F>(magnitude32(raw)));
  const std::uint32_t w = square_q31(r.m);
  const std::uint64_t sin_r = sin_kernel(r.m, w);
  const std::uint64_t cos_r = cos_kernel(w);
  return SinCos{signed_q1_30(raw < 0, r.odd_quadrant ? cos_r : sin_r),
                signed_q1_30(r.beyond_half_pi, r.odd_quadrant ? sin_r : cos_r)};
}

}  // namespace trig
}  // namespace detail

template <typename QType, std::uint32_t MaxMag>
class Bounded;  // bounded.hpp, which includes this header

/// sincos() of an angle whose magnitude is bounded at compile time (an
/// fx::Bounded) by at most 2.015 rad in Q3.28 (near_turns()): the same bits
/// as sincos() of angle_rad.q() for every angle within the bound, from a
/// cheaper reduction (two products instead of three, two quadrants instead
/// of four). docs/fixedpoint.md gives the proof and the exhaustive check
/// over every Q3.28 angle of the rover's joints. Cannot fail.
template <std::int32_t F, std::uint32_t MaxMag>
[[nodiscard]] constexpr SinCos sincos(Bounded<Q<std::int32_t, F>, MaxMag> angle_rad, Status& status) noexcept {
  static_cast<void>(status);
  static_assert(MaxMag <= detail::trig::k_near_limit<F>, "an angle bound within near_turns()'s exact range");
  static_assert(detail::trig::near_turns<F>(MaxMag) < (std::uint64_t{3U} << 61U), "an angle bound below 3 pi/4");
  return detail::trig::near_sincos<F>(angle_rad.raw());
}

/// asin(x) in radians, Q3_28, within 1 LSB (2^-28) of the exact value.
/// |x| > 1 raises Flag::domain and returns zero (no silent clamp).
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q3_28 asin(Q<S, F> x, Status& status) noexcept {
  const std::uint64_t one = std::uint64_t{1U} << static_cast<std::uint32_t>(F);
  const std::uint64_t m = detail::magnitude(x.raw());
  if (m > one) {
    status.raise(Flag::domain);
    return Q3_28::zero();
  }
  const std::uint64_t a = detail::trig::asin_magnitude<F>(m, one - m);
  return detail::trig::q3_28_from_q32((x.raw() < 0) && (a != 0U), a);
}

/// acos(x) in radians, in [0, pi], Q3_28, within 1 LSB of the exact value.
/// |x| > 1 raises Flag::domain and returns zero (no silent clamp).
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q3_28 acos(Q<S, F> x, Status& status) noexcept {
  const std::uint64_t one = std::uint64_t{1U} << static_cast<std::uint32_t>(F);
  const std::uint64_t m = detail::magnitude(x.raw());
  if (m > one) {
    status.raise(Flag::domain);
    return Q3_28::zero();
  }
  const std::uint64_t a = detail::trig::asin_magnitude<F>(m, one - m);
  // acos(x) = pi/2 - asin(x); asin(|x|) <= pi/2 by construction.
  const std::uint64_t angle = (x.raw() < 0) ? (detail::trig::k_half_pi_q32 + a) : (detail::trig::k_half_pi_q32 - a);
  return detail::trig::q3_28_from_q32(false, angle);
}

/// The entry angle theta1 = arccos(1 - z/r) in radians, Q3_28, from the
/// sinkage ratio z/r, within 1 LSB of the exact value. Computed with 1 - z/r
/// never formed in a rounded format: for z/r <= 1/2 it is exactly
/// 2 asin(sqrt(z / (2 r))). z/r < 0 or > 2 raises Flag::domain and returns
/// zero.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q3_28 entry_angle(Q<S, F> sinkage_ratio, Status& status) noexcept {
  const std::uint64_t one = std::uint64_t{1U} << static_cast<std::uint32_t>(F);
  const std::uint64_t m = detail::magnitude(sinkage_ratio.raw());
  if ((sinkage_ratio.raw() < 0) || (m > (2U * one))) {
    status.raise(Flag::domain);
    return Q3_28::zero();
  }
  // y = 1 - z/r. |y| and 1 - |y| are both exact in the input's units.
  if (m <= one) {
    // y >= 0: theta1 = pi/2 - asin(y); with 1 - y = z/r this is the
    // 2 asin(sqrt(z/(2r))) form whenever y > 1/2.
    const std::uint64_t a = detail::trig::asin_magnitude<F>(one - m, m);
    return detail::trig::q3_28_from_q32(false, detail::trig::k_half_pi_q32 - a);
  }
  // y < 0: theta1 = pi/2 + asin(|y|), |y| = z/r - 1, 1 - |y| = 2 - z/r.
  const std::uint64_t a = detail::trig::asin_magnitude<F>(m - one, (2U * one) - m);
  return detail::trig::q3_28_from_q32(false, detail::trig::k_half_pi_q32 + a);
}

/// atan2(y, x): the angle of the vector (x, y) in radians, in (-pi, pi],
/// Q3_28, within 1 LSB of the exact value (for the attitude: roll and pitch
/// from accelerometer components). y and x share a format, which cancels in
/// the ratio. atan2(0, 0) raises Flag::domain and returns zero.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q3_28 atan2(Q<S, F> y, Q<S, F> x, Status& status) noexcept {
  const std::uint64_t my = detail::magnitude(y.raw());
  const std::uint64_t mx = detail::magnitude(x.raw());
  // Fold into the first octant: phi = atan(a / b), a <= b.
  const bool steep = my > mx;
  std::uint64_t a = steep ? mx : my;
  std::uint64_t b = steep ? my : mx;
  // 64-bit magnitudes are brought to 32 bits (rounded, the same shift for
  // both) so that the one division below stays in 64 bits.
  // (Tested as b >= 2^32 rather than on bit_length(b): clang's static
  // analyser, which does not follow bit_length's 32-bit halves, then saw a
  // zero divisor below on the path of a one-word b.)
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  if (b >= kWord) {
    // k in [1, 32] here; the shifts are wide::shl/shr, defined for every
    // count, because the analyser does not bound a count of leading zeros.
    const std::uint32_t k = wide::bit_length(b) - 32U;
    const std::uint64_t half = wide::shl(std::uint64_t{1U}, k - 1U);
    a = wide::shr(a, k) + (((a & half) != 0U) ? 1U : 0U);
    b = wide::shr(b, k) + (((b & half) != 0U) ? 1U : 0U);
  }
  // b = max(|x|, |y|) is zero only for atan2(0, 0) (a non-zero b keeps a
  // bit through the rounding shift). Tested on b itself, the divisor, after
  // the shift, so that a static analyser sees every division below guarded.
  if (b == 0U) {
    status.raise(Flag::domain);
    return Q3_28::zero();
  }
  std::uint64_t phi = 0U;
  if ((a << 31U) <= wide::mul_64x64_low(b, detail::trig::k_tan_pi_8_q31)) {
    // a / b <= tan(pi/8): the series directly. a 2^32 < 0.42 * 2^64.
    const std::uint64_t u = ((a << 32U) + (b >> 1U)) / b;
    phi = detail::trig::atan_poly(u);
  } else {
    // atan(a/b) = pi/4 - atan((b - a) / (b + a)), the argument below tan(pi/8).
    const std::uint64_t den = a + b;
    const std::uint64_t u = (((b - a) << 32U) + (den >> 1U)) / den;
    phi = detail::trig::k_quarter_pi_q32 - detail::trig::atan_poly(u);
  }
  if (steep) {
    phi = detail::trig::k_half_pi_q32 - phi;
  }
  if (x.raw() < 0) {
    phi = detail::trig::k_pi_q32 - phi;
  }
  return detail::trig::q3_28_from_q32((y.raw() < 0) && (phi != 0U), phi);
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_TRIG_HPP
