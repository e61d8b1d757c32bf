// prepared_support.hpp: the flight module's per-cycle functions called on a
// bare parameter table, for tests and property tests.
//
// The flight API has one entry point per operation, on divisors prepared
// once per load (prepared_params.hpp; issue 15 retired the dividing
// overloads). Tests that hold a table, not a load, prepare it here exactly as
// load() does (make_correction_divisors, make_motor_divisors, prepare()) and
// then call that one entry point. The dividing forms the prepared ones are
// checked against bit for bit are in dividing_oracle.hpp.
#ifndef SINKWATCH_HOST_TESTS_PREPARED_SUPPORT_HPP
#define SINKWATCH_HOST_TESTS_PREPARED_SUPPORT_HPP

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace test {

/// flight::corrections_at with the table's divisors prepared.
inline flight::CorrectionResult corrections_of(const flight::CorrectionTable& table, flight::WheelLoadN load_n) {
  return flight::corrections_at(table, flight::make_correction_divisors(table), load_n);
}

/// flight::current_from_torque with the motor's divisors prepared.
inline flight::CurrentResult current_of(const flight::MotorParams& motor, flight::TorqueNm torque_nm,
                                        flight::DriveDirection direction) {
  return flight::current_from_torque(motor, flight::make_motor_divisors(motor), torque_nm, direction);
}

/// Section 7's I_max at `load_n` from a correction table and a motor.
inline flight::CurrentLimitResult current_limit_of(const flight::CorrectionTable& table,
                                                   const flight::MotorParams& motor, flight::LengthM radius_m,
                                                   flight::WheelLoadN load_n, flight::SinkageM allowed_sinkage_m) {
  return flight::current_limit(corrections_of(table, load_n), motor, flight::make_motor_divisors(motor), radius_m,
                               load_n, allowed_sinkage_m);
}

/// The sample with its drive torque from its own current and direction, as
/// RoverStep computes it once per cycle (WheelInput::drive_torque): for tests
/// that feed the monitor directly.
inline flight::WheelInput with_drive_torque(flight::WheelInput in, const flight::MotorParams& motor) {
  in.drive_torque = flight::torque_from_current(motor, in.current_a, in.direction);
  return in;
}

/// Every wheel's sample with its drive torque (with_drive_torque).
inline void set_drive_torques(flight::WheelInput (&inputs)[flight::kMaxWheels], const flight::MotorParams& motor) {
  for (flight::WheelInput& in : inputs) {
    in = with_drive_torque(in, motor);
  }
}

/// prepare(table, rover); the status is in the result's status().
inline flight::PreparedParameters prepared_of(const flight::ParameterTable& table, const flight::RoverParams& rover) {
  flight::PreparedParameters out{};
  static_cast<void>(flight::prepare(table, rover, out));
  return out;
}

/// The table with the Yutu-like rover on the Moon, given the table's wheel
/// radius: table_valid() whenever validate(table) passes, ready() when that
/// radius is one the rover model accepts. For the monitor, which reads only
/// the table.
inline flight::PreparedParameters prepared_of(const flight::ParameterTable& table) {
  flight::RoverParams rover = flight::yutu_like_rover_params(flight::kGravityMoon);
  rover.wheel_radius_m = table.wheel_radius_m;
  return prepared_of(table, rover);
}

/// The rover parameters prepared with the default table, its wheel radius
/// set to theirs (prepare() wants the two equal), for wheel_loads() and
/// drawbar_pulls(), which take prepared parameters only: ready() exactly when
/// validate_rover_params() accepts them, so those give invalid_params and
/// invalid_input for the parameters it refuses.
inline flight::PreparedParameters prepared_rover(const flight::RoverParams& rover) {
  flight::ParameterTable table = flight::default_parameter_table();
  table.wheel_radius_m = rover.wheel_radius_m;
  return prepared_of(table, rover);
}

}  // namespace test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_PREPARED_SUPPORT_HPP
