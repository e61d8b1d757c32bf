// test_n_of_m.cpp: the N-of-M persistence window (flight/src/n_of_m.hpp)
// both monitors count with. count_bits is a branch-free population count of
// the masked window; it must equal counting the newest `window` bits one by
// one, for every 16-bit history and every window (beyond kMaxWindow too).
#include <gtest/gtest.h>

#include <cstdint>

#include "n_of_m.hpp"

namespace {

using sinkwatch::flight::kMaxWindow;
namespace n_of_m = sinkwatch::flight::n_of_m;

std::uint32_t counted_one_by_one(std::uint32_t history, std::uint32_t window) {
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0U; (i < window) && (i < kMaxWindow); ++i) {
    n += (history >> i) & 1U;
  }
  return n;
}

TEST(NOfM, CountBitsEqualsCountingEveryBitOfEveryHistoryAndWindow) {
  for (std::uint32_t history = 0U; history <= 0xFFFFU; ++history) {
    for (std::uint32_t window = 0U; window <= 20U; ++window) {
      ASSERT_EQ(n_of_m::count_bits(static_cast<std::uint16_t>(history), static_cast<std::uint8_t>(window)),
                counted_one_by_one(history, window))
          << history << " " << window;
    }
  }
}

TEST(NOfM, ShiftInPutsTheNewestSampleAtBitZeroAndDropsTheOldest) {
  EXPECT_EQ(n_of_m::shift_in(0x8001U, true), 0x0003U);
  EXPECT_EQ(n_of_m::shift_in(0x8001U, false), 0x0002U);
}

}  // namespace
