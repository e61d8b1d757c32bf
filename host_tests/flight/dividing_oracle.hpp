// dividing_oracle.hpp: the per-cycle functions of the flight module that
// divide by table constants, written with a plain fx::div, as the oracle the
// flight code is checked against.
//
// The flight module divides by the parameter table's constants (Table 2's
// segment widths) through mantissas prepared once per load (correction.hpp's
// SegmentWidth), and claims the result is fx::div's bit for bit;
// the motor's N, eta and Kt through one normalised reciprocal of their
// product (motor.hpp), within the bound current_tolerance_a() states. Before issue 15 each of these functions had a second, dividing
// entry point in the flight code only so that the claim could be tested;
// the dividing forms now live here, in the tests, and the flight API has one
// entry point per operation. The interpolation is the plain Q31.32 one
// (a + f (b - a) rounded once into Q7.24), not the flight code's 64-bit
// shortcut, so the oracle checks that shortcut too.
#ifndef SINKWATCH_HOST_TESTS_DIVIDING_ORACLE_HPP
#define SINKWATCH_HOST_TESTS_DIVIDING_ORACLE_HPP

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace sinkwatch {
namespace oracle {

/// flight::corrections_at with fx::div for the interpolation fraction.
flight::CorrectionResult corrections_at(const flight::CorrectionTable& table, flight::WheelLoadN load_n) noexcept;

/// flight::current_from_torque with fx::div by N, eta and Kt.
flight::CurrentResult current_from_torque(const flight::MotorParams& motor, flight::TorqueNm torque_nm,
                                          flight::DriveDirection direction) noexcept;

/// How far flight::current_from_torque may be from current_from_torque above
/// (docs/flight.md, "Current from torque"), in amperes: the flight's 0.5 LSB
/// + |T / (N eta Kt)| 2^-29 plus the oracle's 0.5 LSB + 2^-33 A (1/(eta Kt) +
/// 1/Kt + 1), for the oracle's current `oracle_a` of `motor`.
double current_tolerance_a(const flight::MotorParams& motor, flight::CurrentA oracle_a) noexcept;

/// flight::current_limit on these corrections with fx::div in the motor model
/// (divisors whose reciprocal is 0 fall back to fx::div).
flight::CurrentLimitResult current_limit(const flight::CorrectionResult& corrections,
                                         const flight::MotorParams& motor, flight::LengthM radius_m,
                                         flight::WheelLoadN load_n, flight::SinkageM allowed_sinkage_m) noexcept;

/// corrections_at(table.correction, W), then current_limit with the table's
/// motor, radius and allowed sinkage: section 7's I_max from the table alone.
flight::CurrentLimitResult current_limit(const flight::ParameterTable& table, flight::WheelLoadN load_n) noexcept;

}  // namespace oracle
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_DIVIDING_ORACLE_HPP
