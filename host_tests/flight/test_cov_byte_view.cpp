// test_cov_byte_view.cpp: the bounded byte windows (byte_view.hpp) at and past
// their ends, and over a null pointer: reads past the end give 0, writes past
// the end are refused and touch nothing, a null buffer is an empty window.
// The codecs only index inside the size they checked, so these paths are
// reached here and nowhere else (docs/coverage.md).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "sinkwatch/flight/byte_view.hpp"

namespace {

using sinkwatch::flight::ByteView;
using sinkwatch::flight::MutableByteView;

// A null pointer the compiler cannot see through: with a constant argument
// the constexpr constructors would be evaluated at compile time, and the
// null check never run.
std::uint8_t* opaque_null() {
  static volatile int zero = 0;
  static std::uint8_t byte = 0U;
  return (zero == 0) ? nullptr : &byte;
}

TEST(ByteView, ReadsInsideAndGivesZeroPastTheEnd) {
  const std::array<std::uint8_t, 3> bytes{0x11U, 0x22U, 0x33U};
  const ByteView v(bytes.data(), bytes.size());
  EXPECT_EQ(v.size(), 3U);
  EXPECT_EQ(v.at(0), 0x11U);
  EXPECT_EQ(v.at(2), 0x33U);
  EXPECT_EQ(v.at(3), 0U);
  EXPECT_EQ(v.at(1000), 0U);
}

TEST(ByteView, NullDataIsAnEmptyWindowWhateverTheSize) {
  const ByteView v(opaque_null(), 64U);
  EXPECT_EQ(v.size(), 0U);
  EXPECT_EQ(v.at(0), 0U);
}

TEST(MutableByteView, WritesInsideAndRefusesPastTheEnd) {
  std::array<std::uint8_t, 4> bytes{0U, 0U, 0U, 0xEEU};
  MutableByteView v(bytes.data(), 3U);  // the last byte is outside the window
  EXPECT_TRUE(v.set(0, 0xAAU));
  EXPECT_TRUE(v.set(2, 0xBBU));
  EXPECT_FALSE(v.set(3, 0xCCU));
  EXPECT_EQ(bytes[0], 0xAAU);
  EXPECT_EQ(bytes[2], 0xBBU);
  EXPECT_EQ(bytes[3], 0xEEU);  // untouched
}

TEST(MutableByteView, NullDataRefusesEveryWrite) {
  MutableByteView v(opaque_null(), 16U);
  EXPECT_EQ(v.size(), 0U);
  EXPECT_FALSE(v.set(0, 1U));
}

}  // namespace
