// literal.hpp: Q constants written as decimal numbers, for constexpr use.
//
//     constexpr auto k_c3 = fx::constant<fx::Q15_16>(0.13);
//
// This is the one place flight code meets a floating-point type, and only in
// constant expressions: a constant that does not fit, or a NaN, calls a
// function that is declared but never defined, which is a compile error in a
// constant expression (and a link error anywhere else). The firmware build
// checks that no soft-float routine is linked (docs/firmware.md), so a
// `constant` evaluated at run time is caught there too.
//
// MISRA C++:2023 deviation (docs/misra.md, D-01): rule 6.9.2 / floating point
// in a fixed-point component, confined to compile-time evaluation.
#ifndef SINKWATCH_FIXEDPOINT_LITERAL_HPP
#define SINKWATCH_FIXEDPOINT_LITERAL_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace fx {
namespace detail {

/// Never defined: reaching it in a constant expression stops compilation.
void constant_does_not_fit_its_format() noexcept;

/// v * 2^F rounded to nearest, ties away from zero; saturates with overflow,
/// NaN raises domain and gives zero. Exact for every double (the scaling is a
/// power of two, and the rounding step is exact below 2^52).
template <typename QType>
constexpr QType from_double(double v, Status& status) noexcept {
  using S = typename QType::storage_type;
  if (!(v == v)) {  // NaN compares unequal to itself
    status.raise(Flag::domain);
    return QType::zero();
  }
  double scaled = v;
  for (std::int32_t i = 0; i < QType::frac_bits; ++i) {
    scaled *= 2.0;
  }
  const bool negative = scaled < 0.0;
  const double m = negative ? -scaled : scaled;
  // 2^(N-1) as a double, by doubling: exact.
  double top = 1.0;
  for (std::uint32_t i = 0U; i < (QType::total_bits - 1U); ++i) {
    top *= 2.0;
  }
  constexpr double k_two52 = 4503599627370496.0;  // 2^52: from here on every double is an integer
  // Below 2^52, split into integer part and fraction; both are exact, and
  // comparing the fraction with 0.5 avoids the (m + 0.5) trap, which rounds
  // 0.49999999999999994 up to 1.
  double rounded = m;
  if (m < k_two52) {
    const double integer_part = static_cast<double>(static_cast<std::uint64_t>(m));
    rounded = ((m - integer_part) >= 0.5) ? (integer_part + 1.0) : integer_part;
  }
  const bool too_big = negative ? (rounded > top) : (rounded >= top);
  if (too_big) {
    status.raise(Flag::overflow);
    return negative ? QType::min() : QType::max();
  }
  const std::uint64_t mag = static_cast<std::uint64_t>(rounded);
  return QType::from_raw(from_sign_magnitude<S>(negative && (mag != 0U), mag, status));
}

}  // namespace detail

/// The Q value nearest to `v`; for constant expressions (see above).
template <typename QType>
constexpr QType constant(double v) noexcept {
  Status status;
  const QType q = detail::from_double<QType>(v, status);
  if (!status.ok()) {
    detail::constant_does_not_fit_its_format();
  }
  return q;
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_LITERAL_HPP
