#include "sinkwatch/flight/crc32.hpp"

#include "sinkwatch/flight/byte_view.hpp"

namespace sinkwatch {
namespace flight {

std::uint32_t crc32(const std::uint8_t* bytes, std::size_t size) noexcept {
  std::uint32_t crc = 0xFFFFFFFFU;
  if (bytes == nullptr) {
    return 0U;
  }
  const ByteView view(bytes, size);
  for (std::size_t i = 0U; i < size; ++i) {
    crc ^= static_cast<std::uint32_t>(view.at(i));
    for (std::uint32_t bit = 0U; bit < 8U; ++bit) {
      const std::uint32_t mask = (crc & 1U) != 0U ? 0xEDB88320U : 0U;
      crc = (crc >> 1U) ^ mask;
    }
  }
  return crc ^ 0xFFFFFFFFU;
}

}  // namespace flight
}  // namespace sinkwatch
