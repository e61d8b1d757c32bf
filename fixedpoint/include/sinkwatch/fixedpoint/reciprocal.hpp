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

// Steps 1 and 2 (wide::detail::kReciprocalSeeds, first_newton_step) are in
// wide.hpp: the 64 / 32-bit division without a divide instruction
// (wide::divide_64_by_32_by_reciprocal) starts from the same z1.

/// Step 3: m ~ 2^63 / v = 2 z1 (1 + d / 2^62), d = 2^62 - v z1 (|d| < 2^47).
constexpr std::uint64_t second_newton_step(std::uint32_t v, std::uint32_t z1) noexcept {
  constexpr std::uint64_t kTwoTo62 = std::uint64_t{1U} << 62U;
  const std::uint64_t t = wide::mul_32x32_64(v, z1);
  const bool below = t <= kTwoTo62;
  const std::uint64_t d_mag = below ? (kTwoTo62 - t) : (t - kTwoTo62);
  const std::uint64_t step = wide::mul_32x32_64(z1, static_cast<std::uint32_t>(d_mag >> 15U)) >> 46U;
  const std::uint64_t twice = 2U * static_cast<std::uint64_t>(z1);
  return below ? (twice + step) : (twice - step);
}

/// floor((2^63 - 1) / v) for v in [2^31, 2^32), with 32 x 32-bit products
/// only (no division: a core without a divide instruction pays about 100
/// instructions for each 32-bit library division, and the long division this
/// replaces took two of them; docs/performance.md, session 13):
///  1. a seed y0 ~ 2^47 / v from a 128-entry table of 16-bit values indexed
///     by v's top byte, within 2^-8 relative;
///  2. one Newton step in 16 x 16 and 16 x 32-bit products:
///     z1 ~ 2^62 / v within about 2^-16 relative;
///  3. a second Newton step at full width: m ~ 2^63 / v within 2 units;
///  4. exact correction against the remainder 2^63 - 1 - m v, at most two
///     units down and one up.
/// The result is the exact floor for every v: checked against the 64-bit
/// division for all 2^31 divisors (throwaway host driver, 0 differ; the
/// estimate of step 3 is 2 below to 1 above the floor), and by
/// test_reciprocal.cpp at every seed interval's ends and at random.
/// The bounds of the intermediates (each below 2^32, the products below
/// 2^64) hold for every v in the range; the same driver checked them.
constexpr std::uint32_t floor_two_to_63_less_1_over(std::uint32_t v) noexcept {
  constexpr std::uint64_t kNumerator = (std::uint64_t{1U} << 63U) - 1U;
  const std::uint32_t y0 = wide::detail::kReciprocalSeeds.y0[(v >> 24U) & 0x7FU];
  const std::uint64_t estimate = second_newton_step(v, wide::detail::first_newton_step(v, y0));
  // The floor is at most 2^32 - 1 (v = 2^31); so is the estimate after this.
  auto m = static_cast<std::uint32_t>((estimate > 0xFFFFFFFFU) ? 0xFFFFFFFFU : estimate);
  std::uint64_t product = wide::mul_32x32_64(m, v);
  // Two counted corrections down, one up (MISRA C++:2023 9.5.1: simple loops).
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if (product > kNumerator) {
      --m;
      product -= v;
    }
  }
  if ((kNumerator - product) >= v) {
    ++m;
  }
  return m;
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
    // (product + 2^(s-1)) >> s, as ((product >> (s-1)) + 1) >> 1: the same
    // integer, with one variable 64-bit shift (a library call on 32-bit
    // cores) instead of two.
    mag = ((product >> (s - 1U)) + 1U) >> 1U;
  }
  return Out::from_raw(detail::from_sign_magnitude<OutS>(negative && (mag != 0U), mag, status));
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_RECIPROCAL_HPP
