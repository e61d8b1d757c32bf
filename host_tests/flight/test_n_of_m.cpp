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

// The wheel monitor counts shifted_in's words, whose bit 16 is the sample
// the history drops (and a word may carry any bits above): the count must be
// the 16-bit history's, for every history, newest sample, window and the
// bits above 16 set in turn.
TEST(NOfM, CountBitsOfAShiftedWordIsTheCountOfItsSixteenBitHistory) {
  for (std::uint32_t history = 0U; history <= 0xFFFFU; ++history) {
    for (const bool bit : {false, true}) {
      const std::uint32_t word = n_of_m::shifted_in(static_cast<std::uint16_t>(history), bit);
      const auto kept = static_cast<std::uint16_t>(((history << 1U) | (bit ? 1U : 0U)) & 0xFFFFU);
      ASSERT_EQ(n_of_m::shift_in(static_cast<std::uint16_t>(history), bit), kept) << history;
      ASSERT_EQ(word & 0xFFFFU, kept) << history;
      ASSERT_EQ(word >> 16U, history >> 15U) << history;
      const std::uint32_t high = 1U << (16U + (history % 16U));
      for (std::uint32_t window = 0U; window <= 20U; ++window) {
        const auto w = static_cast<std::uint8_t>(window);
        ASSERT_EQ(n_of_m::count_bits(word, w), counted_one_by_one(kept, window)) << history << " " << window;
        ASSERT_EQ(n_of_m::count_bits(word | high, w), counted_one_by_one(kept, window)) << history << " " << window;
      }
    }
  }
}

TEST(NOfM, ShiftInPutsTheNewestSampleAtBitZeroAndDropsTheOldest) {
  EXPECT_EQ(n_of_m::shift_in(0x8001U, true), 0x0003U);
  EXPECT_EQ(n_of_m::shift_in(0x8001U, false), 0x0002U);
}

}  // namespace
