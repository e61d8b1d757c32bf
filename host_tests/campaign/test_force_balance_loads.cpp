// The fuller quasi-static balance of the scenario generator
// (rover_loads.hpp force_balance_loads, docs/rover-loads.md section 11):
// it reduces to the flight statics where their assumptions hold, and its
// loads balance every force and moment it claims to when they do not.
#include "sinkwatch/ground/rover_loads.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
  const WheelLoads statics = wheel_loads(g, Attitude{}, JointAngles{}, k_no_drive_torques);
  const ForceBalanceLoads full = force_balance_loads(g, input(0.0, 0.0));
  ASSERT_EQ(full.status, LoadStatus::ok);
  for (std::size_t i = 0; i < k_wheel_count; ++i) EXPECT_NEAR(full.load_n[i], statics.load_n[i], 1e-9) << i;
}

TEST(ForceBalanceLoads, RollWithoutPullEqualsTheFlightStatics) {
  // Pure roll: both models share the assumption (lateral forces in
  // proportion to the normal loads), so the loads must agree.
  const RoverGeometry g = yutu_like_geometry();
  for (const double roll : {-10.0, 4.0, 10.0}) {
    const WheelLoads statics = wheel_loads(g, Attitude{0.0, roll * kDeg}, JointAngles{}, k_no_drive_torques);
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
  const WheelLoads statics = wheel_loads(g, Attitude{pitch * kDeg, roll * kDeg}, JointAngles{}, k_no_drive_torques);
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
    const WheelLoads statics = wheel_loads(g, Attitude{pitch * kDeg, 0.0}, JointAngles{}, k_no_drive_torques);
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

// The statics with torques (the flight twin, section 12) solve the same six
// equations as the fuller balance when each wheel's tangential force is its
// share of m g sin(pitch) split by load and a wheel without a torque keeps
// the free-rolling couple T = r F.
TEST(ForceBalanceLoads, StaticsWithTorquesSolveTheFullerBalance) {
  RoverGeometry g = yutu_like_geometry(k_gravity_earth_mps2);
  g.com_x_m = 0.04;
  g.com_y_m = -0.03;
  std::uint32_t state = 14U;
  const auto uniform = [&state](double lo, double hi) {
    state = state * 1664525U + 1013904223U;
    return lo + (hi - lo) * static_cast<double>(state >> 8) / static_cast<double>(1U << 24);
  };
  int compared = 0;
  for (int k = 0; k < 500; ++k) {
    const Attitude att{uniform(-0.3, 0.3), uniform(-0.3, 0.3)};
    JointAngles j;
    j.rocker_rad = {uniform(-0.2, 0.2), uniform(-0.2, 0.2)};
    j.bogie_rad = {uniform(-0.3, 0.3), uniform(-0.3, 0.3)};
    DriveTorques torques;
    for (std::size_t i = 0; i < k_wheel_count; ++i) {
      torques.usable[i] = uniform(0.0, 1.0) < 0.8;
      torques.torque_nm[i] = torques.usable[i] ? uniform(-20.0, 60.0) : 0.0;
    }
    const WheelLoads statics = wheel_loads(g, att, j, torques);
    if (statics.status != LoadStatus::ok || statics.torque_overload) continue;
    ForceBalanceInput in;
    in.attitude = att;
    in.joints = j;
    const double kx = std::sin(att.pitch_rad) / (std::cos(att.pitch_rad) * std::cos(att.roll_rad));
    for (std::size_t i = 0; i < k_wheel_count; ++i) {
      in.traction.tangential_n[i] = kx * statics.load_n[i];
      in.traction.soil_torque_nm[i] =
          torques.usable[i] ? torques.torque_nm[i] : g.wheel_radius_m * in.traction.tangential_n[i];
    }
    const ForceBalanceLoads full = force_balance_loads(g, in);
    ASSERT_EQ(full.status, LoadStatus::ok) << k;
    EXPECT_NEAR(full.along_residual_n, 0.0, 1e-9) << k;
    for (std::size_t i = 0; i < k_wheel_count; ++i) EXPECT_NEAR(full.load_n[i], statics.load_n[i], 1e-8) << k << " " << i;
    ++compared;
  }
  EXPECT_GT(compared, 400);
}

// A case in the along balance: the pull the slope needs, split so that the
// rear wheels pull `rear_bias` more per newton of load than the front ones
// (soft soil: not by load), and each torque carrying a compaction resistance
// of 5 % of the wheel's load on top of its pull.
WheelTraction uneven_traction(const RoverGeometry& g, const WheelLoads& statics, double pitch_rad, double rear_bias) {
  WheelTraction t;
  double weighted = 0.0;
  for (std::size_t i = 0; i < k_wheel_count; ++i) weighted += statics.load_n[i] * (1.0 + rear_bias * (i % 3) / 2.0);
  const double need_n = g.mass_kg * g.gravity_mps2 * std::sin(pitch_rad);
  for (std::size_t i = 0; i < k_wheel_count; ++i) {
    t.tangential_n[i] = need_n * statics.load_n[i] * (1.0 + rear_bias * (i % 3) / 2.0) / weighted;
    t.soil_torque_nm[i] = g.wheel_radius_m * (t.tangential_n[i] + 0.05 * statics.load_n[i]);
  }
  return t;
}

// Before and after: the fuller balance's rear and front loads over the
// statics without torques and with each wheel's torque (printed), for the
// cases of DriveTorqueReactionShiftsLoadToTheRearWheels (5 % of the weight
// pulled on top of the slope's need, split by load, torque = pull x r) and
// for pulls in the along balance split unevenly with a compaction torque.
TEST(ForceBalanceLoads, TorquesInTheStaticsShrinkTheRearWheelError) {
  const RoverGeometry g = yutu_like_geometry();
  for (const int kind : {0, 1}) {
    for (const double pitch : {0.0, 4.0, 8.0, 12.0}) {
      const Attitude att{pitch * kDeg, 0.0};
      const WheelLoads before = wheel_loads(g, att, JointAngles{}, k_no_drive_torques);
      ForceBalanceInput in = input(pitch, 0.0);
      const double pull_n = g.mass_kg * g.gravity_mps2 * (std::sin(pitch * kDeg) + 0.05);
      in.traction = (kind == 0) ? traction_for(g, before, pull_n) : uneven_traction(g, before, pitch * kDeg, 0.3);
      const ForceBalanceLoads full = force_balance_loads(g, in);
      ASSERT_EQ(full.status, LoadStatus::ok);
      DriveTorques torques;
      for (std::size_t i = 0; i < k_wheel_count; ++i) {
        torques.torque_nm[i] = in.traction.soil_torque_nm[i];
        torques.usable[i] = true;
      }
      const WheelLoads after = wheel_loads(g, att, JointAngles{}, torques);
      ASSERT_EQ(after.status, LoadStatus::ok);
      const double rear_before = full.load_n[2] / before.load_n[2] - 1.0;
      const double rear_after = full.load_n[2] / after.load_n[2] - 1.0;
      const double front_before = full.load_n[0] / before.load_n[0] - 1.0;
      const double front_after = full.load_n[0] / after.load_n[0] - 1.0;
      std::printf("  %s, slope %4.1f deg: fuller balance over the statics, rear %+.2f %% -> %+.2f %%, "
                  "front %+.2f %% -> %+.2f %%\n",
                  (kind == 0) ? "5 % extra pull by load " : "uneven pull, compaction", pitch, 100.0 * rear_before,
                  100.0 * rear_after, 100.0 * front_before, 100.0 * front_after);
      // The rear wheel's error and the worst wheel's error shrink; the front
      // wheel's may grow where two errors cancelled before (printed).
      double worst_before = 0.0, worst_after = 0.0;
      for (std::size_t i = 0; i < k_wheel_count; ++i) {
        worst_before = std::max(worst_before, std::fabs(full.load_n[i] / before.load_n[i] - 1.0));
        worst_after = std::max(worst_after, std::fabs(full.load_n[i] / after.load_n[i] - 1.0));
      }
      EXPECT_LT(std::fabs(rear_after), std::fabs(rear_before)) << kind << " " << pitch;
      EXPECT_LT(worst_after, worst_before) << kind << " " << pitch;
    }
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
