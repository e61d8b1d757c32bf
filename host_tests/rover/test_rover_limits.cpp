// test_rover_limits.cpp: the flight check (validate_rover_params) and the
// double twin's (ground::validate) read their bounds from one header
// (flight/rover_limits.hpp), so they must refuse and accept the same values
// at every bound: on the bound itself and 1e-4 (more than one LSB of every
// field's Q format) either side. Also: the twin's Yutu-like default and the
// flight one are the same rover, and from_flight() carries every field.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/ground/from_flight.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "sinkwatch/ground/rover_loads.hpp"
#include "../flight/quantity_support.hpp"

namespace {

using namespace sinkwatch;
using flight::RoverParams;
using ground::RoverGeometry;
using sinkwatch::test::q;
namespace lim = flight::limits;

/// One field, set to the same double on both sides (the flight side rounds
/// to its Q format).
struct Field {
  const char* name;
  double lower;  ///< the lower bound (0 for the "(0, max]" ranges)
  double upper;
  void (*set_flight)(RoverParams&, double);
  void (*set_twin)(RoverGeometry&, double);
};

const Field kFields[] = {
    {"mass", 0.0, lim::kMaxMassKg, [](RoverParams& p, double v) { p.mass_kg = q<flight::MassKg>(v); },
     [](RoverGeometry& g, double v) { g.mass_kg = v; }},
    {"gravity", 0.0, lim::kMaxGravityMps2,
     [](RoverParams& p, double v) { p.gravity_mps2 = q<flight::AccelMps2>(v); },
     [](RoverGeometry& g, double v) { g.gravity_mps2 = v; }},
    {"wheel radius", lim::kMinWheelRadiusM, lim::kMaxWheelRadiusM,
     [](RoverParams& p, double v) { p.wheel_radius_m = q<flight::LengthM>(v); },
     [](RoverGeometry& g, double v) { g.wheel_radius_m = v; }},
    {"track width", 0.0, lim::kMaxTrackWidthM,
     [](RoverParams& p, double v) { p.track_width_m = q<flight::LengthM>(v); },
     [](RoverGeometry& g, double v) { g.track_width_m = v; }},
    {"com x", -lim::kMaxLinkM, lim::kMaxLinkM, [](RoverParams& p, double v) { p.com_x_m = q<flight::LengthM>(v); },
     [](RoverGeometry& g, double v) { g.com_x_m = v; }},
    {"front axle z", -lim::kMaxLinkM, lim::kMaxLinkM,
     [](RoverParams& p, double v) { p.rocker_front_axle.z_m = q<flight::LengthM>(v); },
     [](RoverGeometry& g, double v) { g.rocker_front_axle.z_m = v; }},
    {"rocker limit", 0.0, lim::kMaxJointLimitRad,
     [](RoverParams& p, double v) { p.rocker_limit_rad = q<flight::AngleRad>(v); },
     [](RoverGeometry& g, double v) { g.rocker_limit_rad = v; }},
    {"bogie limit", 0.0, lim::kMaxJointLimitRad,
     [](RoverParams& p, double v) { p.bogie_limit_rad = q<flight::AngleRad>(v); },
     [](RoverGeometry& g, double v) { g.bogie_limit_rad = v; }},
    {"attitude limit", 0.0, lim::kMaxAttitudeLimitRad,
     [](RoverParams& p, double v) { p.attitude_limit_rad = q<flight::AngleRad>(v); },
     [](RoverGeometry& g, double v) { g.attitude_limit_rad = v; }},
};

bool flight_accepts(const Field& f, double v) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  f.set_flight(p, v);
  return flight::validate_rover_params(p) == flight::RoverParamStatus::ok;
}

bool twin_accepts(const Field& f, double v) {
  RoverGeometry g = ground::yutu_like_geometry();
  f.set_twin(g, v);
  return ground::validate(g).empty();
}

constexpr double kStep = 1e-4;

TEST(RoverLimits, FlightAndTwinAgreeOnAndAroundEveryBound) {
  for (const Field& f : kFields) {
    for (const double bound : {f.lower, f.upper}) {
      for (const double v : {bound - kStep, bound, bound + kStep}) {
        EXPECT_EQ(flight_accepts(f, v), twin_accepts(f, v)) << f.name << " = " << v;
      }
    }
  }
}

TEST(RoverLimits, EachBoundIsWhereAcceptanceChanges) {
  // The (0, max] ranges refuse 0; the closed radius range accepts its minimum.
  for (const Field& f : kFields) {
    EXPECT_TRUE(flight_accepts(f, f.upper)) << f.name;
    EXPECT_FALSE(flight_accepts(f, f.upper + kStep)) << f.name;
    EXPECT_FALSE(twin_accepts(f, f.upper + kStep)) << f.name;
    EXPECT_TRUE(flight_accepts(f, f.lower + kStep)) << f.name;
    EXPECT_FALSE(flight_accepts(f, f.lower - kStep)) << f.name;
  }
}

TEST(RoverLimits, BoundsOnTheQGridAreTheFlightBoundsOfBefore) {
  // Same raw values as the decimal literals the flight code used before.
  EXPECT_EQ(q<flight::LengthM>(lim::kMinWheelRadiusM).raw(), q<flight::LengthM>(0.01).raw());
  EXPECT_EQ(q<flight::AngleRad>(lim::kMaxJointLimitRad).raw(), q<flight::AngleRad>(0.8).raw());
  EXPECT_EQ(q<flight::AngleRad>(lim::kMaxAttitudeLimitRad).raw(), q<flight::AngleRad>(1.05).raw());
}

TEST(RoverLimits, AFlightValueOnABoundConvertedByFromFlightPassesTheTwin) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMoon);
  p.wheel_radius_m = q<flight::LengthM>(lim::kMinWheelRadiusM);
  p.rocker_limit_rad = q<flight::AngleRad>(lim::kMaxJointLimitRad);
  p.attitude_limit_rad = q<flight::AngleRad>(lim::kMaxAttitudeLimitRad);
  ASSERT_EQ(flight::validate_rover_params(p), flight::RoverParamStatus::ok);
  EXPECT_EQ(ground::validate(ground::from_flight(p)), "");
  namespace ref = ground::reference;
  EXPECT_NO_THROW(static_cast<void>(
      ref::sinkage_m(ref::Coefficients{1.0, 1.0, 0.13}, fx::to_double(flight::kMinRadiusM.q()), 100.0, 10.0, 30.0)));
}

TEST(RoverLimits, TheTwinRefusesAWheelRadiusTheFlightCodeRefuses) {
  // Before the shared header the twin accepted any radius > 0.
  const Field& radius = kFields[2];
  EXPECT_FALSE(flight_accepts(radius, 0.005));
  EXPECT_FALSE(twin_accepts(radius, 0.005));
  EXPECT_TRUE(twin_accepts(radius, lim::kMinWheelRadiusM));
}

TEST(RoverLimits, TheEstimatorTwinRefusesTheRadiiTheFlightEstimatorRefuses) {
  namespace ref = ground::reference;
  const ref::Coefficients c{1.0, 1.0, 0.13};
  // Before the shared header the twin took any radius > 0.
  EXPECT_THROW(static_cast<void>(ref::sinkage_m(c, 0.005, 100.0, 10.0, 30.0)), std::invalid_argument);
  EXPECT_THROW(static_cast<void>(ref::sinkage_m(c, lim::kMinWheelRadiusM - kStep, 100.0, 10.0, 30.0)),
               std::invalid_argument);
  EXPECT_NO_THROW(static_cast<void>(ref::sinkage_m(c, lim::kMinWheelRadiusM, 100.0, 10.0, 30.0)));
  EXPECT_TRUE(flight::kMinRadiusM.raw() > q<flight::LengthM>(lim::kMinWheelRadiusM - kStep).raw());
  EXPECT_EQ(flight::kMinRadiusM.raw(), q<flight::LengthM>(lim::kMinWheelRadiusM).raw());
}

TEST(RoverLimits, TheYutuLikeDefaultsAreOneRover) {
  const RoverGeometry twin = ground::yutu_like_geometry(ground::k_gravity_moon_mps2);
  const RoverParams fixed = flight::yutu_like_rover_params(flight::kGravityMoon);
  const RoverGeometry converted = ground::from_flight(fixed);
  const double lsb = std::ldexp(1.0, -16);  // the coarsest format (mass, Q15.16)
  EXPECT_NEAR(converted.mass_kg, twin.mass_kg, lsb);
  EXPECT_NEAR(converted.gravity_mps2, twin.gravity_mps2, lsb);
  EXPECT_NEAR(converted.com_z_m, twin.com_z_m, lsb);
  EXPECT_NEAR(converted.track_width_m, twin.track_width_m, lsb);
  EXPECT_NEAR(converted.wheel_radius_m, twin.wheel_radius_m, lsb);
  EXPECT_NEAR(converted.rocker_front_axle.x_m, twin.rocker_front_axle.x_m, lsb);
  EXPECT_NEAR(converted.rocker_front_axle.z_m, twin.rocker_front_axle.z_m, lsb);
  EXPECT_NEAR(converted.rocker_bogie_pivot.x_m, twin.rocker_bogie_pivot.x_m, lsb);
  EXPECT_NEAR(converted.bogie_middle_axle.z_m, twin.bogie_middle_axle.z_m, lsb);
  EXPECT_NEAR(converted.bogie_rear_axle.x_m, twin.bogie_rear_axle.x_m, lsb);
  EXPECT_NEAR(converted.rocker_limit_rad, twin.rocker_limit_rad, lsb);
  EXPECT_NEAR(converted.bogie_limit_rad, twin.bogie_limit_rad, lsb);
  EXPECT_NEAR(converted.attitude_limit_rad, twin.attitude_limit_rad, lsb);
  EXPECT_NEAR(ground::high_slip_of(fixed), lim::YutuLike::kHighSlip, lsb);
  EXPECT_TRUE(ground::validate(converted).empty());
}

TEST(RoverLimits, FromFlightCarriesEachFieldExactly) {
  RoverParams p = flight::yutu_like_rover_params(flight::kGravityMars);
  p.com_y_m = flight::LengthM::from_raw(12345);
  p.bogie_rear_axle.z_m = flight::LengthM::from_raw(-777777);
  const RoverGeometry g = ground::from_flight(p);
  EXPECT_EQ(g.com_y_m, fx::to_double(p.com_y_m.q()));
  EXPECT_EQ(g.bogie_rear_axle.z_m, fx::to_double(p.bogie_rear_axle.z_m.q()));
  EXPECT_EQ(g.gravity_mps2, fx::to_double(flight::kGravityMars.q()));
  EXPECT_EQ(g.com_x_m, fx::to_double(p.com_x_m.q()));
}

}  // namespace
