// test_sqrt_paths.cpp: fx::sqrt's 64-bit path (radicand below 2^64) gives
// the bits of the former always-128-bit implementation, kept here verbatim as
// the oracle. Every raw value below 2^20, every power of two and its
// neighbours, and 500,000 random values per format pair; with
// SINKWATCH_SQRT_EXHAUSTIVE=1 in the environment, every non-negative int32
// input of Q15.16 and Q1.30 into themselves as well (docs/performance.md records that run).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"

namespace {

namespace fx = sinkwatch::fx;
namespace wide = sinkwatch::fx::wide;

/// The implementation before issue 10: the radicand always in 128 bits.
template <typename Out, typename S, std::int32_t F>
Out old_sqrt(fx::Q<S, F> a, fx::Status& status) {
  using OutS = typename Out::storage_type;
  using W = wide::U128;
  if (a.raw() < 0) {
    status.raise(fx::Flag::domain);
    return Out::zero();
  }
  bool overflowed = false;
  const W radicand = fx::detail::scale_magnitude(wide::from_u64<W>(fx::detail::magnitude(a.raw())),
                                                 F - (2 * Out::frac_bits), overflowed);
  if (overflowed) {
    status.raise(fx::Flag::overflow);
    return Out::max();
  }
  const W root = fx::detail::isqrt_floor(radicand);
  const W r_sq = wide::mul_full(wide::low_u64(root), wide::low_u64(root));
  const W excess = wide::sub(radicand, r_sq);
  const W rounded = wide::less(root, excess) ? wide::add(root, wide::from_u64<W>(1U)) : root;
  return Out::from_raw(fx::detail::from_sign_magnitude<OutS>(false, rounded, status));
}

/// Empty when the new and the old sqrt agree on `raw` (value and flags).
template <typename Out, typename In>
bool same(typename In::storage_type raw) {
  fx::Status s_new;
  fx::Status s_old;
  const Out a = fx::sqrt<Out>(In::from_raw(raw), s_new);
  const Out b = old_sqrt<Out>(In::from_raw(raw), s_old);
  return (a == b) && (s_new.bits() == s_old.bits());
}

template <typename Out, typename In>
void compare_pair() {
  using S = typename In::storage_type;
  std::uint64_t mismatches = 0U;
  for (S raw = 0; raw < (S{1} << 20); ++raw) {
    mismatches += same<Out, In>(raw) ? 0U : 1U;
  }
  constexpr std::uint32_t bits = In::total_bits - 1U;
  for (std::uint32_t k = 0U; k < bits; ++k) {
    const S p = static_cast<S>(std::uint64_t{1} << k);
    mismatches += same<Out, In>(p) ? 0U : 1U;
    mismatches += same<Out, In>(static_cast<S>(p - 1)) ? 0U : 1U;
    mismatches += same<Out, In>(static_cast<S>(p + 1)) ? 0U : 1U;
  }
  mismatches += same<Out, In>(std::numeric_limits<S>::max()) ? 0U : 1U;
  mismatches += same<Out, In>(std::numeric_limits<S>::min()) ? 0U : 1U;
  mismatches += same<Out, In>(S{-1}) ? 0U : 1U;
  std::mt19937_64 rng(0x5157u + bits);
  for (int i = 0; i < 500000; ++i) {
    // A random magnitude at a random scale, so that every bit length occurs.
    const std::uint32_t len = static_cast<std::uint32_t>(rng() % bits) + 1U;
    const std::uint64_t v = rng() >> (64U - len);
    mismatches += same<Out, In>(static_cast<S>(v)) ? 0U : 1U;
  }
  EXPECT_EQ(mismatches, 0U);
}

template <typename Out, typename In>
void compare_exhaustive32() {
  std::uint64_t mismatches = 0U;
  for (std::int64_t raw = 0; raw <= std::numeric_limits<std::int32_t>::max(); ++raw) {
    mismatches += same<Out, In>(static_cast<std::int32_t>(raw)) ? 0U : 1U;
  }
  EXPECT_EQ(mismatches, 0U);
}

bool exhaustive() {
  const char* e = std::getenv("SINKWATCH_SQRT_EXHAUSTIVE");
  return (e != nullptr) && (e[0] == '1');
}

using fx::Q15_16;
using fx::Q1_30;
using fx::Q31_32;
using fx::Q3_28;
using Q24 = fx::Q<std::int32_t, 24>;
using Q0 = fx::Q<std::int32_t, 0>;
using Q62 = fx::Q<std::int64_t, 62>;
using Q16w = fx::Q<std::int64_t, 16>;

TEST(FxSqrtPaths, ThirtyTwoBitFormatsMatchTheOldImplementation) {
  compare_pair<Q15_16, Q15_16>();
  compare_pair<Q1_30, Q1_30>();
  compare_pair<Q3_28, Q3_28>();
  compare_pair<Q24, Q24>();
  compare_pair<Q0, Q0>();
  compare_pair<Q1_30, Q15_16>();  // radicand raw * 2^44: both paths
  compare_pair<Q31_32, Q15_16>();  // radicand raw * 2^48: both paths
}

TEST(FxSqrtPaths, SixtyFourBitFormatsMatchTheOldImplementation) {
  compare_pair<Q31_32, Q31_32>();  // radicand raw * 2^32: both paths
  compare_pair<Q15_16, Q31_32>();  // radicand raw * 2^0: always 64 bits
  compare_pair<Q62, Q62>();        // radicand raw * 2^62: both paths
  compare_pair<Q16w, Q16w>();
}

TEST(FxSqrtPaths, EveryInt32InputWhenAskedQ15_16) {
  if (!exhaustive()) {
    GTEST_SKIP() << "set SINKWATCH_SQRT_EXHAUSTIVE=1 for the exhaustive run";
  }
  compare_exhaustive32<Q15_16, Q15_16>();
}

TEST(FxSqrtPaths, EveryInt32InputWhenAskedQ1_30) {
  if (!exhaustive()) {
    GTEST_SKIP() << "set SINKWATCH_SQRT_EXHAUSTIVE=1 for the exhaustive run";
  }
  compare_exhaustive32<Q1_30, Q1_30>();
}

}  // namespace
