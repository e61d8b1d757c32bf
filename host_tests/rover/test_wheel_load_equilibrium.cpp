// The reference wheel loads against an independent solve of the six
// equilibrium equations in 3-D vectors (Eigen): nothing of the projection of
// docs/rover-loads.md, section 3.2, or of the closed form of section 3.5 is
// reused, so an error in the derivation shows here. Host only (Eigen).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "rover_test_support.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sinkwatch {
namespace {

using rover_test::q;

// ------------------------------------- independent 3-D equilibrium solve

// Solves the six equilibrium equations directly in 3-D vectors (forces
// parallel to gravity, moments as cross products about the real pivot axes),
// with the contact points from rotation matrices: nothing of the projection
// of section 3.2 or of the closed form of section 3.5 is reused.
Eigen::Matrix<double, 6, 1> equilibrium_loads(const ground::RoverGeometry& g, double pitch, double roll,
                                               const ground::JointAngles& j) {
  const Eigen::Vector3d up(std::sin(pitch), std::sin(roll) * std::cos(pitch), std::cos(roll) * std::cos(pitch));
  const auto rot = [](double a) { return Eigen::AngleAxisd(a, -Eigen::Vector3d::UnitY()).toRotationMatrix(); };
  const auto v = [](ground::SidePoint s, double y) { return Eigen::Vector3d(s.x_m, y, s.z_m); };
  Eigen::Vector3d contact[6];
  Eigen::Vector3d bogie_pivot[2];
  for (int s = 0; s < 2; ++s) {
    const double y = (s == 0) ? g.track_width_m / 2 : -g.track_width_m / 2;
    const Eigen::Vector3d pivot(0.0, y, 0.0);
    const Eigen::Vector3d down(0.0, 0.0, -g.wheel_radius_m);
    const Eigen::Matrix3d rr = rot(j.rocker_rad[s]);
    const Eigen::Matrix3d rb = rot(j.rocker_rad[s] + j.bogie_rad[s]);
    bogie_pivot[s] = pivot + rr * v(g.rocker_bogie_pivot, 0.0);
    contact[3 * s + 0] = pivot + rr * v(g.rocker_front_axle, 0.0) + down;
    contact[3 * s + 1] = bogie_pivot[s] + rb * v(g.bogie_middle_axle, 0.0) + down;
    contact[3 * s + 2] = bogie_pivot[s] + rb * v(g.bogie_rear_axle, 0.0) + down;
  }
  const Eigen::Vector3d com(g.com_x_m, g.com_y_m, g.com_z_m);
  const double mg = g.mass_kg * g.gravity_mps2;
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  // Force along u, and the body-x and body-y moments about the origin.
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d m = contact[i].cross(up);
    a(0, i) = 1.0;
    a(1, i) = m.x();
    a(2, i) = m.y();
  }
  rhs(0) = mg;
  const Eigen::Vector3d mc = com.cross(up) * mg;
  rhs(1) = mc.x();
  rhs(2) = mc.y();
  // Bogie pivots: no moment about the lateral axis through B.
  for (int s = 0; s < 2; ++s) {
    for (int k = 1; k < 3; ++k) {
      a(3 + s, 3 * s + k) = (contact[3 * s + k] - bogie_pivot[s]).cross(up).y();
    }
  }
  // Differential: equal moments about the two rocker pivots.
  for (int s = 0; s < 2; ++s) {
    const Eigen::Vector3d pivot(0.0, (s == 0) ? g.track_width_m / 2 : -g.track_width_m / 2, 0.0);
    for (int k = 0; k < 3; ++k) {
      a(5, 3 * s + k) = ((s == 0) ? 1.0 : -1.0) * (contact[3 * s + k] - pivot).cross(up).y();
    }
  }
  const Eigen::Matrix<double, 6, 1> support = a.fullPivLu().solve(rhs);
  return support * up.z();
}

TEST(RoverWheelLoad, ReferenceMatchesIndependentEquilibriumSolve) {
  flight::RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  p.com_x_m = q<flight::LengthM>(0.03);
  p.com_y_m = q<flight::LengthM>(0.02);
  const ground::RoverGeometry g = rover_test::to_ground(p);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int compared = 0;
  for (int it = 0; it < 2000; ++it) {
    ground::JointAngles j;
    for (int s = 0; s < 2; ++s) {
      j.rocker_rad[s] = 0.35 * unit(rng);
      j.bogie_rad[s] = 0.5 * unit(rng);
    }
    const double pitch = 0.7 * unit(rng);
    const double roll = 0.7 * unit(rng);
    const ground::WheelLoads ref = ground::wheel_loads(g, ground::Attitude{pitch, roll}, j, ground::k_no_drive_torques);
    if (ref.status != ground::LoadStatus::ok && ref.status != ground::LoadStatus::tip_over) {
      continue;
    }
    const Eigen::Matrix<double, 6, 1> solved = equilibrium_loads(g, pitch, roll, j);
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(ref.load_n[static_cast<std::size_t>(i)], solved(i), 1e-8 * g.mass_kg * g.gravity_mps2)
          << "wheel " << i << " pitch " << pitch << " roll " << roll;
    }
    ++compared;
  }
  EXPECT_GT(compared, 1500);
}

}  // namespace
}  // namespace sinkwatch
