// table_bytes.hpp: test helpers that take an encoded parameter table apart and
// frame sections into a new one (header, total length, section count, CRC),
// shared by the parameter-table tests so that each can damage exactly one
// thing and know that everything else is right.
#ifndef SINKWATCH_HOST_TESTS_FLIGHT_TABLE_BYTES_HPP
#define SINKWATCH_HOST_TESTS_FLIGHT_TABLE_BYTES_HPP

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace test {

using Bytes = std::vector<std::uint8_t>;

/// The table's bytes; an encoding failure fails the test.
inline Bytes encode_table(const flight::ParameterTable& t) {
  Bytes b(flight::kMaxTableBytes);
  const flight::EncodeResult e = flight::encode(t, b.data(), b.size());
  EXPECT_EQ(e.status, flight::RejectReason::ok);
  b.resize(e.size);
  return b;
}

/// Little-endian stores, as the table format has them.
inline void put_u16(Bytes& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v & 0xFFU);
  b[at + 1U] = static_cast<std::uint8_t>(v >> 8U);
}
inline void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0U; i < 4U; ++i) {
    b[at + i] = static_cast<std::uint8_t>(v >> (8U * i));
  }
}

/// The CRC over everything before it, rewritten after a deliberate change.
inline void fix_crc(Bytes& b) {
  put_u32(b, b.size() - flight::kTableCrcBytes, flight::crc32(b.data(), b.size() - flight::kTableCrcBytes));
}

struct Section {
  std::uint16_t id;
  Bytes payload;
};

/// The sections of an encoded table, in order (header and CRC stripped).
inline std::vector<Section> sections_of(const Bytes& b) {
  std::vector<Section> out;
  std::size_t pos = flight::kTableHeaderBytes;
  while (pos + 4U <= b.size() - flight::kTableCrcBytes) {
    const auto id = static_cast<std::uint16_t>(b[pos] | (b[pos + 1U] << 8U));
    const auto len = static_cast<std::uint16_t>(b[pos + 2U] | (b[pos + 3U] << 8U));
    const auto first = b.begin() + static_cast<std::ptrdiff_t>(pos + 4U);
    out.push_back({id, Bytes(first, first + len)});
    pos += 4U + len;
  }
  return out;
}

/// A table around `sections` with a correct header, total length and CRC, so
/// that the only thing wrong is what the test changed; `count_override`
/// (>= 0) writes another section count into the header.
inline Bytes frame(const std::vector<Section>& sections, int count_override = -1) {
  Bytes b = {0x53, 0x57, 0x50, 0x54, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (const Section& s : sections) {
    b.push_back(static_cast<std::uint8_t>(s.id & 0xFFU));
    b.push_back(static_cast<std::uint8_t>(s.id >> 8U));
    b.push_back(static_cast<std::uint8_t>(s.payload.size() & 0xFFU));
    b.push_back(static_cast<std::uint8_t>(s.payload.size() >> 8U));
    b.insert(b.end(), s.payload.begin(), s.payload.end());
  }
  b.resize(b.size() + flight::kTableCrcBytes);
  put_u32(b, 8U, static_cast<std::uint32_t>(b.size()));
  put_u16(b, 12U, static_cast<std::uint16_t>(count_override >= 0 ? count_override : static_cast<int>(sections.size())));
  fix_crc(b);
  return b;
}

}  // namespace test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_FLIGHT_TABLE_BYTES_HPP
