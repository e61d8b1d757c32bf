// rover_limits.hpp: the facts the flight code and its double twin share, as
// plain numbers with their units in the names: the wheel count, the surface
// gravities, the validity limits of the rover parameters and the assumed
// Yutu-like default rover (docs/rover-loads.md, section 5).
//
// One place for each number, so that the two sides cannot drift (before this
// header the minimum wheel radius was 0.01 m in the flight check and "> 0" in
// the twin's). The flight code turns the doubles into its Q formats at
// compile time through fx::constant (rover_geometry.hpp, wheel_load.cpp); the
// twin (ground/reference) reads them as they are. No code here, only
// constexpr values: nothing of it reaches the step at run time (deviation
// D-01, docs/misra.md: doubles only in constant evaluation; the firmware
// symbol check proves no floating point is left in the object code).
//
// A bound that is not a dyadic fraction (0.01 m, 0.8 rad, 1.05 rad) is given
// as its nearest value in the flight field's Q format (raw / 2^fraction bits,
// the value fx::constant rounds the decimal to), so that
// fx::constant takes it exactly and both sides compare against the same
// number: a flight value exactly on the bound, converted to double by
// ground::from_flight(), is accepted by the twin too. host_tests/rover/
// test_rover_limits.cpp checks that they agree on and 1e-4 around each bound.
//
// Validity intervals (validate_rover_params(), ground::validate()):
//   mass          (0, kMaxMassKg]
//   gravity       (0, kMaxGravityMps2]
//   wheel radius  [kMinWheelRadiusM, kMaxWheelRadiusM]
//   track width   (0, kMaxTrackWidthM]
//   links, com    |v| <= kMaxLinkM, |com_y| < track / 2
//   joint limits  (0, kMaxJointLimitRad]
//   attitude      (0, kMaxAttitudeLimitRad]
//   high slip     (0, kMaxHighSlip]
#ifndef SINKWATCH_FLIGHT_ROVER_LIMITS_HPP
#define SINKWATCH_FLIGHT_ROVER_LIMITS_HPP

#include <cstdint>

namespace sinkwatch {
namespace flight {
namespace limits {

/// Wheels of the rover: every per-wheel array of the flight module, the C
/// interface (SW_WHEELS) and the twin has this many entries.
constexpr std::uint8_t kWheelCount = 6U;

/// Surface gravities, m/s^2.
constexpr double kGravityMoonMps2 = 1.62;
constexpr double kGravityMarsMps2 = 3.71;
constexpr double kGravityEarthMps2 = 9.81;

/// Upper (and the wheel radius's lower) bounds of the rover parameters.
constexpr double kMaxMassKg = 1000.0;
constexpr double kMaxGravityMps2 = 10.0;
constexpr double kMinWheelRadiusM = 167772.0 / 16777216.0;  ///< 0.01 m on the Q7.24 grid (0.01 - 9.5e-9 m)
constexpr double kMaxWheelRadiusM = 1.0;
/// The estimator's (and the parameter table's) wheel radius is
/// [kMinWheelRadiusM, kMaxEstimatorRadiusM]: wider than the rover model's.
constexpr double kMaxEstimatorRadiusM = 2.0;
constexpr double kMaxTrackWidthM = 4.0;
constexpr double kMaxLinkM = 2.0;
constexpr double kMaxJointLimitRad = 214748365.0 / 268435456.0;     ///< 0.8 rad on the Q3.28 grid
constexpr double kMaxAttitudeLimitRad = 281857229.0 / 268435456.0;  ///< 1.05 rad on the Q3.28 grid
constexpr double kMaxHighSlip = 1.0;

/// The assumed Yutu-like rover: 140 kg and the 0.15 m wheel radius are
/// published, the link lengths and limits are assumed (docs/rover-loads.md).
/// Link points are (x forward, z up) in the side's plane.
struct YutuLike {
  static constexpr double kMassKg = 140.0;
  static constexpr double kComXM = 0.0;
  static constexpr double kComYM = 0.0;
  static constexpr double kComZM = 0.10;
  static constexpr double kTrackWidthM = 0.90;
  static constexpr double kWheelRadiusM = 0.15;
  static constexpr double kRockerFrontAxleXM = 0.50;
  static constexpr double kRockerFrontAxleZM = -0.30;
  static constexpr double kRockerBogiePivotXM = -0.25;
  static constexpr double kRockerBogiePivotZM = -0.15;
  static constexpr double kBogieMiddleAxleXM = 0.25;
  static constexpr double kBogieMiddleAxleZM = -0.15;
  static constexpr double kBogieRearAxleXM = -0.25;
  static constexpr double kBogieRearAxleZM = -0.15;
  static constexpr double kRockerLimitRad = 0.35;
  static constexpr double kBogieLimitRad = 0.50;
  static constexpr double kAttitudeLimitRad = 1.0;
  static constexpr double kHighSlip = 0.6;
};

}  // namespace limits
}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ROVER_LIMITS_HPP
