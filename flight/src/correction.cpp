// Piecewise-linear corrections over the load breakpoints (correction.hpp).
#include "sinkwatch/flight/correction.hpp"

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

namespace sinkwatch {
namespace flight {

namespace {

/// f = offset / width as raw Q0.32, bit for bit fx::div<WideQ>(offset, width),
/// for 0 <= offset < width (raw Q15.16; for another offset a number that
/// means nothing, which corrections_at does not use: unsigned words, no
/// undefined behaviour). Then
/// a = offset 2^shift < v = width 2^shift < 2^32 is exact in 32 bits. With
/// m = floor((2^63 - 1)/v), 2^63 - m v is in [1, v], so q' = floor(a m / 2^31)
/// lies below a 2^32 / v by a (2^63 - m v) / (v 2^31) <= a / 2^31 < 2: q' is
/// the quotient q = floor(a 2^32 / v) or one or two below it, and the
/// remainder a 2^32 - q' v (below 3 v < 2^34) corrects it in at most two
/// steps, on its two 32-bit words, 0 to 2 and the low word (session 18:
/// three steps on the 64-bit remainder before).
/// Then q is rounded half up, as fx::div rounds a magnitude: below 2^32,
/// since offset < width < 2^31 raw keeps offset / width below 1 - 2^-31.
SW_FX_INLINE std::uint32_t fraction_of(std::uint32_t offset, const SegmentWidth& width) noexcept {
  const std::uint32_t v = width.normalised;
  const std::uint32_t a = offset << width.shift;  // < v
  // floor(a m / 2^31) (< 2^32) from the product's words.
  const detail::ProductWords estimate = detail::product_words(a, width.mantissa);
  std::uint32_t quotient = (estimate.high << 1U) | (estimate.low >> 31U);
  const detail::ProductWords product = detail::product_words(quotient, v);
  // a 2^32 - q' v (< 3 v) as two words: the low one wraps by design, and
  // the high one takes a borrow when the product's low word is not zero
  // (its top bit or its negation's is then set).
  std::uint32_t low = 0U - product.low;
  std::uint32_t high = a - product.high - ((product.low | low) >> 31U);
  // MISRA C++:2023 9.5.1: a simple counted loop, no break.
  for (std::uint32_t step = 0U; step < 2U; ++step) {
    if ((high != 0U) || (low >= v)) {
      high -= (low < v) ? 1U : 0U;
      low -= v;
      ++quotient;
    }
  }
  const bool round_up = low >= (v - low);  // the remainder is below v here
  return quotient + (round_up ? 1U : 0U);
}

/// Every field of `out` (assigned field by field: a result record assigned
/// whole is a memcpy call on the Cortex-M0); `status` returned.
SW_FX_INLINE EstimateStatus put(CorrectionResult& out, Ratio c1, Ratio c2, Ratio c3, Ratio dp_max_ratio, LoadClamp clamp,
                      EstimateStatus status) noexcept {
  out.coefficients.c1 = c1;
  out.coefficients.c2 = c2;
  out.coefficients.c3 = c3;
  out.dp_max_ratio = dp_max_ratio;
  out.clamp = clamp;
  out.status = status;
  return status;
}

SW_FX_INLINE EstimateStatus from_row(const CorrectionRow& row, LoadClamp clamp, CorrectionResult& out) noexcept {
  return put(out, row.c1, row.c2, row.c3, row.dp_max_ratio, clamp, EstimateStatus::ok);
}

/// No number: `status` says why.
SW_FX_INLINE EstimateStatus refused(EstimateStatus status, CorrectionResult& out) noexcept {
  return put(out, Ratio::zero(), Ratio::zero(), Ratio::zero(), Ratio::zero(), LoadClamp::none, status);
}

/// The segment's width in raw Q15.16 as the divisors hold it (0: no segment).
SW_FX_INLINE std::uint32_t width_raw(const SegmentWidth& width) noexcept {
  return width.normalised >> width.shift;
}

/// The values at `offset` = W - lo.load, below the width `width` (checked by
/// the caller), of the segment from `lo` to `hi` into `out`; ok returned.
SW_FX_INLINE EstimateStatus interpolated_at(const CorrectionRow& lo, const CorrectionRow& hi, const SegmentWidth& width,
                                            std::uint32_t offset, CorrectionResult& out) noexcept {
  // The fraction's halves once for the four coefficients (session 19: one
  // lerp call per coefficient, each splitting it, before).
  const detail::FractionHalves f = detail::halves_of(fraction_of(offset, width));
  return put(out, Ratio::from_raw(detail::interpolate_raw(lo.c1.raw(), hi.c1.raw(), f)),
             Ratio::from_raw(detail::interpolate_raw(lo.c2.raw(), hi.c2.raw(), f)),
             Ratio::from_raw(detail::interpolate_raw(lo.c3.raw(), hi.c3.raw(), f)),
             Ratio::from_raw(detail::interpolate_raw(lo.dp_max_ratio.raw(), hi.dp_max_ratio.raw(), f)),
             LoadClamp::none, EstimateStatus::ok);
}

/// The load `load_n` in the segment from `lo` to `hi` of width `width`
/// (lo.load <= W < hi.load) into `out`; its status returned.
SW_FX_INLINE EstimateStatus interpolated(const CorrectionRow& lo, const CorrectionRow& hi, const SegmentWidth& width,
                                         WheelLoadN load_n, CorrectionResult& out) noexcept {
  // W - W_k: W_k <= W (above) makes the modular difference of the two raw
  // values exact. It is below the width for every segment whose width
  // make_correction_divisors() prepared (W < W_k+1); a segment without one
  // (not increasing, or its width overflowed: a table validate() refuses)
  // has a zero width, so this one test refuses it (round 14: the zero width
  // and W < W_k were tested apart, the latter never true).
  const std::uint32_t offset = static_cast<std::uint32_t>(load_n.raw()) - static_cast<std::uint32_t>(lo.load_n.raw());
  if (offset >= width_raw(width)) {
    return refused(EstimateStatus::invalid_coefficient, out);
  }
  return interpolated_at(lo, hi, width, offset, out);
}

/// The loads W - W_0 (raw, modular) below which a load is in the first
/// segment and interpolated there by correction_of, for every table:
/// nonzero only where W_0 > 0 and W_0 < W_1 <= W_last (so count >= 2: with
/// one row W_last is W_0), and at most both W_1 - W_0 and the divisors'
/// width (the two are equal for divisors made from this table). Then an
/// offset below it means W_0 <= W < W_1 (W_0 > 0 and W_1 < 2^31: W_0 +
/// offset, offset < W_1 - W_0, cannot wrap, and a W below W_0 wraps to at
/// least 2^31 - W_0 > W_1 - W_0), so W > 0, W is below W_last, and its
/// offset passes the width's test: correction_of's path to the first
/// segment, past its four load tests and the width's, in one comparison
/// (round 15). The step's loads fall there on a lunar rover with Table 2's
/// breakpoints.
std::uint32_t first_segment_span(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                 std::uint32_t last) noexcept {
  const std::int32_t w0 = table.rows[0].load_n.raw();
  const std::int32_t w1 = table.rows[1].load_n.raw();
  if ((w0 <= 0) || (w1 <= w0) || (w1 > table.rows[last].load_n.raw())) {
    return 0U;
  }
  const auto span = static_cast<std::uint32_t>(w1 - w0);  // positive, below 2^31
  const std::uint32_t width = width_raw(divisors.width[0]);
  return (width < span) ? width : span;
}

/// One load's corrections into `out`, for a table whose row count is in
/// 1..kMaxCorrectionRows (`last` = count - 1, checked by the caller); its
/// status returned.
[[gnu::noinline]] EstimateStatus correction_of(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                               std::uint32_t last, WheelLoadN load_n, CorrectionResult& out) noexcept {
  if (load_n <= WheelLoadN::zero()) {
    return refused(EstimateStatus::invalid_load, out);
  }
  if (load_n < table.rows[0].load_n) {
    return from_row(table.rows[0], LoadClamp::below_first, out);
  }
  const CorrectionRow& final_row = table.rows[last];
  if (load_n >= final_row.load_n) {
    return from_row(final_row, (load_n > final_row.load_n) ? LoadClamp::above_last : LoadClamp::none, out);
  }
  // Here count >= 2 and rows[0].load <= W < rows[last].load. The segment is
  // the first k with W < W_k+1: then W_k <= W too (k = 0, or k - 1 was not
  // taken), for any breakpoints, increasing or not; and k = last - 1 when no
  // earlier one is, since W < W_last. So there is no "no segment" outcome.
  // A lunar rover's wheel loads (tens of newtons) lie in Table 2's first
  // segment, which corrections_at interpolates without this search.
  std::uint32_t seg = last - 1U;
  for (std::uint32_t i = 0U; i < seg; ++i) {
    if (load_n < table.rows[i + 1U].load_n) {
      seg = i;
      break;
    }
  }
  return interpolated(table.rows[seg], table.rows[seg + 1U], divisors.width[seg], load_n, out);
}

/// The fields a coefficient is written to: one type per field, so that the
/// per-coefficient loops below are written once (flight code has no lambdas).
struct C1Field {
  static Ratio& of(CorrectionResult& r) noexcept { return r.coefficients.c1; }
};
struct C2Field {
  static Ratio& of(CorrectionResult& r) noexcept { return r.coefficients.c2; }
};
struct C3Field {
  static Ratio& of(CorrectionResult& r) noexcept { return r.coefficients.c3; }
};
struct DpMaxField {
  static Ratio& of(CorrectionResult& r) noexcept { return r.dp_max_ratio; }
};

/// One coefficient's values from `lo` to `hi` at each load's fraction into
/// its field of `out`: the pair's comparisons made once for the N loads
/// (round 16: per load and coefficient before), and a constant coefficient
/// (Table 2's C1, C2 and DP_max/W) stored without a product.
template <typename Field, std::uint32_t N>
SW_FX_INLINE void interpolated_field(Ratio lo, Ratio hi, const std::uint32_t (&fractions)[N],
                                     CorrectionResult (&out)[N]) noexcept {
  if (hi == lo) {
    for (std::uint32_t i = 0U; i < N; ++i) {
      Field::of(out[i]) = lo;
    }
    return;
  }
  const detail::Interpolant c = detail::interpolant_of(lo.raw(), hi.raw());
  for (std::uint32_t i = 0U; i < N; ++i) {
    Field::of(out[i]) = Ratio::from_raw(detail::interpolated_value(c, detail::halves_of(fractions[i])));
  }
}

}  // namespace

template <std::uint32_t N>
bool corrections_at(const CorrectionTable& table, const CorrectionDivisors& divisors, const WheelLoadN (&load_n)[N],
                    CorrectionResult (&out)[N]) noexcept {
  // count in 1..kMaxCorrectionRows, as one unsigned comparison (0 wraps).
  const std::uint32_t last = static_cast<std::uint32_t>(table.count) - 1U;
  if (last >= kMaxCorrectionRows) {
    for (std::uint32_t i = 0U; i < N; ++i) {
      static_cast<void>(refused(EstimateStatus::invalid_coefficient, out[i]));
    }
    return false;
  }
  // Every load taken as one of the first segment (round 16): its fraction
  // there, then each coefficient for all loads at once. A load elsewhere
  // (its offset W - W_0 at or beyond first_span: then so is the largest
  // offset) gets a fraction and values that mean nothing, which
  // correction_of then overwrites, every field.
  const std::uint32_t first_span = first_segment_span(table, divisors, last);
  const auto w0 = static_cast<std::uint32_t>(table.rows[0].load_n.raw());
  const SegmentWidth width = divisors.width[0];
  std::uint32_t fractions[N];
  std::uint32_t farthest = 0U;  // the largest offset
  for (std::uint32_t i = 0U; i < N; ++i) {
    const std::uint32_t offset = static_cast<std::uint32_t>(load_n[i].raw()) - w0;
    farthest = (offset > farthest) ? offset : farthest;
    fractions[i] = fraction_of(offset, width);
  }
  for (std::uint32_t i = 0U; i < N; ++i) {
    out[i].clamp = LoadClamp::none;
    out[i].status = EstimateStatus::ok;
  }
  const CorrectionRow& lo = table.rows[0];
  const CorrectionRow& hi = table.rows[1];
  interpolated_field<C1Field>(lo.c1, hi.c1, fractions, out);
  interpolated_field<C2Field>(lo.c2, hi.c2, fractions, out);
  interpolated_field<C3Field>(lo.c3, hi.c3, fractions, out);
  interpolated_field<DpMaxField>(lo.dp_max_ratio, hi.dp_max_ratio, fractions, out);
  // The statuses ORed: ok is 0, so the OR is 0 when every one is ok.
  static_assert(static_cast<std::uint32_t>(EstimateStatus::ok) == 0U, "ok must be the OR's identity");
  std::uint32_t failures = 0U;
  if (farthest >= first_span) {
    for (std::uint32_t i = 0U; i < N; ++i) {
      if ((static_cast<std::uint32_t>(load_n[i].raw()) - w0) >= first_span) {
        failures |= static_cast<std::uint32_t>(correction_of(table, divisors, last, load_n[i], out[i]));
      }
    }
  }
  return failures == 0U;
}

template bool corrections_at<1U>(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                 const WheelLoadN (&load_n)[1U], CorrectionResult (&out)[1U]) noexcept;
template bool corrections_at<limits::kWheelCount>(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                                  const WheelLoadN (&load_n)[limits::kWheelCount],
                                                  CorrectionResult (&out)[limits::kWheelCount]) noexcept;

CorrectionDivisors make_correction_divisors(const CorrectionTable& table) noexcept {
  CorrectionDivisors d{};
  for (std::uint8_t i = 0U; (i + 1U) < kMaxCorrectionRows; ++i) {
    fx::Status st;
    const LoadQ width = fx::sub(table.rows[i + 1U].load_n.q(), table.rows[i].load_n.q(), st);
    if (((i + 1U) < table.count) && st.ok() && (width.raw() > 0)) {
      const auto raw = static_cast<std::uint32_t>(width.raw());  // below 2^31
      const std::uint32_t shift = 32U - fx::wide::bit_length32(raw);
      const std::uint32_t normalised = raw << shift;
      d.width[i] = SegmentWidth{normalised, shift, fx::normalised_reciprocal(normalised, 0).mantissa};
    }
  }
  const Ratio c1 = table.rows[0].c1;
  if (c1.raw() > 0) {
    d.c1_raw = c1.raw();
    d.c1_mantissa = fx::normalised_reciprocal(c1.q()).mantissa;
  }
  return d;
}

}  // namespace flight
}  // namespace sinkwatch
