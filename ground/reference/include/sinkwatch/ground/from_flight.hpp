// from_flight.hpp: the double twin's parameters built from the flight
// module's, so that the reference runs on exactly the numbers the fixed-point
// code holds (every Q value converted exactly to double) instead of on a
// second hand-copied set.
#ifndef SINKWATCH_GROUND_FROM_FLIGHT_HPP
#define SINKWATCH_GROUND_FROM_FLIGHT_HPP

#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace ground {

/// The twin's geometry of a flight RoverParams: every field the exact double
/// of its Q value. (high_slip is not part of the geometry: the twin takes it
/// in DrawbarParams; high_slip_of() gives it.)
[[nodiscard]] RoverGeometry from_flight(const flight::RoverParams& p);

/// The flight parameters' high-slip level as a double.
[[nodiscard]] double high_slip_of(const flight::RoverParams& p);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_FROM_FLIGHT_HPP
