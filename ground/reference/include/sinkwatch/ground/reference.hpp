// reference.hpp: the double-precision twin of every flight function of
// issue 3 (flight/include/sinkwatch/flight/*.hpp), for the ground tools and as
// the oracle of the property tests.
//
//   sinkage_m / drawbar_pull_n   Eq. 11 both ways: DP/W = C1 T/(rW) - C2 z/r - C3
//   corrections_at               C1..C3 and DP_max/W over the load (Table 2)
//   torque_nm / current_a        T = N eta Kt (I - d I0) and its inverse
//   torque_limit_nm /
//   current_limit_a              section 7: Eq. 11 at DP_max, z_max, then the motor
//
// Same formulas, same clamping, no rounding: where the flight code returns
// a status, this code throws std::invalid_argument naming the input. The
// flight parameter table converts with from_flight().
#ifndef SINKWATCH_GROUND_REFERENCE_HPP
#define SINKWATCH_GROUND_REFERENCE_HPP

#include <vector>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace ground {
namespace reference {

struct Coefficients {
  double c1 = 1.0;
  double c2 = 1.0;
  double c3 = 0.0;
};

struct Motor {
  double gear_ratio = 1.0;
  double efficiency = 1.0;
  double kt_nm_per_a = 1.0;
  double no_load_current_a = 0.0;
  double current_abs_max_a = 1.0;
};

struct CorrectionRow {
  double load_n = 0.0;
  double c1 = 1.0;
  double c2 = 1.0;
  double c3 = 0.0;
  double dp_max_ratio = 0.0;
};

enum class Clamp { none, below_first, above_last };

struct Corrections {
  Coefficients coefficients;
  double dp_max_ratio = 0.0;
  Clamp clamp = Clamp::none;
};

/// The flight parameter table in double precision (the fields the estimator,
/// the limit and the monitor thresholds use).
struct Parameters {
  double wheel_radius_m = 0.0;
  Motor motor;
  std::vector<CorrectionRow> correction;
  double allowed_sinkage_m = 0.0;
  double caution_sinkage_m = 0.0;
  double stop_sinkage_m = 0.0;
};

/// Eq. 11 for z. Throws when r <= 0, W <= 0 or C2 == 0.
double sinkage_m(const Coefficients& c, double radius_m, double load_n, double torque_nm, double drawbar_pull_n);

/// Eq. 11 for DP. Throws when r <= 0 or W <= 0.
double drawbar_pull_n(const Coefficients& c, double radius_m, double load_n, double torque_nm, double sinkage_m);

/// T = N eta Kt (I - d I0). Throws when |I| > current_abs_max.
double torque_nm(const Motor& m, double current_a, flight::DriveDirection direction);

/// I = T / (N eta Kt) + d I0.
double current_a(const Motor& m, double torque_nm, flight::DriveDirection direction);

/// Piecewise linear in the load, held (and reported) outside the breakpoints.
/// Throws for an empty table or W <= 0.
Corrections corrections_at(const std::vector<CorrectionRow>& table, double load_n);

/// T_max = (W / C1) (r (DP_max/W + C3) + C2 z_max).
double torque_limit_nm(const Coefficients& c, double dp_max_ratio, double radius_m, double load_n,
                       double allowed_sinkage_m);

/// I_max = T_max(C(W)) / (N eta Kt) + I0.
double current_limit_a(const std::vector<CorrectionRow>& table, const Motor& m, double radius_m, double load_n,
                       double allowed_sinkage_m);

/// Exact conversions of the flight table's Q values.
Coefficients from_flight(const flight::Coefficients& c);
Motor from_flight(const flight::MotorParams& m);
std::vector<CorrectionRow> from_flight(const flight::CorrectionTable& t);
Parameters from_flight(const flight::ParameterTable& t);

}  // namespace reference
}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_REFERENCE_HPP
