// n_of_m.hpp: the N-of-M persistence window both monitors share (the wheel
// monitor, monitor.hpp, and the motion-resistance check, traction.hpp): a
// 16-bit history, bit 0 the newest sample.
#ifndef SINKWATCH_FLIGHT_SRC_N_OF_M_HPP
#define SINKWATCH_FLIGHT_SRC_N_OF_M_HPP

#include <cstdint>

#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace flight {
namespace n_of_m {

/// Set bits among the newest `window` samples (at most kMaxWindow).
inline std::uint8_t count_bits(std::uint16_t bits, std::uint8_t window) noexcept {
  std::uint8_t n = 0U;
  for (std::uint8_t i = 0U; (i < window) && (i < kMaxWindow); ++i) {
    if (((static_cast<std::uint32_t>(bits) >> i) & 1U) != 0U) {
      ++n;
    }
  }
  return n;
}

/// The history with `bit` as its newest sample.
inline std::uint16_t shift_in(std::uint16_t history, bool bit) noexcept {
  return static_cast<std::uint16_t>((static_cast<std::uint32_t>(history) << 1U) | (bit ? 1U : 0U));
}

}  // namespace n_of_m
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_SRC_N_OF_M_HPP
