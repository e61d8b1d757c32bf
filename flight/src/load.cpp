// Bytes to prepared parameters in one call; see load.hpp.
#include "sinkwatch/flight/load.hpp"

#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace flight {
namespace {

/// The CRC trailer of bytes that decode() accepted (so the 4 bytes exist).
std::uint32_t trailer_crc(const std::uint8_t* bytes, std::size_t size) noexcept {
  std::uint32_t crc = 0U;
  for (std::size_t k = 0U; k < kTableCrcBytes; ++k) {
    const std::uint32_t byte = bytes[(size - kTableCrcBytes) + k];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic) size checked by decode()
    crc |= byte << (8U * static_cast<std::uint32_t>(k));
  }
  return crc;
}

}  // namespace

RejectReason load(const std::uint8_t* bytes, std::size_t size, PreparedParameters& out) noexcept {
  ParameterTable table{};
  // decode() validates the table; section 6 is only framed here and decoded
  // (and validated) once below.
  const RejectReason framing = decode(bytes, size, table, nullptr);
  if (framing != RejectReason::ok) {
    return framing;
  }
  RoverParams rover = yutu_like_rover_params(kGravityMoon);
  if (table.rover_geometry.present && (decode_rover_section(table.rover_geometry, rover) != RoverParamStatus::ok)) {
    return RejectReason::extension_rejected;
  }
  if (rover.wheel_radius_m != table.wheel_radius_m) {
    return RejectReason::rover_radius_mismatch;
  }
  prepare_validated(table, rover, trailer_crc(bytes, size), out);
  return RejectReason::ok;
}

void load_default(PreparedParameters& out) noexcept {
  // The default table and rover are compile-time constants that
  // host_tests/rover check valid and of the same radius.
  prepare_validated(default_parameter_table(), yutu_like_rover_params(kGravityMoon), 0U, out);
}

}  // namespace flight
}  // namespace sinkwatch
