// libFuzzer harness: the fixed-point library's 128-bit unsigned division
// (fixedpoint/wide.hpp, wide::divmod and bit_length), the kernel under every
// Q31.32 division of the flight code, checked bit for bit against the
// compiler's unsigned __int128 (host only: the library must not use it,
// because 32-bit ARM has no __int128).
//
// Input: 32 bytes, dividend then divisor, each as two little-endian 64-bit
// halves (high first); a zero divisor is skipped (the caller's duty).
// Checked: quotient and remainder equal __int128's; bit_length of every half
// equals 64 - clz.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "sinkwatch/fixedpoint/wide.hpp"

namespace w = sinkwatch::fx::wide;
__extension__ typedef unsigned __int128 Native;

namespace {
void check(bool condition) {
  if (!condition) {
    std::abort();
  }
}
std::uint64_t u64(const std::uint8_t* p) {
  std::uint64_t v = 0U;
  for (int i = 0; i < 8; ++i) {
    v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  }
  return v;
}
Native native(const w::U128& a) { return (static_cast<Native>(a.hi) << 64U) | a.lo; }
std::uint32_t reference_bit_length(std::uint64_t v) {
  return v == 0U ? 0U : 64U - static_cast<std::uint32_t>(__builtin_clzll(v));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 32U) {
    return 0;
  }
  const w::U128 num{u64(data), u64(data + 8)};
  const w::U128 den{u64(data + 16), u64(data + 24)};
  check(w::bit_length(num.hi) == reference_bit_length(num.hi));
  check(w::bit_length(num.lo) == reference_bit_length(num.lo));
  if (w::is_zero(den)) {
    return 0;
  }
  const w::DivMod<w::U128> qr = w::divmod(num, den);
  check(native(qr.quotient) == native(num) / native(den));
  check(native(qr.remainder) == native(num) % native(den));
  return 0;
}
