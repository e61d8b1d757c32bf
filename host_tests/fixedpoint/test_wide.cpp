// test_wide.cpp: the documented contracts of the 128-bit helpers
// (wide.hpp) at the arguments the Q operations never pass them: shift counts
// at and past the width, a zero shift, and long divisions whose divisor or
// remainder needs the top bit. docs/coverage.md says why the Q operations
// cannot reach these cases; these tests pin the helpers' own contract.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "sinkwatch/fixedpoint/wide.hpp"

namespace {

namespace wide = sinkwatch::fx::wide;
using wide::U128;

constexpr std::uint64_t kAllOnes = 0xFFFFFFFFFFFFFFFFULL;

::testing::AssertionResult same(const U128& a, const U128& b) {
  if (wide::equal(a, b)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << std::hex << "{0x" << a.hi << ", 0x" << a.lo << "} != {0x" << b.hi << ", 0x"
                                       << b.lo << "}";
}

// q * d + r == n and r < d, in 128 bits (q * d computed from its halves).
::testing::AssertionResult division_identity(const U128& n, const U128& d, const wide::DivMod<U128>& qr) {
  if (!wide::less(qr.remainder, d)) {
    return ::testing::AssertionFailure() << "remainder not below the divisor";
  }
  // q * d with q < 2^64 or d < 2^64 (true in every case below): three partial products.
  const U128 lo_lo = wide::mul_full(qr.quotient.lo, d.lo);
  const U128 q_hi_d_lo = wide::mul_full(qr.quotient.hi, d.lo);
  const U128 q_lo_d_hi = wide::mul_full(qr.quotient.lo, d.hi);
  const U128 product{lo_lo.hi + q_hi_d_lo.lo + q_lo_d_hi.lo, lo_lo.lo};
  return same(wide::add(product, qr.remainder), n);
}

TEST(FxWide, ShiftsByTheFullWidthOrMoreGiveZero) {
  EXPECT_EQ(wide::shr(kAllOnes, 64U), 0U);
  EXPECT_EQ(wide::shr(kAllOnes, 200U), 0U);
  EXPECT_EQ(wide::shl(kAllOnes, 64U), 0U);
  EXPECT_EQ(wide::shl(std::uint64_t{1}, 99U), 0U);
  EXPECT_TRUE(same(wide::shr(U128{kAllOnes, kAllOnes}, 128U), U128{0U, 0U}));
  EXPECT_TRUE(same(wide::shr(U128{kAllOnes, kAllOnes}, 1000U), U128{0U, 0U}));
  EXPECT_TRUE(same(wide::shl(U128{kAllOnes, kAllOnes}, 128U), U128{0U, 0U}));
  EXPECT_TRUE(same(wide::shl(U128{0U, 1U}, 300U), U128{0U, 0U}));
}

TEST(FxWide, ShiftByZeroIsTheIdentity) {
  const U128 v{0x0123456789ABCDEFULL, 0xFEDCBA9876543210ULL};
  EXPECT_TRUE(same(wide::shr(v, 0U), v));
  EXPECT_TRUE(same(wide::shl(v, 0U), v));
  EXPECT_EQ(wide::shr(std::uint64_t{0x8000000000000001ULL}, 0U), 0x8000000000000001ULL);
  EXPECT_EQ(wide::shl(std::uint64_t{0x8000000000000001ULL}, 0U), 0x8000000000000001ULL);
}

TEST(FxWide, ShiftsAcrossTheHalvesMoveTheRightBits) {
  EXPECT_TRUE(same(wide::shr(U128{1U, 0U}, 64U), U128{0U, 1U}));
  EXPECT_TRUE(same(wide::shl(U128{0U, 1U}, 127U), U128{0x8000000000000000ULL, 0U}));
  EXPECT_TRUE(same(wide::shr(U128{0x8000000000000000ULL, 0U}, 127U), U128{0U, 1U}));
  EXPECT_TRUE(same(wide::shl(U128{0U, 0x8000000000000000ULL}, 1U), U128{1U, 0U}));
}

TEST(FxWide, EqualityComparesBothHalves) {
  EXPECT_TRUE(wide::equal(U128{1U, 2U}, U128{1U, 2U}));
  EXPECT_FALSE(wide::equal(U128{1U, 2U}, U128{2U, 2U}));
  EXPECT_FALSE(wide::equal(U128{1U, 2U}, U128{1U, 3U}));
  EXPECT_TRUE(wide::less(U128{0U, kAllOnes}, U128{1U, 0U}));
  EXPECT_FALSE(wide::less(U128{1U, 0U}, U128{1U, 0U}));
}

/// The definition: the position of the highest set bit, counted one by one.
std::uint32_t bit_length_by_bits(std::uint32_t a) {
  std::uint32_t n = 0U;
  for (std::uint32_t v = a; v != 0U; v >>= 1U) {
    ++n;
  }
  return n;
}

// Both forms on every target: the count-leading-zeros form where the core
// has the instruction, and the halving form the ARMv6-M build uses.
TEST(FxWide, BitLength32EqualsTheBitByBitCount) {
  for (std::uint32_t k = 0U; k < 32U; ++k) {
    const std::uint32_t p = std::uint32_t{1U} << k;
    for (const std::uint32_t a : {p - 1U, p, p + 1U, p | (p - 1U)}) {
      ASSERT_EQ(wide::bit_length32(a), bit_length_by_bits(a)) << a;
      ASSERT_EQ(wide::bit_length32_by_halves(a), bit_length_by_bits(a)) << a;
    }
  }
  std::mt19937 rng(32U);
  for (int i = 0; i < 10000000; ++i) {
    const std::uint32_t a = static_cast<std::uint32_t>(rng()) >> (static_cast<std::uint32_t>(rng()) % 32U);
    ASSERT_EQ(wide::bit_length32(a), bit_length_by_bits(a)) << a;
    ASSERT_EQ(wide::bit_length32_by_halves(a), bit_length_by_bits(a)) << a;
  }
}

static_assert(wide::bit_length32(0U) == 0U, "constexpr: zero has no significant bit");
static_assert(wide::bit_length32(0x80000000U) == 32U, "constexpr: the top bit");
static_assert(wide::bit_length32_by_halves(0x00012345U) == 17U, "constexpr: by halves");

TEST(FxWide, LeadingWordIsTheTopThirtyTwoBitsFromTheLeadingOne) {
  EXPECT_EQ(wide::leading_word(0U, 0U), 0U);
  EXPECT_EQ(wide::leading_word(1U, 1U), 0x80000000U);
  EXPECT_EQ(wide::leading_word(kAllOnes, 64U), 0xFFFFFFFFU);
  EXPECT_EQ(wide::leading_word(std::uint64_t{1U} << 63U, 64U), 0x80000000U);
  std::mt19937_64 rng(64U);
  for (int i = 0; i < 1000000; ++i) {
    const std::uint64_t a = (rng() >> (rng() % 64U)) | 1U;
    const std::uint32_t bits = wide::bit_length(a);
    const std::uint64_t expected = (bits <= 32U) ? (a << (32U - bits)) : (a >> (bits - 32U));
    ASSERT_EQ(wide::leading_word(a, bits), expected) << a;
  }
}

TEST(FxWide, BitLengthCountsEverySignificantBit) {
  EXPECT_EQ(wide::bit_length32(0U), 0U);
  EXPECT_EQ(wide::bit_length32(1U), 1U);
  EXPECT_EQ(wide::bit_length32(0xFFFFFFFFU), 32U);
  EXPECT_EQ(wide::bit_length(std::uint64_t{0}), 0U);
  EXPECT_EQ(wide::bit_length(kAllOnes), 64U);
  EXPECT_EQ(wide::bit_length(U128{1U, 0U}), 65U);
  EXPECT_EQ(wide::bit_length(U128{kAllOnes, 0U}), 128U);
}

// Divisor below 2^64 but above 2^63: the doubled remainder overflows 64
// bits (the `carry` of the single-word loop). 2^127 / (2^64 - 1) is
// 2^63 + 0 remainder 2^63: the classic case.
TEST(FxWide, LongDivisionByADivisorAboveTwoToThe63IsExact) {
  const U128 n{0x8000000000000000ULL, 0U};
  const U128 d{0U, kAllOnes};
  const wide::DivMod<U128> qr = wide::divmod(n, d);
  EXPECT_TRUE(same(qr.quotient, U128{0U, 0x8000000000000000ULL}));
  EXPECT_TRUE(same(qr.remainder, U128{0U, 0x8000000000000000ULL}));
  EXPECT_TRUE(division_identity(n, d, qr));

  const U128 n2{0xFFFFFFFFFFFFFFFEULL, 0x0123456789ABCDEFULL};
  const U128 d2{0U, 0xC000000000000001ULL};
  const wide::DivMod<U128> qr2 = wide::divmod(n2, d2);
  EXPECT_TRUE(division_identity(n2, d2, qr2));
  EXPECT_EQ(qr2.quotient.hi, 1U);  // (2^128 - small) / (3 * 2^62) is about 1.33 * 2^64
}

// Divisor of 2^64 or more: the two-word remainder loop, with quotient bits set.
TEST(FxWide, LongDivisionByATwoWordDivisorIsExact) {
  const U128 n{0x0000000500000000ULL, 0x0000000000000007ULL};
  const U128 d{0x0000000100000000ULL, 0U};  // 2^96
  const wide::DivMod<U128> qr = wide::divmod(n, d);
  EXPECT_TRUE(same(qr.quotient, U128{0U, 5U}));
  EXPECT_TRUE(same(qr.remainder, U128{0U, 7U}));

  const U128 n2{kAllOnes, kAllOnes};
  const U128 d2{3U, 0x1234567890ABCDEFULL};
  const wide::DivMod<U128> qr2 = wide::divmod(n2, d2);
  EXPECT_TRUE(division_identity(n2, d2, qr2));
  EXPECT_GT(qr2.quotient.lo, 0U);

  // Divisor larger than the dividend: quotient zero, remainder the dividend.
  const U128 small{1U, 0U};
  const wide::DivMod<U128> qr3 = wide::divmod(small, U128{2U, 0U});
  EXPECT_TRUE(same(qr3.quotient, U128{0U, 0U}));
  EXPECT_TRUE(same(qr3.remainder, small));
}

// The single-word-divisor loop starts past the dividend's top
// bit_length(den) - 1 bits (their quotient bits are zero): q d + r == n and
// r < d (which fix q and r) for 400,000 dividends of every length from 65 to
// 128 bits and divisors of every length from 1 to 64 bits: random, powers of
// two, all ones, and just above a power of two. Portable (no __int128), so
// it runs on ARM32 too.
TEST(FxWide, LongDivisionSkippingTheLeadingZeroQuotientBitsIsExact) {
  std::mt19937_64 rng(15U);
  std::uint32_t compared = 0U;
  for (std::uint32_t k = 0U; k < 400000U; ++k) {
    const std::uint32_t n_len = 65U + static_cast<std::uint32_t>(rng() % 64U);  // 65..128
    const std::uint32_t d_len = 1U + (k % 64U);
    // The top word has n_len - 64 bits, its leading one set.
    const std::uint64_t top = (rng() >> (128U - n_len)) | (std::uint64_t{1U} << (n_len - 65U));
    const U128 num{top, rng()};
    std::uint64_t d = (rng() >> (64U - d_len)) | (std::uint64_t{1U} << (d_len - 1U));
    const std::uint32_t mode = (k / 64U) % 4U;
    if (mode == 1U) {
      d = std::uint64_t{1U} << (d_len - 1U);  // a power of two
    } else if (mode == 2U) {
      d = (d_len == 64U) ? kAllOnes : ((std::uint64_t{1U} << d_len) - 1U);  // all ones
    } else if ((mode == 3U) && (d_len > 1U)) {
      d = (std::uint64_t{1U} << (d_len - 1U)) + 1U;  // just above a power of two
    } else {
      // random, as drawn
    }
    const U128 den{0U, d};
    const wide::DivMod<U128> qr = wide::divmod(num, den);
    // The quotient times d stays below 2^128: no partial product is lost.
    ASSERT_EQ(wide::mul_full(qr.quotient.hi, d).hi, 0U) << "k " << k;
    ASSERT_TRUE(division_identity(num, den, qr)) << "k " << k;
    ++compared;
  }
  EXPECT_EQ(compared, 400000U);
}

/// divmod_by_word_normalising (the one-word divisor's form without a divide
/// instruction, wide.hpp) and wide::divmod on 64 bits give the built-in
/// quotient and remainder.
void expect_word_division_exact(std::uint64_t num, std::uint32_t den) {
  const wide::DivMod<std::uint64_t> normalising = wide::divmod_by_word_normalising(num, den);
  ASSERT_EQ(normalising.quotient, num / den) << num << " / " << den;
  ASSERT_EQ(normalising.remainder, num % den) << num << " / " << den;
  const wide::DivMod<std::uint64_t> selected = wide::divmod(num, std::uint64_t{den});
  ASSERT_EQ(selected.quotient, num / den) << num << " / " << den;
  ASSERT_EQ(selected.remainder, num % den) << num << " / " << den;
}

/// A random value of exactly `bits` significant bits (0 for bits == 0).
std::uint64_t of_length(std::mt19937_64& rng, std::uint32_t bits) {
  if (bits == 0U) {
    return 0U;
  }
  const std::uint64_t top = std::uint64_t{1U} << (bits - 1U);
  return top | (rng() & (top - 1U));
}

// Every divisor length (so every normalising shift 0..31) against every
// dividend length, at random and at the edges: powers of two, all ones, the
// largest dividend, remainders of den - 1.
TEST(FxWide, DivisionByAOneWordDivisorEqualsTheBuiltInDivision) {
  std::mt19937_64 rng(16U);
  for (std::uint32_t d_len = 1U; d_len <= 32U; ++d_len) {
    const std::uint32_t power = 1U << (d_len - 1U);
    const std::uint32_t ones = (d_len == 32U) ? 0xFFFFFFFFU : ((1U << d_len) - 1U);
    for (const std::uint32_t den : {power, ones, power + 1U, ones - 1U}) {
      if (den == 0U) {
        continue;
      }
      for (const std::uint64_t num : {std::uint64_t{0U}, std::uint64_t{1U}, std::uint64_t{den} - 1U,
                                      std::uint64_t{den}, kAllOnes, kAllOnes - 1U, std::uint64_t{1U} << 63U,
                                      std::uint64_t{0xFFFFFFFFU}, std::uint64_t{1U} << 32U,
                                      (kAllOnes / den) * den, ((kAllOnes / den) * den) - 1U}) {
        expect_word_division_exact(num, den);
      }
    }
    for (std::uint32_t n_len = 0U; n_len <= 64U; ++n_len) {
      for (int i = 0; i < 400; ++i) {
        const auto den = static_cast<std::uint32_t>(of_length(rng, d_len));
        const std::uint64_t num = of_length(rng, n_len);
        expect_word_division_exact(num, den);
        // The same quotient with the largest remainder, where it fits.
        const std::uint64_t q = num / den;
        if (q <= ((kAllOnes - (den - 1U)) / den)) {
          expect_word_division_exact((q * den) + (den - 1U), den);
        }
      }
    }
  }
}

// Two-word divisors keep the built-in division.
TEST(FxWide, DivisionByATwoWordDivisorEqualsTheBuiltInDivision) {
  std::mt19937_64 rng(17U);
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t den = of_length(rng, 33U + static_cast<std::uint32_t>(rng() % 32U));
    const std::uint64_t num = rng();
    const wide::DivMod<std::uint64_t> qr = wide::divmod(num, den);
    ASSERT_EQ(qr.quotient, num / den);
    ASSERT_EQ(qr.remainder, num % den);
  }
}

}  // namespace
