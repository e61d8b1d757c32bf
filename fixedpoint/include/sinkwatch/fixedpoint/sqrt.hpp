// sqrt.hpp: square root and reciprocal in Q format.
//
// sqrt: within 0.5 LSB of the exact root (rounded to nearest; a root of an
// integer is never exactly halfway, so there are no ties). Negative input
// raises Flag::domain and returns zero.
// reciprocal: 1/x through div, within 0.5 LSB; x == 0 raises div_by_zero.
#ifndef SINKWATCH_FIXEDPOINT_SQRT_HPP
#define SINKWATCH_FIXEDPOINT_SQRT_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace fx {
namespace detail {

/// floor(sqrt(x)) by the bit-by-bit method: one step per result bit, so at
/// most width/2 steps, and no division.
template <typename W>
constexpr W isqrt_floor(const W& x) noexcept {
  W remainder = x;
  W root = wide::from_u64<W>(0U);
  // The highest power of four not above x.
  const std::uint32_t len = wide::bit_length(x);
  if (len == 0U) {
    return root;
  }
  std::uint32_t shift = (len - 1U) & ~1U;
  W bit4 = wide::shl(wide::from_u64<W>(1U), shift);
  const std::uint32_t steps = (shift / 2U) + 1U;
  for (std::uint32_t i = 0U; i < steps; ++i) {
    const W trial = wide::add(root, bit4);
    root = wide::shr(root, 1U);
    if (!wide::less(remainder, trial)) {
      remainder = wide::sub(remainder, trial);
      root = wide::add(root, bit4);
    }
    bit4 = wide::shr(bit4, 2U);
  }
  return root;
}

/// r^2 of a root r = isqrt_floor(x), exactly: r < 2^(width/2).
constexpr std::uint64_t square_of_root(std::uint64_t root) noexcept {
  return wide::mul_full(static_cast<std::uint32_t>(root), static_cast<std::uint32_t>(root));
}
constexpr wide::U128 square_of_root(const wide::U128& root) noexcept {
  return wide::mul_full(wide::low_u64(root), wide::low_u64(root));
}

/// round(sqrt(x)) of an integer radicand in the wide type W.
template <typename W>
constexpr W rounded_root(const W& radicand) noexcept {
  const W root = isqrt_floor(radicand);
  // Round: up when x - r^2 > r, i.e. x >= r^2 + r + 1 > (r + 1/2)^2.
  const W excess = wide::sub(radicand, square_of_root(root));
  return wide::less(root, excess) ? wide::add(root, wide::from_u64<W>(1U)) : root;
}

}  // namespace detail

/// sqrt(a) in the format Out, within 0.5 LSB. Needs 2 * Fo >= Fa so that the
/// radicand is an integer: raw_out = round(sqrt(raw_a * 2^(2 Fo - Fa))).
template <typename Out, typename S, std::int32_t F>
[[nodiscard]] constexpr Out sqrt(Q<S, F> a, Status& status) noexcept {
  static_assert((2 * Out::frac_bits) >= F, "sqrt needs 2*Fout >= Fin");
  using OutS = typename Out::storage_type;
  if (a.raw() < 0) {
    status.raise(Flag::domain);
    return Out::zero();
  }
  const std::uint64_t mag = detail::magnitude(a.raw());
  const std::int32_t up = (2 * Out::frac_bits) - F;  // the radicand is mag * 2^up
  // When the radicand fits in 64 bits (every 32-bit format into itself, and
  // small values of the others) the same algorithm runs on uint64_t: the
  // same integers, so the same root, without the 128-bit loop.
  if ((up < 64) && (wide::bit_length(mag) <= static_cast<std::uint32_t>(64 - up))) {
    const std::uint64_t radicand = wide::shl(mag, static_cast<std::uint32_t>(up));
    return Out::from_raw(detail::from_sign_magnitude<OutS>(false, detail::rounded_root(radicand), status));
  }
  // The radicand may need twice the output's width: 128 bits.
  using W = wide::U128;
  bool overflowed = false;
  const W radicand = detail::scale_magnitude(wide::from_u64<W>(mag), -up, overflowed);
  if (overflowed) {
    // radicand >= 2^128: the root is >= 2^64, beyond every format.
    status.raise(Flag::overflow);
    return Out::max();
  }
  return Out::from_raw(detail::from_sign_magnitude<OutS>(false, detail::rounded_root(radicand), status));
}

/// sqrt(a) in a's format.
template <typename S, std::int32_t F>
[[nodiscard]] constexpr Q<S, F> sqrt(Q<S, F> a, Status& status) noexcept {
  return sqrt<Q<S, F>>(a, status);
}

/// 1 / a in the format Out, within 0.5 LSB; a == 0 raises div_by_zero.
template <typename Out, typename S, std::int32_t F>
[[nodiscard]] constexpr Out reciprocal(Q<S, F> a, Status& status) noexcept {
  // 1 as a Q<S, 0>: exact, and div rounds once. Same storage as `a`, so for
  // 32-bit formats the division stays in 64 bits (2^(Fo + F) <= 2^60) instead
  // of taking the 128-bit long-division loop.
  return div<Out>(Q<S, 0>::from_raw(1), a, status);
}

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_SQRT_HPP
