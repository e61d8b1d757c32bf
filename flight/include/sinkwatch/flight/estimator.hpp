// estimator.hpp: the sinkage estimation function, the paper's Eq. 11, both ways.
//
//     DP/W = C1 * T/(r W) - C2 * z/r - C3                          (Eq. 11)
//
//   sinkage_from_pull:  z  = (C1 * T/W - r * (C3 + DP/W)) / C2
//   pull_from_sinkage:  DP = C1 * T/r - W * (C2 * z/r + C3)
//
// Eq. 10 is C = (1, 1, 0), Eq. 14 is C = (1, 1, 0.2) and Eq. 15, the function
// the paper uses on board, is C = (1, 1, 0.13): parameter choices, not code.
// The coefficients for a given load come from correction.hpp (Table 2).
// docs/derivation.md derives Eq. 11 from the Wong-Reece integrals; the
// validity limits of the linearisation are written down there.
//
// sinkage_from_pull is one division, z = (C1 T - r C3 W - r DP) / (C2 W), of
// 64-bit operands (fixedpoint/normalised_quotient.hpp): within 0.5 LSB +
// |z| 2^-29 + 2^-30/C2 + 2^-41/(C2 W), below 0.0004 mm over the envelope.
// pull_from_sinkage computes in Q31.32 and rounds once: within 0.5 LSB +
// (C1 + 2 + W (C2 + 1)) 2^-33 N. docs/flight.md, "Error budget", derives both.
#ifndef SINKWATCH_FLIGHT_ESTIMATOR_HPP
#define SINKWATCH_FLIGHT_ESTIMATOR_HPP

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

/// The three corrections of Eq. 11 at one wheel load.
struct Coefficients {
  Ratio c1;  ///< scales the drive coefficient T/(rW)
  Ratio c2;  ///< scales the sinkage ratio z/r; never zero (validated range)
  Ratio c3;  ///< offset of the traction coefficient
};

/// Validity envelope of the estimator's inputs. The parameter table enforces
/// the same limits, so a validated table never produces invalid_coefficient.
/// C1, C2 in [1/4, 4] keep the division by C2 from amplifying rounding by more
/// than 4 (docs/flight.md); the paper's values are all 1.
constexpr LengthM kMinRadiusM{fx::constant<LengthQ>(limits::kMinWheelRadiusM)};
constexpr LengthM kMaxRadiusM{fx::constant<LengthQ>(limits::kMaxEstimatorRadiusM)};
constexpr Ratio kMinC12{fx::constant<RatioQ>(0.25)};
constexpr Ratio kMaxC12{fx::constant<RatioQ>(4.0)};
constexpr Ratio kMinC3{fx::constant<RatioQ>(-1.0)};
constexpr Ratio kMaxC3{fx::constant<RatioQ>(1.0)};

struct SinkageResult {
  SinkageM sinkage_m;     ///< zero unless status == ok
  EstimateStatus status{EstimateStatus::ok};
};

struct DrawbarPullResult {
  DrawbarPullN drawbar_pull_n;  ///< zero unless status == ok
  EstimateStatus status{EstimateStatus::ok};
};

/// Eq. 11 solved for the sinkage z. A negative z is returned as computed
/// (it means the data lie above the fitted plane); the monitor treats it as
/// no sinkage, the ground tools see the raw number.
[[nodiscard]] SinkageResult sinkage_from_pull(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                              TorqueNm torque_nm, DrawbarPullN drawbar_pull_n) noexcept;

/// Eq. 11 solved for the drawbar pull DP.
[[nodiscard]] DrawbarPullResult pull_from_sinkage(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                                  TorqueNm torque_nm, SinkageM sinkage_m) noexcept;

/// Checks the inputs shared by both directions; ok when they are usable.
[[nodiscard]] EstimateStatus check_estimator_inputs(const Coefficients& c, LengthM radius_m,
                                                    WheelLoadN load_n) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ESTIMATOR_HPP
