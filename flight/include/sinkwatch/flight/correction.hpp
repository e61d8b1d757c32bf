// correction.hpp: the corrections C1, C2, C3 of Eq. 11 as functions of the
// wheel load (the paper's Table 2), and the soil-bin drawbar-pull maximum
// DP_max/W (section 7, Fig. 10) over the same load breakpoints.
//
// Each is piecewise linear between the breakpoints and held constant beyond
// the first and the last; a load outside the breakpoints is reported
// (LoadClamp), because the fit says nothing about loads it was not made at.
// Default: Table 2's five soil-bin loads 3, 7, 10, 15, 20 kg times
// 9.81 N/kg, C1 = C2 = 1, C3 = 0.20, 0.15, 0.13, 0.13, 0.13 (param_table.hpp).
//
// DP_max is stored as the traction coefficient DP_max/W, not in newtons:
// Table 1 and Fig. 10 give it as a coefficient, and a coefficient carries over
// between loads where a force does not.
#ifndef SINKWATCH_FLIGHT_CORRECTION_HPP
#define SINKWATCH_FLIGHT_CORRECTION_HPP

#include <cstdint>

#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

constexpr std::uint8_t kMaxCorrectionRows = 8U;

/// One soil-bin load and its fitted corrections.
struct CorrectionRow {
  WheelLoadN load_n;   ///< breakpoint; strictly increasing along the table
  Ratio c1;
  Ratio c2;
  Ratio c3;
  Ratio dp_max_ratio;  ///< DP_max / W at high slip for this load
};

struct CorrectionTable {
  std::uint8_t count{0U};  ///< rows in use, 1..kMaxCorrectionRows
  CorrectionRow rows[kMaxCorrectionRows];
};

/// Where the load fell relative to the breakpoints.
enum class LoadClamp : std::uint8_t {
  none = 0U,         ///< within [first, last]: interpolated
  below_first = 1U,  ///< below the first breakpoint: the first row's values
  above_last = 2U,   ///< above the last breakpoint: the last row's values
};

struct CorrectionResult {
  Coefficients coefficients;
  Ratio dp_max_ratio;
  LoadClamp clamp{LoadClamp::none};
  EstimateStatus status{EstimateStatus::ok};  ///< invalid_load for W <= 0, invalid_coefficient for a malformed table
};

/// A segment width W_k+1 - W_k (raw Q15.16, positive) shifted left until its
/// top bit is bit 31, and its reciprocal's mantissa (fixedpoint/reciprocal.hpp).
/// The interpolation fraction (W - W_k) / width is then one product with the
/// mantissa, at most two below the quotient, and a remainder that corrects
/// it: the exact quotient, so the fraction has fx::div's bits without a
/// division per cycle (correction.cpp, fraction_of).
struct SegmentWidth {
  std::uint32_t normalised{0U};  ///< width * 2^shift, in [2^31, 2^32); 0: no segment
  std::uint32_t shift{0U};
  std::uint32_t mantissa{0U};  ///< floor((2^63 - 1) / normalised)
};

/// The segment widths of a table, prepared once per table load.
struct CorrectionDivisors {
  SegmentWidth width[kMaxCorrectionRows];  ///< [k]: rows k..k+1; unused entries: zero
};

/// Once per table load. Widths that are not positive (a table validate()
/// refuses) stay zero, and corrections_at below then fails with a status,
/// never a number.
[[nodiscard]] CorrectionDivisors make_correction_divisors(const CorrectionTable& table) noexcept;

/// C1..C3 and DP_max/W at the load `load_n`, the interpolation fraction's
/// division by the segment width done with `divisors` (made from this
/// table). A table that passed validate() never gives a status other than ok
/// or invalid_load. The per-cycle step is the only user; its parameters come
/// prepared (prepared_params.hpp). host_tests/flight/dividing_oracle.hpp keeps
/// the same function with a plain fx::div as the oracle it is checked
/// against bit for bit.
[[nodiscard]] CorrectionResult corrections_at(const CorrectionTable& table, const CorrectionDivisors& divisors,
                                              WheelLoadN load_n) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_CORRECTION_HPP
