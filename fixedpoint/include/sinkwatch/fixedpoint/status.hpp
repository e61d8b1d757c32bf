// status.hpp: the sticky status every fixed-point operation reports into.
//
// Why sticky: a flight computation chains dozens of operations; checking a
// status after each one buries the arithmetic. Instead every operation takes a
// Status& and ORs its flags into it, and the caller checks once at the end of
// a computation, before it uses the number. A flag is never cleared by an
// operation, so no error can be lost between two checks.
//
// The value an operation returns with a flag raised is documented per
// operation (saturated, or zero for a domain error); it is never a sentinel:
// the status, not the value, says whether the value may be used.
#ifndef SINKWATCH_FIXEDPOINT_STATUS_HPP
#define SINKWATCH_FIXEDPOINT_STATUS_HPP

#include <cstdint>

namespace sinkwatch {
namespace fx {

/// One reason an operation could not return the exact rounded result.
enum class Flag : std::uint8_t {
  overflow = 0x01U,     ///< result outside the format; the value saturated
  div_by_zero = 0x02U,  ///< divisor was zero
  domain = 0x04U,       ///< argument outside the function's domain (sqrt(-1), asin(2), NaN)
};

/// Accumulated flags of a chain of operations.
class Status {
 public:
  constexpr Status() noexcept = default;

  constexpr void raise(Flag flag) noexcept {
    bits_ = static_cast<std::uint8_t>(bits_ | static_cast<std::uint8_t>(flag));
  }
  /// Adds the flags of another chain (for example a sub-computation).
  constexpr void merge(Status other) noexcept {
    bits_ = static_cast<std::uint8_t>(bits_ | other.bits_);
  }
  [[nodiscard]] constexpr bool ok() const noexcept { return bits_ == 0U; }
  [[nodiscard]] constexpr bool has(Flag flag) const noexcept {
    return (bits_ & static_cast<std::uint8_t>(flag)) != 0U;
  }
  [[nodiscard]] constexpr std::uint8_t bits() const noexcept { return bits_; }
  constexpr void clear() noexcept { bits_ = 0U; }

 private:
  std::uint8_t bits_{0U};
};

}  // namespace fx
}  // namespace sinkwatch

#endif  // SINKWATCH_FIXEDPOINT_STATUS_HPP
