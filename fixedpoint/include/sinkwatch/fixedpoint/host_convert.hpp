// host_convert.hpp: conversions between Q and double, for host tests and
// ground tools only. Flight code must not include this header; the firmware
// build defines SINKWATCH_FIRMWARE, which turns an include into an error.
#ifndef SINKWATCH_FIXEDPOINT_HOST_CONVERT_HPP
#define SINKWATCH_FIXEDPOINT_HOST_CONVERT_HPP

#if defined(SINKWATCH_FIRMWARE)
#error "host_convert.hpp is host-only: flight code computes in fixed point"
#endif

#include <cstdint>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace fx {

/// The exact value raw * 2^-F, as far as a double holds it (exact for 32-bit
/// storage; for 64-bit storage rounded to 53 significant bits).
template <typename S, std::int32_t F>
[[nodiscard]] double to_double(Q<S, F> q) noexcept {
  double value = static_cast<double>(q.raw());
  for (std::int32_t i = 0; i < F; ++i) {
    value *= 0.5;
  }
  return value;
}

/// The Q value nearest to `v` at run time (host only): saturates with
/// overflow, NaN raises domain.
template <typename QType>
[[nodiscard]] QType from_double(double v, Status& status) noexcept {
  return detail::from_double<QType>(v, status);
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_HOST_CONVERT_HPP
