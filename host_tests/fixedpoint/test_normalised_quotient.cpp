// test_normalised_quotient.cpp: fx::divide_normalised and its form for a
// positive divisor, fx::quotient_by_positive (normalised_quotient.hpp),
// and the long division under it (wide::divide_64_by_32, both forms: by
// digits and by reciprocal, wide.hpp).
// The long division is checked against the built-in 64-bit division; every
// quotient against the exact one, computed in double with its own rounding
// (3 * 2^-53 relative) added to the documented bound 0.5 LSB + |n/d| 2^-29.
// Plain integer and double arithmetic only, so the test runs under qemu-arm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace {

namespace fx = sinkwatch::fx;

/// A random value of a random bit length (1..bits), so every normalisation shift is drawn.
std::uint64_t random_magnitude(std::mt19937_64& rng, std::uint32_t bits) {
  const std::uint32_t length = 1U + static_cast<std::uint32_t>(rng() % bits);
  const std::uint64_t top = std::uint64_t{1U} << (length - 1U);
  return top | (rng() & (top - 1U));
}

/// The quotient is within 0.5 LSB + |n/d| 2^-29 of n/d, or saturated with
/// overflow only where n/d is beyond Out (up to the same bound).
template <typename Out>
void expect_within_bound(fx::ScaledMagnitude n, fx::ScaledMagnitude d) {
  fx::Status st;
  const Out got = fx::divide_normalised<Out>(n, d, st);
  const double sign = (n.negative != d.negative) ? -1.0 : 1.0;
  const double exact_raw = sign * std::ldexp(static_cast<double>(n.magnitude) / static_cast<double>(d.magnitude),
                                             (d.frac_bits - n.frac_bits) + Out::frac_bits);
  const double slack = 0.5 + std::fabs(exact_raw) * (std::ldexp(1.0, -29) + std::ldexp(3.0, -53));
  const double max_raw = static_cast<double>(std::numeric_limits<typename Out::storage_type>::max());
  if (!st.ok()) {
    EXPECT_TRUE(st.has(fx::Flag::overflow)) << n.magnitude << " / " << d.magnitude;
    EXPECT_GE(std::fabs(exact_raw) + slack, max_raw) << n.magnitude << " / " << d.magnitude;
    EXPECT_TRUE((got == Out::max()) || (got == Out::min()));
    return;
  }
  EXPECT_LE(std::fabs(static_cast<double>(got.raw()) - exact_raw), slack) << n.magnitude << " / " << d.magnitude;
}

/// Both forms of the 64 / 32-bit long division (wide.hpp), and the one this
/// core takes, give the built-in division's quotient and remainder; the
/// quotient-only form (quotient_64_by_32) its quotient.
void expect_long_division_exact(std::uint64_t u, std::uint32_t v) {
  const std::uint64_t quotient = u / v;
  const std::uint64_t remainder = u % v;
  const fx::wide::DivMod<std::uint32_t> by_digits = fx::wide::divide_64_by_32_by_digits(u, v);
  const fx::wide::DivMod<std::uint32_t> by_reciprocal = fx::wide::divide_64_by_32_by_reciprocal(u, v);
  const fx::wide::DivMod<std::uint32_t> selected = fx::wide::divide_64_by_32(u, v);
  ASSERT_EQ(by_digits.quotient, quotient) << u << " / " << v;
  ASSERT_EQ(by_digits.remainder, remainder) << u << " / " << v;
  ASSERT_EQ(by_reciprocal.quotient, quotient) << u << " / " << v;
  ASSERT_EQ(by_reciprocal.remainder, remainder) << u << " / " << v;
  ASSERT_EQ(selected.quotient, quotient) << u << " / " << v;
  ASSERT_EQ(selected.remainder, remainder) << u << " / " << v;
  ASSERT_EQ(fx::wide::quotient_64_by_32(u, v), quotient) << u << " / " << v;
}

/// Dividends for the divisor v that stress the digits' corrections: the
/// extremes, every remainder's extremes, quotients at the digits' edges.
void expect_long_division_exact_at_edges(std::uint32_t v, std::mt19937_64& rng) {
  const std::uint64_t top = std::uint64_t{v} << 32U;  // the first dividend whose quotient needs 33 bits
  constexpr std::uint32_t kQuotients[] = {0U, 1U, 0xFFFFU, 0x10000U, 0x1FFFFU, 0xFFFF0000U, 0xFFFF0001U,
                                          0xFFFFFFFEU, 0xFFFFFFFFU};
  for (const std::uint32_t q : kQuotients) {
    const std::uint64_t base = std::uint64_t{q} * v;
    expect_long_division_exact(base, v);
    expect_long_division_exact(base + (v - 1U), v);
    expect_long_division_exact(base + (v / 2U), v);
  }
  expect_long_division_exact(top - 1U, v);
  expect_long_division_exact(top - 2U, v);
  for (int i = 0; i < 64; ++i) {
    // The high word at its largest (v - 1), any low word; any quotient with
    // the largest remainder.
    expect_long_division_exact(top - 1U - (rng() & 0xFFFFFFFFU), v);
    expect_long_division_exact((std::uint64_t{static_cast<std::uint32_t>(rng())} * v) + (v - 1U), v);
  }
}

// Both forms in constant evaluation: 2^63 - 1 = (2^32 - 1) 2^31 + (2^31 - 1),
// and 0xFFFFFFFEFFFFFFFF = (2^32 - 1)^2 + (2^32 - 2).
static_assert(fx::wide::divide_64_by_32_by_digits(0x7FFFFFFFFFFFFFFFULL, 0x80000000U).quotient == 0xFFFFFFFFU,
              "by digits: the largest quotient");
static_assert(fx::wide::divide_64_by_32_by_reciprocal(0x7FFFFFFFFFFFFFFFULL, 0x80000000U).quotient == 0xFFFFFFFFU,
              "by reciprocal: the largest quotient");
static_assert(fx::wide::divide_64_by_32_by_reciprocal(0x7FFFFFFFFFFFFFFFULL, 0x80000000U).remainder == 0x7FFFFFFFU,
              "by reciprocal: its remainder");
static_assert(fx::wide::divide_64_by_32_by_reciprocal(0xFFFFFFFEFFFFFFFFULL, 0xFFFFFFFFU).remainder == 0xFFFFFFFEU,
              "by reciprocal: the largest divisor");
static_assert(fx::wide::divmod_by_word_normalising(0xFFFFFFFFFFFFFFFFULL, 3U).quotient == 0x5555555555555555ULL,
              "normalising: a 64-bit quotient");

TEST(NormalisedQuotient, LongDivisionEqualsTheBuiltInDivisionAtEdges) {
  std::mt19937_64 rng(20261126U);
  // The smallest and largest divisors, and both ends and the middle of every
  // seed interval of the reciprocal (v / 2^24 in [k, k + 1)): the estimate's
  // error is largest at v = 2^31 and moves with the seed.
  for (std::uint32_t k = 128U; k < 256U; ++k) {
    const std::uint32_t start = k << 24U;
    const std::uint32_t last = start + 0xFFFFFFU;
    for (const std::uint32_t v : {start, start + 1U, start + 0x800000U, last - 1U, last}) {
      expect_long_division_exact_at_edges(v, rng);
    }
  }
  expect_long_division_exact((std::uint64_t{0x80000000U} << 32U) - 1U, 0x80000000U);
  constexpr std::uint64_t kLargest = (std::uint64_t{0xFFFFFFFFU} << 32U) - 1U;
  EXPECT_EQ(fx::wide::divide_64_by_32(kLargest, 0xFFFFFFFFU).quotient, 0xFFFFFFFFU);
  EXPECT_EQ(fx::wide::divide_64_by_32(kLargest, 0xFFFFFFFFU).remainder, 0xFFFFFFFEU);
}

TEST(NormalisedQuotient, LongDivisionEqualsTheBuiltInDivisionForRandomOperands) {
  std::mt19937_64 rng(20261125U);
  for (int i = 0; i < 1000000; ++i) {
    const auto v = static_cast<std::uint32_t>(rng() | 0x80000000U);
    const std::uint64_t u = rng() % (std::uint64_t{v} << 32U);  // u < v 2^32: the quotient fits 32 bits
    expect_long_division_exact(u, v);
    // Divisors near 2^31, where the reciprocal's error is largest.
    const std::uint32_t small = 0x80000000U + static_cast<std::uint32_t>(rng() % 0x1000000U);
    expect_long_division_exact(rng() % (std::uint64_t{small} << 32U), small);
  }
}

/// One digit of the long division where the core divides words
/// (wide::detail::digit_by_remainder) against the built-in division, and
/// how far its estimate partial / v_high was above the digit (0, 1 or 2).
std::uint32_t expect_digit_by_remainder_exact(std::uint32_t partial, std::uint32_t next, std::uint32_t v) {
  const std::uint32_t v_high = v >> 16U;
  const std::uint64_t x = (std::uint64_t{partial} << 16U) | next;
  const fx::wide::detail::DigitStep step = fx::wide::detail::digit_by_remainder(partial, next, v, v_high);
  EXPECT_EQ(step.digit, x / v) << partial << " " << next << " / " << v;
  EXPECT_EQ(step.remainder, x % v) << partial << " " << next << " / " << v;
  const std::uint64_t over = (partial / v_high) - (x / v);
  EXPECT_LE(over, 2U) << partial << " " << next << " / " << v;
  return static_cast<std::uint32_t>(over);
}

TEST(NormalisedQuotient, DigitByRemainderIsTheExactDigitAfterNoneOneOrTwoCorrections) {
  // Every estimate error (0, 1 and 2, so each correction) is met, among them
  // the estimates 2^16 and 2^16 + 1 that no digit reaches (v_high = 2^15,
  // partial = v - 1), and the digits 0 and 2^16 - 1.
  std::uint32_t seen[3] = {0U, 0U, 0U};
  std::mt19937_64 rng(20261128U);
  const auto count = [&seen](std::uint32_t over) {
    if (over < 3U) {
      ++seen[over];
    }
  };
  for (const std::uint32_t v : {0x80000000U, 0x8000FFFFU, 0x80017FFFU, 0xBFFFFFFFU, 0xFFFF0000U, 0xFFFFFFFFU}) {
    for (const std::uint32_t next : {0U, 1U, 0x7FFFU, 0xFFFFU}) {
      for (const std::uint32_t partial : {0U, 1U, v >> 1U, v - 0x10000U, v - 2U, v - 1U}) {
        count(expect_digit_by_remainder_exact(partial, next, v));
      }
    }
  }
  for (int i = 0; i < 1000000; ++i) {
    // Divisors with a small high half and a large low half, where the
    // estimate is furthest above the digit, and any divisor.
    const auto v = static_cast<std::uint32_t>((i % 2 == 0) ? ((rng() & 0x00FFFFFFU) | 0x80000000U)
                                                            : (rng() | 0x80000000U));
    const auto partial = static_cast<std::uint32_t>(rng() % v);
    count(expect_digit_by_remainder_exact(partial, static_cast<std::uint32_t>(rng() & 0xFFFFU), v));
  }
  EXPECT_GT(seen[0], 0U);
  EXPECT_GT(seen[1], 0U);
  EXPECT_GT(seen[2], 0U);
}

TEST(NormalisedQuotient, QuotientOfLeadingWordsIsTheBuiltInQuotient) {
  // floor(n 2^31 / d) for n, d in [2^31, 2^32): at the words' ends, and random.
  const auto expect_exact = [](std::uint32_t n, std::uint32_t d) {
    ASSERT_EQ(fx::wide::quotient_of_leading_words(n, d), (std::uint64_t{n} << 31U) / d) << n << " / " << d;
  };
  for (const std::uint32_t n : {0x80000000U, 0x80000001U, 0xC0000000U, 0xFFFFFFFEU, 0xFFFFFFFFU}) {
    for (const std::uint32_t d : {0x80000000U, 0x80000001U, 0x8000FFFFU, 0xC0000000U, 0xFFFFFFFEU, 0xFFFFFFFFU}) {
      expect_exact(n, d);
    }
  }
  std::mt19937_64 rng(20261129U);
  for (int i = 0; i < 1000000; ++i) {
    const auto n = static_cast<std::uint32_t>(rng() | 0x80000000U);
    const auto d = static_cast<std::uint32_t>((i % 2 == 0) ? ((rng() & 0x00FFFFFFU) | 0x80000000U)
                                                            : (rng() | 0x80000000U));
    expect_exact(n, d);
  }
}

/// The digits' reciprocal r ~ 2^48 / v is below it by at most 1.5 * 2^32 / v
/// (docs/fixedpoint.md 5.8): r v < 2^48 and 2^48 - r v <= 3 * 2^31.
void expect_digit_reciprocal_bounded(std::uint32_t v) {
  const std::uint64_t product = std::uint64_t{fx::wide::detail::digit_reciprocal(v)} * v;
  constexpr std::uint64_t kTwoTo48 = std::uint64_t{1U} << 48U;
  ASSERT_LT(product, kTwoTo48) << v;
  ASSERT_LE(kTwoTo48 - product, std::uint64_t{3U} << 31U) << v;
}

TEST(NormalisedQuotient, DigitReciprocalIsBelowTwoTo48OverVWithinItsBound) {
  for (std::uint32_t k = 128U; k < 256U; ++k) {
    const std::uint32_t start = k << 24U;
    for (std::uint32_t j = 0U; j < 0x1000U; ++j) {
      expect_digit_reciprocal_bounded(start + j);
      expect_digit_reciprocal_bounded(start + 0xFFFFFFU - j);
      expect_digit_reciprocal_bounded(start + (j << 12U));
    }
    // Where the seed is exact (v near 2^47 / y0) the Newton step's estimate
    // comes closest to 2^62 / v, and only the "- 1" of digit_reciprocal keeps
    // r v below 2^48 (without it, 282 divisors within 2^16 of these centres
    // give r v >= 2^48; found by a scan of all 2^31 divisors).
    const std::uint64_t centre = (std::uint64_t{1U} << 47U) / fx::wide::detail::kReciprocalSeeds.y0[k - 128U];
    const std::uint64_t first = std::max<std::uint64_t>(centre - 0x20000U, start);
    const std::uint64_t last = std::min<std::uint64_t>(centre + 0x20000U, start + 0xFFFFFFU);
    for (std::uint64_t v = first; v <= last; ++v) {
      expect_digit_reciprocal_bounded(static_cast<std::uint32_t>(v));
    }
  }
  std::mt19937_64 rng(5U);
  for (int i = 0; i < 1000000; ++i) {
    expect_digit_reciprocal_bounded(static_cast<std::uint32_t>(rng() | 0x80000000U));
  }
}

TEST(NormalisedQuotient, RandomOperandsOfEveryLengthAreWithinTheBound) {
  std::mt19937_64 rng(7U);
  for (int i = 0; i < 400000; ++i) {
    const fx::ScaledMagnitude n{(rng() & 1U) != 0U, random_magnitude(rng, 64U), static_cast<std::int32_t>(rng() % 64U)};
    const fx::ScaledMagnitude d{(rng() & 1U) != 0U, random_magnitude(rng, 64U), static_cast<std::int32_t>(rng() % 64U)};
    expect_within_bound<fx::Q<std::int32_t, 24>>(n, d);
    expect_within_bound<fx::Q<std::int32_t, 16>>(n, d);
    expect_within_bound<fx::Q<std::int64_t, 40>>(n, d);
  }
}

TEST(NormalisedQuotient, QuotientsNearEachFormatsLimitSaturateOnlyBeyondIt) {
  std::mt19937_64 rng(11U);
  using Out = fx::Q<std::int32_t, 24>;
  for (int i = 0; i < 200000; ++i) {
    // n / d within 2^-20 of 128, the Q7.24 limit, from both sides.
    const std::uint64_t d = random_magnitude(rng, 40U);
    const std::uint64_t offset = rng() % ((d / 1024U) + 1U);
    const std::uint64_t n = ((rng() & 1U) != 0U) ? ((d * 128U) + offset) : ((d * 128U) - offset);
    expect_within_bound<Out>(fx::ScaledMagnitude{false, n, 0}, fx::ScaledMagnitude{false, d, 0});
    expect_within_bound<Out>(fx::ScaledMagnitude{true, n, 0}, fx::ScaledMagnitude{false, d, 0});
  }
}

TEST(NormalisedQuotient, SmallIntegerQuotientsAreExact) {
  using Out = fx::Q<std::int32_t, 24>;
  // fx::constant is evaluated when compiled (a run-time call does not link).
  constexpr Out kThreeAndAHalf = fx::constant<Out>(3.5);
  constexpr Out kMinusTwo = fx::constant<Out>(-2.0);
  fx::Status st;
  EXPECT_EQ(fx::divide_normalised<Out>(fx::Q<std::int64_t, 40>::from_raw(std::int64_t{7} << 40),
                                       fx::Q<std::int32_t, 16>::from_raw(2 << 16), st),
            kThreeAndAHalf);
  EXPECT_EQ(fx::divide_normalised<Out>(fx::Q<std::int64_t, 40>::from_raw(-(std::int64_t{6} << 40)),
                                       fx::Q<std::int32_t, 24>::from_raw(3 << 24), st),
            kMinusTwo);
  EXPECT_TRUE(st.ok());
}

/// A positive or negative integer with no fraction bits.
fx::ScaledMagnitude integer(bool negative, std::uint64_t magnitude) { return fx::ScaledMagnitude{negative, magnitude, 0}; }

TEST(NormalisedQuotient, TinyQuotientsRoundToZeroAndHugeOnesSaturate) {
  using Out = fx::Q<std::int32_t, 24>;
  constexpr std::uint64_t kOne = 1U;
  fx::Status st;
  // 1 / 2^62 in Q7.24 is far below half an LSB.
  EXPECT_EQ(fx::divide_normalised<Out>(integer(true, 1U), integer(false, kOne << 62U), st),
            Out::zero());
  // Half an LSB exactly rounds away from zero: 1 / 2^25.
  EXPECT_EQ(fx::divide_normalised<Out>(integer(false, 1U), integer(false, kOne << 25U), st),
            Out::from_raw(1));
  EXPECT_TRUE(st.ok());
  // 2^62 / 1: beyond any 32- or 64-bit format.
  EXPECT_EQ(fx::divide_normalised<Out>(integer(false, kOne << 62U), integer(false, 1U), st),
            Out::max());
  EXPECT_TRUE(st.has(fx::Flag::overflow));
  fx::Status st_negative;
  EXPECT_EQ(fx::divide_normalised<Out>(integer(false, kOne << 40U), integer(true, 1U), st_negative),
            Out::min());
  EXPECT_TRUE(st_negative.has(fx::Flag::overflow));
}

TEST(NormalisedQuotient, ZeroDivisorReportsDivisionByZero) {
  using Out = fx::Q<std::int32_t, 24>;
  fx::Status st;
  EXPECT_EQ(fx::divide_normalised<Out>(fx::ScaledMagnitude{true, 5U, 0}, fx::ScaledMagnitude{}, st), Out::min());
  EXPECT_TRUE(st.has(fx::Flag::div_by_zero));
  fx::Status st_zero;
  EXPECT_EQ(fx::divide_normalised<Out>(fx::ScaledMagnitude{}, fx::ScaledMagnitude{}, st_zero), Out::zero());
  EXPECT_TRUE(st_zero.has(fx::Flag::div_by_zero));
  fx::Status st_ok;
  EXPECT_EQ(fx::divide_normalised<Out>(fx::ScaledMagnitude{}, fx::ScaledMagnitude{false, 3U, 0}, st_ok), Out::zero());
  EXPECT_TRUE(st_ok.ok());
}

/// The leading word and bit length of a, from wide::bit_length and
/// wide::leading_word (the helpers divide_normalised took until session 18).
void expect_leading_bits(std::uint64_t a) {
  const std::uint32_t bits = fx::wide::bit_length(a);
  const std::uint32_t word = fx::wide::leading_word(a, bits);
  const fx::detail::LeadingBits by_halves = fx::detail::leading_bits_by_halves(a);
  const fx::detail::LeadingBits by_clz = fx::detail::leading_bits_by_clz(a);
  const fx::detail::LeadingBits selected = fx::detail::leading_bits(a);
  ASSERT_EQ(by_halves.bits, bits) << a;
  ASSERT_EQ(by_halves.word, word) << a;
  ASSERT_EQ(by_clz.bits, bits) << a;
  ASSERT_EQ(by_clz.word, word) << a;
  ASSERT_EQ(selected.bits, bits) << a;
  ASSERT_EQ(selected.word, word) << a;
  // The quotient's numerator form: true and the same two integers for a != 0.
  fx::detail::LeadingBits unless_zero_by_clz{0U, 0U};
  fx::detail::LeadingBits unless_zero{0U, 0U};
  ASSERT_EQ(fx::detail::leading_bits_unless_zero_by_clz(a, unless_zero_by_clz), a != 0U) << a;
  ASSERT_EQ(fx::detail::leading_bits_unless_zero(a, unless_zero), a != 0U) << a;
  if (a != 0U) {
    ASSERT_EQ(unless_zero_by_clz.bits, bits) << a;
    ASSERT_EQ(unless_zero_by_clz.word, word) << a;
    ASSERT_EQ(unless_zero.bits, bits) << a;
    ASSERT_EQ(unless_zero.word, word) << a;
    // The divisor's form, for a > 0.
    const fx::detail::LeadingBits positive_by_clz = fx::detail::leading_bits_of_positive_by_clz(a);
    const fx::detail::LeadingBits positive = fx::detail::leading_bits_of_positive(a);
    ASSERT_EQ(positive_by_clz.bits, bits) << a;
    ASSERT_EQ(positive_by_clz.word, word) << a;
    ASSERT_EQ(positive.bits, bits) << a;
    ASSERT_EQ(positive.word, word) << a;
  }
}

// The halving normalisation (the Cortex-M0's), the count of leading zeros
// (the other cores') and the core's own give the bit length and leading word
// of every length: each power of two, its neighbours, all ones below it,
// every shift of a high word with a full low word below it, and 10^6 random
// values of every length; zero gives both forms' word 0 and bit length 1.
TEST(NormalisedQuotient, LeadingBitsAreTheBitLengthAndTheLeadingWord) {
  const fx::detail::LeadingBits zero_by_halves = fx::detail::leading_bits_by_halves(0U);
  const fx::detail::LeadingBits zero_by_clz = fx::detail::leading_bits_by_clz(0U);
  EXPECT_EQ(zero_by_halves.word, 0U);
  EXPECT_EQ(zero_by_clz.word, 0U);
  EXPECT_EQ(zero_by_halves.bits, 1U);
  EXPECT_EQ(zero_by_clz.bits, 1U);
  // Zero answers false and leaves the word untouched in both forms.
  fx::detail::LeadingBits untouched{7U, 9U};
  EXPECT_FALSE(fx::detail::leading_bits_unless_zero_by_clz(0U, untouched));
  EXPECT_FALSE(fx::detail::leading_bits_unless_zero(0U, untouched));
  EXPECT_EQ(untouched.word, 7U);
  EXPECT_EQ(untouched.bits, 9U);
  for (std::uint32_t k = 0U; k < 32U; ++k) {
    expect_leading_bits(std::uint64_t{1U} << k);  // the low-word path of every length
  }
  for (std::uint32_t k = 32U; k < 64U; ++k) {
    const std::uint64_t top = std::uint64_t{1U} << k;
    for (const std::uint64_t low : {std::uint64_t{0xFFFFFFFFU}, std::uint64_t{0x80000000U}, std::uint64_t{1U}}) {
      expect_leading_bits(top | low);
    }
  }
  for (std::uint32_t k = 0U; k < 64U; ++k) {
    const std::uint64_t power = std::uint64_t{1U} << k;
    for (const std::uint64_t a : {power, power + 1U, power | (power - 1U), power | (power >> 1U)}) {
      expect_leading_bits(a);
    }
    if (k > 0U) {
      expect_leading_bits(power - 1U);
    }
  }
  expect_leading_bits(~std::uint64_t{0U});
  std::mt19937_64 rng(20261129U);
  for (int i = 0; i < 1000000; ++i) {
    expect_leading_bits(random_magnitude(rng, 64U));
  }
}

/// q 2^exponent rounded half up as the session 17 code formed it (the
/// rounding on 64 bits), and all ones beyond 64 bits.
std::uint64_t scale_reference(std::uint32_t q, std::int32_t exponent) {
  if (exponent > 32) {
    return ~std::uint64_t{0U};
  }
  if (exponent >= 0) {
    return std::uint64_t{q} << static_cast<std::uint32_t>(exponent);
  }
  if (exponent < -32) {
    return 0U;
  }
  const auto s = static_cast<std::uint32_t>(-exponent);
  return (std::uint64_t{q} + (std::uint64_t{1U} << (s - 1U))) >> s;
}

// The quotient's rounding on one 32-bit word gives the 64-bit rounding's
// integer for every exponent, at the word's edges, at half units and at
// random quotients.
TEST(NormalisedQuotient, ScaledQuotientIsTheSixtyFourBitRounding) {
  std::mt19937_64 rng(20261130U);
  for (std::int32_t e = -40; e <= 40; ++e) {
    for (const std::uint32_t q : {0U, 1U, 2U, 3U, 0x7FFFFFFFU, 0x80000000U, 0x80000001U, 0xFFFFFFFEU, 0xFFFFFFFFU}) {
      ASSERT_EQ(fx::detail::scale_quotient(q, e), scale_reference(q, e)) << q << " " << e;
    }
    if ((e < 0) && (e >= -32)) {
      const std::uint32_t half = 1U << static_cast<std::uint32_t>(-e - 1);
      for (const std::uint32_t q : {half - 1U, half, half + 1U, (3U * half) - 1U, 3U * half}) {
        ASSERT_EQ(fx::detail::scale_quotient(q, e), scale_reference(q, e)) << q << " " << e;
      }
    }
    for (int i = 0; i < 10000; ++i) {
      const auto q = static_cast<std::uint32_t>(rng());
      ASSERT_EQ(fx::detail::scale_quotient(q, e), scale_reference(q, e)) << q << " " << e;
    }
  }
}

TEST(NormalisedQuotient, MostNegativeOperandsAreTheirMagnitudes) {
  using Out = fx::Q<std::int32_t, 0>;
  fx::Status st;
  const auto int64_min = fx::Q<std::int64_t, 0>::from_raw(std::numeric_limits<std::int64_t>::min());
  // -2^63 / -2^62 = 2, exactly.
  EXPECT_EQ(fx::divide_normalised<Out>(int64_min, fx::Q<std::int64_t, 0>::from_raw(-(std::int64_t{1} << 62)), st),
            Out::from_raw(2));
  EXPECT_TRUE(st.ok());
}

// fx::quotient_by_positive (Eq. 11's and the limit's division) against
// fx::divide_normalised, whose form for a positive divisor it is: the same
// raw value and the same overflow decision for every sign, magnitude and
// scale, the exponent of q drawn across every branch (e > 1, 1, 0,
// -1 .. -32, below -32), at the flight code's two output formats.
bool same_as_generic(bool negative, std::uint64_t n, std::int32_t n_frac, std::uint64_t d, std::int32_t d_frac,
                     std::int32_t out_frac) {
  fx::Status st;
  const fx::ScaledMagnitude num{negative, n, n_frac};
  const fx::ScaledMagnitude den{false, d, d_frac};
  std::int32_t raw = 0;
  bool fits = false;
  std::int32_t expected = 0;
  if (out_frac == 24) {
    fits = fx::quotient_by_positive<24>(negative, n, n_frac, d, d_frac, fx::PreparedReciprocal{}, raw);
    expected = fx::divide_normalised<fx::Q<std::int32_t, 24>>(num, den, st).raw();
  } else {
    fits = fx::quotient_by_positive<16>(negative, n, n_frac, d, d_frac, fx::PreparedReciprocal{}, raw);
    expected = fx::divide_normalised<fx::Q<std::int32_t, 16>>(num, den, st).raw();
  }
  if (fits != st.ok()) {
    return false;
  }
  // The same division from d's prepared reciprocal: the same raw value and
  // the same decision.
  const std::uint32_t m = fx::normalised_reciprocal(d, 0).mantissa;
  std::int32_t raw_by_reciprocal = 0;
  const fx::PreparedReciprocal prepared{true, m};
  const bool fits_by_reciprocal =
      (out_frac == 24) ? fx::quotient_by_positive<24>(negative, n, n_frac, d, d_frac, prepared, raw_by_reciprocal)
                       : fx::quotient_by_positive<16>(negative, n, n_frac, d, d_frac, prepared, raw_by_reciprocal);
  if ((fits_by_reciprocal != fits) || (raw_by_reciprocal != raw)) {
    return false;
  }
  return (!fits) || (raw == expected);
}

std::int32_t bit_length_of(std::uint64_t a) { return static_cast<std::int32_t>(fx::wide::bit_length(a)); }

TEST(QuotientByPositive, MatchesDivideNormalisedOverRandomAndEdgeOperands) {
  std::mt19937_64 rng(20261128U);
  std::uniform_int_distribution<std::int32_t> bits_n(0, 63);
  std::uniform_int_distribution<std::int32_t> bits_d(1, 63);
  std::uniform_int_distribution<std::int32_t> target_exponent(-36, 4);
  std::uniform_int_distribution<std::int32_t> d_frac_pick(0, 60);
  std::int64_t failures = 0;
  for (std::int32_t i = 0; i < 400000; ++i) {
    const std::int32_t nb = bits_n(rng);
    const std::int32_t db = bits_d(rng);
    std::uint64_t n = (nb == 0) ? 0U : ((rng() >> (64 - nb)) | (std::uint64_t{1U} << (nb - 1)));
    std::uint64_t d = (rng() >> (64 - db)) | (std::uint64_t{1U} << (db - 1));
    if ((i % 5) == 1) {
      n = (nb == 0) ? 0U : (std::uint64_t{1U} << (nb - 1));  // N = 2^31: q down to 2^30
    }
    if ((i % 7) == 2) {
      d = (db < 32) ? ((std::uint64_t{1U} << db) - 1U) : (~std::uint64_t{0U} >> (64 - db));  // D = 2^32 - 1
    }
    const std::int32_t out_frac = ((i % 2) == 0) ? 24 : 16;
    const std::int32_t d_frac = d_frac_pick(rng);
    // n_frac so that q's exponent is the drawn one.
    const std::int32_t n_frac =
        ((bit_length_of(n) - bit_length_of(d)) - 31) + d_frac + out_frac - target_exponent(rng);
    const bool negative = (rng() & 1U) != 0U;
    if (!same_as_generic(negative, n, n_frac, d, d_frac, out_frac)) {
      ++failures;
      ADD_FAILURE() << "n " << n << " frac " << n_frac << " d " << d << " frac " << d_frac << " neg " << negative
                    << " out " << out_frac;
      if (failures > 5) {
        return;
      }
    }
  }
  // -2^31 exactly (q = 2^30 at exponent 1) and its neighbours.
  const std::uint64_t d_max = 0xFFFFFFFFULL;
  for (std::int32_t e = -34; e <= 3; ++e) {
    for (const std::uint64_t n : {std::uint64_t{1U} << 40U, (std::uint64_t{1U} << 41U) - 1U, std::uint64_t{1U}}) {
      for (const std::uint64_t d : {d_max, std::uint64_t{1U} << 31U, std::uint64_t{3U}, std::uint64_t{1U}}) {
        const std::int32_t n_frac = ((bit_length_of(n) - bit_length_of(d)) - 31) + 16 - e;
        EXPECT_TRUE(same_as_generic(true, n, n_frac, d, 0, 16)) << n << " " << d << " " << e;
        EXPECT_TRUE(same_as_generic(false, n, n_frac, d, 0, 16)) << n << " " << d << " " << e;
      }
    }
  }
  // 2^40 / (2^32 - 1) at exponent 1: q = 2^30, -2^31 fits, +2^31 does not.
  std::int32_t raw = 0;
  constexpr fx::PreparedReciprocal kNone{};
  EXPECT_FALSE(fx::quotient_by_positive<16>(false, std::uint64_t{1U} << 40U, -7, d_max, 0, kNone, raw));
  ASSERT_TRUE(fx::quotient_by_positive<16>(true, std::uint64_t{1U} << 40U, -7, d_max, 0, kNone, raw));
  EXPECT_EQ(raw, std::numeric_limits<std::int32_t>::min());
}

// The limit's quotient from a prepared reciprocal (round 17) against the
// built-in 64 / 32-bit division, for n and d in [2^31, 2^32): random pairs,
// the ends of both ranges, and n = d, n = d - 1, n = d + 1 (where the
// estimate is one below the quotient). Dropping the correction, or taking
// the reciprocal one too small, fails it.
TEST(QuotientOfLeadingWordsByReciprocal, IsTheBuiltInQuotient) {
  constexpr std::uint32_t kLow = 0x80000000U;
  constexpr std::uint32_t kHigh = 0xFFFFFFFFU;
  const auto check = [](std::uint32_t n, std::uint32_t d) {
    const std::uint32_t m = fx::detail::floor_two_to_63_less_1_over(d);
    const auto expected = static_cast<std::uint32_t>((std::uint64_t{n} << 31U) / d);
    return fx::detail::quotient_of_leading_words_by_reciprocal(n, d, m) == expected;
  };
  std::int64_t failures = 0;
  std::int64_t corrected = 0;
  std::mt19937_64 rng(17U);
  for (std::int32_t i = 0; i < 2000000; ++i) {
    const auto n = static_cast<std::uint32_t>(rng()) | kLow;
    const auto d = static_cast<std::uint32_t>(rng()) | kLow;
    const std::uint32_t m = fx::detail::floor_two_to_63_less_1_over(d);
    const auto estimate = static_cast<std::uint32_t>((std::uint64_t{n} * m) >> 32U);
    corrected += (estimate != static_cast<std::uint32_t>((std::uint64_t{n} << 31U) / d)) ? 1 : 0;
    failures += check(n, d) ? 0 : 1;
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(corrected, 0);  // the correction is exercised
  for (const std::uint32_t d : {kLow, kLow + 1U, 0xC0000000U, 0xD1B71759U, kHigh - 1U, kHigh}) {
    for (const std::uint32_t n : {kLow, kLow + 1U, d - 1U, d, d + 1U, kHigh - 1U, kHigh}) {
      if (n >= kLow) {
        EXPECT_TRUE(check(n, d)) << n << " / " << d;
      }
    }
  }
}

}  // namespace
