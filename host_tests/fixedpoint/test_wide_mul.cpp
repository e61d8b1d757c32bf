// test_wide_mul.cpp: the 32 x 32 -> 64-bit products of wide.hpp
// (docs/performance.md, finding 7). On ARMv6-M mul_32x32_64 and
// mul_64x64_low are built from 16-bit halves (mul_32x32_64_halves,
// mul_64x64_low_by_words) instead of __aeabi_lmul; that branch is not
// compiled into the host's products, so its formulas are checked here
// directly against the built-in widening multiply, as well as the dispatching
// helpers themselves. Both must give the built-in product's exact bits.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "sinkwatch/fixedpoint/wide.hpp"

namespace {

namespace wide = sinkwatch::fx::wide;

constexpr std::uint32_t kU32Max = std::numeric_limits<std::uint32_t>::max();
constexpr std::int32_t kI32Max = std::numeric_limits<std::int32_t>::max();
constexpr std::int32_t kI32Min = std::numeric_limits<std::int32_t>::min();

// The halves are exact in constant evaluation too (the constexpr users of
// fx::mul, trig's tables).
static_assert(wide::mul_32x32_64_halves(kU32Max, kU32Max) == 0xFFFFFFFE00000001ULL, "halves: max * max");
static_assert(wide::mul_32x32_64(kI32Min, kI32Min) == (std::int64_t{1} << 62), "signed: min * min");
static_assert(wide::mul_32x32_rounded_high_by_columns(kU32Max, kU32Max) == 0xFFFFFFFEU, "rounded high: max * max");

// Edge words: zero, one, the half-word boundaries, the signed limits.
std::vector<std::uint32_t> edge_words() {
  return {0U, 1U, 2U, 0xFFFFU, 0x10000U, 0x10001U, 0x7FFFFFFFU, 0x80000000U, 0x80000001U, 0xFFFF0000U, 0xFFFEFFFFU,
          kU32Max - 1U, kU32Max};
}

std::uint64_t builtin_product(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b);
}

TEST(WideMul, HalvesGiveTheBuiltinProductAtEdgeWords) {
  for (const std::uint32_t a : edge_words()) {
    for (const std::uint32_t b : edge_words()) {
      EXPECT_EQ(wide::mul_32x32_64_halves(a, b), builtin_product(a, b)) << a << " * " << b;
      EXPECT_EQ(wide::mul_32x32_64(a, b), builtin_product(a, b)) << a << " * " << b;
    }
  }
}

TEST(WideMul, HalvesGiveTheBuiltinProductForRandomWords) {
  std::mt19937 rng(0x15u);
  for (int i = 0; i < 1000000; ++i) {
    const std::uint32_t a = rng();
    // Every length of b, so that the carries of short and long operands both occur.
    const std::uint32_t b = rng() >> (static_cast<std::uint32_t>(i) % 32U);
    ASSERT_EQ(wide::mul_32x32_64_halves(a, b), builtin_product(a, b)) << a << " * " << b;
    ASSERT_EQ(wide::mul_32x32_64(a, b), builtin_product(a, b)) << a << " * " << b;
  }
}

TEST(WideMul, SignedProductIsTheExactProductAtEdgesAndRandomly) {
  const std::vector<std::int32_t> edges = {0, 1, -1, 2, -2, 0xFFFF, -0xFFFF, 0x10000, -0x10000, kI32Max, kI32Max - 1,
                                           kI32Min, kI32Min + 1};
  for (const std::int32_t a : edges) {
    for (const std::int32_t b : edges) {
      EXPECT_EQ(wide::mul_32x32_64(a, b), static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b))
          << a << " * " << b;
    }
  }
  std::mt19937 rng(0x1515u);
  for (int i = 0; i < 1000000; ++i) {
    const auto a = static_cast<std::int32_t>(rng());
    const auto b = static_cast<std::int32_t>(rng()) / (1 << (i % 31));
    ASSERT_EQ(wide::mul_32x32_64(a, b), static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b))
        << a << " * " << b;
  }
}

TEST(WideMul, LowProductByWordsIsTheBuiltinProductModulo2To64) {
  std::vector<std::uint64_t> edges = {0U, 1U, 0xFFFFFFFFU, 0x100000000ULL, 0x1FFFFFFFFULL, 0x8000000000000000ULL,
                                      0xFFFFFFFFFFFFFFFFULL};
  for (const std::uint32_t w : edge_words()) {
    edges.push_back(w);
    edges.push_back(std::uint64_t{w} << 32U);
  }
  for (const std::uint64_t a : edges) {
    for (const std::uint64_t b : edges) {
      EXPECT_EQ(wide::mul_64x64_low_by_words(a, b), a * b) << a << " * " << b;
      EXPECT_EQ(wide::mul_64x64_low(a, b), a * b) << a << " * " << b;
    }
  }
  std::mt19937_64 rng(0x64u);
  for (int i = 0; i < 1000000; ++i) {
    const std::uint64_t a = rng() >> (static_cast<std::uint32_t>(i) % 64U);
    const std::uint64_t b = rng() >> (static_cast<std::uint32_t>(i / 64) % 64U);
    ASSERT_EQ(wide::mul_64x64_low_by_words(a, b), a * b) << a << " * " << b;
  }
}

// mul_full's four partial products now come from mul_32x32_64: the 128-bit
// product divided back by b (the long division, an independent algorithm)
// must give a and no remainder. Portable (no __int128), so it runs on ARM32.
TEST(WideMul, FullProductOf64BitValuesDividesBackExactly) {
  std::mt19937_64 rng(0x128u);
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t a = rng() >> (static_cast<std::uint32_t>(i) % 64U);
    const std::uint64_t b = (rng() >> (static_cast<std::uint32_t>(i / 64) % 64U)) | 1U;
    const wide::U128 product = wide::mul_full(a, b);
    const wide::DivMod<wide::U128> qr = wide::divmod(product, wide::make_u128(b));
    ASSERT_EQ(qr.quotient.hi, 0U) << a << " * " << b;
    ASSERT_EQ(qr.quotient.lo, a) << a << " * " << b;
    ASSERT_TRUE(wide::is_zero(qr.remainder)) << a << " * " << b;
  }
}

// The ARMv6-M form of mul_full (16-bit halves, zero high words skipped) gives
// the same 128 bits as the host's, for operands with and without high words.
TEST(WideMul, FullProductSkippingZeroWordsEqualsTheFullProduct) {
  std::vector<std::uint64_t> edges = {0U, 1U, 0xFFFFFFFFU, 0x100000000ULL, 0xFFFFFFFFFFFFFFFFULL};
  for (const std::uint64_t a : edges) {
    for (const std::uint64_t b : edges) {
      EXPECT_TRUE(wide::equal(wide::mul_full_skipping_zero_words(a, b), wide::mul_full(a, b))) << a << " * " << b;
    }
  }
  std::mt19937_64 rng(0x5u);
  for (int i = 0; i < 400000; ++i) {
    // Both operands of every length, so that each of the four cases occurs.
    const std::uint64_t a = rng() >> (static_cast<std::uint32_t>(i) % 64U);
    const std::uint64_t b = rng() >> (static_cast<std::uint32_t>(i / 64) % 64U);
    ASSERT_TRUE(wide::equal(wide::mul_full_skipping_zero_words(a, b), wide::mul_full(a, b))) << a << " * " << b;
  }
}

// round(a b / 2^32) half up: the ARMv6-M columns (only the high word and
// the carry of bits 16..31 plus 2^15) and the dispatching form against the
// built-in product, on edge words, random words of every length and, for
// each random b, the a whose product's low word lies at the rounding's tie
// 2^31 and either side of it (the drawbar pulls' shares, session 19).
TEST(WideMul, RoundedHighWordIsTheProductRoundedHalfUp) {
  const auto check = [](std::uint32_t a, std::uint32_t b) {
    const auto rounded = static_cast<std::uint32_t>((builtin_product(a, b) + (1ULL << 31U)) >> 32U);
    ASSERT_EQ(wide::mul_32x32_rounded_high_by_columns(a, b), rounded) << a << " * " << b;
    ASSERT_EQ(wide::mul_32x32_rounded_high(a, b), rounded) << a << " * " << b;
  };
  for (const std::uint32_t a : edge_words()) {
    for (const std::uint32_t b : edge_words()) {
      check(a, b);
    }
  }
  std::mt19937_64 rng(0x19u);
  for (int i = 0; i < 1000000; ++i) {
    const auto a = static_cast<std::uint32_t>((rng() >> 32U) >> (static_cast<std::uint32_t>(i) % 33U));
    const auto b = static_cast<std::uint32_t>((rng() >> 32U) >> (static_cast<std::uint32_t>(i / 33) % 33U));
    check(a, b);
    if (b != 0U) {
      const std::uint64_t target = (builtin_product(a, b) & ~0xFFFFFFFFULL) + (1ULL << 31U);
      const std::uint64_t a_tie = target / b;
      for (std::uint64_t x = (a_tie > 1U) ? (a_tie - 1U) : 0U; (x <= a_tie + 1U) && (x <= kU32Max); ++x) {
        check(static_cast<std::uint32_t>(x), b);
      }
    }
  }
}

}  // namespace
