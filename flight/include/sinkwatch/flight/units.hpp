// units.hpp: the physical quantities of the flight module as strong types.
//
// Every quantity that crosses a flight API is a Quantity<Tag, Q>: a Q-format
// number that only compares with, and is only accepted as, the same quantity.
// A load in newtons cannot be passed where a torque is expected, and the name
// of each type carries its unit. The Q format of each quantity is chosen for
// its physical range (docs/flight.md, "Q formats"):
//
//   quantity            type                 format  range            LSB
//   wheel load          WheelLoadN           Q15.16  +-32768 N        1.5e-5 N
//   drive torque        TorqueNm             Q15.16  +-32768 N m      1.5e-5 N m
//   drawbar pull        DrawbarPullN         Q15.16  +-32768 N        1.5e-5 N
//   motor current       CurrentA             Q11.20  +-2048 A         9.5e-7 A
//   sinkage             SinkageM             Q7.24   +-128 m          6.0e-8 m
//   wheel radius        LengthM              Q7.24   +-128 m          6.0e-8 m
//   C1..C3, DP/W        Ratio                Q7.24   +-128            6.0e-8
//   gear ratio N        GearRatio            Q15.16  +-32768          1.5e-5
//   efficiency eta      Efficiency           Q1.30   +-2              9.3e-10
//   torque constant Kt  TorqueConstantNmPerA Q3.28   +-8 N m/A        3.7e-9 N m/A
//
// Intermediates are computed in Q31.32 (int64_t), so that each chain rounds
// only at its ends; docs/flight.md derives the error bound of every function.
#ifndef SINKWATCH_FLIGHT_UNITS_HPP
#define SINKWATCH_FLIGHT_UNITS_HPP

#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"

namespace sinkwatch {
namespace flight {

/// A Q-format value with a unit. Tag only distinguishes the types.
template <typename Tag, typename QType>
class Quantity {
 public:
  using q_type = QType;
  using storage_type = typename QType::storage_type;

  constexpr Quantity() noexcept = default;
  constexpr explicit Quantity(QType value) noexcept : q_(value) {}

  [[nodiscard]] static constexpr Quantity from_raw(storage_type raw_bits) noexcept {
    return Quantity(QType::from_raw(raw_bits));
  }
  [[nodiscard]] static constexpr Quantity zero() noexcept { return Quantity(QType::zero()); }

  [[nodiscard]] constexpr QType q() const noexcept { return q_; }
  [[nodiscard]] constexpr storage_type raw() const noexcept { return q_.raw(); }

  friend constexpr bool operator==(Quantity a, Quantity b) noexcept { return a.q_ == b.q_; }
  friend constexpr bool operator!=(Quantity a, Quantity b) noexcept { return a.q_ != b.q_; }
  friend constexpr bool operator<(Quantity a, Quantity b) noexcept { return a.q_ < b.q_; }
  friend constexpr bool operator<=(Quantity a, Quantity b) noexcept { return a.q_ <= b.q_; }
  friend constexpr bool operator>(Quantity a, Quantity b) noexcept { return a.q_ > b.q_; }
  friend constexpr bool operator>=(Quantity a, Quantity b) noexcept { return a.q_ >= b.q_; }

 private:
  QType q_{};
};

/// Formats, named once so that every module uses the same ones.
using LoadQ = fx::Q<std::int32_t, 16>;        ///< Q15.16, newtons and newton-metres
using CurrentQ = fx::Q<std::int32_t, 20>;     ///< Q11.20, amperes
using LengthQ = fx::Q<std::int32_t, 24>;      ///< Q7.24, metres
using RatioQ = fx::Q<std::int32_t, 24>;       ///< Q7.24, dimensionless
using GearQ = fx::Q<std::int32_t, 16>;        ///< Q15.16, dimensionless
using EfficiencyQ = fx::Q<std::int32_t, 30>;  ///< Q1.30, dimensionless
using KtQ = fx::Q<std::int32_t, 28>;          ///< Q3.28, N m / A
using WideQ = fx::Q<std::int64_t, 32>;        ///< Q31.32, intermediates only
using AngleQ = fx::Q<std::int32_t, 28>;       ///< Q3.28, radians (rover_geometry.hpp)

struct WheelLoadTag;
struct TorqueTag;
struct DrawbarPullTag;
struct CurrentTag;
struct SinkageTag;
struct LengthTag;
struct RatioTag;
struct GearRatioTag;
struct EfficiencyTag;
struct TorqueConstantTag;
struct AngleTag;

using WheelLoadN = Quantity<WheelLoadTag, LoadQ>;
using TorqueNm = Quantity<TorqueTag, LoadQ>;
using DrawbarPullN = Quantity<DrawbarPullTag, LoadQ>;
using CurrentA = Quantity<CurrentTag, CurrentQ>;
using SinkageM = Quantity<SinkageTag, LengthQ>;
using LengthM = Quantity<LengthTag, LengthQ>;
using Ratio = Quantity<RatioTag, RatioQ>;
using GearRatio = Quantity<GearRatioTag, GearQ>;
using Efficiency = Quantity<EfficiencyTag, EfficiencyQ>;
using TorqueConstantNmPerA = Quantity<TorqueConstantTag, KtQ>;
using AngleRad = Quantity<AngleTag, AngleQ>;

/// Time of a telemetry sample, milliseconds of the on-board clock. Wraps
/// after 49.7 days; every comparison uses the wrapping difference.
struct TimeMs {
  std::uint32_t ms{0U};
};

/// Milliseconds from `earlier` to `later`, correct across one wrap.
[[nodiscard]] constexpr std::uint32_t elapsed_ms(TimeMs earlier, TimeMs later) noexcept {
  return later.ms - earlier.ms;  // unsigned arithmetic wraps by definition
}

/// The wheel's commanded direction of rotation. Forward means the current and
/// torque that drive the rover forward are positive.
enum class DriveDirection : std::uint8_t { forward = 0U, reverse = 1U };

/// Why a flight computation returned no usable number. `ok` is the only
/// status whose value may be used.
enum class EstimateStatus : std::uint8_t {
  ok = 0U,
  invalid_radius = 1U,       ///< wheel radius outside (0, kMaxRadius]
  invalid_load = 2U,         ///< wheel load not positive or outside the envelope
  invalid_coefficient = 3U,  ///< C1 or C2 outside their validated range
  invalid_current = 4U,      ///< |I| above the sensor's valid range
  invalid_motor = 5U,        ///< gear ratio, efficiency or Kt not positive
  invalid_direction = 6U,    ///< direction value not forward/reverse
  overflow = 7U,             ///< a result or intermediate left its Q format
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_UNITS_HPP
