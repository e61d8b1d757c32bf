// estimator_bounds.hpp: the documented error bounds of Eq. 11's sinkage and
// the section 7 torque limit (docs/flight.md, "Error budget"), written once
// for the unit tests and the property tests that assert them.
#ifndef SINKWATCH_HOST_TESTS_ESTIMATOR_BOUNDS_HPP
#define SINKWATCH_HOST_TESTS_ESTIMATOR_BOUNDS_HPP

#include <cmath>

namespace sinkwatch {
namespace test {

/// |sinkage_from_pull - z| for the exact z at C2 and W (newtons), in metres:
/// the quotient's rounding and relative error, r C3 rounded to Q2.29 and
/// r C3 W to Q23.40, over C2 W.
inline double sinkage_error_bound_m(double c2, double load_n, double sinkage_m) {
  return std::ldexp(0.5, -24) + std::fabs(sinkage_m) * std::ldexp(1.0, -29) + std::ldexp(1.0, -30) / c2 +
         std::ldexp(1.0, -41) / (c2 * load_n);
}

/// |torque_limit - T_max| for the exact T_max on exact coefficients, in N m:
/// the rounding into Q15.16, the lever's leading 31 bits and the normalised
/// division.
inline double torque_limit_error_bound_nm(double torque_limit_nm) {
  return std::ldexp(0.5, -16) + std::fabs(torque_limit_nm) * std::ldexp(1.0, -28);
}

}  // namespace test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_ESTIMATOR_BOUNDS_HPP
