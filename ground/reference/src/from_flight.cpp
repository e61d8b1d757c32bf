// The twin's parameters from the flight module's; see from_flight.hpp.
#include "sinkwatch/ground/from_flight.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

namespace sinkwatch {
namespace ground {
namespace {

template <typename Quantity>
double d(Quantity q) {
  return fx::to_double(q.q());
}

SidePoint d(flight::SidePointM p) { return SidePoint{d(p.x_m), d(p.z_m)}; }

}  // namespace

RoverGeometry from_flight(const flight::RoverParams& p) {
  RoverGeometry g;
  g.mass_kg = d(p.mass_kg);
  g.gravity_mps2 = d(p.gravity_mps2);
  g.com_x_m = d(p.com_x_m);
  g.com_y_m = d(p.com_y_m);
  g.com_z_m = d(p.com_z_m);
  g.track_width_m = d(p.track_width_m);
  g.wheel_radius_m = d(p.wheel_radius_m);
  g.rocker_front_axle = d(p.rocker_front_axle);
  g.rocker_bogie_pivot = d(p.rocker_bogie_pivot);
  g.bogie_middle_axle = d(p.bogie_middle_axle);
  g.bogie_rear_axle = d(p.bogie_rear_axle);
  g.rocker_limit_rad = d(p.rocker_limit_rad);
  g.bogie_limit_rad = d(p.bogie_limit_rad);
  g.attitude_limit_rad = d(p.attitude_limit_rad);
  return g;
}

double high_slip_of(const flight::RoverParams& p) { return d(p.high_slip); }

}  // namespace ground
}  // namespace sinkwatch
