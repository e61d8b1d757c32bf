// Bytes to prepared parameters in one call; see load.hpp.
#include "sinkwatch/flight/load.hpp"

#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace flight {

RejectReason load(const std::uint8_t* bytes, std::size_t size, PreparedParameters& out) noexcept {
  ParameterTable table{};
  // decode() is the one validation: the table's ranges and, when section 6
  // is present, the rover's rules and its wheel radius against the table's.
  const RejectReason reason = decode(bytes, size, table);
  if (reason != RejectReason::ok) {
    return reason;
  }
  // Without section 6 the Yutu-like rover on the Moon stands in; it is a
  // compile-time constant (valid: host_tests/rover), but its wheel must
  // still be the table's.
  const RoverParams rover =
      table.rover_geometry.present ? table.rover_geometry.params : yutu_like_rover_params(kGravityMoon);
  if (rover.wheel_radius_m != table.wheel_radius_m) {
    return RejectReason::rover_radius_mismatch;
  }
  prepare_validated(table, rover, table_crc(bytes, size), out);
  return RejectReason::ok;
}

void load_default(PreparedParameters& out) noexcept {
  // The default table and rover are compile-time constants that
  // host_tests/rover check valid and of the same radius.
  prepare_validated(default_parameter_table(), yutu_like_rover_params(kGravityMoon), 0U, out);
}

}  // namespace flight
}  // namespace sinkwatch
