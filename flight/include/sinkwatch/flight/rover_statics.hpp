// rover_statics.hpp: the rover's lengths and weight in the formats of the
// wheel-load statics (wheel_load.hpp; docs/rover-loads.md, section 7.4),
// converted once per parameter load instead of once per control cycle.
//
// The statics solve every balance in metres, with forces as fractions of the
// normal weight, first in Q6.25 and, where an intermediate leaves it (a
// quotient by a lever of a few millimetres, far beyond the stability limit),
// again in Q10.21 and then Q15.16 (docs/rover-loads.md, section 7.4). The
// link vectors, the half track, the centre of mass, the weight m g and its
// reciprocal depend only on the rover parameters, so prepare() converts them
// once into each of the three formats (PreparedParameters holds them: 204
// bytes, none of them on the step's stack) and each cycle starts from the
// attitude and the joint angles. For parameters that validate_rover_params()
// accepts every length is at most 4 m (rover_limits.hpp): its conversion from
// Q7.24 is exact in Q6.25 and rounded once in Q10.21 and Q15.16, the same
// values the passes computed per cycle before session 16.
//
// The lengths are held as fx::Bounded values (fixedpoint/bounded.hpp) under
// the bounds validation guarantees, so the statics' geometry (rotations,
// sums and projections of positions) needs no saturation check per cycle:
// each bound below is a limit of rover_limits.hpp in the format P.
//
// After the geometry the balances' values depend on quotients and keep their
// checks; the checked operations they use in the 32-bit formats are in
// `detail` below: cheaper forms of fx's sums, differences, quotients by a
// normalised reciprocal and reciprocals, the same bits and flags
// (docs/rover-loads.md, section 7.6).
#ifndef SINKWATCH_FLIGHT_ROVER_STATICS_HPP
#define SINKWATCH_FLIGHT_ROVER_STATICS_HPP

#include <cstdint>
#include <limits>
#include <type_traits>

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

/// The statics' formats: metres and shares of the normal weight.
using StaticsQ = fx::Q<std::int32_t, 25>;        ///< Q6.25, every cycle's first evaluation
using StaticsMidQ = fx::Q<std::int32_t, 21>;     ///< Q10.21, where Q6.25 overflowed
using StaticsCoarseQ = fx::Q<std::int32_t, 16>;  ///< Q15.16, where Q10.21 overflowed too

/// The raw magnitude of `metres` in P (a limit of rover_limits.hpp).
template <typename P>
constexpr std::uint32_t bound_in(double metres) noexcept {
  return static_cast<std::uint32_t>(fx::constant<P>(metres).raw());
}
/// |link component|, |centre of mass|, track / 2: at most kMaxLinkM (2 m; a
/// track of at most 4 m), exact on every grid, so rounding stays within it.
template <typename P>
constexpr std::uint32_t kLinkBound = bound_in<P>(limits::kMaxLinkM);
/// The weight m g: at most kMaxMassKg kMaxGravityMps2 (10 kN, exact in
/// Q15.16), which its rounding cannot pass.
inline constexpr std::uint32_t kWeightBound = bound_in<LoadQ>(limits::kMaxMassKg * limits::kMaxGravityMps2);
/// The wheel radius: at most kMaxWheelRadiusM (1 m).
template <typename P>
constexpr std::uint32_t kRadiusBound = bound_in<P>(limits::kMaxWheelRadiusM);

template <typename P>
using StaticsLength = fx::Bounded<P, kLinkBound<P>>;
/// A link vector in one side's plane (x forward, z up), in the format P.
template <typename P>
using StaticsLink = fx::BoundedPoint<P, kLinkBound<P>>;

/// The rover's constant quantities of the statics, in the format P.
template <typename P>
struct StaticsConstants {
  StaticsLink<P> rocker_front;  ///< RoverParams::rocker_front_axle
  StaticsLink<P> rocker_bogie;  ///< RoverParams::rocker_bogie_pivot
  StaticsLink<P> bogie_middle;  ///< RoverParams::bogie_middle_axle
  StaticsLink<P> bogie_rear;    ///< RoverParams::bogie_rear_axle
  fx::Bounded<P, kRadiusBound<P>> wheel_radius;  ///< contacts lie one radius below the axles
  StaticsLength<P> half_track;                   ///< half the track width
  StaticsLength<P> com_x;                        ///< the centre of mass, body frame
  StaticsLength<P> com_y;
  StaticsLength<P> com_z;
  fx::Bounded<LoadQ, kWeightBound> weight_n;  ///< m g, newtons (Q15.16, rounded once)
  fx::NormalisedReciprocal inv_weight;  ///< 1 / (m g), from the exact product of mass and gravity
};

namespace detail {
// Checked operations of the statics' balances on 32-bit formats
// (wheel_load.cpp), cheaper than the fx operations they stand for, with the
// same bits and flags: saturating beyond the format and raising overflow.
// host_tests/rover/test_wheel_load.cpp compares each with its fx operation
// at random and at the edges (docs/rover-loads.md 7.6).

/// A magnitude in 32 bits, or none (`fits` false: at least 2^32).
struct WordMagnitude {
  std::uint32_t mag;
  bool fits;
};

/// p / 2^s rounded half up, for p < 2^63 and s in [1, 63], from shifts of
/// 32-bit words: for ARMv6-M, where a 64-bit shift by a run-time count is a
/// library call (__aeabi_llsr). With p = h 2^32 + l:
///  * s > 32, t = s - 32: (h + 2^(t-1)) / 2^t floored, as l / 2^32 < 1 adds
///    nothing to the floor of a quotient whose numerator is an integer;
///  * s = 32: h plus l's top bit;
///  * s < 32: h 2^(32-s) + l / 2^s floored plus l's bit s - 1, which fits
///    only when h / 2^s is zero and the rounding carries no further.
/// The host tests call it directly, as it is not on the host's path.
SW_FX_INLINE constexpr WordMagnitude shifted_rounded_by_words(std::uint64_t p, std::uint32_t s) noexcept {
  const auto h = static_cast<std::uint32_t>(p >> 32U);
  const auto l = static_cast<std::uint32_t>(p);
  if (s > 32U) {
    const std::uint32_t t = s - 32U;
    return WordMagnitude{(h + (1U << (t - 1U))) >> t, true};  // h < 2^31: no carry out
  }
  if (s == 32U) {
    return WordMagnitude{h + (l >> 31U), true};
  }
  const std::uint32_t floored = (h << (32U - s)) | (l >> s);
  const std::uint32_t rounded = floored + ((l >> (s - 1U)) & 1U);
  return WordMagnitude{rounded, ((h >> s) == 0U) && (rounded >= floored)};
}

/// The same from 64-bit shifts, fx::times_reciprocal's own formula (p +
/// 2^(s-1) as (p / 2^(s-1) + 1) / 2), where a core shifts 64-bit values
/// inline (ARMv7-M: the Cortex-M4 takes 229 instructions fewer per step than
/// with the words; the host).
SW_FX_INLINE constexpr WordMagnitude shifted_rounded_wide(std::uint64_t p, std::uint32_t s) noexcept {
  const std::uint64_t mag = ((p >> (s - 1U)) + 1U) >> 1U;
  return WordMagnitude{static_cast<std::uint32_t>(mag), (mag >> 32U) == 0U};
}

/// p / 2^s rounded half up in 32 bits, or `fits` false: by words on ARMv6-M
/// (the cores without a widening multiply, fx::wide::kMul32x32BySoftware,
/// are those whose 64-bit shifts are library calls), else by 64-bit shifts.
/// The same value either way.
SW_FX_INLINE constexpr WordMagnitude shifted_rounded(std::uint64_t p, std::uint32_t s) noexcept {
  if constexpr (fx::wide::kMul32x32BySoftware) {
    return shifted_rounded_by_words(p, s);
  } else {
    return shifted_rounded_wide(p, s);
  }
}

/// The raw bits of fx::mul<P>(a, b) for 32-bit operands and a 32-bit P
/// whose product is rounded by a right shift of Shift (17 to 31; the
/// statics' Q6.25 products: 25), with the same saturation and flag, by
/// 32-bit words for ARMv6-M: the rounding of
/// fx::detail::product_rounded_by_words (docs/fixedpoint.md 5.9), its
/// magnitude hh 2^(32-s) + the column's share tested against the format's
/// limit in words (fx::mul assembles and shifts the 64-bit product). The
/// high part fits a word when hh < 2^s; the sum then wraps only beyond
/// 2^32. The host tests compare it with fx::mul.
template <std::int32_t Shift>
constexpr std::int32_t product_checked_by_words(std::int32_t a, std::int32_t b, fx::Status& st) noexcept {
  constexpr auto kHighShift = static_cast<std::uint32_t>(32 - Shift);
  constexpr auto kLowShift = static_cast<std::uint32_t>(Shift - 16);
  const bool negative = (a < 0) != (b < 0);
  const fx::detail::RoundingWords w =
      fx::detail::rounding_words<Shift>(fx::detail::magnitude32(a), fx::detail::magnitude32(b));
  const std::uint32_t hh = w.hh;
  const std::uint32_t high = hh << kHighShift;
  const std::uint32_t mag = high + (w.column >> kLowShift);
  // fx::detail::from_sign_magnitude's limits: 2^31 fits a negative product.
  const std::uint32_t limit = negative ? 0x80000000U : 0x7FFFFFFFU;
  if (((hh >> static_cast<std::uint32_t>(Shift)) != 0U) || (mag < high) || (mag > limit)) {
    st.raise(fx::Flag::overflow);
    return negative ? std::numeric_limits<std::int32_t>::min() : std::numeric_limits<std::int32_t>::max();
  }
  const auto value = static_cast<std::int64_t>(mag);
  return static_cast<std::int32_t>(negative ? -value : value);
}

/// What the statics know of an operand's sign bit (product_of_signs):
/// validate_suspension orders the links (the front axle and the middle axle
/// ahead of their pivots, x > 0; the bogie pivot and the rear axle behind,
/// x < 0), and a rocker angle within its limit (at most 0.8 rad,
/// check_inputs) has a cosine of at least 0.69 (StaticsArithmetic.
/// RockerCosineIsPositive samples fx::sincos there).
enum class SignOf : std::uint8_t { positive, negative, any };

/// a's sign bit, a constant where S knows it.
template <SignOf S>
SW_FX_INLINE constexpr std::uint32_t sign_bit(std::int32_t a) noexcept {
  if constexpr (S == SignOf::any) {
    return static_cast<std::uint32_t>(a) >> 31U;
  } else {
    return (S == SignOf::negative) ? 1U : 0U;
  }
}

/// fx::detail::product_rounded_signed<Shift>(a, b)'s bits, floor((a b +
/// 2^(s-1) - [sign bits differ]) / 2^s) (fx::mul's rounding, half away from
/// zero), for operands whose sign bits are SA's and SB's: the term of the
/// sign bits is a constant where both are known and one shift where one is
/// (three instructions where neither is). The caller bounds the product
/// below 2^31 as for fx::mul of fx::Bounded values.
/// StaticsArithmetic.ProductOfKnownSignsIsTheBoundedProduct compares the two.
template <std::int32_t Shift, SignOf SA, SignOf SB>
SW_FX_INLINE constexpr std::int32_t product_of_signs(std::int32_t a, std::int32_t b) noexcept {
  static_assert((Shift > 0) && (Shift < 32), "a product rounded by a right shift of 1 to 31 bits");
  const std::uint32_t differ = sign_bit<SA>(a) ^ sign_bit<SB>(b);
  const auto addend = static_cast<std::int64_t>((std::uint32_t{1U} << static_cast<std::uint32_t>(Shift - 1)) - differ);
  const auto sum = static_cast<std::uint64_t>(addend + (static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b)));
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(sum >> static_cast<std::uint32_t>(Shift)));
}

/// The raw bits of fx::times_reciprocal<Out>(x, r) for a 32-bit Out, given
/// shift = F_x + r.scale - F_out: the same bits, flags and saturation, with
/// the magnitude's limits in 32-bit words (shifted_rounded): the body of
/// quotient_raw's one function for every format (quotient).
SW_FX_INLINE constexpr std::int32_t quotient_raw_inline(std::int32_t x, fx::NormalisedReciprocal r,
                                                        std::int32_t shift, fx::Status& st) noexcept {
  const bool negative = x < 0;
  if (r.mantissa == 0U) {
    st.raise(fx::Flag::div_by_zero);
    if (x == 0) {
      return 0;
    }
    return negative ? std::numeric_limits<std::int32_t>::min() : std::numeric_limits<std::int32_t>::max();
  }
  const std::uint64_t product = fx::wide::mul_32x32_64(fx::detail::magnitude32(x), r.mantissa);  // < 2^63
  WordMagnitude m{0U, true};  // shift >= 64: below half an LSB
  // Shifts of 1 to 63 (every quotient of a valid rover's statics) first.
  if (static_cast<std::uint32_t>(shift - 1) < 63U) {
    m = shifted_rounded(product, static_cast<std::uint32_t>(shift));
  } else if (shift <= 0) {
    // A non-zero product (>= 2^31) would only grow: beyond every format.
    m.fits = product == 0U;
  } else {
    m.mag = 0U;
  }
  // fx::detail::from_sign_magnitude in 32-bit words: 2^31 fits a negative
  // quotient, 2^31 - 1 a positive one.
  const std::uint32_t limit = negative ? 0x80000000U : 0x7FFFFFFFU;
  if (!m.fits || (m.mag > limit)) {
    st.raise(fx::Flag::overflow);
    return negative ? std::numeric_limits<std::int32_t>::min() : std::numeric_limits<std::int32_t>::max();
  }
  const auto value = static_cast<std::int64_t>(m.mag);
  return static_cast<std::int32_t>(negative ? -value : value);
}

/// quotient_raw_inline for a reciprocal that exists (mantissa != 0) and a
/// shift of 1 to 63, whose caller has tested both (the same bits and flags
/// there): the statics' couples test them once per cycle for six wheels
/// (wheel_load.cpp, couples_of) instead of twice per quotient.
SW_FX_INLINE constexpr std::int32_t quotient_raw_in_range(std::int32_t x, std::uint32_t mantissa, std::uint32_t shift,
                                                          fx::Status& st) noexcept {
  const bool negative = x < 0;
  const WordMagnitude m =
      shifted_rounded(fx::wide::mul_32x32_64(fx::detail::magnitude32(x), mantissa), shift);  // product < 2^63
  const std::uint32_t limit = negative ? 0x80000000U : 0x7FFFFFFFU;
  if (!m.fits || (m.mag > limit)) {
    st.raise(fx::Flag::overflow);
    return negative ? std::numeric_limits<std::int32_t>::min() : std::numeric_limits<std::int32_t>::max();
  }
  const auto value = static_cast<std::int64_t>(m.mag);
  return static_cast<std::int32_t>(negative ? -value : value);
}

/// Whether quotient_raw_in_range takes the shift (1 to 63).
SW_FX_INLINE constexpr bool shift_in_range(std::int32_t shift) noexcept {
  return static_cast<std::uint32_t>(shift - 1) < 63U;
}

/// quotient_raw_inline as one function for every format.
constexpr std::int32_t quotient_raw(std::int32_t x, fx::NormalisedReciprocal r, std::int32_t shift,
                                    fx::Status& st) noexcept {
  return quotient_raw_inline(x, r, shift, st);
}

/// fx::times_reciprocal<Out>(x, r) for a 32-bit Out (quotient_raw).
template <typename Out, std::int32_t Fx>
SW_FX_INLINE constexpr Out quotient(fx::Q<std::int32_t, Fx> x, fx::NormalisedReciprocal r, fx::Status& st) noexcept {
  static_assert(std::is_same<typename Out::storage_type, std::int32_t>::value, "a 32-bit quotient");
  return Out::from_raw(quotient_raw(x.raw(), r, (Fx + r.scale) - Out::frac_bits, st));
}

/// fx::normalised_reciprocal of a 32-bit Q value: its normalisation in
/// 32-bit words (the general form's 64-bit one costs the Cortex-M0 a
/// 64-bit bit count and a library shift), the same mantissa and scale.
/// Forced inline (seven per cycle, the division itself a call): 31
/// instructions per step fewer on the Cortex-M4, 93 and 24 B of stack fewer
/// on the Cortex-M0 (round 14).
template <std::int32_t F>
[[nodiscard]] SW_FX_INLINE constexpr fx::NormalisedReciprocal reciprocal_of(fx::Q<std::int32_t, F> d) noexcept {
  if (d.raw() <= 0) {
    return fx::NormalisedReciprocal{};
  }
  const auto v = static_cast<std::uint32_t>(d.raw());
  const std::uint32_t n = fx::wide::bit_length32(v);  // 1 to 31
  return fx::NormalisedReciprocal{fx::detail::floor_two_to_63_less_1_over(v << (32U - n)),
                                  (31 + static_cast<std::int32_t>(n)) - F};
}

/// reciprocal_of for a divisor its caller has shown positive, without the
/// test: gravity_frame's cos(pitch) cos(roll) and cos(roll), at least
/// cos^2(1.05) = 0.2476 and cos(1.05) = 0.4976 for attitudes within the
/// validated limit (StaticsArithmetic.GravitySlopesAreWithinTheirBounds
/// checks both positive at the limit's corners). The same mantissa and
/// scale; for a d <= 0 the value is meaningless.
template <std::int32_t F>
[[nodiscard]] SW_FX_INLINE constexpr fx::NormalisedReciprocal reciprocal_of_positive(fx::Q<std::int32_t, F> d) noexcept {
  const auto v = static_cast<std::uint32_t>(d.raw()) | 1U;  // the same bit length for a positive d
  const std::uint32_t n = fx::wide::bit_length32(v);        // 1 to 32
  const std::uint32_t normalised = static_cast<std::uint32_t>(d.raw()) << ((32U - n) & 31U);
  return fx::NormalisedReciprocal{fx::detail::floor_two_to_63_less_1_over(normalised),
                                  (31 + static_cast<std::int32_t>(n)) - F};
}

}  // namespace detail

/// The constants in each of the statics' formats.
struct RoverStatics {
  StaticsConstants<StaticsQ> fine;
  StaticsConstants<StaticsMidQ> mid;
  StaticsConstants<StaticsCoarseQ> coarse;
};

/// The constants of `params`, which validate_rover_params() accepted (for
/// other parameters the values are meaningless; prepare() only keeps them
/// with a valid rover).
[[nodiscard]] RoverStatics make_rover_statics(const RoverParams& params) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ROVER_STATICS_HPP
