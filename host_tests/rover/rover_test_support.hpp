// Host-side helpers shared by host_tests/rover and props/rover: the exact
// double of a flight parameter set and of flight inputs, so that the
// reference runs on exactly the numbers the fixed-point code saw.
#ifndef SINKWATCH_HOST_TESTS_ROVER_TEST_SUPPORT_HPP
#define SINKWATCH_HOST_TESTS_ROVER_TEST_SUPPORT_HPP

#include <cmath>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/from_flight.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace rover_test {

template <typename Quantity>
double d(Quantity q) {
  return fx::to_double(q.q());
}

inline ground::SidePoint d(flight::SidePointM p) { return ground::SidePoint{d(p.x_m), d(p.z_m)}; }

inline ground::RoverGeometry to_ground(const flight::RoverParams& p) { return ground::from_flight(p); }

/// Nearest Q value of a double (test inputs only); the conversion must fit.
template <typename Quantity>
Quantity q(double v) {
  fx::Status st;
  const auto value = fx::from_double<typename Quantity::q_type>(v, st);
  return st.ok() ? Quantity{value} : Quantity::zero();
}

inline flight::RoverAttitude attitude(double pitch, double roll) {
  return flight::RoverAttitude{q<flight::AngleRad>(pitch), q<flight::AngleRad>(roll)};
}

inline flight::JointAnglesRad joints(double rocker_l, double rocker_r, double bogie_l, double bogie_r) {
  flight::JointAnglesRad j{};
  j.rocker_rad[0] = q<flight::AngleRad>(rocker_l);
  j.rocker_rad[1] = q<flight::AngleRad>(rocker_r);
  j.bogie_rad[0] = q<flight::AngleRad>(bogie_l);
  j.bogie_rad[1] = q<flight::AngleRad>(bogie_r);
  return j;
}

inline ground::Attitude to_ground(const flight::RoverAttitude& a) {
  return ground::Attitude{d(a.pitch_rad), d(a.roll_rad)};
}

inline ground::JointAngles to_ground(const flight::JointAnglesRad& j) {
  ground::JointAngles g;
  for (std::size_t s = 0U; s < 2U; ++s) {
    g.rocker_rad[s] = d(j.rocker_rad[s]);
    g.bogie_rad[s] = d(j.bogie_rad[s]);
  }
  return g;
}

/// docs/rover-loads.md, section 7.4 (the statics in Q6.25, shares of the
/// normal weight): |W_fixed - W_ref| <= 2^-15 N + 2^-18 m g.
inline double load_bound_n(double weight_n) { return std::ldexp(1.0, -15) + std::ldexp(weight_n, -18); }

/// docs/rover-loads.md, section 12.5: the bound with drive torques adds
/// 2^-24 (1/m) x the sum of the used torques' magnitudes [N m].
inline double load_bound_with_torques_n(double weight_n, double torque_abs_sum_nm) {
  return load_bound_n(weight_n) + std::ldexp(torque_abs_sum_nm, -24);
}

/// docs/rover-loads.md, section 7.3.
inline double drawbar_bound_n(double weight_n, double total_n) {
  return std::ldexp(1.0, -17) + std::ldexp(weight_n + std::fabs(total_n), -28);
}

}  // namespace rover_test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_ROVER_TEST_SUPPORT_HPP
