// drawbar_pull.hpp: each wheel's drawbar pull DP from the rover's motion, the
// paper's key technology 4 ("drawbar-pull estimation from the rover's
// behaviour", section 7), for Eq. 15.
//
// Along the path the wheels' net tractions balance gravity and inertia:
//
//     sum_i DP_i = m (a + g sin(pitch))          (docs/rover-loads.md, 6.1)
//
// with a the acceleration along the path (IMU or odometry / VO) and pitch the
// path slope. The total is split in proportion to the wheel loads,
// DP_i = total W_i / sum(W), so that every wheel has the same DP/W, the
// paper's own normalisation (choice justified in docs/rover-loads.md, 6.2).
// Each share is limited to +-DP_max,i = +-(DP_max/W)_i W_i, the soil-bin
// plateau at high slip (Fig. 10); when the measured slip is at or above the
// high-slip level, every wheel is taken at DP_max,i, as the paper proposes.
//
// Fixed point: total in Q31.32, shares rounded once to Q15.16; the error
// bound is in docs/rover-loads.md, section 7, asserted by
// props/rover/prop_drawbar_pull.cpp against ground/reference rover_loads.hpp.
#ifndef SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP
#define SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP

#include <cstdint>

#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace flight {

/// Accepted magnitude of the along-path acceleration: far above anything a
/// rover does at walking pace, so a larger value is a sensor fault.
constexpr AccelMps2 kMaxAbsAccel{fx::constant<AccelQ>(10.0)};
/// Accepted range of DP_max/W (the correction table's own range).
constexpr Ratio kMaxDpMaxRatio{fx::constant<RatioQ>(2.0)};

struct DrawbarInput {
  AccelMps2 accel_mps2;  ///< along the path (body x), positive speeding up forward
  AngleRad pitch_rad;    ///< path slope; the body pitch, positive nose up
  bool slip_known{false};  ///< whether `slip` holds a measurement this cycle
  Ratio slip;            ///< rover slip 1 - v/(r w), at most 1
  Ratio dp_max_ratio[kWheelCount];  ///< (DP_max/W) at each wheel's load, (0, 2]
};

enum class DrawbarStatus : std::uint8_t {
  ok = 0U,
  capped = 1U,          ///< a share beyond +-DP_max was limited (see capped_mask)
  saturated = 2U,       ///< slip at or above params.high_slip: every wheel at DP_max
  invalid_loads = 3U,   ///< the wheel loads were not ok
  invalid_input = 4U,   ///< acceleration, slope, slip or a ratio out of range
  overflow = 5U,
};

struct DrawbarResult {
  DrawbarPullN dp_n[kWheelCount];  ///< zero unless status is ok, capped or saturated
  DrawbarPullN total_n;            ///< m (a + g sin(pitch)) before any limit
  std::uint8_t capped_mask{0U};    ///< bit i: wheel i was limited
  DrawbarStatus status{DrawbarStatus::invalid_input};  ///< a default result is never usable
};

/// True for the statuses whose dp_n may be used.
[[nodiscard]] constexpr bool usable(DrawbarStatus s) noexcept {
  return (s == DrawbarStatus::ok) || (s == DrawbarStatus::capped) || (s == DrawbarStatus::saturated);
}

/// The drawbar pulls for rover parameters checked once per load (prepare(),
/// prepared_params.hpp): invalid_input unless prepared.ready(), and no
/// validation per call.
[[nodiscard]] DrawbarResult drawbar_pulls(const PreparedParameters& prepared, const WheelLoadResult& loads,
                                          const DrawbarInput& input) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_DRAWBAR_PULL_HPP
