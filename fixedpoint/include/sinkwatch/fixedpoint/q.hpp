// q.hpp: the Q-format number type and its exact or correctly rounded
// arithmetic.
//
// Q<Storage, F> holds the real number raw * 2^-F in a two's-complement
// Storage (int32_t or int64_t), F fraction bits fixed at compile time, so the
// format is visible at every use site. Q<int32_t, 16> is Q15.16.
//
// Policies (docs/fixedpoint.md gives the proofs of the error bounds):
//  * Rounding: to nearest, ties away from zero, on x, / and rescale. Every
//    rounding is done on the magnitude and the sign put back afterwards, so
//    round(-x) == -round(x) exactly (the classic asymmetric-rounding bug of
//    arithmetic-shift libraries is impossible by construction).
//  * Error: add, sub, neg, abs, min, max, clamp and widening rescale are exact;
//    mul, div, narrowing rescale and sqrt are within 0.5 LSB of the exact real
//    result. That holds whenever the status stays clean.
//  * Overflow: the result saturates to the format's max or min and
//    Flag::overflow is raised in the caller's Status. neg(min) and abs(min)
//    saturate to max and raise it too.
//  * Division by zero raises Flag::div_by_zero and returns max, min or zero
//    by the sign of the dividend; sqrt of a negative raises Flag::domain and
//    returns zero. A raised flag, never the value, marks a result unusable.
//  * No undefined or implementation-defined behaviour: all bit shifts are on
//    unsigned magnitudes (MISRA C++:2023 rule 7.0.4), signed values are never
//    shifted, and the only signed conversions are of values known to fit. The
//    results are therefore the same bits on every target.
//
// There are deliberately no arithmetic operators: an operator has nowhere to
// report an overflow. Comparisons, which cannot fail, are operators.
//
// The sign-magnitude helpers, the raw accessors and two comparisons are
// SW_FX_INLINE (inline.hpp, wide.hpp): forced inline for the -Os firmware.
#ifndef SINKWATCH_FIXEDPOINT_Q_HPP
#define SINKWATCH_FIXEDPOINT_Q_HPP

#include <cstdint>
#include <limits>
#include <type_traits>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace fx {

template <typename Storage, std::int32_t FracBits>
class Q;

namespace detail {

template <typename Storage>
struct StorageTraits;
template <>
struct StorageTraits<std::int32_t> {
  static constexpr std::uint32_t bits = 32U;
};
template <>
struct StorageTraits<std::int64_t> {
  static constexpr std::uint32_t bits = 64U;
};

/// The unsigned type wide enough for the exact intermediate of an operation
/// on the given storages: 64 bits when all are int32_t, else 128 bits.
template <typename... Storages>
struct WideFor {
  using type = typename std::conditional<((StorageTraits<Storages>::bits == 32U) && ...), std::uint64_t,
                                         wide::U128>::type;
};

/// |x| without overflow, also for the most negative value.
template <typename Storage>
SW_FX_INLINE constexpr std::uint64_t magnitude(Storage x) noexcept {
  if (x >= 0) {
    return static_cast<std::uint64_t>(x);
  }
  // -(x + 1) cannot overflow; adding 1 back in unsigned arithmetic is exact.
  return static_cast<std::uint64_t>(-(x + 1)) + 1U;
}

/// |x| of a 32-bit value in 32 bits (2^31 for the most negative value).
SW_FX_INLINE constexpr std::uint32_t magnitude32(std::int32_t x) noexcept {
  const auto bits = static_cast<std::uint32_t>(x);
  return (x >= 0) ? bits : (0U - bits);
}

/// Largest magnitude of a result with the given sign: 2^(N-1) - 1 or 2^(N-1).
template <typename Storage>
SW_FX_INLINE constexpr std::uint64_t magnitude_limit(bool negative) noexcept {
  const std::uint64_t top = std::uint64_t{1U} << (StorageTraits<Storage>::bits - 1U);
  return negative ? top : (top - 1U);
}

/// Builds a raw value from sign and magnitude, saturating on overflow.
template <typename Storage, typename W>
SW_FX_INLINE constexpr Storage from_sign_magnitude(bool negative, const W& mag, Status& status) noexcept {
  const W limit = wide::from_u64<W>(magnitude_limit<Storage>(negative));
  if (wide::less(limit, mag)) {
    status.raise(Flag::overflow);
    return negative ? std::numeric_limits<Storage>::min() : std::numeric_limits<Storage>::max();
  }
  const std::uint64_t m = wide::low_u64(mag);
  if (!negative) {
    return static_cast<Storage>(m);
  }
  if (m == magnitude_limit<Storage>(true)) {
    return std::numeric_limits<Storage>::min();
  }
  return static_cast<Storage>(-static_cast<Storage>(m));
}

/// Scales a magnitude by 2^-shift: a right shift rounded to nearest with ties
/// away from zero for shift > 0, an exact left shift for shift < 0. A left
/// shift that would lose bits sets `overflowed` (the result is then beyond
/// every format this library has).
template <typename W>
SW_FX_INLINE constexpr W scale_magnitude(const W& mag, std::int32_t shift, bool& overflowed) noexcept {
  overflowed = false;
  if (shift > 0) {
    const std::uint32_t s = static_cast<std::uint32_t>(shift);
    const W truncated = wide::shr(mag, s);
    // The bit just below the result's LSB is the half: adding it rounds
    // half away from zero, and cannot carry past the width because the
    // shifted value has at least one leading zero bit. (One add of 0 or 1
    // rather than a choice between two wide values, which the Cortex-M0
    // build copied through memcpy.)
    return wide::add(truncated, wide::from_u64<W>(wide::bit(mag, s - 1U) ? 1U : 0U));
  }
  if (shift < 0) {
    const std::uint32_t s = static_cast<std::uint32_t>(-shift);
    // Bits lost iff bit_length(mag) + s > width, that is iff mag has a bit at
    // or above width - s: one shift instead of counting the bits.
    const bool loses_bits = (s >= wide::width(mag)) ? !wide::is_zero(mag)
                                                    : !wide::is_zero(wide::shr(mag, wide::width(mag) - s));
    if (loses_bits) {
      overflowed = !wide::is_zero(mag);
      return wide::is_zero(mag) ? mag : wide::from_u64<W>(0U);
    }
    return wide::shl(mag, s);
  }
  return mag;
}

template <typename Storage>
SW_FX_INLINE constexpr bool is_negative(Storage x) noexcept {
  return x < 0;
}

}  // namespace detail

/// A fixed-point number: the real value raw() * 2^-F.
template <typename Storage, std::int32_t FracBits>
class Q {
  static_assert(std::is_same<Storage, std::int32_t>::value || std::is_same<Storage, std::int64_t>::value,
                "Q storage is int32_t or int64_t");
  static_assert(FracBits >= 0, "Q needs a non-negative number of fraction bits");
  static_assert(FracBits < static_cast<std::int32_t>(detail::StorageTraits<Storage>::bits - 1U),
                "Q needs at least the sign bit and one more outside the fraction");

 public:
  using storage_type = Storage;
  static constexpr std::int32_t frac_bits = FracBits;
  static constexpr std::uint32_t total_bits = detail::StorageTraits<Storage>::bits;
  /// Bits left of the binary point, excluding the sign.
  static constexpr std::int32_t int_bits = static_cast<std::int32_t>(total_bits) - 1 - FracBits;

  constexpr Q() noexcept = default;

  [[nodiscard]] SW_FX_INLINE static constexpr Q from_raw(Storage raw_bits) noexcept { return Q(raw_bits); }
  [[nodiscard]] SW_FX_INLINE static constexpr Q zero() noexcept { return Q(0); }
  [[nodiscard]] static constexpr Q max() noexcept { return Q(std::numeric_limits<Storage>::max()); }
  [[nodiscard]] static constexpr Q min() noexcept { return Q(std::numeric_limits<Storage>::min()); }
  /// The smallest positive value, 2^-F: one LSB.
  [[nodiscard]] SW_FX_INLINE static constexpr Q lsb() noexcept { return Q(1); }
  /// The value 1; raises overflow (and returns max) when F leaves no integer bit.
  [[nodiscard]] static constexpr Q one(Status& status) noexcept { return from_int(1, status); }

  /// The integer `value`, exactly; saturates and raises overflow when it does
  /// not fit.
  [[nodiscard]] static constexpr Q from_int(std::int64_t value, Status& status) noexcept {
    using W = typename detail::WideFor<Storage>::type;
    bool overflowed = false;
    const W mag =
        detail::scale_magnitude(wide::from_u64<W>(detail::magnitude(value)), -FracBits, overflowed);
    const bool negative = value < 0;
    if (overflowed) {
      status.raise(Flag::overflow);
      return negative ? min() : max();
    }
    return Q(detail::from_sign_magnitude<Storage>(negative, mag, status));
  }

  [[nodiscard]] SW_FX_INLINE constexpr Storage raw() const noexcept { return raw_; }

  friend constexpr bool operator==(Q a, Q b) noexcept { return a.raw_ == b.raw_; }
  friend constexpr bool operator!=(Q a, Q b) noexcept { return a.raw_ != b.raw_; }
  SW_FX_INLINE friend constexpr bool operator<(Q a, Q b) noexcept { return a.raw_ < b.raw_; }
  friend constexpr bool operator<=(Q a, Q b) noexcept { return a.raw_ <= b.raw_; }
  SW_FX_INLINE friend constexpr bool operator>(Q a, Q b) noexcept { return a.raw_ > b.raw_; }
  friend constexpr bool operator>=(Q a, Q b) noexcept { return a.raw_ >= b.raw_; }

 private:
  constexpr explicit Q(Storage raw_bits) noexcept : raw_(raw_bits) {}
  Storage raw_{0};
};

/// Common formats. The name gives integer.fraction bits (sign excluded).
using Q15_16 = Q<std::int32_t, 16>;
using Q1_30 = Q<std::int32_t, 30>;
using Q3_28 = Q<std::int32_t, 28>;
using Q31_32 = Q<std::int64_t, 32>;

namespace detail {
/// fx::add on 32-bit storage: one wrapping add of the words and one sign
/// test (the sum overflowed iff it lacks the sign both operands have);
/// beyond the format, the limit of the operands' sign. Forced inline where a
/// caller asks for it by name (the statics' every-cycle pass,
/// flight/src/wheel_load.cpp); fx::add itself stays a call.
template <std::int32_t F>
SW_FX_INLINE constexpr Q<std::int32_t, F> add_word(Q<std::int32_t, F> a, Q<std::int32_t, F> b,
                                                   Status& status) noexcept {
  const auto x = static_cast<std::uint32_t>(a.raw());
  const auto y = static_cast<std::uint32_t>(b.raw());
  const std::uint32_t wrapped = x + y;  // modulo 2^32 by design
  if ((((x ^ wrapped) & (y ^ wrapped)) >> 31U) != 0U) {
    status.raise(Flag::overflow);
    return (a.raw() < 0) ? Q<std::int32_t, F>::min() : Q<std::int32_t, F>::max();
  }
  // Formed on 64 bits, where it cannot overflow (it fits 32 bits here).
  return Q<std::int32_t, F>::from_raw(static_cast<std::int32_t>(static_cast<std::int64_t>(a.raw()) + b.raw()));
}

/// fx::sub on 32-bit storage, as add_word: the difference overflowed iff the
/// operands' signs differ and it lacks a's; beyond the format, the limit of
/// a's sign.
template <std::int32_t F>
SW_FX_INLINE constexpr Q<std::int32_t, F> sub_word(Q<std::int32_t, F> a, Q<std::int32_t, F> b,
                                                   Status& status) noexcept {
  const auto x = static_cast<std::uint32_t>(a.raw());
  const auto y = static_cast<std::uint32_t>(b.raw());
  const std::uint32_t wrapped = x - y;  // modulo 2^32 by design
  if ((((x ^ y) & (x ^ wrapped)) >> 31U) != 0U) {
    status.raise(Flag::overflow);
    return (a.raw() < 0) ? Q<std::int32_t, F>::min() : Q<std::int32_t, F>::max();
  }
  // Formed on 64 bits, where it cannot overflow (it fits 32 bits here).
  return Q<std::int32_t, F>::from_raw(static_cast<std::int32_t>(static_cast<std::int64_t>(a.raw()) - b.raw()));
}
}  // namespace detail

/// a + b, exact; saturates on overflow.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> add(Q<S, F> a, Q<S, F> b, Status& status) noexcept {
  if constexpr (std::is_same<S, std::int32_t>::value) {
    return detail::add_word(a, b, status);
  } else {
    const S x = a.raw();
    const S y = b.raw();
    if ((y > 0) && (x > (std::numeric_limits<S>::max() - y))) {
      status.raise(Flag::overflow);
      return Q<S, F>::max();
    }
    if ((y < 0) && (x < (std::numeric_limits<S>::min() - y))) {
      status.raise(Flag::overflow);
      return Q<S, F>::min();
    }
    return Q<S, F>::from_raw(static_cast<S>(x + y));
  }
}

/// a - b, exact; saturates on overflow.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> sub(Q<S, F> a, Q<S, F> b, Status& status) noexcept {
  if constexpr (std::is_same<S, std::int32_t>::value) {
    return detail::sub_word(a, b, status);
  } else {
    const S x = a.raw();
    const S y = b.raw();
    if ((y < 0) && (x > (std::numeric_limits<S>::max() + y))) {
      status.raise(Flag::overflow);
      return Q<S, F>::max();
    }
    if ((y > 0) && (x < (std::numeric_limits<S>::min() + y))) {
      status.raise(Flag::overflow);
      return Q<S, F>::min();
    }
    return Q<S, F>::from_raw(static_cast<S>(x - y));
  }
}

/// -a, exact; -min saturates to max and raises overflow.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> neg(Q<S, F> a, Status& status) noexcept {
  if (a == Q<S, F>::min()) {
    status.raise(Flag::overflow);
    return Q<S, F>::max();
  }
  return Q<S, F>::from_raw(static_cast<S>(-a.raw()));
}

/// |a|, exact; |min| saturates to max and raises overflow.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> abs(Q<S, F> a, Status& status) noexcept {
  return (a.raw() < 0) ? neg(a, status) : a;
}

template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> min(Q<S, F> a, Q<S, F> b) noexcept {
  return (b < a) ? b : a;
}

template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> max(Q<S, F> a, Q<S, F> b) noexcept {
  return (a < b) ? b : a;
}

/// a limited to [lo, hi]. lo > hi is a caller's error: raises domain and
/// returns lo.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> clamp(Q<S, F> a, Q<S, F> lo, Q<S, F> hi, Status& status) noexcept {
  if (hi < lo) {
    status.raise(Flag::domain);
    return lo;
  }
  return min(max(a, lo), hi);
}

/// a in the format Out: exact when Out has at least as many fraction bits,
/// else rounded to nearest (ties away from zero); saturates on overflow.
template <typename Out, typename S, std::int32_t F>
[[nodiscard]] constexpr Out rescale(Q<S, F> a, Status& status) noexcept {
  using OutS = typename Out::storage_type;
  // 64 bits hold every intermediate: |a| <= 2^63, a right shift only shrinks
  // it, and a left shift that leaves 64 bits leaves every output format too
  // (it overflows here as it would saturate in from_sign_magnitude).
  using W = std::uint64_t;
  const bool negative = detail::is_negative(a.raw());
  bool overflowed = false;
  const W mag = detail::scale_magnitude(detail::magnitude(a.raw()), F - Out::frac_bits, overflowed);
  if (overflowed) {
    // Past 64 bits, so past Out: saturate as from_sign_magnitude would.
    status.raise(Flag::overflow);
    return negative ? Out::min() : Out::max();
  }
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative, mag, status));
}

namespace detail {
// One product per wide type, as a specialised class template (MISRA
// C++:2023 17.8.1: no explicit specialisation of a function template).
template <typename W>
struct WideProduct;
template <>
struct WideProduct<std::uint64_t> {
  SW_FX_INLINE static constexpr std::uint64_t of(std::uint64_t a, std::uint64_t b) noexcept {
    // Only used when both operands come from int32_t storage: each <= 2^31.
    return wide::mul_full(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
  }
};
template <>
struct WideProduct<wide::U128> {
  SW_FX_INLINE static constexpr wide::U128 of(std::uint64_t a, std::uint64_t b) noexcept { return wide::mul_full(a, b); }
};

/// Exact product of two magnitudes in the wide type W.
template <typename W>
SW_FX_INLINE constexpr W wide_product(std::uint64_t a, std::uint64_t b) noexcept {
  return WideProduct<W>::of(a, b);
}

/// The signed result of an exact product magnitude scaled by 2^-shift.
template <typename Out, typename W>
constexpr Out finish_product(bool negative, const W& product, std::int32_t shift, Status& status) noexcept {
  bool overflowed = false;
  const W mag = scale_magnitude(product, shift, overflowed);
  if (overflowed) {
    status.raise(Flag::overflow);
    return negative ? Out::min() : Out::max();
  }
  using OutS = typename Out::storage_type;
  return Out::from_raw(from_sign_magnitude<OutS>(negative && !wide::is_zero(mag), mag, status));
}
}  // namespace detail

namespace detail {
/// p / 2^Shift rounded half up (a magnitude's ties away from zero), for a
/// compile-time Shift in [0, 63) and p + 2^(Shift-1) < 2^64 (no carry out).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::uint64_t round_shift_const(std::uint64_t p) noexcept {
  if constexpr (Shift == 0) {
    return p;
  } else {
    return (p + (std::uint64_t{1U} << static_cast<std::uint32_t>(Shift - 1))) >> static_cast<std::uint32_t>(Shift);
  }
}

/// The magnitude w * v / 2^Shift, rounded half up, for w <= 2^63, v <= 2^32
/// and Shift in [0, 32], without a 128-bit intermediate: with w = hi 2^32 + lo,
/// w v = hi v 2^32 + lo v and, as 2^Shift divides hi v 2^32,
///   round(w v / 2^Shift) = hi v 2^(32 - Shift) + round(lo v / 2^Shift)
/// exactly. hi v <= 2^63 and lo v + 2^(Shift-1) < 2^64 fit 64 bits; false
/// when the result does not (every format then saturates).
template <std::int32_t Shift>
SW_FX_INLINE constexpr bool word_product(std::uint64_t w, std::uint64_t v, std::uint64_t& mag) noexcept {
  static_assert((Shift >= 0) && (Shift <= 32), "a right shift of 0 to 32 bits");
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  const auto hi = static_cast<std::uint32_t>(w >> 32U);
  const auto lo = static_cast<std::uint32_t>(w & (kWord - 1U));
  // v == 2^32 (a Q31.32 one, a whole load's fraction) is a shift.
  const std::uint64_t high = (v == kWord) ? (std::uint64_t{hi} << 32U) : wide::mul_full(hi, static_cast<std::uint32_t>(v));
  const std::uint64_t low = (v == kWord) ? (std::uint64_t{lo} << 32U) : wide::mul_full(lo, static_cast<std::uint32_t>(v));
  const std::uint64_t low_rounded = round_shift_const<Shift>(low);  // low < 2^64 - 2^32: no carry out
  if constexpr (Shift < 32) {
    if ((high >> static_cast<std::uint32_t>(32 + Shift)) != 0U) {
      return false;
    }
  }
  mag = (high << static_cast<std::uint32_t>(32 - Shift)) + low_rounded;
  return mag >= low_rounded;  // no carry out of 64 bits
}

/// The signed result of a magnitude that fitted 64 bits (`fits`), or
/// saturated by the sign when it did not (beyond every format).
template <typename Out>
SW_FX_INLINE constexpr Out finish_64(bool negative, bool fits, std::uint64_t mag, Status& status) noexcept {
  if (!fits) {
    status.raise(Flag::overflow);
    return negative ? Out::min() : Out::max();
  }
  using OutS = typename Out::storage_type;
  return Out::from_raw(from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

/// |a| |b| 2^-Shift rounded into Out where the formats need a 128-bit
/// intermediate: in 64 bits when both magnitudes are below 2^32 (one product
/// instead of four, no 128-bit shifts: docs/performance.md, finding 8) or
/// one is at most 2^32 and Shift is in [0, 32] (word_product: every
/// per-cycle product of the flight code with a 64-bit operand, ninth round);
/// in W otherwise.
template <typename Out, typename W, std::int32_t Shift>
constexpr Out mul_magnitudes(bool negative, std::uint64_t mag_a, std::uint64_t mag_b, Status& status) noexcept {
  constexpr std::uint64_t kWord = std::uint64_t{1U} << 32U;
  if ((mag_a < kWord) && (mag_b < kWord)) {
    return finish_product<Out, std::uint64_t>(
        negative, wide::mul_full(static_cast<std::uint32_t>(mag_a), static_cast<std::uint32_t>(mag_b)), Shift, status);
  }
  if constexpr ((Shift >= 0) && (Shift <= 32)) {
    if ((mag_a <= kWord) || (mag_b <= kWord)) {
      std::uint64_t mag = 0U;
      const bool fits = (mag_b <= kWord) ? word_product<Shift>(mag_a, mag_b, mag) : word_product<Shift>(mag_b, mag_a, mag);
      return finish_64<Out>(negative, fits, mag, status);
    }
  }
  return finish_product<Out, W>(negative, wide_product<W>(mag_a, mag_b), Shift, status);
}
}  // namespace detail

namespace detail {
/// a b 2^-Shift into a 32-bit Out through the magnitudes: one 32 x 32 ->
/// 64-bit product (at most 2^62, so adding the half cannot carry out),
/// rounded half up and given its sign, saturated beyond Out. fx::mul's form
/// for cores without a widening multiply (ARMv6-M: mul_full's 16-bit
/// products); the host tests call it directly.
template <typename Out, std::int32_t Shift>
SW_FX_INLINE constexpr Out mul_word_by_magnitudes(std::int32_t a, std::int32_t b, Status& status) noexcept {
  const bool negative = (a < 0) != (b < 0);
  const std::uint64_t mag = round_shift_const<Shift>(wide::mul_full(magnitude32(a), magnitude32(b)));
  return finish_64<Out>(negative, true, mag, status);
}

/// a b + 2^(Shift-1) - [a and b of opposite signs], modulo 2^64, for a
/// shift of 1 to 31: one multiply-accumulate where the core has it (SMLAL on
/// ARMv7-M). Its floor over 2^Shift is a b 2^-Shift rounded half away from
/// zero (the half less one for a negative product: |p| rounded half up with
/// the sign put back; a zero product floors to zero either way). The one
/// rounding of the signed word products: mul_word_signed's and the bounded
/// products' (bounded.hpp, product_rounded_signed).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::uint64_t rounding_sum(std::int32_t a, std::int32_t b) noexcept {
  static_assert((Shift > 0) && (Shift < 32), "a product rounded by a right shift of 1 to 31 bits");
  const std::uint32_t signs_differ = (static_cast<std::uint32_t>(a) ^ static_cast<std::uint32_t>(b)) >> 31U;
  const auto addend = static_cast<std::int64_t>((std::uint32_t{1U} << static_cast<std::uint32_t>(Shift - 1)) -
                                                signs_differ);
  return static_cast<std::uint64_t>(addend + (static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b)));
}

/// The same from the signed product p = a b (one SMULL or SMLAL where the
/// core has it). For a shift of 1 to 31, rounding_sum's floor over 2^Shift
/// fits 32 bits exactly when the sum lies in [-2^(31+Shift), 2^(31+Shift)),
/// that is when its high word, as a signed value, lies in [-2^(Shift-1),
/// 2^(Shift-1)): one test on the high word, and the result bits Shift to
/// Shift + 31 of the sum (round 14: 2 to 4 instructions fewer per product on
/// the Cortex-M4 than the offset form it replaced). Where the result does
/// not fit, a b is not zero and has the operands' sign. For a shift of 32 to
/// 62 the result always fits (|a b| <= 2^62): floor((p + 2^(Shift-1) -
/// [p < 0]) / 2^Shift), taken on p + 2^63 as an unsigned shift and
/// 2^(63-Shift) taken off again. The same bits and flags as
/// mul_word_by_magnitudes (test_q checks both against the exact product).
template <typename Out, std::int32_t Shift>
SW_FX_INLINE constexpr Out mul_word_signed(std::int32_t a, std::int32_t b, Status& status) noexcept {
  static_assert((Shift > 0) && (Shift < 63), "a product rounded by a right shift of 1 to 62 bits");
  static_assert(std::is_same<typename Out::storage_type, std::int32_t>::value, "a 32-bit result");
  if constexpr (Shift < 32) {
    constexpr std::uint32_t kHalf = std::uint32_t{1U} << static_cast<std::uint32_t>(Shift - 1);
    const std::uint64_t sum = rounding_sum<Shift>(a, b);
    const auto high = static_cast<std::uint32_t>(sum >> 32U);
    if (((high + kHalf) >> static_cast<std::uint32_t>(Shift)) != 0U) {
      status.raise(Flag::overflow);
      return ((a < 0) != (b < 0)) ? Out::min() : Out::max();
    }
    const auto bits = static_cast<std::uint32_t>(sum >> static_cast<std::uint32_t>(Shift));
    return Out::from_raw(static_cast<std::int32_t>(bits));
  } else {
    // |a b| <= 2^62, so the rounded value is at most 2^(62-Shift) <= 2^30
    // in magnitude: it always fits Out, and no test is made.
    static_cast<void>(status);
    const auto p = static_cast<std::uint64_t>(static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b));
    constexpr std::uint64_t kOffset =
        (std::uint64_t{1U} << 63U) + (std::uint64_t{1U} << static_cast<std::uint32_t>(Shift - 1));
    const std::uint64_t floored = ((p + kOffset) - (p >> 63U)) >> static_cast<std::uint32_t>(Shift);
    constexpr std::uint64_t kOffsetAfterShift = std::uint64_t{1U} << static_cast<std::uint32_t>(63 - Shift);
    const std::uint64_t rounded = floored - kOffsetAfterShift;  // modulo 2^64 where negative: by design
    return Out::from_raw(static_cast<std::int32_t>(static_cast<std::int64_t>(rounded)));
  }
}

/// a b 2^-Shift into a 32-bit Out by the core's cheaper form: the signed
/// product where the core multiplies 32 x 32 -> 64 signed in one
/// instruction and the result is rounded (docs/performance.md, session 18),
/// else the magnitudes. The same bits and flags either way.
template <typename Out, std::int32_t Shift>
SW_FX_INLINE constexpr Out mul_word(std::int32_t a, std::int32_t b, Status& status) noexcept {
  if constexpr ((Shift > 0) && !wide::kMul32x32BySoftware) {
    return mul_word_signed<Out, Shift>(a, b, status);
  } else {
    return mul_word_by_magnitudes<Out, Shift>(a, b, status);
  }
}
}  // namespace detail

/// a * b in the format Out, rounded to nearest (ties away from zero), within
/// 0.5 LSB of Out; saturates on overflow. One exact product, rounded once;
/// the paths differ only in the width they need (docs/fixedpoint.md 4), so
/// every path gives the same bits.
template <typename Out, typename SA, std::int32_t FA, typename SB, std::int32_t FB>
[[nodiscard]] constexpr Out mul(Q<SA, FA> a, Q<SB, FB> b, Status& status) noexcept {
  using W = typename detail::WideFor<SA, SB, typename Out::storage_type>::type;
  constexpr std::int32_t shift = (FA + FB) - Out::frac_bits;
  constexpr bool kWordOperands = (detail::StorageTraits<SA>::bits == 32U) && (detail::StorageTraits<SB>::bits == 32U);
  if constexpr (kWordOperands && (shift >= 0) && (shift < 63)) {
    // Both operands on 32 bits and no left shift, whatever Out's storage:
    // 32-bit magnitudes, one 32 x 32 -> 64-bit product (at most 2^62, so
    // adding the half cannot carry out) and a constant shift (what it saves
    // per step: docs/performance.md, eighth and ninth rounds).
    if constexpr (std::is_same<typename Out::storage_type, std::int64_t>::value) {
      // |a b| <= 2^62 < 2^63 - 1 whatever the shift: a 64-bit result cannot
      // saturate, so no test (the Q23.40 and Q15.48 products of Eq. 11 and
      // the torque limit; docs/performance.md, session 17).
      static_cast<void>(status);
      const bool negative = (a.raw() < 0) != (b.raw() < 0);
      const std::uint64_t product = wide::mul_full(detail::magnitude32(a.raw()), detail::magnitude32(b.raw()));
      const auto m = static_cast<std::int64_t>(detail::round_shift_const<shift>(product));
      return Out::from_raw(negative ? -m : m);
    } else {
      return detail::mul_word<Out, shift>(a.raw(), b.raw(), status);
    }
  } else if constexpr (std::is_same<W, std::uint64_t>::value) {
    const bool negative = detail::is_negative(a.raw()) != detail::is_negative(b.raw());
    return detail::finish_product<Out, W>(
        negative, detail::wide_product<W>(detail::magnitude(a.raw()), detail::magnitude(b.raw())), shift, status);
  } else {
    const bool negative = detail::is_negative(a.raw()) != detail::is_negative(b.raw());
    return detail::mul_magnitudes<Out, W, shift>(negative, detail::magnitude(a.raw()), detail::magnitude(b.raw()),
                                                 status);
  }
}

/// a * b in a's format.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> mul(Q<S, F> a, Q<S, F> b, Status& status) noexcept {
  return mul<Q<S, F>>(a, b, status);
}

namespace detail {
/// |a| 2^K / |b| rounded into Out (b != 0) when both scaled operands fit 64
/// bits: the quotient, remainder and rounding of the 128-bit path from one
/// 64-bit division (the step's slip and acceleration: docs/performance.md,
/// ninth round; wide::divmod, which divides by a one-word divisor without a
/// library call on a core without a divide instruction, docs/fixedpoint.md
/// 5.8). False, and `out` untouched, when they do not fit.
template <typename Out, std::int32_t K>
constexpr bool quotient_in_64_bits(bool negative, std::uint64_t mag_a, std::uint64_t mag_b, Out& out,
                                   Status& status) noexcept {
  constexpr std::uint32_t up = (K > 0) ? static_cast<std::uint32_t>(K) : 0U;
  constexpr std::uint32_t down = (K < 0) ? static_cast<std::uint32_t>(-K) : 0U;
  if ((wide::shr(mag_a, 64U - up) != 0U) || (wide::shr(mag_b, 64U - down) != 0U)) {
    return false;
  }
  const std::uint64_t den = wide::shl(mag_b, down);  // != 0: b != 0, no bit lost
  const wide::DivMod<std::uint64_t> qr = wide::divmod(wide::shl(mag_a, up), den);
  const std::uint64_t mag = qr.quotient + ((qr.remainder >= (den - qr.remainder)) ? 1U : 0U);
  out = finish_64<Out>(negative, true, mag, status);
  return true;
}
}  // namespace detail

/// a / b in the format Out, rounded to nearest (ties away from zero), within
/// 0.5 LSB of Out; saturates on overflow. b == 0 raises div_by_zero and gives
/// max, min or zero by the sign of a.
template <typename Out, typename SA, std::int32_t FA, typename SB, std::int32_t FB>
[[nodiscard]] constexpr Out div(Q<SA, FA> a, Q<SB, FB> b, Status& status) noexcept {
  using OutS = typename Out::storage_type;
  using W = typename detail::WideFor<SA, SB, OutS>::type;
  const bool negative = detail::is_negative(a.raw()) != detail::is_negative(b.raw());
  if (b.raw() == 0) {
    status.raise(Flag::div_by_zero);
    if (a.raw() == 0) {
      return Out::zero();
    }
    return detail::is_negative(a.raw()) ? Out::min() : Out::max();
  }
  // raw_out = |a| * 2^(Fo + FB - FA) / |b|; the power of two goes on the
  // dividend when positive and on the divisor when negative, both exact.
  constexpr std::int32_t k = (Out::frac_bits + FB) - FA;
  if constexpr (!std::is_same<W, std::uint64_t>::value && (k > -64) && (k < 64)) {
    Out out{};
    if (detail::quotient_in_64_bits<Out, k>(negative, detail::magnitude(a.raw()), detail::magnitude(b.raw()), out,
                                            status)) {
      return out;
    }
  }
  bool num_overflow = false;
  bool den_overflow = false;
  const W num = detail::scale_magnitude(wide::from_u64<W>(detail::magnitude(a.raw())), (k > 0) ? -k : 0,
                                        num_overflow);
  const W den = detail::scale_magnitude(wide::from_u64<W>(detail::magnitude(b.raw())), (k < 0) ? k : 0,
                                        den_overflow);
  if (num_overflow) {
    // |a| * 2^k >= 2^width while |b| <= 2^(N-1): the quotient is at least
    // 2^(width - N + 1), beyond every output format (docs/fixedpoint.md).
    status.raise(Flag::overflow);
    return negative ? Out::min() : Out::max();
  }
  if (den_overflow) {
    // The divisor exceeds 2^width > 2 |a|: the quotient rounds to zero.
    return Out::zero();  // GCOVR_EXCL_LINE defensive, unreachable: the divisor is shifted <= 62 bits (docs/coverage.md)
  }
  const wide::DivMod<W> qr = wide::divmod(num, den);
  // Round half away from zero: up when remainder >= divisor - remainder.
  const bool round_up = !wide::less(qr.remainder, wide::sub(den, qr.remainder));
  const W mag = round_up ? wide::add(qr.quotient, wide::from_u64<W>(1U)) : qr.quotient;
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative && !wide::is_zero(mag), mag, status));
}

/// a / b in a's format.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> div(Q<S, F> a, Q<S, F> b, Status& status) noexcept {
  return div<Q<S, F>>(a, b, status);
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_Q_HPP
