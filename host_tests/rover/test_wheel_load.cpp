// Wheel loads of the rocker-bogie: the flight function and its double twin
// against the analytic cases of docs/rover-loads.md (sections 3.7, 3.8, 4)
// and every status. Plain C++ (no Eigen), so that it also runs on ARM; the
// independent 3-D equilibrium solve is in test_wheel_load_equilibrium.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "prepared_support.hpp"
#include "rover_test_support.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_statics.hpp"
#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/rover_loads.hpp"
#include "../flight/table_bytes.hpp"

namespace sinkwatch {
namespace {

using flight::RoverParams;
using flight::WheelLoadStatus;
using rover_test::d;
using rover_test::q;

constexpr double kPi = 3.14159265358979323846;

RoverParams earth() { return flight::yutu_like_rover_params(flight::kGravityEarth); }

double weight(const RoverParams& p) { return d(p.mass_kg) * d(p.gravity_mps2); }

// ------------------------------------------------------------- flat ground

TEST(RoverWheelLoad, FlatGroundDefaultGivesEqualSixths) {
  for (const flight::AccelMps2 g : {flight::kGravityMoon, flight::kGravityMars, flight::kGravityEarth}) {
    const RoverParams p = flight::yutu_like_rover_params(g);
    const double sixth = weight(p) / 6.0;
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
    ASSERT_EQ(r.status, WheelLoadStatus::ok);
    const ground::WheelLoads ref =
        ground::wheel_loads(rover_test::to_ground(p), ground::Attitude{}, ground::JointAngles{}, ground::k_no_drive_torques);
    ASSERT_EQ(ref.status, ground::LoadStatus::ok);
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_NEAR(ref.load_n[i], sixth, 1e-9 * sixth) << "wheel " << i;
      EXPECT_NEAR(d(r.load_n[i]), sixth, rover_test::load_bound_n(weight(p))) << "wheel " << i;
    }
  }
}

// Section 3.7 with the centre of mass off the pivot axis and off the centre
// line: S_L = m g (1/2 + y_c/t), M = m g x_c / 2, lever rules per side.
TEST(RoverWheelLoad, FlatGroundOffCentreMatchesAnalyticSplit) {
  RoverParams p = earth();
  p.com_x_m = q<flight::LengthM>(0.06);
  p.com_y_m = q<flight::LengthM>(-0.04);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  const ground::RoverGeometry g = rover_test::to_ground(p);
  const double mg = weight(p);
  const double t = g.track_width_m;
  const double a = g.rocker_front_axle.x_m;
  const double b = -g.rocker_bogie_pivot.x_m;
  const double x_m = g.rocker_bogie_pivot.x_m + g.bogie_middle_axle.x_m;
  const double x_r = g.rocker_bogie_pivot.x_m + g.bogie_rear_axle.x_m;
  const double beta = (g.rocker_bogie_pivot.x_m - x_r) / (x_m - x_r);
  const double moment = mg * g.com_x_m / 2.0;
  const double side[2] = {mg * (0.5 + g.com_y_m / t), mg * (0.5 - g.com_y_m / t)};
  double expected[6];
  for (int s = 0; s < 2; ++s) {
    const double front = (moment + b * side[s]) / (a + b);
    expected[3 * s + 0] = front;
    expected[3 * s + 1] = beta * (side[s] - front);
    expected[3 * s + 2] = (1.0 - beta) * (side[s] - front);
  }
  const ground::WheelLoads ref = ground::wheel_loads(g, ground::Attitude{}, ground::JointAngles{}, ground::k_no_drive_torques);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  ASSERT_EQ(ref.status, ground::LoadStatus::ok);
  ASSERT_EQ(r.status, WheelLoadStatus::ok);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(ref.load_n[i], expected[i], 1e-9 * mg) << "wheel " << i;
    EXPECT_NEAR(d(r.load_n[i]), expected[i], rover_test::load_bound_n(mg)) << "wheel " << i;
  }
  // Forward centre of mass loads the front wheels, leftward... here rightward.
  EXPECT_GT(expected[0], expected[2]);
  EXPECT_GT(expected[3], expected[0]);
}

// ----------------------------------------------------- sum = m g cos cos

TEST(RoverWheelLoad, LoadsSumToNormalWeightComponent) {
  const RoverParams p = earth();
  const ground::RoverGeometry g = rover_test::to_ground(p);
  const double mg = weight(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int it = 0; it < 3000; ++it) {
    const flight::RoverAttitude att = rover_test::attitude(0.6 * unit(rng), 0.6 * unit(rng));
    const flight::JointAnglesRad j =
        rover_test::joints(0.35 * unit(rng), 0.35 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng));
    const double expected = mg * std::cos(d(att.pitch_rad)) * std::cos(d(att.roll_rad));
    const ground::WheelLoads ref = ground::wheel_loads(g, rover_test::to_ground(att), rover_test::to_ground(j), ground::k_no_drive_torques);
    if (ref.status == ground::LoadStatus::degenerate) {
      continue;
    }
    double ref_sum = 0.0;
    for (const double w : ref.load_n) ref_sum += w;  // holds for tip_over numbers too
    EXPECT_NEAR(ref_sum, expected, 1e-9 * mg);
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, j, flight::kNoDriveTorques);
    if (r.status != WheelLoadStatus::ok) {
      continue;
    }
    double sum = 0.0;
    for (const flight::WheelLoadN w : r.load_n) sum += d(w);
    // Six independently rounded loads, each within the bound.
    EXPECT_NEAR(sum, expected, 6.0 * rover_test::load_bound_n(mg));
    EXPECT_NEAR(d(r.weight_normal_n), expected, rover_test::load_bound_n(mg));
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

// ------------------------------------------------------ tilted, by hand

// docs/rover-loads.md, section 3.8: pure pitch, zero joint angles.
TEST(RoverWheelLoad, PurePitchMatchesHandComputation) {
  const RoverParams p = earth();
  const double mg = weight(p);
  for (const double theta : {-0.5, -0.3, -0.1, 0.1, 0.3, 0.5}) {
    const flight::RoverAttitude att = rover_test::attitude(theta, 0.0);
    const double th = d(att.pitch_rad);
    const double tau = std::tan(th);
    const double front = mg * (0.125 - 0.125 * tau) / (0.75 + 0.3 * tau);
    const double beta = (0.25 - 0.3 * tau) / 0.5;
    const double bogie = mg / 2.0 - front;
    const double expected[3] = {front * std::cos(th), beta * bogie * std::cos(th),
                                (1.0 - beta) * bogie * std::cos(th)};
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
    ASSERT_EQ(r.status, WheelLoadStatus::ok) << theta;
    for (std::size_t s = 0; s < 2; ++s) {
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(d(r.load_n[3 * s + k]), expected[k], rover_test::load_bound_n(mg)) << theta << " " << k;
      }
    }
  }
  // The numbers quoted in the document (0.3 rad, Earth).
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0.3, 0.0), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  ASSERT_EQ(r.status, WheelLoadStatus::ok);
  EXPECT_NEAR(d(r.load_n[0]), 134.40, 0.005);
  EXPECT_NEAR(d(r.load_n[1]), 164.00, 0.005);
  EXPECT_NEAR(d(r.load_n[2]), 357.63, 0.005);
}

TEST(RoverWheelLoad, PureRollMatchesHandComputation) {
  const RoverParams p = earth();
  const double mg = weight(p);
  for (const double phi : {-0.6, -0.3, 0.2, 0.45, 0.6}) {
    const flight::RoverAttitude att = rover_test::attitude(0.0, phi);
    const double ph = d(att.roll_rad);
    const double left = mg * (0.45 - 0.55 * std::tan(ph)) / 0.9;
    const double right = mg - left;
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
    ASSERT_EQ(r.status, WheelLoadStatus::ok) << phi;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(d(r.load_n[k]), left / 3.0 * std::cos(ph), rover_test::load_bound_n(mg)) << phi;
      EXPECT_NEAR(d(r.load_n[3 + k]), right / 3.0 * std::cos(ph), rover_test::load_bound_n(mg)) << phi;
    }
  }
}

// --------------------------------------------------------- stability limit

double bisect_limit(const ground::RoverGeometry& g, bool pitch_axis, double sign) {
  double lo = 0.0;
  double hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const ground::Attitude a = pitch_axis ? ground::Attitude{sign * mid, 0.0} : ground::Attitude{0.0, sign * mid};
    (ground::wheel_loads(g, a, ground::JointAngles{}, ground::k_no_drive_torques).status == ground::LoadStatus::ok ? lo : hi) = mid;
  }
  return lo;
}

TEST(RoverWheelLoad, TipOverLimitsMatchClosedForm) {
  const ground::RoverGeometry g = rover_test::to_ground(earth());
  const double pitch_limit = std::atan(0.25 / 0.30);
  const double roll_limit = std::atan(0.45 / 0.55);
  EXPECT_NEAR(bisect_limit(g, true, 1.0), pitch_limit, 1e-6);
  EXPECT_NEAR(bisect_limit(g, true, -1.0), pitch_limit, 1e-6);
  EXPECT_NEAR(bisect_limit(g, false, 1.0), roll_limit, 1e-6);
  EXPECT_NEAR(bisect_limit(g, false, -1.0), roll_limit, 1e-6);
  std::printf("tip-over limits, default geometry: pitch %.2f deg, roll %.2f deg\n", pitch_limit * 180.0 / kPi,
              roll_limit * 180.0 / kPi);
}

TEST(RoverWheelLoad, BeyondStabilityLimitReturnsStatusNotNumber) {
  const RoverParams p = earth();
  const double pitch_limit = std::atan(0.25 / 0.30);
  const double roll_limit = std::atan(0.45 / 0.55);
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  struct Case {
    double pitch, roll;
    std::uint32_t lifting_mask;  // bit i: wheel i may be the one reported lifting
  };
  // In pure roll with the centre of mass on the pivot axis (x_c = 0) the
  // pivot moment is zero and each wheel of a side carries a third of the
  // side's (here negative) total: the three tie in exact arithmetic, and
  // which of them is lowest is decided by the last bit of the rounding, so
  // any wheel of the lifting side is the right answer.
  const Case cases[] = {
      {pitch_limit + 0.01, 0.0, 0x12U},   // nose up: a middle wheel (1 or 4)
      {-pitch_limit - 0.01, 0.0, 0x24U},  // nose down: a rear wheel (2 or 5)
      {0.0, roll_limit + 0.01, 0x07U},    // right side down: a left wheel lifts
      {0.0, -roll_limit - 0.01, 0x38U},   // left side down: a right wheel lifts
  };
  for (const Case& c : cases) {
    const flight::WheelLoadResult inside =
        flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(c.pitch * 0.98, c.roll * 0.98), zero, flight::kNoDriveTorques);
    EXPECT_EQ(inside.status, WheelLoadStatus::ok) << c.pitch << " " << c.roll;
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(c.pitch, c.roll), zero, flight::kNoDriveTorques);
    EXPECT_EQ(r.status, WheelLoadStatus::tip_over) << c.pitch << " " << c.roll;
    ASSERT_LT(r.lifting_wheel, flight::kWheelCount);
    EXPECT_NE((c.lifting_mask >> r.lifting_wheel) & 1U, 0U) << r.lifting_wheel;
    for (const flight::WheelLoadN w : r.load_n) EXPECT_EQ(w.raw(), 0);
    EXPECT_EQ(r.weight_normal_n.raw(), 0);
  }
  // A rocker at its limit brings the pitch limit down (section 4: 26 deg).
  const flight::JointAnglesRad rocked = rover_test::joints(0.35, -0.35, 0, 0);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0.44, 0.0), rocked, flight::kNoDriveTorques).status, WheelLoadStatus::ok);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0.47, 0.0), rocked, flight::kNoDriveTorques).status, WheelLoadStatus::tip_over);
}

// ------------------------------------------------------------ input statuses

TEST(RoverWheelLoad, AttitudeAndJointsBeyondLimitsAreRejected) {
  const RoverParams p = earth();
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(1.01, 0), zero, flight::kNoDriveTorques).status, WheelLoadStatus::attitude_out_of_range);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, -1.01), zero, flight::kNoDriveTorques).status, WheelLoadStatus::attitude_out_of_range);
  flight::RoverAttitude extreme{flight::AngleRad{flight::AngleQ::min()}, flight::AngleRad::zero()};
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), extreme, zero, flight::kNoDriveTorques).status, WheelLoadStatus::attitude_out_of_range);
  const flight::RoverAttitude level = rover_test::attitude(0, 0);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), level, rover_test::joints(0.36, 0, 0, 0), flight::kNoDriveTorques).status,
            WheelLoadStatus::joint_out_of_range);
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), level, rover_test::joints(0, 0, 0, -0.51), flight::kNoDriveTorques).status,
            WheelLoadStatus::joint_out_of_range);
  // The limits themselves are inside.
  EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), level, rover_test::joints(0.35, -0.35, 0.5, -0.5), flight::kNoDriveTorques).status, WheelLoadStatus::ok);
}

// Each angle against its limit to the last bit (check_inputs' one-comparison
// test): the limit itself and its negation are inside, one LSB beyond either
// and the ends of the format outside.
TEST(RoverWheelLoad, AnglesAreCheckedAgainstTheirLimitsToTheLastBit) {
  const RoverParams p = earth();
  const flight::PreparedParameters prepared = test::prepared_rover(p);
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  const flight::RoverAttitude level = rover_test::attitude(0, 0);
  const auto angle = [](std::int64_t raw) { return flight::AngleRad::from_raw(static_cast<std::int32_t>(raw)); };
  const auto verdict = [](std::int64_t raw, std::int64_t limit) {
    return ((raw <= limit) && (raw >= -limit)) ? WheelLoadStatus::ok : WheelLoadStatus::attitude_out_of_range;
  };
  const std::int64_t limits[] = {p.attitude_limit_rad.raw(), p.rocker_limit_rad.raw(), p.bogie_limit_rad.raw()};
  for (int which = 0; which < 7; ++which) {
    const std::int64_t limit = (which < 2) ? limits[0] : ((which % 2 == 0) ? limits[1] : limits[2]);
    for (const std::int64_t raw : {-limit - 1, -limit, -limit + 1, std::int64_t{0}, limit - 1, limit, limit + 1,
                                   std::int64_t{INT32_MIN}, std::int64_t{INT32_MIN} + 1, std::int64_t{INT32_MAX}}) {
      flight::RoverAttitude att = level;
      flight::JointAnglesRad j = zero;
      WheelLoadStatus expected = verdict(raw, limit);
      if (which == 0) att.pitch_rad = angle(raw);
      if (which == 1) att.roll_rad = angle(raw);
      if (which >= 2) {
        expected = (expected == WheelLoadStatus::ok) ? WheelLoadStatus::ok : WheelLoadStatus::joint_out_of_range;
        const std::uint32_t side = (which >= 4) ? 1U : 0U;
        if (which % 2 == 0) j.rocker_rad[side] = angle(raw);
        else j.bogie_rad[side] = angle(raw);
      }
      const flight::WheelLoadResult r = flight::wheel_loads(prepared, att, j, flight::kNoDriveTorques);
      if (expected == WheelLoadStatus::ok) {
        EXPECT_NE(r.status, WheelLoadStatus::attitude_out_of_range) << which << " " << raw;
        EXPECT_NE(r.status, WheelLoadStatus::joint_out_of_range) << which << " " << raw;
      } else {
        EXPECT_EQ(r.status, expected) << which << " " << raw;
      }
    }
  }
}

TEST(RoverWheelLoad, EveryParameterRuleHasItsReason) {
  using S = flight::RoverParamStatus;
  const RoverParams good = earth();
  EXPECT_EQ(flight::validate_rover_params(good), S::ok);
  struct Mutation {
    void (*apply)(RoverParams&);
    S expected;
  };
  const Mutation mutations[] = {
      {[](RoverParams& p) { p.mass_kg = flight::MassKg::zero(); }, S::bad_mass},
      {[](RoverParams& p) { p.mass_kg = q<flight::MassKg>(1000.5); }, S::bad_mass},
      {[](RoverParams& p) { p.gravity_mps2 = q<flight::AccelMps2>(-1.62); }, S::bad_gravity},
      {[](RoverParams& p) { p.gravity_mps2 = q<flight::AccelMps2>(10.5); }, S::bad_gravity},
      {[](RoverParams& p) { p.wheel_radius_m = q<flight::LengthM>(0.005); }, S::bad_wheel_radius},
      {[](RoverParams& p) { p.track_width_m = flight::LengthM::zero(); }, S::bad_track_width},
      {[](RoverParams& p) { p.com_y_m = q<flight::LengthM>(0.45); }, S::bad_com},
      {[](RoverParams& p) { p.com_z_m = q<flight::LengthM>(2.5); }, S::bad_com},
      {[](RoverParams& p) { p.rocker_front_axle.x_m = q<flight::LengthM>(-0.1); }, S::bad_link_order},
      {[](RoverParams& p) { p.bogie_rear_axle.x_m = q<flight::LengthM>(0.1); }, S::bad_link_order},
      {[](RoverParams& p) { p.bogie_middle_axle.z_m = q<flight::LengthM>(-2.5); }, S::bad_link_length},
      {[](RoverParams& p) { p.rocker_limit_rad = flight::AngleRad::zero(); }, S::bad_joint_limit},
      {[](RoverParams& p) { p.bogie_limit_rad = q<flight::AngleRad>(0.9); }, S::bad_joint_limit},
      {[](RoverParams& p) { p.attitude_limit_rad = q<flight::AngleRad>(1.2); }, S::bad_attitude_limit},
      {[](RoverParams& p) { p.high_slip = q<flight::Ratio>(1.5); }, S::bad_high_slip},
  };
  for (const Mutation& m : mutations) {
    RoverParams p = good;
    m.apply(p);
    EXPECT_EQ(flight::validate_rover_params(p), m.expected);
    EXPECT_EQ(flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques).status,
              WheelLoadStatus::invalid_params);
  }
}

TEST(RoverWheelLoad, CollapsedLeverIsDegenerateNotANumber) {
  // A bogie whose axles sit one above the other projects to zero span on flat
  // ground: the flight code must refuse to divide by it.
  RoverParams p = earth();
  p.bogie_middle_axle = flight::SidePointM{q<flight::LengthM>(0.0005), q<flight::LengthM>(0.10)};
  p.bogie_rear_axle = flight::SidePointM{q<flight::LengthM>(-0.0001), q<flight::LengthM>(-0.30)};
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), rover_test::joints(0, 0, 0, 0), flight::kNoDriveTorques);
  EXPECT_EQ(r.status, WheelLoadStatus::degenerate);
  EXPECT_EQ(ground::wheel_loads(rover_test::to_ground(p), ground::Attitude{}, ground::JointAngles{}, ground::k_no_drive_torques).status,
            ground::LoadStatus::degenerate);
}

// ---------------------------------------------- the bound's own premises

// docs/rover-loads.md, section 7.2 builds the error bound on the largest
// sensitivities of the loads to an angle (S_a <= 1.75 /rad) and to a position
// (S_p <= 1.3 /m), per unit weight, over the default envelope's stable part.
// ------------------------------------------------------------ drive torques

flight::DriveTorques all_torques(double torque_nm) {
  flight::DriveTorques t{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    t.torque_nm[i] = q<flight::TorqueNm>(torque_nm);
    t.usable[i] = true;
  }
  return t;
}

TEST(RoverWheelLoad, DriveTorqueLiftsTheFrontAndPressesTheRear) {
  // Level ground, equal sixths without torques; 10 N m forward on every
  // wheel (section 12.3): front - 10/0.75, middle - 20/0.5, rear + 20/0.5
  // N per side before the roll balance (which is symmetric here).
  const RoverParams p = earth();
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), zero, all_torques(10.0));
  ASSERT_EQ(r.status, WheelLoadStatus::ok);
  EXPECT_EQ(r.torque_fallback_mask, 0U);
  EXPECT_FALSE(r.torque_overload);
  const double sixth = weight(p) / 6.0;
  // Projected from the axles on level ground: the same levers.
  EXPECT_NEAR(d(r.load_n[0]), sixth - 10.0 / 0.75, 1e-4);
  EXPECT_NEAR(d(r.load_n[1]), sixth + 10.0 / 0.75 / 2.0 - 20.0 / 0.5, 1e-4);
  EXPECT_NEAR(d(r.load_n[2]), sixth + 10.0 / 0.75 / 2.0 + 20.0 / 0.5, 1e-4);
  double sum = 0.0;
  for (const flight::WheelLoadN w : r.load_n) sum += d(w);
  EXPECT_NEAR(sum, weight(p), 1e-3);
}

TEST(RoverWheelLoad, UnusableTorqueFallsBackToTheStaticsAndSaysSo) {
  const RoverParams p = earth();
  const flight::RoverAttitude att = rover_test::attitude(0.15, -0.05);
  const flight::JointAnglesRad j = rover_test::joints(0.05, -0.05, 0.1, -0.1);
  const flight::WheelLoadResult none = flight::wheel_loads(test::prepared_rover(p), att, j, flight::kNoDriveTorques);
  EXPECT_EQ(none.torque_fallback_mask, 0x3FU);
  flight::DriveTorques torques = all_torques(12.0);
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) torques.usable[i] = false;
  // Unusable wheels ignore whatever torque value they carry: the old statics, bit for bit.
  const flight::WheelLoadResult ignored = flight::wheel_loads(test::prepared_rover(p), att, j, torques);
  EXPECT_EQ(ignored.torque_fallback_mask, 0x3FU);
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) EXPECT_EQ(ignored.load_n[i], none.load_n[i]) << i;
  // One wheel's current is bad: only its bit, and its loads follow the twin.
  torques = all_torques(12.0);
  torques.usable[4] = false;
  const flight::WheelLoadResult one = flight::wheel_loads(test::prepared_rover(p), att, j, torques);
  ASSERT_EQ(one.status, WheelLoadStatus::ok);
  EXPECT_EQ(one.torque_fallback_mask, 1U << 4U);
  ground::DriveTorques gt{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    gt.usable[i] = torques.usable[i];
    gt.torque_nm[i] = d(torques.torque_nm[i]);
  }
  const ground::WheelLoads ref =
      ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(att), rover_test::to_ground(j), gt);
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    EXPECT_NEAR(d(one.load_n[i]), ref.load_n[i], rover_test::load_bound_with_torques_n(weight(p), 60.0)) << i;
  }
}

// The fallback mask names exactly the wheels whose torque is not usable, for
// each of the 64 combinations, on every path that sets it: loads computed,
// angles refused, parameters not prepared (a refused result is otherwise
// failed(status): no loads, no lifting wheel).
TEST(RoverWheelLoad, FallbackMaskNamesEachUnusableTorqueOnEveryPath) {
  const RoverParams p = earth();
  const flight::PreparedParameters prepared = test::prepared_rover(p);
  const flight::PreparedParameters unprepared{};
  const flight::RoverAttitude att = rover_test::attitude(0.15, -0.05);
  const flight::RoverAttitude steep = rover_test::attitude(1.01, 0);
  const flight::JointAnglesRad j = rover_test::joints(0.05, -0.05, 0.1, -0.1);
  const flight::JointAnglesRad bent = rover_test::joints(0.36, 0, 0, 0);
  for (std::uint32_t usable_bits = 0U; usable_bits < 64U; ++usable_bits) {
    flight::DriveTorques torques{};
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) torques.usable[i] = ((usable_bits >> i) & 1U) != 0U;
    const std::uint32_t expected = (~usable_bits) & 0x3FU;
    const flight::WheelLoadResult ok = flight::wheel_loads(prepared, att, j, torques);
    EXPECT_EQ(ok.status, WheelLoadStatus::ok) << usable_bits;
    EXPECT_EQ(ok.torque_fallback_mask, expected) << usable_bits;
    const struct {
      flight::WheelLoadResult r;
      WheelLoadStatus status;
    } refused[] = {{flight::wheel_loads(prepared, steep, j, torques), WheelLoadStatus::attitude_out_of_range},
                   {flight::wheel_loads(prepared, att, bent, torques), WheelLoadStatus::joint_out_of_range},
                   {flight::wheel_loads(unprepared, att, j, torques), WheelLoadStatus::invalid_params}};
    for (const auto& c : refused) {
      EXPECT_EQ(c.r.status, c.status) << usable_bits;
      EXPECT_EQ(c.r.torque_fallback_mask, expected) << usable_bits;
      EXPECT_EQ(c.r.lifting_wheel, flight::kWheelCount) << usable_bits;
      EXPECT_FALSE(c.r.torque_overload) << usable_bits;
      for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) EXPECT_EQ(c.r.load_n[i].raw(), 0) << usable_bits;
    }
  }
}

TEST(RoverWheelLoad, TorquesThatWouldLiftAWheelFallBackToTheWeightAlone) {
  // 100 N m forward on 229 N wheels (r W = 34 N m: far beyond traction)
  // would lift the middle wheels (229 - 3.33 x 100 N < 0, section 12.3): the loads are those without torques, flagged;
  // stability stays the weight's decision (not tip_over).
  const RoverParams p = earth();
  const flight::JointAnglesRad zero = rover_test::joints(0, 0, 0, 0);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), zero, all_torques(100.0));
  ASSERT_EQ(r.status, WheelLoadStatus::ok);
  EXPECT_TRUE(r.torque_overload);
  EXPECT_EQ(r.torque_fallback_mask, 0x3FU);
  const flight::WheelLoadResult none = flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0, 0), zero, flight::kNoDriveTorques);
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) EXPECT_EQ(r.load_n[i], none.load_n[i]) << i;
  // Beyond the weight's own stability limit it is still tip_over.
  const flight::WheelLoadResult tipped =
      flight::wheel_loads(test::prepared_rover(p), rover_test::attitude(0.0, 0.8), zero, all_torques(100.0));
  EXPECT_EQ(tipped.status, WheelLoadStatus::tip_over);
  EXPECT_FALSE(tipped.torque_overload);
}

TEST(RoverWheelLoad, SensitivitiesBehindTheErrorBoundHold) {
  const ground::RoverGeometry g = rover_test::to_ground(earth());
  const double mg = g.mass_kg * g.gravity_mps2;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double h = 1e-6;
  double s_angle = 0.0;
  double s_pos = 0.0;
  for (int it = 0; it < 20000; ++it) {
    ground::Attitude a{unit(rng), unit(rng)};
    ground::JointAngles j;
    for (int s = 0; s < 2; ++s) {
      j.rocker_rad[s] = 0.35 * unit(rng);
      j.bogie_rad[s] = 0.5 * unit(rng);
    }
    const ground::WheelLoads base = ground::wheel_loads(g, a, j, ground::k_no_drive_torques);
    if (base.status != ground::LoadStatus::ok) continue;
    for (int k = 0; k < 6; ++k) {
      ground::Attitude a2 = a;
      ground::JointAngles j2 = j;
      double* angle[6] = {&a2.pitch_rad, &a2.roll_rad, &j2.rocker_rad[0], &j2.rocker_rad[1], &j2.bogie_rad[0],
                          &j2.bogie_rad[1]};
      *angle[k] += h;
      const ground::WheelLoads r = ground::wheel_loads(g, a2, j2, ground::k_no_drive_torques);
      if (r.status != ground::LoadStatus::ok) continue;
      for (std::size_t i = 0; i < 6; ++i) s_angle = std::max(s_angle, std::fabs(r.load_n[i] - base.load_n[i]) / h / mg);
    }
    for (int k = 0; k < 4; ++k) {
      ground::RoverGeometry g2 = g;
      double* pos[4] = {&g2.com_x_m, &g2.com_y_m, &g2.com_z_m, &g2.track_width_m};
      *pos[k] += h;
      const ground::WheelLoads r = ground::wheel_loads(g2, a, j, ground::k_no_drive_torques);
      if (r.status != ground::LoadStatus::ok) continue;
      for (std::size_t i = 0; i < 6; ++i) s_pos = std::max(s_pos, std::fabs(r.load_n[i] - base.load_n[i]) / h / mg);
    }
  }
  std::printf("sampled sensitivities: S_a = %.3f /rad, S_p = %.3f /m\n", s_angle, s_pos);
  EXPECT_LE(s_angle, 1.75);
  EXPECT_LE(s_pos, 1.3);
}

// ------------------------------------------------- parameter-table section 6

flight::ParameterTable table_with(const RoverParams& p) {
  flight::ParameterTable t = flight::default_parameter_table();
  t.rover_geometry = flight::RoverSection{true, p};
  return t;
}

flight::RejectReason decode_bytes(const std::vector<std::uint8_t>& b, flight::ParameterTable& out) {
  return flight::decode(b.data(), b.size(), out);
}

TEST(RoverParamSection, RoundTripsThroughTheTable) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMars);
  p.com_y_m = q<flight::LengthM>(-0.0123);
  const std::vector<std::uint8_t> bytes = test::encode_table(table_with(p));
  flight::ParameterTable back{};
  ASSERT_EQ(decode_bytes(bytes, back), flight::RejectReason::ok);
  ASSERT_TRUE(back.rover_geometry.present);
  const RoverParams& out = back.rover_geometry.params;
  EXPECT_EQ(out.com_y_m, p.com_y_m);
  EXPECT_EQ(out.gravity_mps2, p.gravity_mps2);
  EXPECT_EQ(out.bogie_rear_axle.z_m, p.bogie_rear_axle.z_m);
  EXPECT_EQ(out.high_slip, p.high_slip);
}

TEST(RoverParamSection, AbsentSectionDecodesAsAbsentAndBadValuesAreRefused) {
  const RoverParams p = earth();
  flight::ParameterTable out = table_with(p);  // must stay untouched on failure
  const std::vector<std::uint8_t> plain = test::encode_table(flight::default_parameter_table());
  flight::ParameterTable absent{};
  ASSERT_EQ(decode_bytes(plain, absent), flight::RejectReason::ok);
  EXPECT_FALSE(absent.rover_geometry.present);

  RoverParams heavy = p;
  heavy.mass_kg = q<flight::MassKg>(2000.0);
  ASSERT_EQ(flight::validate_rover_params(heavy), flight::RoverParamStatus::bad_mass);
  EXPECT_EQ(decode_bytes(test::encode_table(table_with(heavy)), out), flight::RejectReason::extension_rejected);
  EXPECT_EQ(out.rover_geometry.params.mass_kg, p.mass_kg);
}

TEST(RoverParamSection, ParameterTableRejectsABadGeometrySection) {
  flight::ParameterTable decoded{};
  ASSERT_EQ(decode_bytes(test::encode_table(table_with(earth())), decoded), flight::RejectReason::ok);
  EXPECT_EQ(decoded.rover_geometry.params.track_width_m, earth().track_width_m);

  RoverParams bad = earth();
  bad.track_width_m = flight::LengthM::zero();
  EXPECT_EQ(decode_bytes(test::encode_table(table_with(bad)), decoded), flight::RejectReason::extension_rejected);
  EXPECT_EQ(flight::validate(table_with(bad)), flight::RejectReason::extension_rejected);
}

/// Attitudes and joints (raw Q3.28) at which the default rover's smallest
/// share of the weight is beyond Q6.25 (-64) or beyond Q10.21 (-1024): the
/// statics' wider passes (docs/rover-loads.md, section 7.4) must still say
/// tip-over, with the twin's lifting wheel.
/// A pose as raw Q3.28 angles.
struct RawPose {
  std::int32_t pitch, roll, rocker_left, rocker_right, bogie_left, bogie_right;
};

flight::RoverAttitude attitude_of(const RawPose& pose) {
  return flight::RoverAttitude{flight::AngleRad::from_raw(pose.pitch), flight::AngleRad::from_raw(pose.roll)};
}

flight::JointAnglesRad joints_of(const RawPose& pose) {
  flight::JointAnglesRad j{};
  j.rocker_rad[0] = flight::AngleRad::from_raw(pose.rocker_left);
  j.rocker_rad[1] = flight::AngleRad::from_raw(pose.rocker_right);
  j.bogie_rad[0] = flight::AngleRad::from_raw(pose.bogie_left);
  j.bogie_rad[1] = flight::AngleRad::from_raw(pose.bogie_right);
  return j;
}

/// The twin's loads without torques at a pose.
ground::WheelLoads twin_without_torques(const RoverParams& p, const RawPose& pose) {
  return ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(attitude_of(pose)),
                             rover_test::to_ground(joints_of(pose)), ground::k_no_drive_torques);
}

struct FarBeyondTipOver {
  RawPose pose;
  double min_share;  ///< the twin's smallest load / m g, for the record
};

void expect_tip_over_like_the_twin(const FarBeyondTipOver& c,
                                   const RoverParams& p = flight::yutu_like_rover_params(flight::kGravityEarth)) {
  const ground::WheelLoads ref = twin_without_torques(p, c.pose);
  ASSERT_EQ(ref.status, ground::LoadStatus::tip_over);
  const double mg = d(p.mass_kg) * d(p.gravity_mps2);
  EXPECT_NEAR(ref.min_load_n / mg, c.min_share, 1.0);
  std::uint32_t lowest = 0U;
  for (std::uint32_t i = 1U; i < flight::kWheelCount; ++i) {
    lowest = (ref.load_n[i] < ref.load_n[lowest]) ? i : lowest;
  }
  const flight::WheelLoadResult r =
      flight::wheel_loads(test::prepared_rover(p), attitude_of(c.pose), joints_of(c.pose), flight::kNoDriveTorques);
  EXPECT_EQ(r.status, WheelLoadStatus::tip_over);
  EXPECT_EQ(r.lifting_wheel, lowest);
}

/// Beyond Q10.21, where shares saturate: without torques the twin says
/// tip-over, and so does the flight, naming a wheel whose load is negative in
/// the twin (not necessarily the lowest).
void expect_a_lifting_wheel_like_the_twin(const RawPose& pose, const RoverParams& p) {
  const ground::WheelLoads ref = twin_without_torques(p, pose);
  ASSERT_EQ(ref.status, ground::LoadStatus::tip_over);
  const flight::WheelLoadResult r =
      flight::wheel_loads(test::prepared_rover(p), attitude_of(pose), joints_of(pose), flight::kNoDriveTorques);
  EXPECT_EQ(r.status, WheelLoadStatus::tip_over);
  ASSERT_LT(r.lifting_wheel, flight::kWheelCount);
  EXPECT_LT(ref.load_n[r.lifting_wheel], 0.0);
}

TEST(RoverWheelLoad, ShareBeyondQ6_25IsDecidedAsTipOverInQ10_21) {
  expect_tip_over_like_the_twin({{-249035111, -13546449, -52126579, -64655453, 59230544, -93846949}, -208.6});
  expect_tip_over_like_the_twin({{-208467396, -147721787, -91654940, -49777567, 24188275, -70202580}, -353.8});
}

TEST(RoverWheelLoad, ShareBeyondQ10_21IsDecidedAsTipOverInQ15_16) {
  expect_tip_over_like_the_twin({{-225615807, -144820051, -74571252, 83272519, 26331901, 102875640}, -5578.3});
  expect_tip_over_like_the_twin({{-265000558, -62902611, 82426320, -27831358, 12493817, -106800594}, -2451.3});
}

// A rocker lever of 1.003 mm (Q10.21) that Q15.16 rounds to 0.992 mm, with
// shares beyond Q10.21 (the differential fuzzer's finding of session 13):
// the Q6.25 pass has decided the lever against 1 mm, so the Q15.16 pass
// must not call it collapsed; it says tip-over, as the twin does, where it
// said overflow before.
TEST(RoverWheelLoad, LeverJustAbove1mmIsNotDecidedAgainInTheWiderPasses) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  p.com_y_m = flight::LengthM::from_raw(275242);
  p.com_z_m = flight::LengthM::from_raw(839268);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  expect_tip_over_like_the_twin({{-266128588, -232574156, -5713113, -11939, -34406, 3031}, -508.2}, p);
}

// Bogie spans of 1.8 and 1.9 mm, no torque (the fifth fuzz finding of
// session 14, where the torques had already fallen back): the shares leave
// every format, Q15.16 included, and the twin says tip-over. The Q15.16
// pass reads its saturated shares for the tip-over after the overflow
// (loads_in); before, the step refused the cycle as an overflow.
TEST(RoverWheelLoad, ShareBeyondEveryFormatIsATipOver) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  p.com_x_m = flight::LengthM::from_raw(1320);
  p.com_y_m = flight::LengthM::from_raw(262185);
  p.com_z_m = flight::LengthM::from_raw(839268);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  expect_tip_over_like_the_twin({{257119283, -48226270, 45759016, 45726140, 116192205, 116190445}, -143069.5}, p);
}

// The twin's conditioning of the lateral span, which the differential
// fuzzer reads to tell where the flight's refusal may be named otherwise
// (docs/rover-loads.md 7.4): on level ground every term up to the span is a
// few units at most, the bogie share beta and 1 - beta among them, and the
// shortest lever is the shorter of a + b and the bogie span; in the folded
// pose of ShareBeyondQ10_21WithACoarseSpanCollapsedIsATipOver (below) the
// bogie share is beyond Q6.25's range; a bogie span collapsed below 1 mm
// forms no quotient by it, so no term is bounded.
TEST(RoverWheelLoad, TwinLargestTermTellsALateralSpanBeyondQ6_25) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  const ground::WheelLoads level = twin_without_torques(p, RawPose{0, 0, 0, 0, 0, 0});
  ASSERT_EQ(level.status, ground::LoadStatus::ok);
  const ground::RoverGeometry g = rover_test::to_ground(p);
  const double a_plus_b = g.rocker_front_axle.x_m - g.rocker_bogie_pivot.x_m;
  const double bogie_span = g.bogie_middle_axle.x_m - g.bogie_rear_axle.x_m;
  EXPECT_NEAR(level.shortest_lever_m, std::min(a_plus_b, bogie_span), 1e-12);
  EXPECT_LT(level.largest_term, 2.0);
  const double beta = -g.bogie_rear_axle.x_m / bogie_span;
  EXPECT_GE(level.largest_term, std::max(beta, 1.0 - beta));

  p.com_x_m = flight::LengthM::from_raw(1320);
  p.com_y_m = flight::LengthM::from_raw(262185);
  p.com_z_m = flight::LengthM::from_raw(839268);
  const ground::WheelLoads folded =
      twin_without_torques(p, RawPose{257119037, -48226270, 45759016, 45726140, 116192205, 116190445});
  ASSERT_EQ(folded.status, ground::LoadStatus::tip_over);
  EXPECT_GE(folded.shortest_lever_m, 1e-3);
  EXPECT_GE(folded.largest_term, 64.0);

  // The same pose with the left bogie turned further until its span collapses.
  bool collapsed = false;
  for (std::int32_t step = 0; (step < 100000) && !collapsed; ++step) {
    const ground::WheelLoads r =
        twin_without_torques(p, RawPose{257119037, -48226270, 45759016, 45726140, 116192205 + (step * 64), 116190445});
    if (r.shortest_lever_m < 1e-3) {
      collapsed = true;
      EXPECT_EQ(r.status, ground::LoadStatus::degenerate);
      EXPECT_TRUE(std::isinf(r.largest_term));
    }
  }
  EXPECT_TRUE(collapsed);
}

// Parameters that pass validate_rover_params() at the edge of its ranges: a
// rocker whose front axle is 5.5 mm ahead of its pivot, the bogie pivot
// 1.1 mm behind it (found by a random search over valid parameters, one case
// in 14.6 million; formerly test_cov_wheel_load.cpp, which expected an
// overflow). Tilted, the shares leave every format (the twin's smallest is
// -508,439 m g); the twin says tip-over, and since session 14 so does the
// Q15.16 pass. Several of its shares saturate there, so the wheel it names
// is one that lifts (negative in the twin too), not necessarily the lowest.
TEST(RoverWheelLoad, EdgeOfTheRangesBeyondEveryFormatIsATipOver) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.mass_kg = flight::MassKg::from_raw(44843363);              // 684.3 kg
  p.gravity_mps2 = flight::AccelMps2::from_raw(70844758);      // 4.22 m/s^2
  p.wheel_radius_m = flight::LengthM::from_raw(1257371);       // 0.075 m
  p.track_width_m = flight::LengthM::from_raw(17982918);       // 1.072 m
  p.com_x_m = flight::LengthM::from_raw(-30890866);            // -1.841 m
  p.com_y_m = flight::LengthM::from_raw(-4067800);             // -0.242 m
  p.com_z_m = flight::LengthM::from_raw(-25162605);            // -1.500 m
  p.rocker_front_axle = flight::SidePointM{flight::LengthM::from_raw(92540), flight::LengthM::from_raw(-23068015)};
  p.rocker_bogie_pivot = flight::SidePointM{flight::LengthM::from_raw(-17804), flight::LengthM::from_raw(-23989935)};
  p.bogie_middle_axle = flight::SidePointM{flight::LengthM::from_raw(31117171), flight::LengthM::from_raw(11953817)};
  p.bogie_rear_axle = flight::SidePointM{flight::LengthM::from_raw(-25849548), flight::LengthM::from_raw(-87804)};
  p.rocker_limit_rad = flight::AngleRad::from_raw(214748365);    // 0.8 rad
  p.bogie_limit_rad = flight::AngleRad::from_raw(214748365);     // 0.8 rad
  p.attitude_limit_rad = flight::AngleRad::from_raw(281857229);  // 1.05 rad
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  expect_a_lifting_wheel_like_the_twin({-168791173, -42756740, -107096556, -60749518, -131018337, 121485577}, p);
}

// The same rover, tilted a little more (the sixth fuzz finding of session
// 14): Q10.21 reads the lateral span as 0.066 m with a clean status before
// its shares overflow, Q15.16 reads it as -0.044 m (the middle wheel's
// share of the 1.8 mm bogie is about 170 there) and calls it collapsed. The
// shares alone overflowed Q10.21, so a wheel lifts: a tip-over, as the twin
// says, where the step refused the cycle before. Saturated shares name a
// wheel that lifts, not necessarily the lowest.
TEST(RoverWheelLoad, ShareBeyondQ10_21WithACoarseSpanCollapsedIsATipOver) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityEarth);
  p.com_x_m = flight::LengthM::from_raw(1320);
  p.com_y_m = flight::LengthM::from_raw(262185);
  p.com_z_m = flight::LengthM::from_raw(839268);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  expect_a_lifting_wheel_like_the_twin({257119037, -48226270, 45759016, 45726140, 116192205, 116190445}, p);
}

// Thousands of newton-metres on a rover whose bogie span, projected from the
// axles as the torques' balance takes it, is 1.4 mm (a fuzz finding of
// session 14 against the first form of the fallback that
// CouplesBeyondEachFormatAreATorqueOverload, below, checks): the twin calls the balance with the
// torques degenerate (a collapsed lateral span) and does not fall back, and
// the Q15.16 pass takes it for a collapsed span too. That is not a balance
// beyond every format, so the flight does not fall back to the loads
// without torques (a tip-over there) either: it stays an overflow, which
// the step refuses as it refuses degenerate.
void expect_collapsed_span_with_torques(const double (&torque_nm)[flight::kWheelCount]) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.com_x_m = flight::LengthM::from_raw(-952);
  p.com_y_m = flight::LengthM::from_raw(-838861);
  p.com_z_m = flight::LengthM::from_raw(838861);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  const RawPose pose{-241591897, 261786011, 22817013, -192565, -60397980, -34405};
  const flight::RoverAttitude att = attitude_of(pose);
  const flight::JointAnglesRad j = joints_of(pose);
  flight::DriveTorques t{};
  ground::DriveTorques ref_t{};
  for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
    t.usable[i] = (torque_nm[i] != 0.0);
    t.torque_nm[i] = q<flight::TorqueNm>(torque_nm[i]);
    ref_t.usable[i] = t.usable[i];
    ref_t.torque_nm[i] = d(t.torque_nm[i]);
  }
  const ground::WheelLoads ref =
      ground::wheel_loads(rover_test::to_ground(p), rover_test::to_ground(att), rover_test::to_ground(j), ref_t);
  ASSERT_EQ(ref.status, ground::LoadStatus::degenerate);
  const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), att, j, t);
  EXPECT_EQ(r.status, WheelLoadStatus::overflow);
  EXPECT_FALSE(r.torque_overload);
  EXPECT_EQ(r.torque_fallback_mask, 0x12U);  // wheels 1 and 4 had no torque
}

// The second set is five times larger: another quantity overflows the
// Q15.16 pass before its span guard, which still names the collapsed span
// (kSpanFits in wheel_load.cpp; the next fuzz finding).
TEST(RoverWheelLoad, ABalanceTakenForACollapsedSpanIsNotATorqueOverload) {
  expect_collapsed_span_with_torques({5364.285644531, 0.0, -1455.106323242, 4224.239959717, 0.0, 2839.290054321});
  expect_collapsed_span_with_torques({26251.858398438, 0.0, -7121.031158447, 20672.677886963, 0.0, 13894.979782104});
}

// Couples T / (m g cos(pitch) cos(roll)) beyond Q6.25 (a 10 g rover with
// 10 N m on a wheel: about 600 m), beyond Q10.21 (100 N m: about 6,000 m)
// and beyond Q15.16 (1,000 N m: about 60,000 m): the wider passes see the
// torques lift a wheel, or the balance with them leaves every format, so the
// loads are those without torques, flagged as an overload (section 12.4),
// never an overflow (the last one was, until session 14's fuzz finding).
TEST(RoverWheelLoad, CouplesBeyondEachFormatAreATorqueOverload) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.mass_kg = q<flight::MassKg>(0.01);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  const flight::WheelLoadResult plain = flight::wheel_loads(test::prepared_rover(p), flight::RoverAttitude{}, flight::JointAnglesRad{},
                                                            flight::kNoDriveTorques);
  ASSERT_EQ(plain.status, WheelLoadStatus::ok);
  for (const double torque_nm : {10.0, 100.0, 1000.0}) {
    flight::DriveTorques t{};
    t.usable[0] = true;
    t.torque_nm[0] = q<flight::TorqueNm>(torque_nm);
    const flight::WheelLoadResult r = flight::wheel_loads(test::prepared_rover(p), flight::RoverAttitude{}, flight::JointAnglesRad{}, t);
    EXPECT_EQ(r.status, WheelLoadStatus::ok) << torque_nm;
    EXPECT_TRUE(r.torque_overload) << torque_nm;
    EXPECT_EQ(r.torque_fallback_mask, flight::kEveryTorqueFallsBack) << torque_nm;
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      EXPECT_EQ(r.load_n[i], plain.load_n[i]) << torque_nm << " " << i;
    }
  }
}

// ------------------------------------------- the statics' checked operations

// The checked operations of the statics (rover_statics.hpp, detail) against
// the fx operations they stand for: the same bits and the same flags, at
// random and at the edges of the 32-bit range (docs/rover-loads.md 7.6).
namespace statics_arithmetic {

using P = flight::StaticsQ;

/// A raw 32-bit value: an edge of the range or of a sign, or a random one
/// of random length.
std::int32_t raw32(std::mt19937_64& rng) {
  switch (rng() % 10U) {
    case 0U: return INT32_MIN + static_cast<std::int32_t>(rng() % 3U);
    case 1U: return INT32_MAX - static_cast<std::int32_t>(rng() % 3U);
    case 2U: return static_cast<std::int32_t>(rng() % 5U) - 2;
    case 3U: return static_cast<std::int32_t>(0x40000000U) - static_cast<std::int32_t>(rng() % 3U);
    default: {
      const std::uint32_t bits = 1U + static_cast<std::uint32_t>(rng() % 31U);
      const auto mag = static_cast<std::int32_t>(rng() & ((std::uint64_t{1U} << bits) - 1U));
      return ((rng() % 2U) == 0U) ? mag : -mag;
    }
  }
}

/// A reciprocal: of a random divisor, or a random mantissa and scale (shifts
/// from below 0 to beyond 63), or none (mantissa 0).
fx::NormalisedReciprocal reciprocal(std::mt19937_64& rng) {
  switch (rng() % 4U) {
    case 0U: {
      const std::int32_t d = raw32(rng);
      return fx::normalised_reciprocal(P::from_raw((d == INT32_MIN) ? 1 : ((d < 0) ? -d : d)));
    }
    case 1U: return fx::NormalisedReciprocal{};
    default:
      return fx::NormalisedReciprocal{0x80000000U | static_cast<std::uint32_t>(rng() & 0x7FFFFFFFU),
                                      static_cast<std::int32_t>(rng() % 80U) - 10};
  }
}

/// detail::quotient against fx::times_reciprocal for one pair of formats.
template <typename Out, std::int32_t Fx>
int compare_quotients(std::mt19937_64& rng, int trials) {
  int saturated = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const fx::Q<std::int32_t, Fx> x = fx::Q<std::int32_t, Fx>::from_raw(raw32(rng));
    const fx::NormalisedReciprocal r = reciprocal(rng);
    fx::Status fast;
    fx::Status chain;
    const Out q = flight::detail::quotient<Out>(x, r, fast);
    const Out expected = fx::times_reciprocal<Out>(x, r, chain);
    EXPECT_EQ(q.raw(), expected.raw()) << x.raw() << " " << r.mantissa << " " << r.scale;
    EXPECT_EQ(fast.bits(), chain.bits()) << x.raw() << " " << r.mantissa << " " << r.scale;
    if (q.raw() != expected.raw()) {
      return -1;
    }
    saturated += chain.has(fx::Flag::overflow) ? 1 : 0;
  }
  return saturated;
}

TEST(StaticsArithmetic, QuotientIsTimesReciprocalBitForBit) {
  std::mt19937_64 rng(18U);
  // Every pair of formats the statics use (couples, levers, slopes).
  EXPECT_GT((compare_quotients<P, 25>(rng, 1000000)), 10000);
  EXPECT_GT((compare_quotients<P, 16>(rng, 500000)), 5000);
  EXPECT_GT((compare_quotients<flight::StaticsMidQ, 21>(rng, 300000)), 3000);
  EXPECT_GT((compare_quotients<flight::StaticsMidQ, 16>(rng, 300000)), 3000);
  EXPECT_GT((compare_quotients<flight::StaticsCoarseQ, 16>(rng, 300000)), 3000);
  EXPECT_GT((compare_quotients<fx::Q3_28, 30>(rng, 300000)), 3000);
}

/// detail::quotient_raw_in_range (the couples' quotients, their reciprocal
/// and shift tested once per cycle) against fx::times_reciprocal for Out
/// from Fx, over reciprocals that exist and shifts of 1 to 63: random
/// mantissas and the reciprocals of random divisors, shifts weighted to
/// those of the couples (about 30 to 40) and both ends.
template <typename Out, std::int32_t Fx>
int compare_quotients_in_range(std::mt19937_64& rng, int trials) {
  int saturated = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const std::int32_t x = raw32(rng);
    const auto shift = static_cast<std::int32_t>(
        ((trial % 3) == 0) ? (1U + (rng() % 63U)) : (((trial % 3) == 1) ? (28U + (rng() % 14U)) : (1U + (rng() % 4U))));
    fx::NormalisedReciprocal r{};
    if ((trial % 2) == 0) {
      const std::int32_t d = raw32(rng);
      // A positive divisor: d, or -d, or 1 for zero and INT32_MIN.
      r = fx::normalised_reciprocal(P::from_raw((d > 0) ? d : ((d > INT32_MIN) ? std::max(1, -d) : 1)));
    } else {
      r.mantissa = 0x80000000U | static_cast<std::uint32_t>(rng() & 0x7FFFFFFFU);
    }
    r.scale = (shift - Fx) + Out::frac_bits;
    fx::Status fast;
    fx::Status chain;
    const std::int32_t q = flight::detail::quotient_raw_in_range(x, r.mantissa, static_cast<std::uint32_t>(shift), fast);
    const Out expected = fx::times_reciprocal<Out>(fx::Q<std::int32_t, Fx>::from_raw(x), r, chain);
    EXPECT_EQ(q, expected.raw()) << x << " " << r.mantissa << " " << shift;
    EXPECT_EQ(fast.bits(), chain.bits()) << x << " " << r.mantissa << " " << shift;
    if ((q != expected.raw()) || (fast.bits() != chain.bits())) {
      return -1;
    }
    saturated += chain.has(fx::Flag::overflow) ? 1 : 0;
  }
  return saturated;
}

TEST(StaticsArithmetic, QuotientInRangeIsTimesReciprocalBitForBit) {
  std::mt19937_64 rng(15U);
  EXPECT_GT((compare_quotients_in_range<P, 16>(rng, 600000)), 10000);  // T / (m g)
  EXPECT_GT((compare_quotients_in_range<P, 25>(rng, 600000)), 10000);  // per weight / normal fraction
  // The ends of the shift and of x, each against each.
  for (const std::int32_t x : {INT32_MIN, INT32_MIN + 1, -1, 0, 1, INT32_MAX}) {
    for (const std::uint32_t mantissa : {0x80000000U, 0x80000001U, 0xFFFFFFFFU}) {
      for (std::int32_t shift = 1; shift < 64; ++shift) {
        fx::Status fast;
        fx::Status chain;
        const fx::NormalisedReciprocal r{mantissa, shift};
        const std::int32_t q = flight::detail::quotient_raw_in_range(x, mantissa, static_cast<std::uint32_t>(shift), fast);
        EXPECT_EQ(q, (fx::times_reciprocal<fx::Q<std::int32_t, 0>>(fx::Q<std::int32_t, 0>::from_raw(x), r, chain).raw()))
            << x << " " << mantissa << " " << shift;
        EXPECT_EQ(fast.bits(), chain.bits()) << x << " " << mantissa << " " << shift;
      }
    }
  }
}

// Both forms of the rounded shift (by words for ARMv6-M, by 64-bit shifts
// elsewhere) against fx::times_reciprocal's formula, for every shift: the
// host runs the words' form only here.
TEST(StaticsArithmetic, RoundedShiftByWordsIsTheWideShift) {
  std::mt19937_64 rng(18U);
  for (int trial = 0; trial < 200000; ++trial) {
    // Products below 2^63, of random length, with runs of ones and zeros
    // below the rounding bit weighted in.
    const std::uint32_t bits = 1U + static_cast<std::uint32_t>(rng() % 63U);
    std::uint64_t p = rng() & ((std::uint64_t{1U} << bits) - 1U);
    if ((trial % 4) == 1) {
      p |= (std::uint64_t{1U} << (bits - 1U)) - 1U;
    }
    for (std::uint32_t s = 1U; s < 64U; ++s) {
      const std::uint64_t exact = ((p >> (s - 1U)) + 1U) >> 1U;
      const flight::detail::WordMagnitude words = flight::detail::shifted_rounded_by_words(p, s);
      const flight::detail::WordMagnitude wide = flight::detail::shifted_rounded_wide(p, s);
      ASSERT_EQ(words.fits, exact < (std::uint64_t{1U} << 32U)) << p << " >> " << s;
      ASSERT_EQ(wide.fits, words.fits) << p << " >> " << s;
      if (words.fits) {
        ASSERT_EQ(words.mag, exact) << p << " >> " << s;
        ASSERT_EQ(wide.mag, exact) << p << " >> " << s;
      }
    }
  }
}

/// product_checked_by_words<Shift> against fx::mul (bits and flag) for two
/// Q values whose fraction bits add up to Shift more than the result's.
template <typename Out, std::int32_t Fa, std::int32_t Fb>
int compare_checked_products(std::mt19937_64& rng, int trials) {
  constexpr std::int32_t kShift = (Fa + Fb) - Out::frac_bits;
  int saturated = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::int32_t a = raw32(rng);
    std::int32_t b = raw32(rng);
    if ((trial % 5) == 0) {
      // Near the format's limits: a product within a few LSB of 2^31 either
      // side, and ties (b an odd multiple of half an LSB of the result).
      const std::uint32_t half = 1U << static_cast<std::uint32_t>(kShift - 1);
      a = static_cast<std::int32_t>(1U + (rng() % 255U)) * (((rng() % 2U) == 0U) ? 1 : -1);
      const std::uint64_t target = ((std::uint64_t{1U} << 31U) << static_cast<std::uint32_t>(kShift)) /
                                   static_cast<std::uint64_t>(a < 0 ? -a : a);
      const std::uint64_t near = (trial % 10 == 0) ? (target + (rng() % 7U)) - 3U
                                                   : (((rng() % 2U) == 0U) ? half : 3U * half);
      b = static_cast<std::int32_t>(std::min<std::uint64_t>(near, 0x7FFFFFFFU)) * (((rng() % 2U) == 0U) ? 1 : -1);
    }
    fx::Status words;
    fx::Status general;
    const std::int32_t q = flight::detail::product_checked_by_words<kShift>(a, b, words);
    const Out expected = fx::mul<Out>(fx::Q<std::int32_t, Fa>::from_raw(a), fx::Q<std::int32_t, Fb>::from_raw(b), general);
    EXPECT_EQ(q, expected.raw()) << a << " * " << b;
    EXPECT_EQ(words.bits(), general.bits()) << a << " * " << b;
    if (q != expected.raw()) {
      return -1;
    }
    saturated += general.has(fx::Flag::overflow) ? 1 : 0;
  }
  return saturated;
}

TEST(StaticsArithmetic, CheckedProductByWordsIsFxMulBitForBit) {
  std::mt19937_64 rng(25U);
  // The statics' Q6.25 products, and the shifts' ends.
  EXPECT_GT((compare_checked_products<P, 25, 25>(rng, 1000000)), 10000);
  EXPECT_GT((compare_checked_products<fx::Q<std::int32_t, 0>, 16, 1>(rng, 300000)), 3000);
  // (a shift of 31 leaves Q31.0 only for operands near both ends: fewer)
  EXPECT_GT((compare_checked_products<fx::Q<std::int32_t, 0>, 16, 15>(rng, 300000)), 100);
  EXPECT_GT((compare_checked_products<fx::Q<std::int32_t, 10>, 20, 20>(rng, 300000)), 3000);
}

/// A load as wheel_load.cpp's load_of forms it (fx::Bounded's product of a
/// share in [0, 1] and any weight of at least zero, in place or called)
/// against fx::mul<LoadQ>'s checked product of the same two values.
template <typename Share, fx::Rounding Where>
void expect_bounded_load_is_checked_product(std::int32_t share_raw, std::int32_t weight_raw) {
  using ShareB = fx::Bounded<Share, flight::bound_in<Share>(1.0)>;
  using Weight = fx::Bounded<flight::LoadQ, fx::kMaxBound>;
  fx::Status st;
  const flight::LoadQ checked = fx::mul<flight::LoadQ>(Share::from_raw(share_raw), flight::LoadQ::from_raw(weight_raw), st);
  const flight::LoadQ bounded =
      fx::mul<flight::LoadQ, Where>(ShareB::trusted(share_raw), Weight::trusted(weight_raw)).q();
  ASSERT_TRUE(st.ok()) << share_raw << " * " << weight_raw;
  ASSERT_EQ(bounded.raw(), checked.raw()) << share_raw << " * " << weight_raw;
}

template <typename Share>
void compare_bounded_loads(std::mt19937_64& rng, int trials) {
  constexpr auto kOne = static_cast<std::int32_t>(flight::bound_in<Share>(1.0));
  const std::int32_t edges[] = {0, 1, 2, kOne / 2, kOne - 1, kOne};
  for (int trial = 0; trial < trials; ++trial) {
    // Shares at the ends of [0, 1] and at random; weights of every length,
    // up to Q15.16's largest, and odd ones (ties of the rounding's half).
    const std::int32_t share = ((trial % 3) == 0) ? edges[static_cast<std::size_t>(trial / 3) % 6U]
                                                  : static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(kOne + 1));
    const std::uint32_t bits = static_cast<std::uint32_t>(rng() % 32U);
    const auto weight = static_cast<std::int32_t>((rng() & ((std::uint64_t{1U} << bits) - 1U)) | ((trial % 4) == 1 ? 1U : 0U));
    expect_bounded_load_is_checked_product<Share, fx::Rounding::inlined>(share, weight);
    expect_bounded_load_is_checked_product<Share, fx::Rounding::called>(share, weight);
    expect_bounded_load_is_checked_product<Share, fx::Rounding::inlined>(share, 0x7FFFFFFF - static_cast<std::int32_t>(trial % 5));
  }
}

TEST(StaticsArithmetic, BoundedLoadIsTheCheckedProduct) {
  std::mt19937_64 rng(31U);
  compare_bounded_loads<P>(rng, 300000);
  compare_bounded_loads<flight::StaticsMidQ>(rng, 100000);
  compare_bounded_loads<flight::StaticsCoarseQ>(rng, 100000);
  // The normal weight (wheel_load.cpp's body_of): a weight of at most
  // kWeightBound times any Q1.30 value but INT32_MIN, in place and called.
  using Weight = fx::Bounded<flight::LoadQ, flight::kWeightBound>;
  using Fraction = fx::Bounded<fx::Q1_30, fx::kMaxBound>;
  for (int trial = 0; trial < 300000; ++trial) {
    const auto w = static_cast<std::int32_t>(rng() % (std::uint64_t{flight::kWeightBound} + 1U));
    auto f = static_cast<std::int32_t>(rng()) >> static_cast<std::uint32_t>(rng() % 32U);
    f = ((trial % 5) == 0) ? (0x7FFFFFFF - (trial % 7)) * (((trial % 2) == 0) ? 1 : -1) : f;
    const auto weight = ((trial % 11) == 0) ? static_cast<std::int32_t>(flight::kWeightBound) : w;
    fx::Status st;
    const flight::LoadQ checked = fx::mul<flight::LoadQ>(flight::LoadQ::from_raw(weight), fx::Q1_30::from_raw(f), st);
    ASSERT_TRUE(st.ok()) << weight << " * " << f;
    ASSERT_EQ((fx::mul<flight::LoadQ, fx::Rounding::inlined>(Weight::trusted(weight), Fraction::trusted(f)).raw()),
              checked.raw())
        << weight << " * " << f;
    ASSERT_EQ((fx::mul<flight::LoadQ, fx::Rounding::called>(Weight::trusted(weight), Fraction::trusted(f)).raw()),
              checked.raw())
        << weight << " * " << f;
  }
  // Ties of the rounding's half: share 2^-1 LSB multiples times odd weights.
  for (std::int32_t w = 1; w < 5000; w += 2) {
    expect_bounded_load_is_checked_product<P, fx::Rounding::inlined>(1 << 24, w);
    expect_bounded_load_is_checked_product<P, fx::Rounding::inlined>(3 << 23, w);
  }
}

/// Whether fx::bound_sincos would leave fx::sincos(raw) as it is: its
/// magnitudes at most 2^30 and no flag (wheel_load.cpp's unit_sincos takes
/// the values without the tests).
bool sincos_within_one(std::int32_t raw) {
  fx::Status st;
  const fx::SinCos sc = fx::sincos(fx::Q3_28::from_raw(raw), st);
  const fx::BoundedSinCos bounded = fx::bound_sincos(sc, st);
  return st.ok() && (bounded.sin.raw() == sc.sin.raw()) && (bounded.cos.raw() == sc.cos.raw());
}

/// The gravity frame's slopes as gravity_frame forms them (wheel_load.cpp:
/// the normal fraction fx::mul's bits, each slope a quotient by a
/// normalised reciprocal), for pitch and roll in raw Q3.28; false where a
/// flag was raised or a slope leaves the bound wheel_load.cpp trusts it to
/// keep (kKxBound 3.51 and kKyBound 1.75 in Q3.28).
bool slopes_within_bounds(std::int32_t pitch_raw, std::int32_t roll_raw, std::int32_t kx_bound, std::int32_t ky_bound) {
  fx::Status st;
  const fx::SinCos pitch = fx::sincos(fx::Q3_28::from_raw(pitch_raw), st);
  const fx::SinCos roll = fx::sincos(fx::Q3_28::from_raw(roll_raw), st);
  const fx::Q1_30 normal_fraction = fx::mul(pitch.cos, roll.cos, st);
  const fx::NormalisedReciprocal inv_normal = fx::normalised_reciprocal(normal_fraction);
  const fx::Q3_28 kx = fx::times_reciprocal<fx::Q3_28>(pitch.sin, inv_normal, st);
  const fx::Q3_28 ky = fx::times_reciprocal<fx::Q3_28>(roll.sin, fx::normalised_reciprocal(roll.cos), st);
  // Both divisors positive: gravity_frame takes their reciprocals without
  // that test (detail::reciprocal_of_positive), and the couples' quotients
  // by the normal fraction (shift = its scale, Q6.25 to Q6.25) take its
  // mantissa and a shift of 29 to 32 untested (couples_of).
  return st.ok() && (normal_fraction.raw() <= 0x40000000) && (normal_fraction.raw() > 0) && (roll.cos.raw() > 0) &&
         (inv_normal.mantissa != 0U) && (inv_normal.scale >= 29) && (inv_normal.scale <= 32) &&
         (std::abs(kx.raw()) <= kx_bound) && (std::abs(ky.raw()) <= ky_bound);
}

// gravity_frame takes the slopes tan(pitch) / cos(roll) and tan(roll) as
// bounded values without testing them (Kx::trusted, Ky::trusted): within the
// attitude limit (1.05 rad) they are at most 3.5037 and 1.7433, rounding
// included. Every pair of the last 2^12 LSB below the limit at both signs,
// and random pairs within it.
TEST(StaticsArithmetic, GravitySlopesAreWithinTheirBounds) {
  constexpr std::int32_t kLimit = 281857229;  // kMaxAttitudeLimitRad in Q3.28
  constexpr std::int32_t kx_bound = fx::constant<fx::Q3_28>(3.51).raw();
  constexpr std::int32_t ky_bound = fx::constant<fx::Q3_28>(1.75).raw();
  constexpr std::int32_t kx_too_tight = fx::constant<fx::Q3_28>(3.50).raw();
  constexpr std::int32_t ky_too_tight = fx::constant<fx::Q3_28>(1.74).raw();
  for (std::int32_t dp = 0; dp < 4096; dp += 7) {
    for (std::int32_t dr = 0; dr < 4096; dr += 5) {
      for (const std::int32_t sp : {-1, 1}) {
        for (const std::int32_t sr : {-1, 1}) {
          ASSERT_TRUE(slopes_within_bounds(sp * (kLimit - dp), sr * (kLimit - dr), kx_bound, ky_bound)) << dp << " " << dr;
        }
      }
    }
  }
  std::mt19937_64 rng(15U);
  for (int trial = 0; trial < 200000; ++trial) {
    const auto pitch = static_cast<std::int32_t>(rng() % (2U * kLimit + 1U)) - kLimit;
    const auto roll = static_cast<std::int32_t>(rng() % (2U * kLimit + 1U)) - kLimit;
    ASSERT_TRUE(slopes_within_bounds(pitch, roll, kx_bound, ky_bound)) << pitch << " " << roll;
  }
  // The bounds are tight enough to matter: 3.50 does not hold at the limit.
  EXPECT_FALSE(slopes_within_bounds(kLimit, kLimit, kx_too_tight, ky_bound));
  EXPECT_FALSE(slopes_within_bounds(kLimit, kLimit, kx_bound, ky_too_tight));
}

TEST(StaticsArithmetic, JointSinesAndCosinesAreWithinOne) {
  // The joints' range: |rocker + bogie| <= 2 x 0.8 rad (kMaxJointLimitRad),
  // sampled every 97 LSB, and every angle within 2^18 LSB (1 mrad) of the
  // places where a sine or a cosine is one (0 and +-pi/2) and of the ends.
  constexpr std::int32_t kLimit = 429496730;  // 1.6 rad in Q3.28
  constexpr std::int32_t kHalfPi = 421657428;  // pi/2 in Q3.28, rounded
  for (std::int32_t raw = -kLimit; raw <= kLimit; raw += 97) {
    ASSERT_TRUE(sincos_within_one(raw)) << raw;
  }
  for (const std::int32_t centre : {-kLimit, -kHalfPi, 0, kHalfPi, kLimit}) {
    for (std::int32_t d = -(1 << 18); d <= (1 << 18); ++d) {
      ASSERT_TRUE(sincos_within_one(centre + d)) << centre + d;
    }
  }
}

TEST(StaticsArithmetic, RockerCosineIsPositive) {
  // rotate() takes a rocker angle's cosine as of sign bit 0
  // (detail::SignOf::positive): |rocker| <= 0.8 rad (kMaxJointLimitRad,
  // check_inputs), sampled every 97 LSB, and every angle within 2^18 LSB
  // (1 mrad) of the ends, where the cosine is smallest.
  constexpr std::int32_t kLimit = 214748365;  // 0.8 rad in Q3.28
  const auto cosine_positive = [](std::int32_t raw) {
    fx::Status st;
    return fx::sincos(fx::Q3_28::from_raw(raw), st).cos.raw() > 0;
  };
  for (std::int32_t raw = -kLimit; raw <= kLimit; raw += 97) {
    ASSERT_TRUE(cosine_positive(raw)) << raw;
  }
  for (const std::int32_t end : {-kLimit, kLimit}) {
    for (std::int32_t d = -(1 << 18); d <= 0; ++d) {
      ASSERT_TRUE(cosine_positive((end < 0) ? (end - d) : (end + d))) << end << " " << d;
    }
  }
}

/// detail::product_of_signs<30, SA, SB>(a, b) for b a sine or cosine
/// (|b| <= 2^30, so the product fits any a) with every choice of SA and SB
/// that a and b's sign bits allow, against fx::mul's checked product and
/// fx::detail::product_rounded_signed.
void expect_product_of_signs(std::int32_t a, std::int32_t b) {
  using Unit = fx::Q1_30;
  using flight::detail::SignOf;
  using flight::detail::product_of_signs;
  fx::Status st;
  const std::int32_t expected = fx::mul<P>(P::from_raw(a), Unit::from_raw(b), st).raw();
  ASSERT_TRUE(st.ok()) << a << " " << b;
  ASSERT_EQ(fx::detail::product_rounded_signed<30>(a, b), expected) << a << " " << b;
  ASSERT_EQ((product_of_signs<30, SignOf::any, SignOf::any>(a, b)), expected) << a << " " << b;
  if (a >= 0) {
    ASSERT_EQ((product_of_signs<30, SignOf::positive, SignOf::any>(a, b)), expected) << a << " " << b;
    if (b >= 0) {
      ASSERT_EQ((product_of_signs<30, SignOf::positive, SignOf::positive>(a, b)), expected) << a << " " << b;
      ASSERT_EQ((product_of_signs<30, SignOf::any, SignOf::positive>(a, b)), expected) << a << " " << b;
    }
  } else {
    ASSERT_EQ((product_of_signs<30, SignOf::negative, SignOf::any>(a, b)), expected) << a << " " << b;
    if (b >= 0) {
      ASSERT_EQ((product_of_signs<30, SignOf::negative, SignOf::positive>(a, b)), expected) << a << " " << b;
      ASSERT_EQ((product_of_signs<30, SignOf::any, SignOf::positive>(a, b)), expected) << a << " " << b;
    }
  }
}

TEST(StaticsArithmetic, ProductOfKnownSignsIsTheBoundedProduct) {
  std::mt19937_64 rng(16U);
  constexpr std::int32_t kOne = 0x40000000;  // 1 in Q1.30
  for (int trial = 0; trial < 2000000; ++trial) {
    // A bounded operand: of magnitude below 2^31 (fx::kMaxBound), where
    // -2^31 times -1 would leave the format.
    const std::int32_t a = std::max(raw32(rng), INT32_MIN + 1);
    // A sine or cosine: random within one, one, a half (ties for odd a), or near zero.
    constexpr std::uint64_t kUnits = (2U * static_cast<std::uint64_t>(kOne)) + 1U;  // -1 to 1
    std::int32_t b = static_cast<std::int32_t>(static_cast<std::int64_t>(rng() % kUnits) - kOne);
    switch (rng() % 4U) {
      case 0U: b = ((rng() % 2U) == 0U) ? kOne : -kOne; break;
      case 1U: b = (((rng() % 2U) == 0U) ? 1 : -1) * (kOne / 2); break;
      case 2U: b = static_cast<std::int32_t>(rng() % 5U) - 2; break;
      default: break;
    }
    ASSERT_NO_FATAL_FAILURE(expect_product_of_signs(a, b));
  }
}

/// detail::product_of_signs<S, positive, positive>(a, b) against fx::mul<Out>
/// for a, b >= 0 whose product fits Out: the statics' products of operands
/// known non-negative (wheel_load.cpp, product_of_non_negative): a share in
/// [0, 1] (Q6.25) times the normal weight (Q15.16, S = 25), the weight
/// times the normal fraction (Q15.16 by Q1.30, S = 30) and cos(pitch)
/// cos(roll) (S = 30).
template <typename A, typename B, typename Out>
void expect_non_negative_product(std::int32_t a, std::int32_t b) {
  using flight::detail::SignOf;
  constexpr std::int32_t kShift = (A::frac_bits + B::frac_bits) - Out::frac_bits;
  fx::Status st;
  const std::int32_t expected = fx::mul<Out>(A::from_raw(a), B::from_raw(b), st).raw();
  ASSERT_TRUE(st.ok()) << a << " " << b;
  ASSERT_EQ((flight::detail::product_of_signs<kShift, SignOf::positive, SignOf::positive>(a, b)), expected)
      << a << " " << b;
}

TEST(StaticsArithmetic, ProductOfNonNegativeOperandsIsTheBoundedProduct) {
  using flight::LoadQ;
  std::mt19937_64 rng(17U);
  constexpr std::int32_t kShareOne = 1 << 25;  // 1 in Q6.25
  constexpr std::int32_t kUnit = 1 << 30;      // 1 in Q1.30
  const std::int32_t share_edges[] = {0, 1, 2, 3, kShareOne / 2, (kShareOne / 2) + 1, kShareOne - 1, kShareOne};
  const std::int32_t weight_edges[] = {0, 1, 2, 3, 0x00800000, 0x00800001, 0x7FFFFFFE, INT32_MAX};
  const std::int32_t unit_edges[] = {0, 1, 2, 3, kUnit / 2, (kUnit / 2) + 1, kUnit - 1, kUnit};
  for (const std::int32_t share : share_edges) {
    for (const std::int32_t weight : weight_edges) {
      ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<P, LoadQ, LoadQ>(share, weight)));
    }
  }
  for (const std::int32_t fraction : unit_edges) {
    for (const std::int32_t weight : weight_edges) {
      ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<LoadQ, fx::Q1_30, LoadQ>(weight, fraction)));
    }
    for (const std::int32_t other : unit_edges) {
      ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<fx::Q1_30, fx::Q1_30, fx::Q1_30>(fraction, other)));
    }
  }
  for (int trial = 0; trial < 1000000; ++trial) {
    const auto weight = static_cast<std::int32_t>(rng() & 0x7FFFFFFFU);
    // Random shares and fractions, every fourth an odd multiple of half an
    // LSB of the product (a tie) where the weight's low bit allows.
    auto share = static_cast<std::int32_t>(rng() % (static_cast<std::uint64_t>(kShareOne) + 1U));
    auto fraction = static_cast<std::int32_t>(rng() % (static_cast<std::uint64_t>(kUnit) + 1U));
    if ((trial % 4) == 0) {
      share = kShareOne / 2;
      fraction = kUnit / 2;
    }
    ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<P, LoadQ, LoadQ>(share, weight)));
    ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<LoadQ, fx::Q1_30, LoadQ>(weight, fraction)));
    ASSERT_NO_FATAL_FAILURE((expect_non_negative_product<fx::Q1_30, fx::Q1_30, fx::Q1_30>(
        fraction, static_cast<std::int32_t>(rng() % (static_cast<std::uint64_t>(kUnit) + 1U)))));
  }
}

TEST(StaticsArithmetic, ReciprocalOfAQIsTheNormalisedReciprocal) {
  std::mt19937_64 rng(18U);
  for (int trial = 0; trial < 1000000; ++trial) {
    const P d = P::from_raw(raw32(rng));
    const fx::NormalisedReciprocal fast = flight::detail::reciprocal_of(d);
    const fx::NormalisedReciprocal general = fx::normalised_reciprocal(d);
    ASSERT_EQ(fast.mantissa, general.mantissa) << d.raw();
    ASSERT_EQ(fast.scale, general.scale) << d.raw();
    const fx::Q1_30 c = fx::Q1_30::from_raw(raw32(rng));
    ASSERT_EQ(flight::detail::reciprocal_of(c).mantissa, fx::normalised_reciprocal(c).mantissa) << c.raw();
    ASSERT_EQ(flight::detail::reciprocal_of(c).scale, fx::normalised_reciprocal(c).scale) << c.raw();
    // Without the sign test, for the positive divisors its callers give it.
    const fx::Q1_30 positive = fx::Q1_30::from_raw(std::max(1, static_cast<std::int32_t>(raw32(rng) & INT32_MAX)));
    ASSERT_EQ(flight::detail::reciprocal_of_positive(positive).mantissa,
              fx::normalised_reciprocal(positive).mantissa)
        << positive.raw();
    ASSERT_EQ(flight::detail::reciprocal_of_positive(positive).scale, fx::normalised_reciprocal(positive).scale)
        << positive.raw();
  }
  // Each bit length's ends (1, 2^k - 1, 2^k, 2^k + 1) up to INT32_MAX.
  for (std::uint32_t k = 0U; k < 31U; ++k) {
    const std::int64_t p = std::int64_t{1} << k;
    for (const std::int64_t raw : {p - 1, p, p + 1, (2 * p) - 1}) {
      if ((raw < 1) || (raw > INT32_MAX)) {
        continue;
      }
      const fx::Q1_30 d = fx::Q1_30::from_raw(static_cast<std::int32_t>(raw));
      ASSERT_EQ(flight::detail::reciprocal_of_positive(d).mantissa, fx::normalised_reciprocal(d).mantissa) << raw;
      ASSERT_EQ(flight::detail::reciprocal_of_positive(d).scale, fx::normalised_reciprocal(d).scale) << raw;
    }
  }
}

}  // namespace statics_arithmetic

}  // namespace
}  // namespace sinkwatch
