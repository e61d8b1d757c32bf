// load.hpp: the one path from a parameter table's bytes to the parameters
// the per-cycle step runs on (PreparedParameters).
//
// load() decodes the framing, the CRC and every section (param_table.hpp),
// the rover geometry of section 6 included, in one pass over the bytes;
// validates the table once (validate(), inside decode(), which also checks the
// rover section and its wheel radius); takes the Yutu-like rover on the Moon
// when the table carries no section 6 (and checks that its wheel is the
// table's); and prepares the reciprocals the step divides by. The C interface (sw_load_table) and the
// ground's replay call this and nothing else to load a table, so every
// consumer of table bytes applies the same checks in the same order.
#ifndef SINKWATCH_FLIGHT_LOAD_HPP
#define SINKWATCH_FLIGHT_LOAD_HPP

#include <cstddef>
#include <cstdint>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"

namespace sinkwatch {
namespace flight {

/// Decodes, validates and prepares `size` bytes. On ok, `out` holds the new
/// parameters (ready(), with the table's CRC); otherwise `out` is untouched
/// and the reason says which check refused the bytes: a framing or range
/// reason of decode() (extension_rejected when section 6 does not hold valid
/// rover parameters), rover_radius_mismatch when the rover's wheel radius is
/// not the table's.
[[nodiscard]] RejectReason load(const std::uint8_t* bytes, std::size_t size, PreparedParameters& out) noexcept;

/// The built-in parameters: default_parameter_table() and the Yutu-like rover
/// on the Moon, prepared (CRC 0). What a context holds before any load.
void load_default(PreparedParameters& out) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_LOAD_HPP
