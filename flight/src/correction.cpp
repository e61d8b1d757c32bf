// Piecewise-linear corrections over the load breakpoints (correction.hpp).
#include "sinkwatch/flight/correction.hpp"

namespace sinkwatch {
namespace flight {

namespace {

/// a + f * (b - a) with f in [0, 1]: one rounding into Q7.24 at the end.
Ratio lerp(Ratio a, Ratio b, WideQ fraction, fx::Status& st) noexcept {
  const WideQ span = fx::sub(fx::rescale<WideQ>(b.q(), st), fx::rescale<WideQ>(a.q(), st), st);
  const WideQ step = fx::mul<WideQ>(fraction, span, st);
  const WideQ value = fx::add(fx::rescale<WideQ>(a.q(), st), step, st);
  return Ratio(fx::rescale<RatioQ>(value, st));
}

CorrectionResult from_row(const CorrectionRow& row, LoadClamp clamp) noexcept {
  return CorrectionResult{Coefficients{row.c1, row.c2, row.c3}, row.dp_max_ratio, clamp, EstimateStatus::ok};
}

/// The widths of the segments, or null for plain division.
CorrectionResult corrections_with(const CorrectionTable& table, const CorrectionDivisors* divisors,
                                  WheelLoadN load_n) noexcept {
  const CorrectionResult failed{Coefficients{Ratio::zero(), Ratio::zero(), Ratio::zero()}, Ratio::zero(),
                                LoadClamp::none, EstimateStatus::invalid_coefficient};
  if ((table.count == 0U) || (table.count > kMaxCorrectionRows)) {
    return failed;
  }
  if (load_n <= WheelLoadN::zero()) {
    CorrectionResult r = failed;
    r.status = EstimateStatus::invalid_load;
    return r;
  }
  const std::uint8_t last = static_cast<std::uint8_t>(table.count - 1U);
  if (load_n < table.rows[0].load_n) {
    return from_row(table.rows[0], LoadClamp::below_first);
  }
  if (load_n > table.rows[last].load_n) {
    return from_row(table.rows[last], LoadClamp::above_last);
  }
  if (load_n == table.rows[last].load_n) {
    return from_row(table.rows[last], LoadClamp::none);
  }
  // Here count >= 2 and rows[0].load <= W < rows[last].load: one segment holds W.
  for (std::uint8_t i = 0U; i < last; ++i) {
    const CorrectionRow& lo = table.rows[i];
    const CorrectionRow& hi = table.rows[i + 1U];
    if ((load_n >= lo.load_n) && (load_n < hi.load_n)) {
      fx::Status st;
      const LoadQ offset = fx::sub(load_n.q(), lo.load_n.q(), st);
      const WideQ fraction = (divisors != nullptr)
                                 ? div_by_constant<WideQ>(offset, divisors->width[i], st)
                                 : fx::div<WideQ>(offset, fx::sub(hi.load_n.q(), lo.load_n.q(), st), st);
      const Coefficients c{lerp(lo.c1, hi.c1, fraction, st), lerp(lo.c2, hi.c2, fraction, st),
                           lerp(lo.c3, hi.c3, fraction, st)};
      const Ratio dp = lerp(lo.dp_max_ratio, hi.dp_max_ratio, fraction, st);
      if (!st.ok()) {
        return failed;
      }
      return CorrectionResult{c, dp, LoadClamp::none, EstimateStatus::ok};
    }
  }
  // Breakpoints not increasing: validate() refuses such a table.
  return failed;
}

}  // namespace

CorrectionResult corrections_at(const CorrectionTable& table, WheelLoadN load_n) noexcept {
  return corrections_with(table, nullptr, load_n);
}

CorrectionResult corrections_at(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                WheelLoadN load_n) noexcept {
  return corrections_with(table, &divisors, load_n);
}

CorrectionDivisors make_correction_divisors(const CorrectionTable& table) noexcept {
  CorrectionDivisors d{};
  for (std::uint8_t i = 0U; (i + 1U) < kMaxCorrectionRows; ++i) {
    fx::Status st;
    const LoadQ width = fx::sub(table.rows[i + 1U].load_n.q(), table.rows[i].load_n.q(), st);
    if (((i + 1U) < table.count) && st.ok() && (width.raw() > 0)) {
      d.width[i] = make_divisor(width);
    }
  }
  return d;
}

}  // namespace flight
}  // namespace sinkwatch
