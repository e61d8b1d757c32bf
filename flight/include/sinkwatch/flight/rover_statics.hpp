// rover_statics.hpp: the rover's lengths and weight in the formats of the
// wheel-load statics (wheel_load.hpp; docs/rover-loads.md, section 7.4),
// converted once per parameter load instead of once per control cycle.
//
// The statics solve every balance in metres, with forces as fractions of the
// normal weight, first in Q6.25 and, where an intermediate leaves it (a
// quotient by a lever of a few millimetres, far beyond the stability limit),
// again in Q10.21 and then Q15.16 (docs/rover-loads.md, section 7.4). The
// link vectors, the half track, the centre of mass, the weight m g and its
// reciprocal depend only on the rover parameters, so prepare() converts them
// once into each of the three formats (PreparedParameters holds them: 204
// bytes, none of them on the step's stack) and each cycle starts from the
// attitude and the joint angles. For parameters that validate_rover_params()
// accepts every length is at most 4 m (rover_limits.hpp): its conversion from
// Q7.24 is exact in Q6.25 and rounded once in Q10.21 and Q15.16, the same
// values the passes computed per cycle before session 16.
//
// The lengths are held as fx::Bounded values (fixedpoint/bounded.hpp) under
// the bounds validation guarantees, so the statics' geometry (rotations,
// sums and projections of positions) needs no saturation check per cycle:
// each bound below is a limit of rover_limits.hpp in the format P.
#ifndef SINKWATCH_FLIGHT_ROVER_STATICS_HPP
#define SINKWATCH_FLIGHT_ROVER_STATICS_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

/// The statics' formats: metres and shares of the normal weight.
using StaticsQ = fx::Q<std::int32_t, 25>;        ///< Q6.25, every cycle's first evaluation
using StaticsMidQ = fx::Q<std::int32_t, 21>;     ///< Q10.21, where Q6.25 overflowed
using StaticsCoarseQ = fx::Q<std::int32_t, 16>;  ///< Q15.16, where Q10.21 overflowed too

/// The raw magnitude of `metres` in P (a limit of rover_limits.hpp).
template <typename P>
constexpr std::uint32_t bound_in(double metres) noexcept {
  return static_cast<std::uint32_t>(fx::constant<P>(metres).raw());
}
/// |link component|, |centre of mass|, track / 2: at most kMaxLinkM (2 m; a
/// track of at most 4 m), exact on every grid, so rounding stays within it.
template <typename P>
constexpr std::uint32_t kLinkBound = bound_in<P>(limits::kMaxLinkM);
/// The wheel radius: at most kMaxWheelRadiusM (1 m).
template <typename P>
constexpr std::uint32_t kRadiusBound = bound_in<P>(limits::kMaxWheelRadiusM);

template <typename P>
using StaticsLength = fx::Bounded<P, kLinkBound<P>>;
/// A link vector in one side's plane (x forward, z up), in the format P.
template <typename P>
using StaticsLink = fx::BoundedPoint<P, kLinkBound<P>>;

/// The rover's constant quantities of the statics, in the format P.
template <typename P>
struct StaticsConstants {
  StaticsLink<P> rocker_front;  ///< RoverParams::rocker_front_axle
  StaticsLink<P> rocker_bogie;  ///< RoverParams::rocker_bogie_pivot
  StaticsLink<P> bogie_middle;  ///< RoverParams::bogie_middle_axle
  StaticsLink<P> bogie_rear;    ///< RoverParams::bogie_rear_axle
  fx::Bounded<P, kRadiusBound<P>> wheel_radius;  ///< contacts lie one radius below the axles
  StaticsLength<P> half_track;                   ///< half the track width
  StaticsLength<P> com_x;                        ///< the centre of mass, body frame
  StaticsLength<P> com_y;
  StaticsLength<P> com_z;
  WheelLoadN weight_n;                  ///< m g, newtons (Q15.16, rounded once)
  fx::NormalisedReciprocal inv_weight;  ///< 1 / (m g), from the exact product of mass and gravity
};

/// The constants in each of the statics' formats.
struct RoverStatics {
  StaticsConstants<StaticsQ> fine;
  StaticsConstants<StaticsMidQ> mid;
  StaticsConstants<StaticsCoarseQ> coarse;
};

/// The constants of `params`, which validate_rover_params() accepted (for
/// other parameters the values are meaningless; prepare() only keeps them
/// with a valid rover).
[[nodiscard]] RoverStatics make_rover_statics(const RoverParams& params) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ROVER_STATICS_HPP
