// byte_view.hpp: bounded windows on a caller's byte buffer (pointer + size),
// the one place where the byte codecs (crc32.cpp, param_table.cpp) index a
// raw pointer. Every access checks the index against the size first, so an
// index past the end reads 0 or writes nothing and is reported, instead of
// touching memory that is not the buffer's. C++17 has no std::span, and the
// C interface hands over plain pointers; the indexing below is deviation D-05
// (docs/misra.md), which clang-tidy's cppcoreguidelines-pro-bounds-pointer-
// arithmetic would otherwise report at every byte reader.
#ifndef SINKWATCH_FLIGHT_BYTE_VIEW_HPP
#define SINKWATCH_FLIGHT_BYTE_VIEW_HPP

#include <cstddef>
#include <cstdint>

namespace sinkwatch {
namespace flight {

/// Read-only window: `size` bytes at `data`. A null `data` is an empty window.
class ByteView {
 public:
  constexpr ByteView(const std::uint8_t* data, std::size_t size) noexcept
      : data_(data), size_((data == nullptr) ? 0U : size) {}

  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }

  /// Byte `index`, or 0 when index >= size() (the callers check the index
  /// first; the 0 only keeps a mistake from reading outside the buffer).
  [[nodiscard]] constexpr std::uint8_t at(std::size_t index) const noexcept {
    if (index >= size_) {
      return 0U;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): D-05, index < size_ checked above
    return data_[index];
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
};

/// Writable window: `size` bytes at `data`. A null `data` is an empty window.
class MutableByteView {
 public:
  constexpr MutableByteView(std::uint8_t* data, std::size_t size) noexcept
      : data_(data), size_((data == nullptr) ? 0U : size) {}

  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }

  /// Writes byte `index`; false (and nothing written) when index >= size().
  constexpr bool set(std::size_t index, std::uint8_t value) noexcept {
    if (index >= size_) {
      return false;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): D-05, index < size_ checked above
    data_[index] = value;
    return true;
  }

 private:
  std::uint8_t* data_;
  std::size_t size_;
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_BYTE_VIEW_HPP
