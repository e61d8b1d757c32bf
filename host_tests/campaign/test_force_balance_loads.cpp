// The fuller quasi-static balance of the scenario generator
// (rover_loads.hpp force_balance_loads, docs/rover-loads.md section 11):
// it reduces to the flight statics where their assumptions hold, and its
// loads balance every force and moment it claims to when they do not.
#include "sinkwatch/ground/rover_loads.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

using namespace sinkwatch::ground;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

ForceBalanceInput input(double pitch_deg, double roll_deg) {
  ForceBalanceInput in;
  in.attitude = Attitude{pitch_deg * kDeg, roll_deg * kDeg};
  return in;
}

// Tangential forces in proportion to the flight statics' loads with a given
// total, and each wheel's soil torque as if its force acted at the rim.
WheelTraction traction_for(const RoverGeometry& g, const WheelLoads& statics, double total_n) {
  WheelTraction t;
  double sum = 0.0;
  for (const double w : statics.load_n) sum += w;
  for (std::size_t i = 0; i < k_wheel_count; ++i) {
    t.tangential_n[i] = total_n * statics.load_n[i] / sum;
    t.soil_torque_nm[i] = t.tangential_n[i] * g.wheel_radius_m;
  }
  return t;
}

TEST(ForceBalanceLoads, FlatGroundWithoutPullEqualsTheFlightStatics) {
  const RoverGeometry g = yutu_like_geometry();
  const WheelLoads statics = wheel_loads(g, Attitude{}, JointAngles{});
  const ForceBalanceLoads full = force_balance_loads(g, input(0.0, 0.0));
  ASSERT_EQ(full.status, LoadStatus::ok);
  for (std::size_t i = 0; i < k_wheel_count; ++i) EXPECT_NEAR(full.load_n[i], statics.load_n[i], 1e-9) << i;
}

TEST(ForceBalanceLoads, RollWithoutPullEqualsTheFlightStatics) {
  // Pure roll: both models share the assumption (lateral forces in
  // proportion to the normal loads), so the loads must agree.
  const RoverGeometry g = yutu_like_geometry();
  for (const double roll : {-10.0, 4.0, 10.0}) {
    const WheelLoads statics = wheel_loads(g, Attitude{0.0, roll * kDeg}, JointAngles{});
    const ForceBalanceLoads full = force_balance_loads(g, input(0.0, roll));
    ASSERT_EQ(full.status, LoadStatus::ok);
    for (std::size_t i = 0; i < k_wheel_count; ++i) EXPECT_NEAR(full.load_n[i], statics.load_n[i], 1e-9) << roll;
  }
}

TEST(ForceBalanceLoads, OnASlopeTheLoadsBalanceGravityAndEveryMoment) {
  RoverGeometry g = yutu_like_geometry();
  g.com_x_m = 0.03;
  g.com_y_m = 0.02;
  const double pitch = 8.0, roll = 5.0, accel = 0.01;
  const WheelLoads statics = wheel_loads(g, Attitude{pitch * kDeg, roll * kDeg}, JointAngles{});
  ForceBalanceInput in = input(pitch, roll);
  in.accel_mps2 = accel;
  const double need_n = g.mass_kg * (g.gravity_mps2 * std::sin(pitch * kDeg) + accel);
  in.traction = traction_for(g, statics, need_n);
  in.traction.tangential_n[0] += 1.0;  // an uneven split: the front wheel pulls more,
  in.traction.tangential_n[2] -= 1.0;  // the rear less
  const ForceBalanceLoads full = force_balance_loads(g, in);
  ASSERT_EQ(full.status, LoadStatus::ok);
  double normal = 0.0, moment_about_rear = 0.0;
  const SideContacts c = side_contacts(g, 0.0, 0.0);
  const double x[3] = {c.front.x_m, c.middle.x_m, c.rear.x_m};
  const double z[3] = {c.front.z_m, c.middle.z_m, c.rear.z_m};
  for (std::size_t i = 0; i < k_wheel_count; ++i) {
    normal += full.load_n[i];
    // Pitch moment about the left rear contact (a point the solver never used).
    moment_about_rear += (z[i % 3] + g.wheel_radius_m - z[2]) * in.traction.tangential_n[i] -
                         (x[i % 3] - x[2]) * full.load_n[i] - in.traction.soil_torque_nm[i];
  }
  const double m = g.mass_kg, gr = g.gravity_mps2;
  moment_about_rear += (g.com_z_m - z[2]) * (-m * (gr * std::sin(pitch * kDeg) + accel)) +
                       (g.com_x_m - x[2]) * m * gr * std::cos(pitch * kDeg) * std::cos(roll * kDeg);
  EXPECT_NEAR(normal, m * gr * std::cos(pitch * kDeg) * std::cos(roll * kDeg), 1e-9);
  EXPECT_NEAR(full.along_residual_n, 0.0, 1e-9);
  EXPECT_NEAR(moment_about_rear, 0.0, 1e-9);
  // Each bogie: the middle and rear wheels' moment about the bogie pivot.
  for (std::size_t s = 0; s < 2; ++s) {
    double bogie = 0.0;
    for (std::size_t k = 1; k < 3; ++k) {
      const std::size_t i = 3 * s + k;
      bogie += (z[k] + g.wheel_radius_m - c.bogie_pivot.z_m) * in.traction.tangential_n[i] -
               (x[k] - c.bogie_pivot.x_m) * full.load_n[i] - in.traction.soil_torque_nm[i];
    }
    EXPECT_NEAR(bogie, 0.0, 1e-9) << s;
  }
}

TEST(ForceBalanceLoads, DriveTorqueReactionShiftsLoadToTheRearWheels) {
  // Driving up a slope: the flight statics put the pull through the
  // contacts parallel to gravity; the fuller balance adds the drive-torque
  // reaction on the links, which lifts the front and presses the rear.
  const RoverGeometry g = yutu_like_geometry();
  for (const double pitch : {0.0, 4.0, 8.0, 12.0}) {
    const WheelLoads statics = wheel_loads(g, Attitude{pitch * kDeg, 0.0}, JointAngles{});
    ForceBalanceInput in = input(pitch, 0.0);
    const double pull_n = g.mass_kg * g.gravity_mps2 * std::sin(pitch * kDeg) + 0.05 * g.mass_kg * g.gravity_mps2;
    in.traction = traction_for(g, statics, pull_n);  // 5 % of the weight for rolling resistance on top
    const ForceBalanceLoads full = force_balance_loads(g, in);
    ASSERT_EQ(full.status, LoadStatus::ok);
    const double rear = full.load_n[2] / statics.load_n[2] - 1.0;
    const double front = full.load_n[0] / statics.load_n[0] - 1.0;
    std::printf("  slope %4.1f deg: rear wheel %+.1f %%, front wheel %+.1f %% against the flight statics\n", pitch,
                100.0 * rear, 100.0 * front);
    EXPECT_GT(rear, 0.0) << pitch;
    EXPECT_LT(front, 0.0) << pitch;
  }
}

TEST(ForceBalanceLoads, RefusesWhatTheStaticsRefuse) {
  const RoverGeometry g = yutu_like_geometry();
  EXPECT_EQ(force_balance_loads(g, input(80.0, 0.0)).status, LoadStatus::attitude_out_of_range);
  ForceBalanceInput in = input(0.0, 0.0);
  in.traction.tangential_n[1] = std::nan("");
  EXPECT_EQ(force_balance_loads(g, in).status, LoadStatus::degenerate);
}

}  // namespace
