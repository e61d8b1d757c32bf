// test_cov_constant_divisor.cpp: div_by_constant (constant_divisor.hpp) for
// one format triple only, Q31.32 / Q15.16 -> Q1.30 (dividend scaled by 2^14),
// against fx::div bit for bit and flag for flag: a zero divisor, dividends
// too wide for the 64-bit path (the fx::div fallback), both signs, a
// negative quotient that rounds to zero, and a deterministic sweep. One
// instantiation per translation unit on purpose: gcov reports a template's
// branches only where it is instantiated once (docs/coverage.md).
#include <gtest/gtest.h>

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/flight/constant_divisor.hpp"

namespace {

namespace fx = sinkwatch::fx;
using sinkwatch::flight::div_by_constant;
using sinkwatch::flight::make_divisor;
using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;

struct Both {
  Q1_30 plain;
  fx::Status plain_status;
  Q1_30 prepared;
  fx::Status prepared_status;
};

Both divide(std::int64_t a_raw, std::int32_t b_raw) {
  Both r{};
  const Q31_32 a = Q31_32::from_raw(a_raw);
  const Q15_16 b = Q15_16::from_raw(b_raw);
  r.plain = fx::div<Q1_30>(a, b, r.plain_status);
  r.prepared = div_by_constant<Q1_30>(a, make_divisor(b), r.prepared_status);
  return r;
}

#define EXPECT_SAME_DIVISION(a_raw, b_raw)                                         \
  do {                                                                             \
    const Both r_ = divide((a_raw), (b_raw));                                      \
    EXPECT_EQ(r_.prepared.raw(), r_.plain.raw()) << (a_raw) << " / " << (b_raw);   \
    EXPECT_EQ(r_.prepared_status.bits(), r_.plain_status.bits()) << (a_raw) << " / " << (b_raw); \
  } while (0)

TEST(DivByConstantQ31_32ByQ15_16, ZeroDivisorGivesFxDivsAnswerAndFlag) {
  const Both r = divide(std::int64_t{3} << 32, 0);
  EXPECT_TRUE(r.prepared_status.has(fx::Flag::div_by_zero));
  EXPECT_EQ(r.prepared, Q1_30::max());
  EXPECT_SAME_DIVISION(std::int64_t{3} << 32, 0);
  EXPECT_SAME_DIVISION(-(std::int64_t{3} << 32), 0);
  EXPECT_SAME_DIVISION(0, 0);
}

TEST(DivByConstantQ31_32ByQ15_16, DividendTooWideForThe64BitPathFallsBackToFxDiv) {
  // |a| >= 2^50 raw: shifted by 2^14 it no longer fits 64 bits.
  EXPECT_SAME_DIVISION(std::int64_t{1} << 50, 1 << 30);
  EXPECT_SAME_DIVISION(-(std::int64_t{1} << 55), 0x7FFFFFFF);
  EXPECT_SAME_DIVISION(INT64_MIN, -1);
  const Both r = divide(std::int64_t{1} << 52, 1 << 30);  // 2^20 / 2^14 = 64: beyond Q1.30
  EXPECT_TRUE(r.prepared_status.has(fx::Flag::overflow));
}

TEST(DivByConstantQ31_32ByQ15_16, SignsAndRoundingMatchFxDiv) {
  const Both third = divide(std::int64_t{1} << 32, 3 << 16);  // 1/3
  EXPECT_EQ(third.prepared.raw(), 357913941);  // round(2^30 / 3)
  EXPECT_TRUE(third.prepared_status.ok());
  EXPECT_SAME_DIVISION(std::int64_t{1} << 32, 3 << 16);
  EXPECT_SAME_DIVISION(-(std::int64_t{1} << 32), 3 << 16);
  EXPECT_SAME_DIVISION(std::int64_t{1} << 32, -(3 << 16));
  EXPECT_SAME_DIVISION(-(std::int64_t{1} << 32), -(3 << 16));
  // -2^-32 / 32767: rounds to zero, which must come back as +0, not -0.
  const Both tiny = divide(-1, 0x7FFFFFFF);
  EXPECT_EQ(tiny.prepared.raw(), 0);
  EXPECT_SAME_DIVISION(-1, 0x7FFFFFFF);
}

TEST(DivByConstantQ31_32ByQ15_16, DeterministicSweepMatchesFxDiv) {
  // A 64-bit LCG (Knuth's MMIX constants): operands of every bit length.
  std::uint64_t x = 0x9E3779B97F4A7C15ULL;
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    x = (x * 6364136223846793005ULL) + 1442695040888963407ULL;
    const std::uint32_t a_len = static_cast<std::uint32_t>(x >> 58);          // 0..63
    const std::uint32_t b_len = static_cast<std::uint32_t>((x >> 53) & 31U);  // 0..31
    const std::uint64_t a_mag = (a_len == 0U) ? 0U : (x >> (64U - a_len));
    const std::uint64_t b_mag = (b_len == 0U) ? 1U : ((x * 0x2545F4914F6CDD1DULL) >> (64U - b_len));
    const auto a = static_cast<std::int64_t>(a_mag) * (((x >> 7) & 1U) != 0U ? -1 : 1);
    const auto b = static_cast<std::int32_t>(b_mag) * (((x >> 9) & 1U) != 0U ? -1 : 1);
    const Both r = divide(a, b);
    ASSERT_EQ(r.prepared.raw(), r.plain.raw()) << a << " / " << b;
    ASSERT_EQ(r.prepared_status.bits(), r.plain_status.bits()) << a << " / " << b;
    ++checked;
  }
  EXPECT_EQ(checked, 20000);
}

}  // namespace
