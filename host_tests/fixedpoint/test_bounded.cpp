// Bounded values (fixedpoint/bounded.hpp): the entry check saturates and
// reports, the bounds in the types are what the operations can reach, and
// every operation gives the bits of the checked one it replaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <random>
#include <type_traits>

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace {

namespace fx = sinkwatch::fx;
using Q6_25 = fx::Q<std::int32_t, 25>;
using Q15_16 = fx::Q<std::int32_t, 16>;

constexpr std::uint32_t kTwoMetres = 2U << 25U;  // 2.0 in Q6.25
constexpr std::uint32_t kOneQ30 = 1U << 30U;     // 1.0 in Q1.30
constexpr std::uint32_t kKx = 942229340U;        // about 3.51 in Q3.28

/// A raw value uniformly in [-m, m].
std::int32_t draw(std::mt19937& rng, std::uint32_t m) {
  std::uniform_int_distribution<std::int32_t> d(-static_cast<std::int32_t>(m), static_cast<std::int32_t>(m));
  return d(rng);
}

TEST(BoundedTest, BoundToKeepsValuesWithinTheBoundAndSaturatesBeyondIt) {
  const std::int32_t m = static_cast<std::int32_t>(kTwoMetres);
  for (const std::int32_t v : {0, 1, -1, m, -m, m - 1, -(m - 1)}) {
    fx::Status st;
    EXPECT_EQ(fx::bound_to<kTwoMetres>(Q6_25::from_raw(v), st).raw(), v);
    EXPECT_TRUE(st.ok()) << v;
  }
  fx::Status above;
  EXPECT_EQ(fx::bound_to<kTwoMetres>(Q6_25::from_raw(m + 1), above).raw(), m);
  EXPECT_TRUE(above.has(fx::Flag::overflow));
  fx::Status below;
  EXPECT_EQ(fx::bound_to<kTwoMetres>(Q6_25::min(), below).raw(), -m);
  EXPECT_TRUE(below.has(fx::Flag::overflow));
}

TEST(BoundedTest, ResultTypesCarryTheIntervalBounds) {
  using Link = fx::Bounded<Q6_25, kTwoMetres>;
  using Unit = fx::Bounded<fx::Q1_30, kOneQ30>;
  static_assert(std::is_same<decltype(fx::add(Link{}, Link{})), fx::Bounded<Q6_25, 2U * kTwoMetres>>::value, "sum");
  static_assert(std::is_same<decltype(fx::sub(Link{}, Link{})), fx::Bounded<Q6_25, 2U * kTwoMetres>>::value, "diff");
  static_assert(std::is_same<decltype(fx::neg(Link{})), Link>::value, "neg");
  static_assert(std::is_same<decltype(fx::mul<Q6_25>(Link{}, Unit{})), Link>::value, "a product by one or less");
  // The bound is reached: the largest operands give it exactly.
  const auto top = fx::mul<Q6_25>(fx::bounded_raw<Q6_25, static_cast<std::int32_t>(kTwoMetres)>(),
                                   fx::bounded_raw<fx::Q1_30, -static_cast<std::int32_t>(kOneQ30)>());
  EXPECT_EQ(top.raw(), -static_cast<std::int32_t>(kTwoMetres));
  EXPECT_EQ(fx::widen<3U * kTwoMetres>(Link::trusted(5)).raw(), 5);
}

TEST(BoundedTest, SumsDifferencesAndNegationsEqualTheCheckedOperations) {
  std::mt19937 rng(20261125U);
  using Big = fx::Bounded<Q6_25, 0x3FFFFFFFU>;
  for (int i = 0; i < 100000; ++i) {
    const Big a = Big::trusted(draw(rng, Big::max_mag));
    const Big b = Big::trusted(draw(rng, Big::max_mag));
    fx::Status st;
    EXPECT_EQ(fx::add(a, b).raw(), fx::add(a.q(), b.q(), st).raw());
    EXPECT_EQ(fx::sub(a, b).raw(), fx::sub(a.q(), b.q(), st).raw());
    EXPECT_EQ(fx::neg(a).raw(), fx::neg(a.q(), st).raw());
    ASSERT_TRUE(st.ok());
  }
}

/// Random operands within the bounds, with their extremes and the ties of
/// the rounding weighted in; the product equals fx::mul's, which stays clean.
template <typename Out, typename QA, std::uint32_t A, typename QB, std::uint32_t B>
void expect_products_match(std::uint32_t seed) {
  std::mt19937 rng(seed);
  constexpr std::int32_t kShift = (QA::frac_bits + QB::frac_bits) - Out::frac_bits;
  const std::int32_t extremes_a[] = {0, 1, -1, static_cast<std::int32_t>(A), -static_cast<std::int32_t>(A)};
  const std::int32_t extremes_b[] = {0, 1, -1, static_cast<std::int32_t>(B), -static_cast<std::int32_t>(B),
                                     std::int32_t{1} << (kShift - 1), -(std::int32_t{1} << (kShift - 1)),
                                     3 * (std::int32_t{1} << (kShift - 1))};
  for (int i = 0; i < 200000; ++i) {
    const std::int32_t ra = (i % 4 == 0) ? extremes_a[static_cast<std::size_t>(i / 4) % 5U] : draw(rng, A);
    const std::int32_t rb = (i % 3 == 0) ? extremes_b[static_cast<std::size_t>(i / 3) % 8U] : draw(rng, B);
    const auto a = fx::Bounded<QA, A>::trusted(ra);
    const auto b = fx::Bounded<QB, B>::trusted((static_cast<std::uint32_t>(rb < 0 ? -rb : rb) <= B) ? rb : 1);
    fx::Status st;
    const Out checked = fx::mul<Out>(a.q(), b.q(), st);
    const auto bounded = fx::mul<Out>(a, b);
    ASSERT_EQ(bounded.raw(), checked.raw()) << ra << " * " << b.raw();
    // Both forms of the rounding, whichever this core uses.
    ASSERT_EQ(fx::detail::product_rounded_by_magnitudes<kShift>(a.raw(), b.raw()), checked.raw());
    ASSERT_EQ(fx::detail::product_rounded_signed<kShift>(a.raw(), b.raw()), checked.raw());
    if constexpr (fx::detail::kRoundsInWords<kShift>) {
      ASSERT_EQ(fx::detail::product_rounded_by_words<kShift>(a.raw(), b.raw()), checked.raw());
    }
    ASSERT_TRUE(st.ok());
    ASSERT_LE(static_cast<std::uint32_t>(bounded.raw() < 0 ? -bounded.raw() : bounded.raw()),
              decltype(bounded)::max_mag);
  }
}

TEST(BoundedTest, ProductsEqualTheCheckedProductBitForBit) {
  // The statics' products: a length by a sine or cosine, by a projection
  // slope, by one half; in Q6.25 and in Q15.16.
  expect_products_match<Q6_25, Q6_25, kTwoMetres, fx::Q1_30, kOneQ30>(1U);
  expect_products_match<Q6_25, Q6_25, 4U * kTwoMetres, fx::Q3_28, kKx>(2U);
  expect_products_match<Q6_25, Q6_25, 0x7FFFFFFFU, Q6_25, 1U << 24U>(3U);
  expect_products_match<Q15_16, Q15_16, 0x7FFFFFFFU, fx::Q1_30, kOneQ30>(4U);
  expect_products_match<Q15_16, Q15_16, 1U << 20U, fx::Q3_28, kKx>(5U);
}

/// A raw value within [-m, m] whose magnitude's 16-bit halves are at their
/// extremes (0, 1, 0xFFFF, the largest the bound allows) or random.
std::int32_t draw_halves(std::mt19937& rng, std::uint32_t m) {
  const std::uint32_t top = m >> 16U;
  const std::uint32_t his[] = {0U, 1U, top, (top > 0U) ? top - 1U : 0U,
                               std::uniform_int_distribution<std::uint32_t>(0U, top)(rng)};
  const std::uint32_t los[] = {0U, 1U, 0xFFFFU, 0x8000U, 0x7FFFU,
                               std::uniform_int_distribution<std::uint32_t>(0U, 0xFFFFU)(rng)};
  std::uint32_t mag = (his[rng() % 5U] << 16U) | los[rng() % 6U];
  if (mag > m) {
    mag = m;
  }
  const auto v = static_cast<std::int32_t>(mag);
  return ((rng() & 1U) != 0U) ? -v : v;
}

/// product_rounded_by_words<Shift> against fx::mul for |a| <= A, |b| <= B
/// (bounds whose rounded product stays below 2^31): random operands, operands whose halves
/// are at their extremes (the middle column's largest values), and the
/// ties of the rounding (b an odd multiple of half an LSB of the result).
template <std::uint32_t A, std::uint32_t B, std::int32_t Shift>
void expect_words_products_match(std::uint32_t seed) {
  static_assert(fx::detail::kRoundsInWords<Shift>, "a shift the words' form holds for");
  static_assert(fx::detail::kProductBound<A, B, Shift> <= fx::kMaxBound, "a product within 31 bits");
  // 16 + 15 fraction bits into 31 - Shift: a right shift by Shift.
  using InA = fx::Q<std::int32_t, 16>;
  using InB = fx::Q<std::int32_t, 15>;
  using Out = fx::Q<std::int32_t, 31 - Shift>;
  std::mt19937 rng(seed);
  for (int i = 0; i < 300000; ++i) {
    std::int32_t a = 0;
    std::int32_t b = 0;
    switch (i % 4) {
      case 0:
        a = draw(rng, A);
        b = draw(rng, B);
        break;
      case 1:
        a = draw_halves(rng, A);
        b = draw_halves(rng, B);
        break;
      case 2:
        a = (i % 8 == 2) ? 1 : -1;
        b = draw(rng, B);
        break;
      default: {
        // a b = (2k + 1) 2^(Shift-1) exactly: a tie.
        a = ((rng() & 1U) != 0U) ? 1 : -1;
        const std::uint32_t half = 1U << static_cast<std::uint32_t>(Shift - 1);
        const std::uint32_t odd = (2U * (rng() % ((B / half + 1U) / 2U + 1U))) + 1U;
        const std::uint32_t mag = (odd * half <= B) ? odd * half : half;
        b = ((rng() & 1U) != 0U) ? static_cast<std::int32_t>(mag) : -static_cast<std::int32_t>(mag);
        if (i % 8 == 7) {
          a = a * static_cast<std::int32_t>(std::min<std::uint32_t>(A, 3U));
        }
        break;
      }
    }
    fx::Status st;
    const Out checked = fx::mul<Out>(InA::from_raw(a), InB::from_raw(b), st);
    ASSERT_TRUE(st.ok()) << a << " * " << b;
    ASSERT_EQ(fx::detail::product_rounded_by_words<Shift>(a, b), checked.raw()) << a << " * " << b;
  }
}

TEST(BoundedTest, WordsProductsEqualTheCheckedProductBitForBit) {
  // The statics' products on ARMv6-M: a link (2 m in Q6.25), a contact
  // height and a span (up to 8 m) by a sine or cosine (Q1.30) or a slope
  // (3.51 in Q3.28); and the largest operands the form accepts at the
  // shifts' ends (the middle column's largest value at 31).
  expect_words_products_match<kTwoMetres, kOneQ30, 30>(21U);
  expect_words_products_match<8U * kTwoMetres, kKx, 28>(22U);
  expect_words_products_match<0x7FFFFFFFU, 0xFFFFU, 17>(23U);
  expect_words_products_match<0x7FFFFFFFU, 0x7FFFFFFFU, 31>(24U);
  expect_words_products_match<0x3FFFFU, 0x3FFFFU, 31>(25U);
  expect_words_products_match<(1U << 30U) - 1U, 0xFFFFU, 20>(26U);
}

TEST(BoundedTest, WordsFormTakesShiftsOf17To31) {
  static_assert(fx::detail::kRoundsInWords<30> && fx::detail::kRoundsInWords<28>, "the statics' shifts");
  static_assert(fx::detail::kRoundsInWords<17> && fx::detail::kRoundsInWords<31>, "the ends");
  static_assert(!fx::detail::kRoundsInWords<16> && !fx::detail::kRoundsInWords<32>, "beyond them");
  SUCCEED();
}

/// wide_product_rounded<Shift> against fx::mul into the 64-bit format with
/// Shift fewer fraction bits, over the whole of both 32-bit operands.
template <std::int32_t Shift>
void expect_wide_products_match(std::uint32_t seed) {
  using In = fx::Q<std::int32_t, 30>;
  using Out = fx::Q<std::int64_t, 60 - Shift>;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::int32_t> any(INT32_MIN, INT32_MAX);
  const std::int32_t extremes[] = {0, 1, -1, INT32_MAX, INT32_MIN, INT32_MIN + 1, 1 << 16, -(1 << 16), 3};
  for (int i = 0; i < 400000; ++i) {
    const std::int32_t a = (i % 5 == 0) ? extremes[static_cast<std::size_t>(i / 5) % 9U] : any(rng);
    const std::int32_t b = (i % 7 == 0) ? extremes[static_cast<std::size_t>(i / 7) % 9U] : any(rng);
    fx::Status st;
    const Out checked = fx::mul<Out>(In::from_raw(a), In::from_raw(b), st);
    ASSERT_TRUE(st.ok());
    ASSERT_EQ(fx::detail::wide_product_rounded<Shift>(a, b), checked.raw()) << a << " * " << b;
  }
}

TEST(BoundedTest, WideProductsEqualTheCheckedProductBitForBit) {
  // Eq. 11's r C3 W (Q2.29 x Q15.16 -> Q23.40), the exact products, and a
  // rounding at every shift the helper allows (ties included: odd multiples
  // of the half among the extremes' products).
  expect_wide_products_match<5>(11U);
  expect_wide_products_match<0>(12U);
  expect_wide_products_match<1>(13U);
  expect_wide_products_match<31>(14U);
  expect_wide_products_match<60>(15U);
}

TEST(BoundedTest, RotatedPointsStayWithinTheirBoundAndEqualTheCheckedRotation) {
  using Link = fx::Bounded<Q6_25, kTwoMetres>;
  using Rotated = fx::BoundedPoint<Q6_25, static_cast<std::uint32_t>(fx::detail::kRotatedBound<kTwoMetres>)>;
  const std::int32_t m = static_cast<std::int32_t>(kTwoMetres);
  std::mt19937 rng(7U);
  std::uint32_t largest = 0U;
  // Angles over two turns, the corners of the link's square (the largest
  // norm) and random points.
  for (std::int32_t k = -20000; k <= 20000; ++k) {
    const fx::Q3_28 angle = fx::Q3_28::from_raw(k * 40000);
    fx::Status st;
    const fx::SinCos sc = fx::sincos(angle, st);
    const fx::BoundedSinCos bsc = fx::bound_sincos(sc, st);
    ASSERT_TRUE(st.ok());
    const std::int32_t x = (k % 3 == 0) ? draw(rng, kTwoMetres) : (((k & 1) != 0) ? m : -m);
    const std::int32_t z = (k % 3 == 0) ? draw(rng, kTwoMetres) : (((k & 2) != 0) ? m : -m);
    Rotated out{};
    fx::rotated(fx::BoundedPoint<Q6_25, kTwoMetres>{Link::trusted(x), Link::trusted(z)}, bsc, out);
    const Q6_25 qx = Q6_25::from_raw(x);
    const Q6_25 qz = Q6_25::from_raw(z);
    const Q6_25 cx = fx::sub(fx::mul<Q6_25>(qx, sc.cos, st), fx::mul<Q6_25>(qz, sc.sin, st), st);
    const Q6_25 cz = fx::add(fx::mul<Q6_25>(qx, sc.sin, st), fx::mul<Q6_25>(qz, sc.cos, st), st);
    ASSERT_EQ(out.x.raw(), cx.raw());
    ASSERT_EQ(out.z.raw(), cz.raw());
    for (const std::int32_t v : {out.x.raw(), out.z.raw()}) {
      const auto mag = static_cast<std::uint32_t>(v < 0 ? -v : v);
      ASSERT_LE(mag, Rotated{}.x.max_mag);
      largest = (mag > largest) ? mag : largest;
    }
  }
  // The bound is tight: it is sqrt(2) times 2 m plus 2^-17 of it, and the
  // corners at 45 degrees come within that margin.
  EXPECT_GT(largest, Rotated{}.x.max_mag - 1024U);
}

}  // namespace
