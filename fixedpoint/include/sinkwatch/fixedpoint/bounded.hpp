// bounded.hpp: 32-bit fixed-point values whose range is proven at compile
// time, and the operations that need no saturation check because of it.
//
// A Bounded<Q, M> is a Q value with |raw| <= M. Each operation computes the
// bound of its result from its operands' bounds (interval arithmetic on the
// magnitudes, rounding included) and static_asserts that it fits the 32-bit
// format, so at run time a sum is one integer add and a product one
// 32 x 32 -> 64-bit product and its rounding: no test, no status. A value
// enters through bound_to<M>(q, status), the one run-time check (beyond M it
// saturates to +-M and raises overflow, as a checked operation would), or
// from a compile-time constant (bounded_raw), and leaves through q().
//
// Rounding and results: the same bits as the checked operations of q.hpp
// (fx::add, fx::sub, fx::neg, fx::mul: ties away from zero on the
// magnitude, within 0.5 LSB of the output), which never saturate on these
// operands because of the bounds; host_tests/fixedpoint/test_bounded.cpp and
// props/fixedpoint/prop_bounded.cpp compare them bit for bit.
//
// rotated() is the one operation whose bound is not interval arithmetic: the
// components of a point turned by an angle whose sine and cosine come from
// fx::sincos (each within 1 LSB of Q1.30 of the exact value, so
// sin^2 + cos^2 <= (1 + 2^-29)^2) are at most sqrt(2) times the point's
// bound, plus one LSB for the two rounded products (docs/fixedpoint.md,
// "Bounded values").
#ifndef SINKWATCH_FIXEDPOINT_BOUNDED_HPP
#define SINKWATCH_FIXEDPOINT_BOUNDED_HPP

#include <cstdint>
#include <type_traits>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace fx {

/// The largest bound a 32-bit format holds: INT32_MAX (|INT32_MIN| is never
/// a bound, so negation is exact).
constexpr std::uint32_t kMaxBound = 0x7FFFFFFFU;

/// A Q value of 32-bit storage with |raw()| <= MaxMag.
template <typename QType, std::uint32_t MaxMag>
class Bounded {
  static_assert(std::is_same<typename QType::storage_type, std::int32_t>::value, "Bounded holds 32-bit formats");
  static_assert(MaxMag <= kMaxBound, "a bound beyond the 32-bit format");

 public:
  using q_type = QType;
  static constexpr std::uint32_t max_mag = MaxMag;

  constexpr Bounded() noexcept = default;

  /// The raw bits `raw`, which the caller has proven within MaxMag (only the
  /// operations below and bound_to use it).
  [[nodiscard]] SW_FX_INLINE static constexpr Bounded trusted(std::int32_t raw) noexcept { return Bounded(raw); }

  [[nodiscard]] SW_FX_INLINE constexpr QType q() const noexcept { return QType::from_raw(raw_); }
  [[nodiscard]] SW_FX_INLINE constexpr std::int32_t raw() const noexcept { return raw_; }

 private:
  SW_FX_INLINE constexpr explicit Bounded(std::int32_t raw) noexcept : raw_(raw) {}
  std::int32_t raw_{0};
};

/// q within +-MaxMag; beyond it, +-MaxMag by its sign and overflow raised.
template <std::uint32_t MaxMag, typename S, std::int32_t F>
[[nodiscard]] SW_FX_INLINE constexpr Bounded<Q<S, F>, MaxMag> bound_to(Q<S, F> q, Status& status) noexcept {
  constexpr auto kLimit = static_cast<std::int32_t>(MaxMag);
  using B = Bounded<Q<S, F>, MaxMag>;
  if (q.raw() > kLimit) {
    status.raise(Flag::overflow);
    return B::trusted(kLimit);
  }
  if (q.raw() < -kLimit) {
    status.raise(Flag::overflow);
    return B::trusted(-kLimit);
  }
  return B::trusted(q.raw());
}

/// The compile-time constant Raw * 2^-F, bounded by its own magnitude.
template <typename QType, std::int32_t Raw>
[[nodiscard]] constexpr Bounded<QType, static_cast<std::uint32_t>((Raw < 0) ? -Raw : Raw)> bounded_raw() noexcept {
  static_assert(Raw > -static_cast<std::int32_t>(kMaxBound) - 1, "INT32_MIN has no 32-bit magnitude");
  return Bounded<QType, static_cast<std::uint32_t>((Raw < 0) ? -Raw : Raw)>::trusted(Raw);
}

/// The same value under a looser bound (so that two branches share a type).
template <std::uint32_t Wider, typename QType, std::uint32_t M>
[[nodiscard]] SW_FX_INLINE constexpr Bounded<QType, Wider> widen(Bounded<QType, M> a) noexcept {
  static_assert(Wider >= M, "widen loosens a bound, never tightens it");
  return Bounded<QType, Wider>::trusted(a.raw());
}

/// a + b, exact: |a + b| <= A + B, which fits.
template <typename QType, std::uint32_t A, std::uint32_t B>
[[nodiscard]] SW_FX_INLINE constexpr Bounded<QType, A + B> add(Bounded<QType, A> a, Bounded<QType, B> b) noexcept {
  static_assert(A <= (kMaxBound - B), "the sum's bound leaves the format");
  return Bounded<QType, A + B>::trusted(static_cast<std::int32_t>(a.raw() + b.raw()));
}

/// a - b, exact: |a - b| <= A + B, which fits.
template <typename QType, std::uint32_t A, std::uint32_t B>
[[nodiscard]] SW_FX_INLINE constexpr Bounded<QType, A + B> sub(Bounded<QType, A> a, Bounded<QType, B> b) noexcept {
  static_assert(A <= (kMaxBound - B), "the difference's bound leaves the format");
  return Bounded<QType, A + B>::trusted(static_cast<std::int32_t>(a.raw() - b.raw()));
}

/// -a, exact (no bound reaches INT32_MIN).
template <typename QType, std::uint32_t A>
[[nodiscard]] SW_FX_INLINE constexpr Bounded<QType, A> neg(Bounded<QType, A> a) noexcept {
  return Bounded<QType, A>::trusted(static_cast<std::int32_t>(-a.raw()));
}

namespace detail {
/// The bound of a product's magnitude |a| |b| 2^-Shift rounded half up, for
/// |a| <= A and |b| <= B: the rounding is monotonic, so it is A B's.
template <std::uint32_t A, std::uint32_t B, std::int32_t Shift>
constexpr std::uint64_t kProductBound = round_shift_const<Shift>(std::uint64_t{A} * std::uint64_t{B});

/// a b 2^-Shift rounded to nearest, ties away from zero, as fx::mul rounds
/// it, for a product whose rounded magnitude the caller has bounded below
/// 2^31: through the magnitudes, for ARMv6-M (mul_full's 16-bit products).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int32_t product_rounded_by_magnitudes(std::int32_t a, std::int32_t b) noexcept {
  static_assert((Shift > 0) && (Shift < 32), "a product rounded by a right shift of 1 to 31 bits");
  // |a| |b| <= 2^62: the rounding's half cannot carry out of 64 bits.
  const std::uint64_t product = wide::mul_full(magnitude32(a), magnitude32(b));
  const auto bits = static_cast<std::int32_t>(round_shift_const<Shift>(product));  // below 2^31: the bound
  return ((a < 0) != (b < 0)) ? -bits : bits;
}

/// The same from the signed product (|a b| <= 2^62) in one multiply-
/// accumulate where the core has it (SMLAL on ARMv7-M): the rounded value is
/// floor((a b + 2^(s-1) - [a, b of opposite signs]) / 2^s), |a b| rounded
/// half up with the sign put back (a zero product takes 2^(s-1) - 1 or
/// 2^(s-1), both floored to zero). Its bits 0 to 31 are bits s to s + 31 of
/// the sum, the same from a logical shift as from an arithmetic one, so no
/// offset is added or taken off around the shift (round 14: an instruction
/// fewer per product on the Cortex-M4 than the offset form it replaces, the
/// same bits; test_bounded checks it against the checked product).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int32_t product_rounded_signed(std::int32_t a, std::int32_t b) noexcept {
  static_assert((Shift > 0) && (Shift < 32), "a product rounded by a right shift of 1 to 31 bits");
  const std::uint64_t sum = rounding_sum<Shift>(a, b);
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(sum >> static_cast<std::uint32_t>(Shift)));
}

/// a b 2^-Shift rounded to nearest, ties away from zero (fx::mul's bits),
/// as a 64-bit value: |a b| <= 2^62, so the half added to the magnitude
/// cannot carry out and the result always fits. For products whose
/// operands' bounds the caller has proven but whose result needs more than
/// 32 bits (Eq. 11's r C3 W in Q23.40).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int64_t wide_product_rounded(std::int32_t a, std::int32_t b) noexcept {
  static_assert((Shift >= 0) && (Shift < 63), "a product rounded by a right shift of 0 to 62 bits");
  const std::uint64_t mag = round_shift_const<Shift>(wide::mul_32x32_64(magnitude32(a), magnitude32(b)));
  const auto m = static_cast<std::int64_t>(mag);  // <= 2^62
  return ((a < 0) != (b < 0)) ? -m : m;
}

/// The bounded product's rounding, by the core's cheaper form (the same
/// bits; test_bounded checks both on every target). One function per shift,
/// whatever the bounds (they only live in the types), and not forced inline:
/// a copy per use cost the Cortex-M4 1.4 KiB of flash for 1.2 % of the step
/// (docs/performance.md, session 17).
template <std::int32_t Shift>
constexpr std::int32_t product_rounded(std::int32_t a, std::int32_t b) noexcept {
  if constexpr (wide::kMul32x32BySoftware) {
    return product_rounded_by_magnitudes<Shift>(a, b);
  } else {
    return product_rounded_signed<Shift>(a, b);
  }
}

/// Whether product_rounded_by_words<Shift> holds: a shift of 17 to 31 (its
/// operands are any bounded ones, below 2^31 in magnitude).
template <std::int32_t Shift>
constexpr bool kRoundsInWords = (Shift >= 17) && (Shift <= 31);

/// product_rounded's bits with the rounding done on 32-bit words, for a
/// shift of 17 to 31 (the statics' rotations and projections: 30 and 28) and
/// a product whose rounded magnitude the caller has bounded below 2^31: on
/// ARMv6-M the 64-bit product's assembly and its 64-bit shift are most of
/// product_rounded_by_magnitudes. With |a| = a_hi 2^16 + a_lo, |b| likewise,
/// |a b| = hh 2^32 + mid 2^16 + ll, and s = Shift:
///   floor((|a b| + 2^(s-1)) / 2^s)
///     = floor((hh 2^16 + mid + 2^(s-17) + floor(ll / 2^16)) / 2^(s-16))
///     = hh 2^(32-s) + floor((mid + 2^(s-17) + floor(ll / 2^16)) / 2^(s-16)),
/// as floor(floor(x / m) / n) = floor(x / (m n)) and hh 2^16 is a multiple of
/// 2^(s-16). The bracket fits a word: with |a|, |b| <= 2^31 - 1 the high
/// halves are below 2^15, so mid <= 2 (2^16 - 1)(2^15 - 1) = 2^32 - 3 2^16 + 2,
/// floor(ll / 2^16) <= 2^16 - 2 and 2^(s-17) <= 2^14. hh 2^(32-s) is at most
/// the rounded magnitude, below 2^31.
/// host_tests/fixedpoint/test_bounded.cpp compares it with fx::mul.
/// Forced inline: the caller chooses (Rounding) between this and the call
/// below.
/// The two parts of that rounding for magnitudes |a|, |b| <= 2^31: hh =
/// a_hi b_hi and the middle column with the rounding half and the low
/// product's top half, below 2^32 (the bound above). The rounded magnitude
/// is hh 2^(32-s) + floor(column / 2^(s-16)); product_checked_by_words
/// (flight's rover_statics.hpp) tests the same two parts against a format's
/// limits.
struct RoundingWords {
  std::uint32_t hh;
  std::uint32_t column;
};

template <std::int32_t Shift>
SW_FX_INLINE constexpr RoundingWords rounding_words(std::uint32_t mag_a, std::uint32_t mag_b) noexcept {
  static_assert(kRoundsInWords<Shift>, "a product rounded by a right shift of 17 to 31 bits");
  constexpr std::uint32_t kHalfMask = 0xFFFFU;
  constexpr std::uint32_t kHalf = 1U << static_cast<std::uint32_t>(Shift - 17);
  const std::uint32_t a_lo = mag_a & kHalfMask;
  const std::uint32_t a_hi = mag_a >> 16U;
  const std::uint32_t b_lo = mag_b & kHalfMask;
  const std::uint32_t b_hi = mag_b >> 16U;
  return RoundingWords{a_hi * b_hi, (((a_lo * b_hi) + (a_hi * b_lo)) + kHalf) + ((a_lo * b_lo) >> 16U)};
}

template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int32_t product_rounded_by_words_inline(std::int32_t a, std::int32_t b) noexcept {
  constexpr auto kLowShift = static_cast<std::uint32_t>(Shift - 16);
  const RoundingWords w = rounding_words<Shift>(magnitude32(a), magnitude32(b));
  const std::uint32_t bits = (w.hh << (32U - static_cast<std::uint32_t>(Shift))) + (w.column >> kLowShift);
  const auto value = static_cast<std::int32_t>(bits);  // below 2^31: the caller's bound
  return ((a < 0) != (b < 0)) ? -value : value;
}

/// The same as one function per shift, not forced inline (as
/// product_rounded).
template <std::int32_t Shift>
constexpr std::int32_t product_rounded_by_words(std::int32_t a, std::int32_t b) noexcept {
  return product_rounded_by_words_inline<Shift>(a, b);
}
}  // namespace detail

/// Where a bounded product's rounding runs: in one function per shift
/// (`called`, the default: the flash of code that runs rarely), or in the
/// caller (`inlined`, for a caller that runs every cycle): the SMULL form
/// where the core has it (about the size of its call), the words' form on
/// ARMv6-M. Every product inlined took 193 instructions off the Cortex-M4's
/// step for 1.4 KiB of flash and 141 off the Cortex-M0's for 3.6 KiB; the
/// statics ask for it in the every-cycle pass only (wheel_load.cpp,
/// kRotationRounding), and on ARMv6-M for the rotations only.
enum class Rounding : std::uint8_t { called, inlined };

namespace detail {
/// The called form: the words' one function per shift where they hold, else
/// product_rounded (two-way branches, for hicpp-multiway-paths-covered).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int32_t product_rounded_called(std::int32_t a, std::int32_t b) noexcept {
  if constexpr (wide::kMul32x32BySoftware && kRoundsInWords<Shift>) {
    return product_rounded_by_words<Shift>(a, b);
  } else {
    return product_rounded<Shift>(a, b);
  }
}

/// The inlined form: the SMULL form, or on ARMv6-M the words' form (the
/// called one for a shift they do not hold).
template <std::int32_t Shift>
SW_FX_INLINE constexpr std::int32_t product_rounded_inlined(std::int32_t a, std::int32_t b) noexcept {
  if constexpr (!wide::kMul32x32BySoftware) {
    return product_rounded_signed<Shift>(a, b);
  } else {
    if constexpr (kRoundsInWords<Shift>) {
      return product_rounded_by_words_inline<Shift>(a, b);
    } else {
      return product_rounded<Shift>(a, b);
    }
  }
}
}  // namespace detail

/// a * b in Out (32-bit storage, no more fraction bits than a and b have
/// together), rounded to nearest, ties away from zero: fx::mul's bits. On
/// ARMv6-M by 32-bit words where the shift allows it (kRoundsInWords).
template <typename Out, Rounding Where = Rounding::called, typename QA, std::uint32_t A, typename QB, std::uint32_t B>
[[nodiscard]] SW_FX_INLINE constexpr auto mul(Bounded<QA, A> a, Bounded<QB, B> b) noexcept {
  constexpr std::int32_t kShift = (QA::frac_bits + QB::frac_bits) - Out::frac_bits;
  constexpr std::uint64_t kBound = detail::kProductBound<A, B, kShift>;
  static_assert(kBound <= kMaxBound, "the product's bound leaves the format");
  using Result = Bounded<Out, static_cast<std::uint32_t>(kBound)>;
  if constexpr (Where == Rounding::inlined) {
    return Result::trusted(detail::product_rounded_inlined<kShift>(a.raw(), b.raw()));
  } else {
    return Result::trusted(detail::product_rounded_called<kShift>(a.raw(), b.raw()));
  }
}

/// fx::sincos's sine and cosine as bounded Q1.30 values (within 1 LSB of
/// values of magnitude at most one; bound_to checks it all the same).
struct BoundedSinCos {
  Bounded<Q1_30, 0x40000000U> sin;
  Bounded<Q1_30, 0x40000000U> cos;
};

[[nodiscard]] SW_FX_INLINE constexpr BoundedSinCos bound_sincos(SinCos sc, Status& status) noexcept {
  return BoundedSinCos{bound_to<0x40000000U>(sc.sin, status), bound_to<0x40000000U>(sc.cos, status)};
}

namespace detail {
/// Bound of x cos - z sin and x sin + z cos for |x|, |z| <= M: the exact
/// value is at most |(x, z)| sqrt(sin^2 + cos^2) <= sqrt(2) M (1 + 2^-29),
/// below M * 1.41422 (sqrt(2) (1 + 2^-29) = 1.4142135651...), and the two
/// products round by half an LSB each.
template <std::uint32_t M>
constexpr std::uint64_t kRotatedBound = ((std::uint64_t{M} * 141422U) / 100000U) + 2U;
}  // namespace detail

/// A point (x forward, z up) of bounded coordinates.
template <typename QType, std::uint32_t M>
struct BoundedPoint {
  Bounded<QType, M> x;
  Bounded<QType, M> z;
};

/// p turned by the angle of `sc` (positive raising the +x end): x cos - z sin,
/// x sin + z cos, each product rounded as fx::mul rounds it. Written into
/// the caller's point (a returned 8-byte point is a copy on the Cortex-M0).
/// `Where` as mul's.
template <Rounding Where = Rounding::called, typename QType, std::uint32_t M>
SW_FX_INLINE void rotated(BoundedPoint<QType, M> p, BoundedSinCos sc,
                          BoundedPoint<QType, static_cast<std::uint32_t>(detail::kRotatedBound<M>)>& out) noexcept {
  constexpr std::uint64_t kBound = detail::kRotatedBound<M>;
  static_assert(kBound <= kMaxBound, "the rotated point's bound leaves the format");
  using Out = Bounded<QType, static_cast<std::uint32_t>(kBound)>;
  out.x = Out::trusted(sub(mul<QType, Where>(p.x, sc.cos), mul<QType, Where>(p.z, sc.sin)).raw());
  out.z = Out::trusted(add(mul<QType, Where>(p.x, sc.sin), mul<QType, Where>(p.z, sc.cos)).raw());
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_BOUNDED_HPP
