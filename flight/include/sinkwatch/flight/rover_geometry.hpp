// rover_geometry.hpp: the rover's mass, centre of mass and rocker-bogie
// geometry, as one validated parameter struct, and the physical quantities the
// rover-level functions add to units.hpp (angles, mass, acceleration, speed).
//
// It feeds the quasi-static wheel-load model (wheel_load.hpp) and the
// drawbar-pull balance (drawbar_pull.hpp): the paper's section 7 needs each
// wheel's load W and drawbar pull DP for Eq. 15 and names "wheel-load
// estimation from the vehicle's kinematic and dynamic model" as a key
// technology. docs/rover-loads.md defines every field, the frames and the
// sign conventions, and gives the assumed Yutu-like default.
//
// Q formats (docs/rover-loads.md, section 7):
//   angle        AngleRad      Q3.28   +-8 rad        3.7e-9 rad
//   mass         MassKg        Q15.16  +-32768 kg     1.5e-5 kg
//   acceleration AccelMps2     Q7.24   +-128 m/s^2    6.0e-8 m/s^2
//   speed        SpeedMps      Q7.24   +-128 m/s      6.0e-8 m/s
//   lengths      LengthM       Q7.24   (units.hpp)
#ifndef SINKWATCH_FLIGHT_ROVER_GEOMETRY_HPP
#define SINKWATCH_FLIGHT_ROVER_GEOMETRY_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

using MassQ = fx::Q<std::int32_t, 16>;   ///< Q15.16, kilograms
using AccelQ = fx::Q<std::int32_t, 24>;  ///< Q7.24, m/s^2
using SpeedQ = fx::Q<std::int32_t, 24>;  ///< Q7.24, m/s

struct MassTag;
struct AccelTag;
struct SpeedTag;

using MassKg = Quantity<MassTag, MassQ>;
using AccelMps2 = Quantity<AccelTag, AccelQ>;
using SpeedMps = Quantity<SpeedTag, SpeedQ>;

/// Wheels in the order used by every rover-level array: left front, middle,
/// rear, then right front, middle, rear.
constexpr std::uint32_t kWheelCount = limits::kWheelCount;
constexpr std::uint32_t kSideCount = 2U;  ///< 0 = left, 1 = right

/// A point in one side's plane (x forward, z up) relative to the link's pivot.
struct SidePointM {
  LengthM x_m;
  LengthM z_m;
};

/// Surface gravities.
constexpr AccelMps2 kGravityMoon{fx::constant<AccelQ>(limits::kGravityMoonMps2)};
constexpr AccelMps2 kGravityMars{fx::constant<AccelQ>(limits::kGravityMarsMps2)};
constexpr AccelMps2 kGravityEarth{fx::constant<AccelQ>(limits::kGravityEarthMps2)};

/// Mass and suspension of a six-wheel rocker-bogie rover with a differential.
/// Body frame: x forward, y left, z up, origin midway between the rocker
/// pivots. Both sides are mirror images. All link vectors are at zero joint
/// angle.
struct RoverParams {
  MassKg mass_kg;            ///< whole rover; rockers and bogies lumped into the body
  AccelMps2 gravity_mps2;    ///< of the body the rover stands on (kGravity*)
  LengthM com_x_m;           ///< centre of mass, body frame
  LengthM com_y_m;
  LengthM com_z_m;
  LengthM track_width_m;     ///< between the left and right wheel contact lines
  LengthM wheel_radius_m;
  SidePointM rocker_front_axle;   ///< front axle from the rocker pivot
  SidePointM rocker_bogie_pivot;  ///< bogie pivot from the rocker pivot
  SidePointM bogie_middle_axle;   ///< middle axle from the bogie pivot
  SidePointM bogie_rear_axle;     ///< rear axle from the bogie pivot
  AngleRad rocker_limit_rad;      ///< |rocker angle| the mechanism allows
  AngleRad bogie_limit_rad;       ///< |bogie angle| the mechanism allows
  AngleRad attitude_limit_rad;    ///< |pitch|, |roll| the model accepts
  /// Slip at or above which every wheel's drawbar pull is taken at the
  /// soil-bin DP_max (drawbar_pull.hpp); in (0, 1].
  Ratio high_slip;
};

/// Why a RoverParams was rejected; `ok` when it is usable.
enum class RoverParamStatus : std::uint8_t {
  ok = 0U,
  bad_mass = 1U,            ///< outside (0, 1000] kg
  bad_gravity = 2U,         ///< outside (0, 10] m/s^2
  bad_wheel_radius = 3U,    ///< outside [0.01, 1] m (rover_limits.hpp for every bound)
  bad_track_width = 4U,     ///< outside (0, 4] m
  bad_com = 5U,             ///< |y| not inside the track, or |x|, |z| > 2 m
  bad_link_order = 6U,      ///< front axle not ahead of the rocker pivot, and so on
  bad_link_length = 7U,     ///< a link coordinate beyond +-2 m
  bad_joint_limit = 8U,     ///< a joint limit outside (0, 0.8] rad
  bad_attitude_limit = 9U,  ///< outside (0, 1.05] rad (60 deg)
  bad_high_slip = 10U,      ///< outside (0, 1]
  bad_encoding = 11U,       ///< parameter-table section absent, wrong length or layout
};

/// Checks every field; the first failing rule is reported.
[[nodiscard]] RoverParamStatus validate_rover_params(const RoverParams& p) noexcept;

namespace detail {
/// Built once at compile time (a variable, not a function body), so that no
/// fx::constant is ever evaluated at run time, even in a -O0 build.
using Yutu = limits::YutuLike;
// Deviation D-01 (docs/misra.md): these two take a double and exist only for
// kYutuLikeRoverParams' constant initialiser below; a run-time call would
// link a soft-float routine, which the firmware symbol check refuses.
constexpr LengthM length_m(double v) noexcept { return LengthM{fx::constant<LengthQ>(v)}; }
constexpr AngleRad angle_rad(double v) noexcept { return AngleRad{fx::constant<AngleQ>(v)}; }
constexpr RoverParams kYutuLikeRoverParams{
    MassKg{fx::constant<MassQ>(Yutu::kMassKg)},
    kGravityMoon,
    length_m(Yutu::kComXM),
    length_m(Yutu::kComYM),
    length_m(Yutu::kComZM),
    length_m(Yutu::kTrackWidthM),
    length_m(Yutu::kWheelRadiusM),
    SidePointM{length_m(Yutu::kRockerFrontAxleXM), length_m(Yutu::kRockerFrontAxleZM)},
    SidePointM{length_m(Yutu::kRockerBogiePivotXM), length_m(Yutu::kRockerBogiePivotZM)},
    SidePointM{length_m(Yutu::kBogieMiddleAxleXM), length_m(Yutu::kBogieMiddleAxleZM)},
    SidePointM{length_m(Yutu::kBogieRearAxleXM), length_m(Yutu::kBogieRearAxleZM)},
    angle_rad(Yutu::kRockerLimitRad),
    angle_rad(Yutu::kBogieLimitRad),
    angle_rad(Yutu::kAttitudeLimitRad),
    Ratio{fx::constant<RatioQ>(Yutu::kHighSlip)},
};
}  // namespace detail

/// The assumed Yutu-like rover (docs/rover-loads.md, section 5): 140 kg and
/// the 0.15 m wheel radius are published, the link lengths are assumed.
[[nodiscard]] constexpr RoverParams yutu_like_rover_params(AccelMps2 gravity_mps2) noexcept {
  RoverParams p = detail::kYutuLikeRoverParams;
  p.gravity_mps2 = gravity_mps2;
  return p;
}

// ------------------------------------------------ parameter-table section 6
//
// The rover geometry travels in the parameter table's section 6
// (SectionId::rover_geometry, ParameterTable::rover_geometry), a typed section
// that the table's codec (flight/src/table_codec.cpp) writes and reads from
// its one field list and validate() checks with validate_rover_params().
// Layout, little-endian:
//   u16 layout version (kRoverSectionLayout), u16 zero,
//   then every RoverParams field in declaration order as the raw int32 of its
//   Q value (mass, gravity, com x y z, track, radius, the four link points
//   x then z, the three limits, high_slip): 19 x 4 bytes.

constexpr std::uint16_t kRoverSectionLayout = 1U;
constexpr std::uint16_t kRoverSectionBytes = 4U + (19U * 4U);

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ROVER_GEOMETRY_HPP
