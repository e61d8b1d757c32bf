// corrections_at against the Q31.32 chain it was written as before issue 10
// (oracle::corrections_at, dividing_oracle.hpp): the interpolation's 64-bit
// form and the prepared divisors must give the same bits and statuses on
// random tables over the whole Q7.24 range of the coefficients (not only the
// validated one) and random loads, and on the shipped tables over every load
// step.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
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

// The products of detail::interpolate_raw and of the fraction as the words
// they read (since session 19 both from fx::wide::mul_32x32_64, whose
// ARMv6-M columns test_wide_mul checks): the high word, bits 16..31 and
// the low word, on random fractions and spans and on the extremes of both.
TEST(CorrectionPaths, ProductTopAndWordsAreTheWideProduct) {
  std::mt19937_64 rng(23U);
  const std::uint32_t edges[] = {0U, 1U, 0xFFFFU, 0x10000U, 0x7FFFFFFFU, 0x80000000U, 0xFFFF0000U, 0xFFFFFFFEU,
                                 0xFFFFFFFFU};
  const auto check = [](std::uint32_t f, std::uint32_t s) {
    const std::uint64_t p = std::uint64_t{f} * std::uint64_t{s};
    const flight::detail::ProductTop top = flight::detail::product_top(flight::detail::halves_of(f), s);
    ASSERT_EQ(top.high, static_cast<std::uint32_t>(p >> 32U)) << f << " " << s;
    ASSERT_EQ(top.bits16, static_cast<std::uint32_t>((p >> 16U) & 0xFFFFU)) << f << " " << s;
    const flight::detail::ProductWords words = flight::detail::product_words(f, s);
    ASSERT_EQ(words.high, static_cast<std::uint32_t>(p >> 32U)) << f << " " << s;
    ASSERT_EQ(words.low, static_cast<std::uint32_t>(p)) << f << " " << s;
  };
  for (const std::uint32_t f : edges) {
    for (const std::uint32_t s : edges) {
      check(f, s);
    }
  }
  for (int k = 0; k < 2000000; ++k) {
    const auto f = static_cast<std::uint32_t>(rng() >> (rng() % 33U));
    const auto s = static_cast<std::uint32_t>(rng() >> (rng() % 33U));
    check(f, s);
  }
}

/// The exact reference of interpolate_raw: the Q31.32 chain's two roundings
/// (the step f |b - a| / 2^24 half up, then the value a 2^8 +- step into
/// Q7.24 half away from zero), on 64-bit integers that hold them exactly:
/// f |b - a| <= (2^32 - 1)^2 leaves room for the half, |a 2^8 +- step| < 2^41.
std::int32_t interpolation_reference(std::int32_t a, std::int32_t b, std::uint32_t f) {
  const std::int64_t d = std::int64_t{b} - a;
  const auto d_mag = static_cast<std::uint64_t>((d < 0) ? -d : d);
  const auto m = static_cast<std::int64_t>(((d_mag * f) + (1ULL << 23U)) >> 24U);
  const std::int64_t v = (std::int64_t{a} * 256) + ((d < 0) ? -m : m);
  const std::int64_t r = (((v < 0) ? -v : v) + 128) >> 8U;
  return static_cast<std::int32_t>((v < 0) ? -r : r);
}

/// The form interpolate_raw replaced (session 18's lerp): the 64-bit product
/// and the high word of its biased sum.
std::int32_t interpolation_64(std::int32_t a, std::int32_t b, std::uint32_t f) {
  const auto a_mag = static_cast<std::uint32_t>((a < 0) ? -static_cast<std::int64_t>(a) : a);
  const bool falling = b < a;
  const std::uint32_t span = falling ? (static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b))
                                     : (static_cast<std::uint32_t>(b) - static_cast<std::uint32_t>(a));
  const std::uint64_t p = std::uint64_t{f} * span;
  const bool against = falling ? (a > 0) : (a < 0);
  const bool crossed = against && (static_cast<std::uint32_t>(p >> 32U) < a_mag);
  const std::uint64_t bias = crossed ? ((1ULL << 31U) - (1ULL << 23U)) : ((1ULL << 31U) + (1ULL << 23U));
  const auto step = static_cast<std::int64_t>((p + bias) >> 32U);
  return static_cast<std::int32_t>(falling ? (std::int64_t{a} - step) : (std::int64_t{a} + step));
}

// interpolate_raw against both, on random ends of every magnitude and sign,
// random fractions, the extremes of the format and fractions near the
// crossings' ties (P's low word near 2^31 +- 2^23 and its high word at |a|).
TEST(CorrectionPaths, InterpolationIsTheWideFormAndTheExactChain) {
  std::mt19937_64 rng(29U);
  const std::int32_t ends[] = {INT32_MIN, INT32_MIN + 1, -(1 << 24), -1, 0, 1, 1 << 24, INT32_MAX - 1, INT32_MAX};
  const std::uint32_t fractions[] = {0U, 1U, 0x7FFFFFFFU, 0x80000000U, 0x80800000U, 0x7F800000U, 0xFFFFFFFFU};
  const auto check = [](std::int32_t a, std::int32_t b, std::uint32_t f) {
    const std::int32_t got = flight::detail::interpolate_raw(a, b, flight::detail::halves_of(f));
    ASSERT_EQ(got, interpolation_64(a, b, f)) << a << " " << b << " " << f;
    ASSERT_EQ(got, interpolation_reference(a, b, f)) << a << " " << b << " " << f;
  };
  for (const std::int32_t a : ends) {
    for (const std::int32_t b : ends) {
      for (const std::uint32_t f : fractions) {
        check(a, b, f);
      }
    }
  }
  for (int k = 0; k < 2000000; ++k) {
    const auto a = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng())) >> (rng() % 32U);
    const auto b = static_cast<std::int32_t>(static_cast<std::uint32_t>(rng())) >> (rng() % 32U);
    check(a, b, static_cast<std::uint32_t>(rng()));
    // A fraction putting the step's rounding next to a tie and the value
    // next to zero: f |d| close to |a| 2^32 + 2^31 +- 2^23.
    const std::uint64_t span = (b < a) ? (std::uint64_t{static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b)})
                                       : (std::uint64_t{static_cast<std::uint32_t>(b) - static_cast<std::uint32_t>(a)});
    const std::uint64_t a_mag = (a < 0) ? (0U - static_cast<std::uint64_t>(static_cast<std::int64_t>(a))) : static_cast<std::uint64_t>(a);
    if ((span != 0U) && (a_mag < span)) {
      // Below 2^64: a_mag < span < 2^32.
      const std::uint64_t target = (a_mag << 32U) + (1ULL << 31U) +
                                   (((k % 2) == 0) ? (1ULL << 23U) : (0ULL - (1ULL << 23U)));
      const auto f0 = static_cast<std::uint64_t>(target / span);
      for (std::uint64_t f = (f0 > 2U) ? (f0 - 2U) : 0U; (f <= f0 + 2U) && (f <= 0xFFFFFFFFU); ++f) {
        check(a, b, static_cast<std::uint32_t>(f));
      }
    }
  }
}


// The six-load form the step calls (round 14): every wheel's result, clamp
// included, is the oracle's for its load, whatever the others are (a
// refused load among them, loads below, inside and above the table, a row
// count the table cannot have), and it returns true exactly when all six
// are ok.
TEST(CorrectionPaths, SixLoadsInOneCallAreEachLoadsOwnResult) {
  std::mt19937_64 rng(59U);
  int failed_batches = 0;
  int ok_batches = 0;
  for (int k = 0; k < 20000; ++k) {
    CorrectionTable t{};
    const std::uint64_t shape = rng() % 16U;
    t.count = static_cast<std::uint8_t>((shape == 0U) ? 0U : ((shape == 1U) ? 9U : (1U + (rng() % 8U))));
    std::int32_t load = static_cast<std::int32_t>(rng() % (1U << 20U)) + 1;
    for (std::uint8_t i = 0U; i < flight::kMaxCorrectionRows; ++i) {
      t.rows[i].load_n = WheelLoadN::from_raw(load);
      // Mostly increasing; now and then a step back (a table validate() refuses).
      const std::int32_t step = static_cast<std::int32_t>((rng() >> (37U + (rng() % 27U))) + 1U);
      load += ((rng() % 32U) == 0U) ? -step : step;
      t.rows[i].c1 = Ratio::from_raw(static_cast<std::int32_t>(rng()));
      t.rows[i].c2 = Ratio::from_raw(static_cast<std::int32_t>(rng() >> (rng() % 32U)));
      t.rows[i].c3 = Ratio::from_raw(-static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U))));
      t.rows[i].dp_max_ratio = Ratio::from_raw(static_cast<std::int32_t>(rng() >> 40U));
    }
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    const std::int64_t first = t.rows[0].load_n.raw();
    WheelLoadN loads[flight::limits::kWheelCount]{};
    for (WheelLoadN& w : loads) {
      const std::uint64_t pick = rng() % 64U;
      const std::int64_t raw = (pick == 0U) ? -static_cast<std::int64_t>(rng() % 1000U)  // not positive
                                            : (first - 4096 + static_cast<std::int64_t>(rng() % (1U << 28U)));
      w = WheelLoadN::from_raw(static_cast<std::int32_t>(std::max<std::int64_t>(raw, INT32_MIN)));
    }
    CorrectionResult out[flight::limits::kWheelCount]{};
    const bool all_ok = flight::corrections_at(t, divisors, loads, out);
    bool every_ok = true;
    for (std::uint32_t i = 0U; i < flight::limits::kWheelCount; ++i) {
      const CorrectionResult expected = oracle::corrections_at(t, loads[i]);
      expect_same(out[i], expected);
      ASSERT_EQ(out[i].clamp, expected.clamp);
      every_ok = every_ok && (expected.status == flight::EstimateStatus::ok);
    }
    ASSERT_EQ(all_ok, every_ok);
    (every_ok ? ok_batches : failed_batches) += 1;
  }
  EXPECT_GT(ok_batches, 1000);
  EXPECT_GT(failed_batches, 1000);
}

// The six-load form's first-segment shortcut (round 15) against the
// oracle, where it must not be taken as well as where it is: a first
// breakpoint at or below zero, a second one not above the first or above
// the last, a one-row table whose second row lies above the first, loads at
// and next to W_0, W_1 and W_last, at zero and at the format's ends.
TEST(CorrectionPaths, FirstSegmentShortcutIsCorrectionOfForEveryTable) {
  std::mt19937_64 rng(83U);
  int shortcut_loads = 0;
  for (int k = 0; k < 20000; ++k) {
    CorrectionTable t{};
    const std::uint64_t shape = rng() % 6U;
    t.count = static_cast<std::uint8_t>((shape == 0U) ? 1U : (2U + (rng() % 7U)));
    std::int32_t load = (shape == 1U) ? -static_cast<std::int32_t>(rng() % 4096U)
                                      : static_cast<std::int32_t>(rng() % (1U << 20U)) + 1;
    for (std::uint8_t i = 0U; i < flight::kMaxCorrectionRows; ++i) {
      t.rows[i].load_n = WheelLoadN::from_raw(load);
      const std::int32_t step = static_cast<std::int32_t>((rng() >> (37U + (rng() % 27U))) + 1U);
      // shape 2: the second breakpoint not above the first; shape 3: the
      // last one below the second (a step back after it).
      const bool back = ((shape == 2U) && (i == 0U)) || ((shape == 3U) && (i > 0U) && ((i + 1U) == t.count - 1U));
      load += back ? -(step + static_cast<std::int32_t>(rng() % 2U) * (load - t.rows[0].load_n.raw())) : step;
      t.rows[i].c1 = Ratio::from_raw(static_cast<std::int32_t>(rng()));
      t.rows[i].c2 = Ratio::from_raw(static_cast<std::int32_t>(rng() >> (rng() % 32U)));
      t.rows[i].c3 = Ratio::from_raw(-static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U))));
      t.rows[i].dp_max_ratio = Ratio::from_raw(static_cast<std::int32_t>(rng() >> 40U));
    }
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(t);
    const std::int64_t w0 = t.rows[0].load_n.raw();
    const std::int64_t w1 = t.rows[1].load_n.raw();
    const std::int64_t wl = t.rows[t.count - 1U].load_n.raw();
    const std::int64_t picks[] = {w0 - 1, w0, w0 + 1, w1 - 1, w1, w1 + 1, wl - 1, wl, wl + 1, 0, -1, 1,
                                  INT32_MIN, INT32_MAX, w0 + static_cast<std::int64_t>(rng() % 4096U)};
    WheelLoadN loads[flight::limits::kWheelCount]{};
    for (std::size_t j = 0U; j < sizeof(picks) / sizeof(picks[0]); ++j) {
      loads[j % 6U] = WheelLoadN::from_raw(static_cast<std::int32_t>(std::clamp<std::int64_t>(picks[j], INT32_MIN, INT32_MAX)));
      if ((j % 6U) != 5U) continue;
      CorrectionResult out[flight::limits::kWheelCount]{};
      static_cast<void>(flight::corrections_at(t, divisors, loads, out));
      for (std::uint32_t i = 0U; i < flight::limits::kWheelCount; ++i) {
        const CorrectionResult expected = oracle::corrections_at(t, loads[i]);
        expect_same(out[i], expected);
        ASSERT_EQ(out[i].clamp, expected.clamp) << k;
        const std::int64_t w = loads[i].raw();
        shortcut_loads += ((t.count > 1U) && (w0 > 0) && (w0 <= w) && (w < w1) && (w1 <= wl)) ? 1 : 0;
      }
    }
  }
  EXPECT_GT(shortcut_loads, 10000);
}

// Divisors whose first width is narrower than the table's first segment
// (not made from this table): a load beyond that width is refused, as
// correction_of's width test refuses it, and one below it is interpolated
// at that width, as the oracle does for a table whose second breakpoint is
// W_0 plus it.
TEST(CorrectionPaths, FirstSegmentShortcutKeepsTheDivisorsWidthTest) {
  std::mt19937_64 rng(89U);
  for (int k = 0; k < 5000; ++k) {
    CorrectionTable t{};
    t.count = static_cast<std::uint8_t>(3U + (rng() % 6U));
    std::int32_t load = static_cast<std::int32_t>(rng() % (1U << 20U)) + 1;
    for (std::uint8_t i = 0U; i < flight::kMaxCorrectionRows; ++i) {
      t.rows[i].load_n = WheelLoadN::from_raw(load);
      load += static_cast<std::int32_t>((rng() % (1U << 20U)) + 4U);
      t.rows[i].c1 = Ratio::from_raw(static_cast<std::int32_t>(rng()));
      t.rows[i].c2 = Ratio::from_raw(static_cast<std::int32_t>(rng() >> (rng() % 32U)));
      t.rows[i].c3 = Ratio::from_raw(-static_cast<std::int32_t>(rng() >> (33U + (rng() % 31U))));
      t.rows[i].dp_max_ratio = Ratio::from_raw(static_cast<std::int32_t>(rng() >> 40U));
    }
    const std::int32_t w0 = t.rows[0].load_n.raw();
    const std::int32_t width = t.rows[1].load_n.raw() - w0;
    CorrectionTable narrow = t;
    const std::int32_t narrow_width = 1 + static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(width - 1));
    narrow.rows[1].load_n = WheelLoadN::from_raw(w0 + narrow_width);
    const flight::CorrectionDivisors divisors = flight::make_correction_divisors(narrow);
    WheelLoadN loads[flight::limits::kWheelCount]{};
    const std::int32_t offsets[flight::limits::kWheelCount] = {
        0, narrow_width - 1, narrow_width, width - 1, static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(narrow_width)),
        narrow_width + static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(width - narrow_width))};
    for (std::uint32_t i = 0U; i < flight::limits::kWheelCount; ++i) {
      loads[i] = WheelLoadN::from_raw(w0 + offsets[i]);
    }
    CorrectionResult out[flight::limits::kWheelCount]{};
    static_cast<void>(flight::corrections_at(t, divisors, loads, out));
    for (std::uint32_t i = 0U; i < flight::limits::kWheelCount; ++i) {
      if (offsets[i] < narrow_width) {
        expect_same(out[i], oracle::corrections_at(narrow, loads[i]));
        ASSERT_EQ(out[i].status, flight::EstimateStatus::ok);
      } else {
        ASSERT_EQ(out[i].status, flight::EstimateStatus::invalid_coefficient) << k << " " << i;
      }
    }
  }
}

}  // namespace
}  // namespace sinkwatch
