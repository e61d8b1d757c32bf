// test_reciprocal.cpp: fx::normalised_reciprocal and fx::times_reciprocal (reciprocal.hpp).
// The mantissa is checked against its definition with the exact 128-bit
// product, and every quotient against fx::div, whose result is within
// 0.5 LSB of the exact one: times_reciprocal() must be within 1 LSB + |q| 2^-30 of it.
// Plain integer arithmetic only, so the test runs unchanged under qemu-arm.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace {

namespace fx = sinkwatch::fx;
namespace wide = sinkwatch::fx::wide;
using P = fx::Q<std::int32_t, 25>;
using K = fx::Q<std::int32_t, 28>;

constexpr std::uint64_t kTwoTo63Less1 = std::numeric_limits<std::uint64_t>::max() >> 1U;

std::uint64_t normalised(std::uint64_t d) {
  const std::uint32_t n = wide::bit_length(d);
  return (n <= 32U) ? (d << (32U - n)) : (d >> (n - 32U));
}

/// mantissa = floor((2^63 - 1) / Dn): m Dn <= 2^63 - 1 < (m + 1) Dn.
void expect_mantissa_is_the_floor(std::uint64_t d, std::int32_t frac_bits) {
  const fx::NormalisedReciprocal r = fx::normalised_reciprocal(d, frac_bits);
  const std::uint64_t dn = normalised(d);
  ASSERT_GE(r.mantissa, 0x80000000U) << d;
  const wide::U128 low = wide::mul_full(std::uint64_t{r.mantissa}, dn);
  const wide::U128 high = wide::mul_full(std::uint64_t{r.mantissa} + 1U, dn);
  const wide::U128 target = wide::make_u128(kTwoTo63Less1);
  EXPECT_FALSE(wide::less(target, low)) << d;
  EXPECT_TRUE(wide::less(target, high)) << d;
  EXPECT_EQ(r.scale, 31 + static_cast<std::int32_t>(wide::bit_length(d)) - frac_bits) << d;
}

/// |times_reciprocal(x, 1/d) - fx::div(x, d)| <= 1 + |q| 2^-30 raw LSB, or both saturate.
template <typename Out, typename QD>
void expect_quotient_near_division(P x, QD d) {
  fx::Status by_reciprocal;
  fx::Status by_division;
  const Out q = fx::times_reciprocal<Out>(x, fx::normalised_reciprocal(d), by_reciprocal);
  const Out ref = fx::div<Out>(x, d, by_division);
  if (by_division.has(fx::Flag::overflow)) {
    EXPECT_TRUE(by_reciprocal.has(fx::Flag::overflow) || (q == ref)) << x.raw() << " / " << d.raw();
    return;
  }
  const double q_raw = static_cast<double>(ref.raw());
  const double allowed = 1.0 + (((q_raw < 0.0) ? -q_raw : q_raw) / 1073741824.0);
  const double diff = static_cast<double>(q.raw()) - q_raw;
  EXPECT_LE((diff < 0.0) ? -diff : diff, allowed) << x.raw() << " / " << d.raw();
  if (!by_reciprocal.ok()) {
    EXPECT_TRUE(by_reciprocal.has(fx::Flag::overflow)) << x.raw() << " / " << d.raw();
  }
}

TEST(NormalisedReciprocal, MantissaIsTheFlooredQuotientAtEdgeDivisors) {
  const std::uint64_t divisors[] = {1U, 2U, 3U, 0x7FFFFFFFU, 0x80000000U, 0x80000001U, 0xFFFFFFFFU,
                                    0x100000000U, 0x1FFFFFFFFU, 0xFFFFFFFFFFFFULL, ~std::uint64_t{0U}};
  for (const std::uint64_t d : divisors) {
    expect_mantissa_is_the_floor(d, 25);
  }
}

/// The seed table changes value where v's top byte does: the mantissa is the
/// floor at both ends of every seed interval and next to them (the Newton
/// steps' estimate is farthest from the floor there).
TEST(NormalisedReciprocal, MantissaIsTheFlooredQuotientAtEverySeedIntervalsEnds) {
  for (std::uint64_t top = 0x80U; top <= 0xFFU; ++top) {
    const std::uint64_t first = top << 24U;
    const std::uint64_t last = first + 0xFFFFFFU;
    for (const std::uint64_t d : {first, first + 1U, first + 0x800000U, last - 1U, last}) {
      expect_mantissa_is_the_floor(d, 25);
    }
  }
}

TEST(NormalisedReciprocal, MantissaIsTheFlooredQuotientForRandomDivisors) {
  std::mt19937_64 rng(20261125U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t bits = 1U + static_cast<std::uint32_t>(rng() % 64U);
    const std::uint64_t d = (rng() >> (64U - bits)) | (std::uint64_t{1U} << (bits - 1U));
    expect_mantissa_is_the_floor(d, static_cast<std::int32_t>(rng() % 48U));
  }
}

TEST(NormalisedReciprocal, QuotientIsWithinOneLsbAndTwoToMinus30OfTheDivision) {
  std::mt19937_64 rng(11250001U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  for (int i = 0; i < 300000; ++i) {
    const std::uint32_t x_bits = static_cast<std::uint32_t>(rng() % 32U);
    // x_bits == 0 gives x = 0 (wide::shr of 64 bits is 0, where >> 64 is undefined).
    const auto x_mag = static_cast<std::int32_t>(wide::shr(rng(), 64U - x_bits));
    const P x = P::from_raw(((rng() & 1U) != 0U) ? -x_mag : x_mag);
    const std::uint32_t d_bits = 1U + static_cast<std::uint32_t>(rng() % 31U);
    const auto d = static_cast<std::int32_t>((rng() >> (64U - d_bits)) | (std::uint64_t{1U} << (d_bits - 1U)));
    expect_quotient_near_division<P>(x, P::from_raw(d));
    expect_quotient_near_division<K>(x, fx::Q1_30::from_raw(d));
  }
}

/// (value + 2^(s-1)) >> s exactly, from a 128-bit sum (no carry lost).
std::uint64_t rounded_shift_reference(std::uint64_t value, std::uint32_t s) {
  const wide::U128 sum = wide::add(wide::make_u128(value), wide::make_u128(std::uint64_t{1U} << (s - 1U)));
  return wide::shr(sum, s).lo;
}

/// The rounding shift of times_reciprocal: the word form (the Cortex-M0's)
/// and the core's own, against the exact sum shifted, for every count at
/// the words' edges and at random values of every length.
TEST(NormalisedReciprocal, RoundingShiftByWordsIsTheSixtyFourBitShift) {
  const std::uint64_t edges[] = {0U,
                                 1U,
                                 2U,
                                 3U,
                                 0x7FFFFFFFU,
                                 0x80000000U,
                                 0xFFFFFFFFU,
                                 0x100000000U,
                                 0x17FFFFFFFULL,
                                 0x180000000ULL,
                                 0x7FFFFFFF80000000ULL,
                                 0x7FFFFFFFFFFFFFFFULL,
                                 0x5555555555555555ULL,
                                 0x2AAAAAAAAAAAAAAAULL};
  for (std::uint32_t s = 1U; s < 64U; ++s) {
    for (const std::uint64_t v : edges) {
      ASSERT_EQ(fx::detail::shift_right_rounded_by_words(v, s), rounded_shift_reference(v, s)) << v << " >> " << s;
      ASSERT_EQ(fx::detail::shift_right_rounded(v, s), rounded_shift_reference(v, s)) << v << " >> " << s;
    }
    // Just below and at half a unit of the result, and the words' boundary.
    const std::uint64_t half = std::uint64_t{1U} << (s - 1U);
    for (const std::uint64_t v : {half - 1U, half, half + 1U, (3U * half) - 1U, 3U * half}) {
      ASSERT_EQ(fx::detail::shift_right_rounded_by_words(v, s), rounded_shift_reference(v, s)) << v << " >> " << s;
    }
  }
  std::mt19937_64 rng(20261126U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  for (int i = 0; i < 1000000; ++i) {
    const std::uint64_t v = rng() >> (1U + (rng() % 63U));  // below 2^63, every length
    const auto s = static_cast<std::uint32_t>(1U + (rng() % 63U));
    ASSERT_EQ(fx::detail::shift_right_rounded_by_words(v, s), rounded_shift_reference(v, s)) << v << " >> " << s;
    ASSERT_EQ(fx::detail::shift_right_rounded(v, s), rounded_shift_reference(v, s)) << v << " >> " << s;
  }
}

TEST(NormalisedReciprocal, ExtremeDividendsSaturateOrRoundToZero) {
  fx::Status st;
  // INT32_MIN / the smallest divisor: far beyond Q6.25.
  const P big = fx::times_reciprocal<P>(P::min(), fx::normalised_reciprocal(P::lsb()), st);
  EXPECT_EQ(big, P::min());
  EXPECT_TRUE(st.has(fx::Flag::overflow));
  fx::Status small_st;
  // One LSB divided by 2^40: rounds to zero, no flag, no negative zero.
  const P tiny = fx::times_reciprocal<P>(fx::neg(P::lsb(), small_st), fx::normalised_reciprocal(std::uint64_t{1U} << 40U, 0), small_st);
  EXPECT_EQ(tiny.raw(), 0);
  EXPECT_TRUE(small_st.ok());
  // A non-zero x with a shift <= 0 overflows; zero stays zero.
  fx::Status shift_st;
  EXPECT_EQ(fx::times_reciprocal<P>(P::lsb(), fx::NormalisedReciprocal{0x80000000U, -40}, shift_st), P::max());
  EXPECT_TRUE(shift_st.has(fx::Flag::overflow));
  fx::Status zero_st;
  EXPECT_EQ(fx::times_reciprocal<P>(P::zero(), fx::NormalisedReciprocal{0x80000000U, -40}, zero_st), P::zero());
  EXPECT_TRUE(zero_st.ok());
}

TEST(NormalisedReciprocal, ZeroDivisorGivesNoReciprocalAndReportsDivisionByZero) {
  fx::Status neg_lsb_st;
  EXPECT_EQ(fx::normalised_reciprocal(P::zero()).mantissa, 0U);
  EXPECT_EQ(fx::normalised_reciprocal(std::uint64_t{0U}, 25).mantissa, 0U);
  EXPECT_EQ(fx::normalised_reciprocal(fx::neg(P::lsb(), neg_lsb_st)).mantissa, 0U);
  fx::Status st;
  EXPECT_EQ(fx::times_reciprocal<P>(P::lsb(), fx::normalised_reciprocal(P::zero()), st), P::max());
  EXPECT_TRUE(st.has(fx::Flag::div_by_zero));
  fx::Status neg_st;
  EXPECT_EQ(fx::times_reciprocal<P>(fx::neg(P::lsb(), neg_st), fx::NormalisedReciprocal{}, neg_st), P::min());
  fx::Status zero_st;
  EXPECT_EQ(fx::times_reciprocal<P>(P::zero(), fx::NormalisedReciprocal{}, zero_st), P::zero());
  EXPECT_TRUE(zero_st.has(fx::Flag::div_by_zero));
}

// times_reciprocal's core on magnitudes (the flight code's current limit
// takes it apart from the sign and the saturation): the product rounded half
// up by every shift 1 to 63 (against the 64-bit sum), zero for shifts of 64
// and more and for shifts <= 0, which grow exactly the non-zero products.
TEST(NormalisedReciprocal, TimesMantissaIsTheRoundedProductAndGrowsWhereAShiftWouldWiden) {
  std::mt19937_64 rng(20261128U);  // NOLINT(cert-msc32-c,cert-msc51-cpp): reproducible samples
  for (std::int32_t i = 0; i < 200000; ++i) {
    // |x| <= 2^31 (a 32-bit value's magnitude): the product is below 2^63,
    // so the rounding sum fits 64 bits (plain arithmetic, also on ARM32).
    const std::uint64_t draw = rng();
    const auto x = ((i % 89) == 0) ? 0U : static_cast<std::uint32_t>(draw >> (33U + (rng() % 31U)));  // 1 to 31 bits
    const auto m = static_cast<std::uint32_t>(((i % 97) == 0) ? 0U : (rng() | 0x80000000U));
    const auto shift = static_cast<std::int32_t>(rng() % 80U) - 8;  // -8 .. 71
    const std::uint64_t product = std::uint64_t{x} * std::uint64_t{m};
    std::uint64_t expected = 0U;
    if ((shift > 0) && (shift < 64)) {
      const auto s = static_cast<std::uint32_t>(shift);
      expected = (product + (std::uint64_t{1U} << (s - 1U))) >> s;
    }
    ASSERT_EQ(fx::detail::times_mantissa(x, m, shift), expected) << x << " " << m << " " << shift;
    ASSERT_EQ(fx::detail::times_mantissa_grows(x, m, shift), (shift <= 0) && (product != 0U))
        << x << " " << m << " " << shift;
  }
}

}  // namespace
