// median.hpp: the middle of a short window of fixed-point samples, by an
// insertion sort of a copy (bounded: N is a compile-time window of a few
// samples). The traction check (traction.cpp, rho_med) and the rover's stop
// record (stop_record.cpp, each wheel's recent sinkage) both take it. Exact:
// no arithmetic on the values, so no rounding and no overflow; an even count
// gives the lower middle. The windows are rings; next_slot steps through one.
#ifndef SINKWATCH_FLIGHT_MEDIAN_HPP
#define SINKWATCH_FLIGHT_MEDIAN_HPP

#include <cstdint>

namespace sinkwatch {
namespace flight {
namespace detail {

/// The middle of the first `count` of `values` (the lower middle of an even
/// count; values[0] when count is 0). `T` needs only a strict order.
template <typename T, std::uint8_t N>
T median_of(const T (&values)[N], std::uint8_t count) noexcept {
  T sorted[N]{};
  for (std::uint8_t i = 0U; (i < count) && (i < N); ++i) {
    const T v = values[i];
    std::uint8_t j = i;
    while ((j > 0U) && (v < sorted[j - 1U])) {
      sorted[j] = sorted[j - 1U];
      --j;
    }
    sorted[j] = v;
  }
  const std::uint8_t used = (count < N) ? count : N;
  const std::uint8_t middle = (used > 0U) ? static_cast<std::uint8_t>((used - 1U) / 2U) : 0U;
  return sorted[middle];
}

/// The slot after `index` (below N) in a ring of N samples, without a
/// remainder: a library division on the Cortex-M0 for an N that is not a
/// power of two.
template <std::uint8_t N>
constexpr std::uint8_t next_slot(std::uint8_t index) noexcept {
  const auto after = static_cast<std::uint8_t>(index + 1U);
  return (after < N) ? after : std::uint8_t{0U};
}

}  // namespace detail
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_MEDIAN_HPP
