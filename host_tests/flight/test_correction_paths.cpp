// corrections_at against the Q31.32 chain it was written as before issue 10
// (oracle::corrections_at, dividing_oracle.hpp): the interpolation's 64-bit
// form and the prepared divisors must give the same bits and statuses on
// random tables over the whole Q7.24 range of the coefficients (not only the
// validated one) and random loads, and on the shipped tables over every load
// step.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "dividing_oracle.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace {

using flight::CorrectionResult;
using flight::CorrectionTable;
using flight::Ratio;
using flight::WheelLoadN;

void expect_same(const CorrectionResult& a, const CorrectionResult& b) {
  ASSERT_EQ(a.status, b.status);
  if (a.status == flight::EstimateStatus::ok) {
    ASSERT_EQ(a.coefficients.c1, b.coefficients.c1);
    ASSERT_EQ(a.coefficients.c2, b.coefficients.c2);
    ASSERT_EQ(a.coefficients.c3, b.coefficients.c3);
    ASSERT_EQ(a.dp_max_ratio, b.dp_max_ratio);
  }
}

TEST(CorrectionPaths, RandomTablesOverTheWholeFormatMatchTheQ3132Chain) {
  std::mt19937_64 rng(31U);
  std::uint32_t segments = 0U;
  for (int k = 0; k < 20000; ++k) {
    CorrectionTable t{};
    t.count = static_cast<std::uint8_t>(2U + (rng() % (flight::kMaxCorrectionRows - 1U)));
    std::int32_t load = static_cast<std::int32_t>(rng() % (1U << 20U)) + 1;
    for (std::uint8_t i = 0U; i < t.count; ++i) {
      t.rows[i].load_n = WheelLoadN::from_raw(load);
      // Widths from 1 LSB to 2^27 raw; coefficients anywhere in Q7.24.
      load += static_cast<std::int32_t>((rng() >> (37U + (rng() % 27U))) + 1U);
      t.rows[i].c1 = Ratio::from_raw(static_cast<std::int32_t>(rng()));
      t.rows[i].c2 = Ratio::from_raw(static_cast<std::int32_t>(rng() >> (rng() % 32U)));
      t.rows[i].c3 = Ratio::from_raw(-static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U))));
      t.rows[i].dp_max_ratio = Ratio::from_raw(static_cast<std::int32_t>(rng() >> 40U));
    }
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    const std::int32_t first = t.rows[0].load_n.raw();
    const std::int32_t span = t.rows[t.count - 1U].load_n.raw() - first;
    for (int j = 0; j < 20; ++j) {
      const WheelLoadN w = WheelLoadN::from_raw(first + static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(span)));
      const CorrectionResult expected = oracle::corrections_at(t, w);
      ASSERT_EQ(expected.clamp, flight::LoadClamp::none);  // inside a segment
      ++segments;
      expect_same(flight::corrections_at(t, divisors, w), expected);
    }
  }
  EXPECT_EQ(segments, 400000U);
}

// The interpolated value crosses zero where a and b differ in sign; there
// the 32-bit form rounds back towards a instead of away from it, and its
// ties (a step of an odd number of half Q7.24 LSB) sit within one raw load
// of the crossing. Every load of two-row tables around it, both directions.
TEST(CorrectionPaths, ValuesCrossingZeroRoundLikeTheQ3132Chain) {
  std::mt19937_64 rng(7U);
  for (int k = 0; k < 2000; ++k) {
    CorrectionTable t{};
    t.count = 2U;
    const std::int32_t width = static_cast<std::int32_t>(1U + (rng() % 4000U));
    t.rows[0].load_n = WheelLoadN::from_raw(1000);
    t.rows[1].load_n = WheelLoadN::from_raw(1000 + width);
    const auto a = static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U)));
    const auto b = static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U)));
    const bool falling = (k % 2) == 0;
    for (flight::CorrectionRow& row : t.rows) {
      row.c1 = Ratio::from_raw(0);
      row.c2 = Ratio::from_raw(0);
      row.c3 = Ratio::from_raw(0);
      row.dp_max_ratio = Ratio::from_raw(0);
    }
    t.rows[0].c1 = Ratio::from_raw(falling ? a : -a);
    t.rows[1].c1 = Ratio::from_raw(falling ? -b : b);
    t.rows[0].c3 = Ratio::from_raw(falling ? -a : a);
    t.rows[1].c3 = Ratio::from_raw(falling ? b : -b);
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    for (std::int32_t raw = 1000; raw < 1000 + width; ++raw) {
      const CorrectionResult expected = oracle::corrections_at(t, WheelLoadN::from_raw(raw));
      expect_same(flight::corrections_at(t, divisors, WheelLoadN::from_raw(raw)), expected);
    }
  }
}

// The fraction's remainder correction (correction.cpp, fraction_of) is
// needed most where the offset is close to the width (the estimate is then
// up to two below the quotient): two-row tables of every width length, each
// loaded at its segment's start, middle and last raw loads, with one
// coefficient spanning the whole Q7.24 range, so that one unit of the Q0.32
// fraction moves the interpolated value by about one LSB.
TEST(CorrectionPaths, LoadsAtTheSegmentEndsMatchTheQ3132Chain) {
  std::mt19937_64 rng(19U);
  std::uint32_t checked = 0U;
  for (int k = 0; k < 20000; ++k) {
    CorrectionTable t{};
    t.count = 2U;
    const std::uint32_t length = 1U + static_cast<std::uint32_t>(k % 31);  // widths of 1 to 31 bits
    const std::uint32_t width = (static_cast<std::uint32_t>(rng()) >> (32U - length)) | (1U << (length - 1U));
    const std::uint32_t start = 1U + static_cast<std::uint32_t>(rng() % (0x7FFFFFFFU - width));
    t.rows[0].load_n = WheelLoadN::from_raw(static_cast<std::int32_t>(start));
    t.rows[1].load_n = WheelLoadN::from_raw(static_cast<std::int32_t>(start + width));
    const bool rising = (k % 2) == 0;
    t.rows[0].c1 = Ratio::from_raw(rising ? INT32_MIN : INT32_MAX);
    t.rows[1].c1 = Ratio::from_raw(rising ? INT32_MAX : INT32_MIN);
    for (flight::CorrectionRow& row : t.rows) {
      row.c2 = Ratio::from_raw(static_cast<std::int32_t>(rng()));
      row.c3 = Ratio::from_raw(static_cast<std::int32_t>(rng()) >> (rng() % 32U));
      row.dp_max_ratio = Ratio::from_raw(static_cast<std::int32_t>(rng() >> 40U));
    }
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    const std::uint32_t offsets[] = {0U, 1U, 2U, width / 2U, (width / 2U) + 1U, width - 3U, width - 2U, width - 1U};
    for (const std::uint32_t offset : offsets) {
      if (offset >= width) {
        continue;  // a narrow segment has fewer distinct loads
      }
      const WheelLoadN w = WheelLoadN::from_raw(static_cast<std::int32_t>(start + offset));
      const CorrectionResult expected = oracle::corrections_at(t, w);
      ASSERT_EQ(expected.clamp, flight::LoadClamp::none);
      expect_same(flight::corrections_at(t, divisors, w), expected);
      ++checked;
    }
  }
  EXPECT_GT(checked, 140000U);
}

TEST(CorrectionPaths, ShippedTablesAtEveryLoadStepMatchTheQ3132Chain) {
  for (const flight::ParameterTable& table : {flight::default_parameter_table(), flight::eq15_parameter_table()}) {
    const CorrectionTable& t = table.correction;
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    for (std::int32_t raw = t.rows[0].load_n.raw(); raw < t.rows[t.count - 1U].load_n.raw(); raw += 61) {
      const CorrectionResult expected = oracle::corrections_at(t, WheelLoadN::from_raw(raw));
      ASSERT_EQ(expected.clamp, flight::LoadClamp::none);
      expect_same(flight::corrections_at(t, divisors, WheelLoadN::from_raw(raw)), expected);
    }
  }
}

}  // namespace
}  // namespace sinkwatch
