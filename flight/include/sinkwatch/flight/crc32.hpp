// crc32.hpp: CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, initial
// value and final XOR 0xFFFFFFFF; check value of "123456789" is 0xCBF43926),
// the checksum of the parameter table. Bitwise, no lookup table: the table is
// checked once per upload, and 1 KiB of code-space tables buys nothing.
#ifndef SINKWATCH_FLIGHT_CRC32_HPP
#define SINKWATCH_FLIGHT_CRC32_HPP

#include <cstddef>
#include <cstdint>

namespace sinkwatch {
namespace flight {

/// CRC-32 of `size` bytes. The loop runs exactly 8 * size times; the caller
/// bounds size (the table loader by kMaxTableBytes).
[[nodiscard]] std::uint32_t crc32(const std::uint8_t* bytes, std::size_t size) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_CRC32_HPP
