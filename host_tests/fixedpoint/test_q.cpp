// test_q.cpp: worked examples and every error path of the core Q operations
// (add, sub, neg, abs, min, max, clamp, from_int, rescale, mul, div) and of
// the sticky Status; constexpr evaluation checked with static_assert.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"

namespace {

namespace fx = sinkwatch::fx;
using fx::Flag;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;
using QInt32 = fx::Q<std::int32_t, 0>;

constexpr std::int32_t k_one = 1 << 16;  // 1.0 in Q15_16

constexpr std::uint8_t only(Flag f) { return static_cast<std::uint8_t>(f); }

Q15_16 q(std::int32_t raw) { return Q15_16::from_raw(raw); }

// ---------------------------------------------------------------- constexpr

constexpr std::int32_t constexpr_mul() {
  fx::Status s;
  return fx::mul(Q15_16::from_raw(3 * k_one / 2), Q15_16::from_raw(-9 * k_one / 4), s).raw();
}
constexpr std::int32_t constexpr_div() {
  fx::Status s;
  return fx::div(Q15_16::from_raw(k_one), Q15_16::from_raw(3 * k_one), s).raw();
}
constexpr bool constexpr_overflow_flag() {
  fx::Status s;
  const Q15_16 r = fx::add(Q15_16::max(), Q15_16::lsb(), s);
  return s.has(Flag::overflow) && r == Q15_16::max();
}
constexpr std::int64_t constexpr_wide_mul() {
  fx::Status s;
  return fx::mul(Q31_32::from_raw(std::int64_t{3} << 31), Q31_32::from_raw(-(std::int64_t{5} << 32)), s).raw();
}
static_assert(constexpr_mul() == -27 * k_one / 8, "1.5 * -2.25 = -3.375 at compile time");
static_assert(constexpr_div() == 21845, "1/3 rounds to 21845 / 65536 at compile time");
static_assert(constexpr_overflow_flag(), "overflow reported at compile time");
static_assert(constexpr_wide_mul() == -(std::int64_t{15} << 31), "1.5 * -5 = -7.5 in Q31_32 at compile time");

// ---------------------------------------------------------------- from_int, one

TEST(FxFromInt, ExactInsideTheRange) {
  fx::Status s;
  EXPECT_EQ(Q15_16::from_int(3, s).raw(), 3 * k_one);
  EXPECT_EQ(Q15_16::from_int(-32768, s), Q15_16::min());
  EXPECT_EQ(Q1_30::one(s).raw(), 1 << 30);
  EXPECT_EQ(QInt32::from_int(std::numeric_limits<std::int32_t>::max(), s), QInt32::max());
  EXPECT_TRUE(s.ok());
}

TEST(FxFromInt, SaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(Q15_16::from_int(32768, s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(Q15_16::from_int(-32769, s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(Q31_32::from_int(std::numeric_limits<std::int64_t>::min(), s3), Q31_32::min());
  EXPECT_TRUE(s3.has(Flag::overflow));
}

// ---------------------------------------------------------------- add, sub

TEST(FxAddSub, WorkedExample) {
  fx::Status s;
  EXPECT_EQ(fx::add(q(3 * k_one / 2), q(9 * k_one / 4), s).raw(), 15 * k_one / 4);
  EXPECT_EQ(fx::sub(q(3 * k_one / 2), q(9 * k_one / 4), s).raw(), -3 * k_one / 4);
  EXPECT_EQ(fx::add(Q15_16::min(), Q15_16::max(), s).raw(), -1);
  EXPECT_TRUE(s.ok());
}

TEST(FxAddSub, OverflowSaturatesUpward) {
  fx::Status s1;
  EXPECT_EQ(fx::add(Q15_16::max(), Q15_16::lsb(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::sub(Q15_16::max(), q(-1), s2), Q15_16::max());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::sub(Q31_32::zero(), Q31_32::min(), s3), Q31_32::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

TEST(FxAddSub, OverflowSaturatesDownward) {
  fx::Status s1;
  EXPECT_EQ(fx::add(Q15_16::min(), q(-1), s1), Q15_16::min());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::sub(Q15_16::min(), Q15_16::lsb(), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::add(Q31_32::min(), Q31_32::min(), s3), Q31_32::min());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

// ---------------------------------------------------------------- neg, abs, min, max, clamp

TEST(FxNegAbs, MostNegativeValueSaturatesToMax) {
  fx::Status s1;
  EXPECT_EQ(fx::neg(Q15_16::min(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::abs(Q15_16::min(), s2), Q15_16::max());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::abs(Q31_32::min(), s3), Q31_32::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
}

TEST(FxNegAbs, EverythingElseIsExact) {
  fx::Status s;
  EXPECT_EQ(fx::neg(Q15_16::max(), s).raw(), std::numeric_limits<std::int32_t>::min() + 1);
  EXPECT_EQ(fx::neg(q(5), s).raw(), -5);
  EXPECT_EQ(fx::abs(q(-5), s).raw(), 5);
  EXPECT_EQ(fx::abs(Q15_16::zero(), s).raw(), 0);
  EXPECT_EQ(fx::abs(fx::neg(Q15_16::max(), s), s), Q15_16::max());
  EXPECT_TRUE(s.ok());
}

TEST(FxMinMaxClamp, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::min(q(-3), q(2)).raw(), -3);
  EXPECT_EQ(fx::max(q(-3), q(2)).raw(), 2);
  EXPECT_EQ(fx::clamp(q(7), q(-2), q(5), s).raw(), 5);
  EXPECT_EQ(fx::clamp(q(-7), q(-2), q(5), s).raw(), -2);
  EXPECT_EQ(fx::clamp(q(1), q(-2), q(5), s).raw(), 1);
  EXPECT_EQ(fx::clamp(q(1), q(1), q(1), s).raw(), 1);
  EXPECT_TRUE(s.ok());
}

TEST(FxMinMaxClamp, LoAboveHiIsReportedNotGuessed) {
  fx::Status s;
  EXPECT_EQ(fx::clamp(q(0), q(5), q(-2), s).raw(), 5);
  EXPECT_EQ(s.bits(), only(Flag::domain));
}

// ---------------------------------------------------------------- rescale

TEST(FxRescale, WideningIsExact) {
  fx::Status s;
  EXPECT_EQ(fx::rescale<Q31_32>(q(-3 * k_one / 2), s).raw(), -(std::int64_t{3} << 31));
  EXPECT_EQ(fx::rescale<Q31_32>(Q15_16::min(), s).raw(), -(std::int64_t{32768} << 32));
  EXPECT_TRUE(s.ok());
}

TEST(FxRescale, NarrowingRoundsHalfAwayFromZeroSymmetrically) {
  using Q16_15 = fx::Q<std::int32_t, 15>;
  fx::Status s;
  // raw 3 in Q15_16 is 1.5 LSB of Q16_15: rounds to 2, and -1.5 to -2.
  EXPECT_EQ(fx::rescale<Q16_15>(q(3), s).raw(), 2);
  EXPECT_EQ(fx::rescale<Q16_15>(q(-3), s).raw(), -2);
  // 0.5 LSB: away from zero, both signs. An arithmetic shift would give 0 and -1.
  EXPECT_EQ(fx::rescale<Q16_15>(q(1), s).raw(), 1);
  EXPECT_EQ(fx::rescale<Q16_15>(q(-1), s).raw(), -1);
  // Below the tie: towards the nearest.
  EXPECT_EQ(fx::rescale<QInt32>(q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_EQ(fx::rescale<QInt32>(q(-k_one / 2 + 1), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxRescale, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::rescale<Q15_16>(Q31_32::from_raw(std::int64_t{40000} << 32), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::rescale<Q15_16>(Q31_32::from_raw(-(std::int64_t{40000} << 32)), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::rescale<Q1_30>(q(2 * k_one), s3), Q1_30::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  // Rounding up into the top of the range is not an overflow; past it is.
  fx::Status s4;
  EXPECT_EQ(fx::rescale<QInt32>(Q31_32::from_raw((std::int64_t{2147483647} << 32) + 0x7FFFFFFF), s4), QInt32::max());
  EXPECT_TRUE(s4.ok());
  EXPECT_EQ(fx::rescale<QInt32>(Q31_32::from_raw((std::int64_t{2147483647} << 32) + 0x80000000LL), s4), QInt32::max());
  EXPECT_EQ(s4.bits(), only(Flag::overflow));
}

TEST(FxRescale, WideningPastSixtyFourBitsSaturatesBySign) {
  // A 64-bit integer moved to 32 fraction bits: 2^40 needs 73 bits, past
  // every format, and the 64-bit intermediate reports it.
  using QInt64 = fx::Q<std::int64_t, 0>;
  fx::Status up;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(std::int64_t{1} << 40), up), Q31_32::max());
  EXPECT_EQ(up.bits(), only(Flag::overflow));
  fx::Status down;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(-(std::int64_t{1} << 40)), down), Q31_32::min());
  EXPECT_EQ(down.bits(), only(Flag::overflow));
  fx::Status zero;
  EXPECT_EQ(fx::rescale<Q31_32>(QInt64::from_raw(0), zero).raw(), 0);
  EXPECT_TRUE(zero.ok());
}

// ---------------------------------------------------------------- mul

TEST(FxMul, SixtyFourBitPathGivesTheSameBitsAsTheWidePath) {
  // Q31.32 products of two magnitudes below 2^32 take the 64-bit path; at
  // and around the 2^32 boundary the two paths must agree with the exact
  // rounded product, (|a| |b| + 2^31) >> 32 in the library's 128-bit helpers
  // (no __int128: this test also runs on ARM32).
  const std::int64_t values[] = {1, 3, 0x7FFFFFFF, 0x80000000LL, 0xFFFFFFFFLL, 0x100000000LL, 0x100000001LL,
                                 0x1234567890LL};
  for (std::int64_t a : values) {
    for (std::int64_t b : values) {
      for (int sign = 0; sign < 4; ++sign) {
        const std::int64_t sa = (sign & 1) != 0 ? -a : a;
        const std::int64_t sb = (sign & 2) != 0 ? -b : b;
        fx::Status s;
        const Q31_32 got = fx::mul(Q31_32::from_raw(sa), Q31_32::from_raw(sb), s);
        namespace w = fx::wide;
        const w::U128 exact = w::shr(w::add(w::mul_full(static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b)),
                                            w::make_u128(std::uint64_t{1} << 31U)),
                                     32U);
        ASSERT_EQ(exact.hi, 0U);
        const auto want = static_cast<std::int64_t>(exact.lo);
        EXPECT_EQ(got.raw(), ((sa < 0) != (sb < 0)) ? -want : want) << sa << " * " << sb;
        EXPECT_TRUE(s.ok());
      }
    }
  }
}

TEST(FxMul, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::mul(q(3 * k_one / 2), q(-9 * k_one / 4), s).raw(), -27 * k_one / 8);
  EXPECT_EQ(fx::mul(Q15_16::min(), q(k_one), s), Q15_16::min());
  EXPECT_EQ(fx::mul<Q31_32>(q(100 * k_one), q(1000 * k_one), s).raw(), std::int64_t{100000} << 32);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, TiesRoundAwayFromZeroSymmetrically) {
  fx::Status s;
  const Q15_16 half = q(k_one / 2);
  EXPECT_EQ(fx::mul(q(1), half, s).raw(), 1);    // 0.5 LSB
  EXPECT_EQ(fx::mul(q(-1), half, s).raw(), -1);  // -0.5 LSB, not 0
  EXPECT_EQ(fx::mul(q(3), half, s).raw(), 2);    // 1.5 LSB
  EXPECT_EQ(fx::mul(q(-3), half, s).raw(), -2);  // -1.5 LSB, not -1
  EXPECT_EQ(fx::mul(q(1), q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_EQ(fx::mul(q(-1), q(k_one / 2 - 1), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, UnderflowToZeroIsNotAnError) {
  fx::Status s;
  EXPECT_EQ(fx::mul(Q15_16::lsb(), Q15_16::lsb(), s).raw(), 0);
  EXPECT_EQ(fx::mul(fx::neg(Q15_16::lsb(), s), Q15_16::lsb(), s).raw(), 0);
  EXPECT_TRUE(s.ok());
}

TEST(FxMul, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::mul(q(256 * k_one), q(128 * k_one), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::mul(q(256 * k_one), q(-129 * k_one), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::mul(Q15_16::min(), Q15_16::min(), s3), Q15_16::max());
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  // -32768 * 1 fits exactly, +32768 does not.
  fx::Status s4;
  EXPECT_EQ(fx::mul(q(-256 * k_one), q(128 * k_one), s4), Q15_16::min());
  EXPECT_TRUE(s4.ok());
  EXPECT_EQ(fx::mul(q(-256 * k_one), q(-128 * k_one), s4), Q15_16::max());
  EXPECT_EQ(s4.bits(), only(Flag::overflow));
  fx::Status s5;
  EXPECT_EQ(fx::mul(Q31_32::max(), Q31_32::min(), s5), Q31_32::min());
  EXPECT_EQ(s5.bits(), only(Flag::overflow));
}

// The product's paths (all-32-bit, 32-bit operands into a 64-bit format, one
// operand within a word, 128-bit) against one exact reference: the full
// 128-bit product rounded half away from zero and saturated, written out
// here with the library's 128-bit helpers (no __int128: this test also runs
// on ARM32). A path that rounded or saturated differently fails here.
namespace paths {

namespace w = fx::wide;

struct Raw {
  std::int64_t raw;
  bool overflow;
};

template <typename Storage>
std::int64_t storage_max() {
  return static_cast<std::int64_t>(std::numeric_limits<Storage>::max());
}

/// (negative ? -1 : 1) mag saturated into Storage.
template <typename Storage>
Raw saturate(bool negative, const w::U128& mag) {
  const auto top = static_cast<std::uint64_t>(storage_max<Storage>()) + 1U;
  const w::U128 limit = w::make_u128(negative ? top : (top - 1U));
  if (w::less(limit, mag)) {
    return Raw{negative ? -storage_max<Storage>() - 1 : storage_max<Storage>(), true};
  }
  // mag <= 2^63 here: its negation is exact in two's complement.
  const std::uint64_t m = mag.lo;
  return Raw{negative ? static_cast<std::int64_t>(0U - m) : static_cast<std::int64_t>(m), false};
}

std::uint64_t magnitude(std::int64_t v) { return (v < 0) ? (0U - static_cast<std::uint64_t>(v)) : static_cast<std::uint64_t>(v); }

template <typename Out, typename A, typename B>
Raw reference_mul(A a, B b) {
  const bool negative = (a.raw() < 0) != (b.raw() < 0);
  w::U128 p = w::mul_full(magnitude(a.raw()), magnitude(b.raw()));
  const std::int32_t shift = (A::frac_bits + B::frac_bits) - Out::frac_bits;
  if (shift > 0) {
    p = w::shr(w::add(p, w::shl(w::make_u128(1U), static_cast<std::uint32_t>(shift - 1))), static_cast<std::uint32_t>(shift));
  } else if (shift < 0) {
    const auto up = static_cast<std::uint32_t>(-shift);
    if (!w::is_zero(w::shr(p, 128U - up))) {
      return Raw{negative ? -storage_max<typename Out::storage_type>() - 1 : storage_max<typename Out::storage_type>(),
                 true};
    }
    p = w::shl(p, up);
  }
  return saturate<typename Out::storage_type>(negative && !w::is_zero(p), p);
}

template <typename Out, typename A, typename B>
Raw reference_div(A a, B b) {
  const bool negative = (a.raw() < 0) != (b.raw() < 0);
  const std::int32_t k = (Out::frac_bits + B::frac_bits) - A::frac_bits;
  const w::U128 num = w::shl(w::make_u128(magnitude(a.raw())), static_cast<std::uint32_t>((k > 0) ? k : 0));
  const w::U128 den = w::shl(w::make_u128(magnitude(b.raw())), static_cast<std::uint32_t>((k < 0) ? -k : 0));
  const w::DivMod<w::U128> qr = w::divmod(num, den);
  const bool up = !w::less(qr.remainder, w::sub(den, qr.remainder));
  const w::U128 mag = up ? w::add(qr.quotient, w::make_u128(1U)) : qr.quotient;
  return saturate<typename Out::storage_type>(negative && !w::is_zero(mag), mag);
}

/// Raw values of every bit length, both signs, and the word boundaries.
template <typename Q>
std::vector<Q> operands(std::uint32_t seed) {
  using S = typename Q::storage_type;
  constexpr std::uint32_t kBits = (sizeof(S) == 8U) ? 64U : 32U;
  std::vector<Q> out;
  const std::int64_t edges[] = {0, 1, -1, 0x7FFFFFFF, -0x7FFFFFFF - 1, 0xFFFFFFFFLL, 0x100000000LL, -0x100000000LL,
                                0x100000001LL, std::numeric_limits<std::int64_t>::max(),
                                std::numeric_limits<std::int64_t>::min()};
  for (const std::int64_t e : edges) {
    if ((e >= static_cast<std::int64_t>(std::numeric_limits<S>::min())) && (e <= storage_max<S>())) {
      out.push_back(Q::from_raw(static_cast<S>(e)));
    }
  }
  std::mt19937_64 rng(seed);
  for (std::uint32_t i = 0U; i < 1000U; ++i) {
    const std::uint64_t bits = rng() >> (i % kBits);
    const auto raw = static_cast<S>(static_cast<std::int64_t>(bits >> (64U - kBits)));
    out.push_back(Q::from_raw(raw));
  }
  return out;
}

/// Which operation a comparison checks: a quotient skips a zero divisor,
/// left to FxDiv.ByZeroReportsAndSaturatesBySignOfDividend.
enum class Op { product, quotient };

/// Every pair of the two operand sets (about a million) through the library's
/// operation and the reference: the same raw value and overflow flag.
template <typename Out, typename A, typename B, typename Operation, typename Reference>
void expect_like_the_reference(std::uint32_t seed, Op op, Operation operation, Reference reference) {
  const char* const sign = (op == Op::quotient) ? " / " : " * ";
  const std::vector<A> as = operands<A>(seed);
  const std::vector<B> bs = operands<B>(seed + 1U);
  for (const A a : as) {
    for (const B b : bs) {
      if ((op == Op::quotient) && (b.raw() == 0)) {
        continue;
      }
      fx::Status s;
      const Out got = operation(a, b, s);
      const Raw want = reference(a, b);
      ASSERT_EQ(static_cast<std::int64_t>(got.raw()), want.raw) << a.raw() << sign << b.raw();
      ASSERT_EQ(s.has(Flag::overflow), want.overflow) << a.raw() << sign << b.raw();
    }
  }
}

template <typename Out, typename A, typename B>
void expect_mul_like_the_reference(std::uint32_t seed) {
  expect_like_the_reference<Out, A, B>(
      seed, Op::product, [](A a, B b, fx::Status& s) { return fx::mul<Out>(a, b, s); },
      [](A a, B b) { return reference_mul<Out>(a, b); });
}

template <typename Out, typename A, typename B>
void expect_div_like_the_reference(std::uint32_t seed) {
  expect_like_the_reference<Out, A, B>(
      seed, Op::quotient, [](A a, B b, fx::Status& s) { return fx::div<Out>(a, b, s); },
      [](A a, B b) { return reference_div<Out>(a, b); });
}

using Q7_24 = fx::Q<std::int32_t, 24>;
using Q23_40 = fx::Q<std::int64_t, 40>;
using Q15_48 = fx::Q<std::int64_t, 48>;
using Q23_8 = fx::Q<std::int32_t, 8>;
using Q29_2 = fx::Q<std::int32_t, 2>;
using QInt64 = fx::Q<std::int64_t, 0>;

}  // namespace paths

TEST(FxMul, EveryPathGivesTheExactProductRoundedAndSaturated) {
  using namespace paths;
  expect_mul_like_the_reference<Q31_32, Q31_32, Q31_32>(1U);  // one word, 128-bit
  expect_mul_like_the_reference<Q31_32, Q7_24, Q31_32>(3U);   // one word (the 32-bit operand)
  expect_mul_like_the_reference<Q15_16, Q31_32, Q1_30>(5U);   // one word, into 32 bits
  expect_mul_like_the_reference<Q23_40, Q7_24, Q15_16>(7U);   // 32-bit operands, exact (shift 0)
  expect_mul_like_the_reference<Q15_48, Q7_24, Q7_24>(9U);    // 32-bit operands, rounded
  expect_mul_like_the_reference<Q15_16, Q15_16, Q15_16>(11U); // all 32-bit
  expect_mul_like_the_reference<Q23_40, Q15_16, Q23_8>(13U);  // a left shift (generic path)
  expect_mul_like_the_reference<Q31_32, Q23_40, Q31_32>(15U); // shift 40: no word path
  expect_mul_like_the_reference<Q31_32, Q31_32, QInt64>(17U);  // one word, shift 0 (times an integer)
  expect_mul_like_the_reference<Q31_32, QInt32, Q31_32>(19U);  // the same, the integer on 32 bits
}

/// Both 32-bit forms of a rounded product (the signed product's, the
/// Cortex-M4's and the host's; the magnitudes', ARMv6-M's) against the exact
/// product rounded and saturated in the test, whichever form this core's
/// fx::mul takes: the same raw value and overflow flag.
template <typename Out, typename A, typename B>
void expect_word_products_like_the_reference(std::uint32_t seed) {
  using namespace paths;
  constexpr std::int32_t kShift = (A::frac_bits + B::frac_bits) - Out::frac_bits;
  expect_like_the_reference<Out, A, B>(
      seed, Op::product,
      [](A a, B b, fx::Status& s) { return fx::detail::mul_word_signed<Out, kShift>(a.raw(), b.raw(), s); },
      [](A a, B b) { return reference_mul<Out>(a, b); });
  expect_like_the_reference<Out, A, B>(
      seed + 2U, Op::product,
      [](A a, B b, fx::Status& s) { return fx::detail::mul_word_by_magnitudes<Out, kShift>(a.raw(), b.raw(), s); },
      [](A a, B b) { return reference_mul<Out>(a, b); });
  // Ties of both signs: a b = (2k + 1) 2^(kShift - 1), the operands'
  // random values above being mostly positive.
  constexpr std::int32_t kB = (kShift - 1 < 30) ? (kShift - 1) : 30;
  const B b = B::from_raw(std::int32_t{1} << kB);
  for (std::int32_t k = -2000; k <= 2000; ++k) {
    const A a = A::from_raw(((2 * k) + 1) * (std::int32_t{1} << ((kShift - 1) - kB)));
    const A neg_a = A::from_raw(-a.raw());
    for (const A x : {a, neg_a}) {
      fx::Status s1;
      fx::Status s2;
      const std::int64_t want = reference_mul<Out>(x, b).raw;
      const Out by_signed = fx::detail::mul_word_signed<Out, kShift>(x.raw(), b.raw(), s1);
      const Out by_magnitudes = fx::detail::mul_word_by_magnitudes<Out, kShift>(x.raw(), b.raw(), s2);
      ASSERT_EQ(by_signed.raw(), want) << k;
      ASSERT_EQ(by_magnitudes.raw(), want) << k;
    }
  }
}

TEST(FxMul, BothWordFormsGiveTheExactProductRoundedAndSaturated) {
  using namespace paths;
  expect_word_products_like_the_reference<Q15_16, Q15_16, Q15_16>(21U);  // shift 16
  expect_word_products_like_the_reference<fx::Q<std::int32_t, 25>, fx::Q<std::int32_t, 25>,
                                          fx::Q<std::int32_t, 25>>(23U);  // the statics' Q6.25
  expect_word_products_like_the_reference<Q7_24, Q7_24, fx::Q<std::int32_t, 20>>(25U);  // f I_max
  expect_word_products_like_the_reference<Q29_2, Q7_24, Q7_24>(27U);  // shift 46: beyond 32
  expect_word_products_like_the_reference<Q15_16, Q1_30, Q1_30>(29U);  // shift 44
  // The multiply-accumulate form's ends (round 14): shifts 1 and 31.
  expect_word_products_like_the_reference<fx::Q<std::int32_t, 0>, fx::Q<std::int32_t, 1>, fx::Q<std::int32_t, 0>>(
      31U);
  expect_word_products_like_the_reference<fx::Q<std::int32_t, 0>, Q15_16, fx::Q<std::int32_t, 15>>(33U);
}

/// fx::add and fx::sub on 32-bit storage (detail::add_word, sub_word)
/// against the exact 64-bit sum, saturated in the test, over random values
/// of every length and the edges: the same raw value and overflow flag.
TEST(FxAddSub, WordFormsGiveTheExactSumSaturated) {
  const std::vector<Q15_16> as = paths::operands<Q15_16>(31U);
  const std::vector<Q15_16> bs = paths::operands<Q15_16>(32U);
  const auto saturated = [](std::int64_t v) {
    return std::min<std::int64_t>(std::max<std::int64_t>(v, INT32_MIN), INT32_MAX);
  };
  for (const Q15_16 a : as) {
    for (const Q15_16 b : bs) {
      fx::Status s;
      const std::int64_t sum = static_cast<std::int64_t>(a.raw()) + b.raw();
      ASSERT_EQ(fx::add(a, b, s).raw(), saturated(sum)) << a.raw() << " + " << b.raw();
      ASSERT_EQ(s.has(Flag::overflow), sum != saturated(sum)) << a.raw() << " + " << b.raw();
      fx::Status d;
      const std::int64_t difference = static_cast<std::int64_t>(a.raw()) - b.raw();
      ASSERT_EQ(fx::sub(a, b, d).raw(), saturated(difference)) << a.raw() << " - " << b.raw();
      ASSERT_EQ(d.has(Flag::overflow), difference != saturated(difference)) << a.raw() << " - " << b.raw();
    }
  }
}

// ---------------------------------------------------------------- div

TEST(FxDiv, WorkedExamples) {
  fx::Status s;
  EXPECT_EQ(fx::div(q(k_one), q(3 * k_one), s).raw(), 21845);       // 21845.33
  EXPECT_EQ(fx::div(q(-k_one), q(3 * k_one), s).raw(), -21845);
  EXPECT_EQ(fx::div(q(2 * k_one), q(3 * k_one), s).raw(), 43691);   // 43690.67
  EXPECT_EQ(fx::div(q(2 * k_one), q(-3 * k_one), s).raw(), -43691);
  EXPECT_EQ(fx::div<Q31_32>(q(k_one), q(3 * k_one), s).raw(), 1431655765);  // 2^32 / 3 = 1431655765.33
  EXPECT_EQ(fx::div<QInt32>(Q1_30::from_raw(3 << 28), q(k_one / 4), s).raw(), 3);
  EXPECT_TRUE(s.ok());
}

TEST(FxDiv, TiesRoundAwayFromZeroSymmetrically) {
  fx::Status s;
  EXPECT_EQ(fx::div(q(1), q(2 * k_one), s).raw(), 1);
  EXPECT_EQ(fx::div(q(-1), q(2 * k_one), s).raw(), -1);
  EXPECT_EQ(fx::div(q(1), q(-2 * k_one), s).raw(), -1);
  EXPECT_EQ(fx::div(q(-3), q(2 * k_one), s).raw(), -2);
  EXPECT_TRUE(s.ok());
}

TEST(FxDiv, ByZeroReportsAndSaturatesBySignOfDividend) {
  fx::Status s1;
  EXPECT_EQ(fx::div(q(5), Q15_16::zero(), s1), Q15_16::max());
  EXPECT_EQ(s1.bits(), only(Flag::div_by_zero));
  fx::Status s2;
  EXPECT_EQ(fx::div(q(-5), Q15_16::zero(), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::div_by_zero));
  fx::Status s3;
  EXPECT_EQ(fx::div(Q15_16::zero(), Q15_16::zero(), s3), Q15_16::zero());
  EXPECT_EQ(s3.bits(), only(Flag::div_by_zero));
  fx::Status s4;
  EXPECT_EQ(fx::div<Q31_32>(q(-5), QInt32::zero(), s4), Q31_32::min());
  EXPECT_EQ(s4.bits(), only(Flag::div_by_zero));
}

TEST(FxDiv, OverflowSaturatesInBothDirections) {
  fx::Status s1;
  EXPECT_EQ(fx::div(q(30000 * k_one), q(65), s1), Q15_16::max());  // / 0.001
  EXPECT_EQ(s1.bits(), only(Flag::overflow));
  fx::Status s2;
  EXPECT_EQ(fx::div(q(-30000 * k_one), q(65), s2), Q15_16::min());
  EXPECT_EQ(s2.bits(), only(Flag::overflow));
  fx::Status s3;
  EXPECT_EQ(fx::div(Q15_16::min(), q(-k_one), s3), Q15_16::max());  // -(-32768)
  EXPECT_EQ(s3.bits(), only(Flag::overflow));
  fx::Status s4;
  EXPECT_EQ(fx::div(Q15_16::min(), q(k_one), s4), Q15_16::min());
  EXPECT_TRUE(s4.ok());
  fx::Status s5;
  EXPECT_EQ(fx::div<Q31_32>(Q31_32::max(), Q31_32::lsb(), s5), Q31_32::max());
  EXPECT_EQ(s5.bits(), only(Flag::overflow));
}

TEST(FxDiv, EveryPathGivesTheExactQuotientRoundedAndSaturated) {
  using namespace paths;
  expect_div_like_the_reference<Q31_32, Q7_24, Q7_24>(21U);    // 64-bit: the slip
  expect_div_like_the_reference<Q31_32, Q31_32, Q31_32>(23U);  // 64-bit or 128-bit by size
  expect_div_like_the_reference<Q7_24, Q31_32, Q31_32>(25U);
  expect_div_like_the_reference<Q15_16, Q31_32, Q15_48>(27U);  // k = 32
  expect_div_like_the_reference<QInt32, Q31_32, Q31_32>(29U);  // k = 0
  expect_div_like_the_reference<Q31_32, Q31_32, QInt64>(35U);  // k = 0: by an integer (the acceleration)
  expect_div_like_the_reference<Q29_2, Q23_40, Q23_8>(31U);    // k = -30: the divisor shifted
  expect_div_like_the_reference<Q15_16, Q15_16, Q15_16>(33U);  // all 32-bit
}

// ---------------------------------------------------------------- status

TEST(FxStatus, IsStickyAcrossOperations) {
  fx::Status s;
  const Q15_16 big = fx::add(Q15_16::max(), Q15_16::max(), s);  // overflow
  const Q15_16 fine = fx::add(q(1), q(2), s);                     // clean op
  EXPECT_EQ(fine.raw(), 3);
  EXPECT_EQ(big, Q15_16::max());
  EXPECT_TRUE(s.has(Flag::overflow));
  static_cast<void>(fx::div(fine, Q15_16::zero(), s));
  EXPECT_TRUE(s.has(Flag::overflow));
  EXPECT_TRUE(s.has(Flag::div_by_zero));
  EXPECT_FALSE(s.has(Flag::domain));
  EXPECT_FALSE(s.ok());
  fx::Status other;
  other.raise(Flag::domain);
  s.merge(other);
  EXPECT_EQ(s.bits(), only(Flag::overflow) | only(Flag::div_by_zero) | only(Flag::domain));
  s.clear();
  EXPECT_TRUE(s.ok());
}

}  // namespace
