// n_of_m.hpp: the N-of-M persistence window both monitors share (the wheel
// monitor, monitor.hpp, and the motion-resistance check, traction.hpp): a
// 16-bit history, bit 0 the newest sample.
#ifndef SINKWATCH_FLIGHT_SRC_N_OF_M_HPP
#define SINKWATCH_FLIGHT_SRC_N_OF_M_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace flight {
namespace n_of_m {

/// Set bits among the newest `window` samples (at most kMaxWindow) of a
/// history word: the
/// window as a mask, then a population count of 16 bits by pairs, nibbles
/// and bytes (no loop: a per-bit loop cost about 110 Cortex-M0 instructions
/// per call, three calls per wheel and cycle; docs/performance.md). An empty
/// history, a quiet wheel's usual one, is answered first (session 18: about
/// 20 Cortex-M0 instructions fewer per such call), and forced inline, so
/// that the answer costs no call (round 14: twelve calls per step in the
/// wheel monitor, M4 -48, M0 -83 instructions per step).
/// The word may carry bits above the 16 a history keeps (shifted_in's bit
/// 16): the window's mask drops them, so they count as nothing.
SW_FX_INLINE std::uint8_t count_bits(std::uint32_t bits, std::uint8_t window) noexcept {
  if (bits == 0U) {
    return 0U;
  }
  const std::uint32_t width = (window < kMaxWindow) ? window : kMaxWindow;
  const std::uint32_t mask = (1U << width) - 1U;  // width <= 16: no overflow
  std::uint32_t v = bits & mask;
  v = v - ((v >> 1U) & 0x5555U);
  v = (v & 0x3333U) + ((v >> 2U) & 0x3333U);
  v = (v + (v >> 4U)) & 0x0F0FU;
  v = (v + (v >> 8U)) & 0x1FU;
  return static_cast<std::uint8_t>(v);
}

/// shift_in's word before its cut to 16 bits: bit 16 holds the sample the
/// history drops. count_bits counts it as the 16-bit history (its mask
/// drops bit 16), so a caller that stores the history and also counts it
/// takes the word, and the cut is the store's alone (the wheel monitor:
/// no zero extension per history and cycle, round 15).
SW_FX_INLINE std::uint32_t shifted_in(std::uint16_t history, bool bit) noexcept {
  return (static_cast<std::uint32_t>(history) << 1U) | (bit ? 1U : 0U);
}

/// The history with `bit` as its newest sample.
inline std::uint16_t shift_in(std::uint16_t history, bool bit) noexcept {
  return static_cast<std::uint16_t>(shifted_in(history, bit));
}

}  // namespace n_of_m
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_SRC_N_OF_M_HPP
