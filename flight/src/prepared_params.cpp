// The once-per-load checks of the step's parameters (prepared_params.hpp).
#include "sinkwatch/flight/prepared_params.hpp"

namespace sinkwatch {
namespace flight {

PrepareStatus prepare(const ParameterTable& table, const RoverParams& rover, PreparedParameters& out) noexcept {
  if (validate(table) != RejectReason::ok) {
    out.status_ = PrepareStatus::invalid_table;
    return out.status_;
  }
  out.table_ = table;
  out.rover_ = rover;
  out.table_crc_ = 0U;
  out.correction_divisors_ = make_correction_divisors(table.correction);
  out.motor_divisors_ = make_motor_divisors(table.motor);
  out.traction_inverse_radius_ = inverse_radius(table.wheel_radius_m);
  if (validate_rover_params(rover) != RoverParamStatus::ok) {
    out.status_ = PrepareStatus::invalid_rover_params;
  } else if (rover.wheel_radius_m != table.wheel_radius_m) {
    // The statics and Eq. 15 must describe the same wheel.
    out.status_ = PrepareStatus::radius_mismatch;
  } else {
    out.rover_statics_ = make_rover_statics(rover);
    out.status_ = PrepareStatus::ok;
  }
  return out.status_;
}

void prepare_validated(const ParameterTable& table, const RoverParams& rover, std::uint32_t crc,
                       PreparedParameters& out) noexcept {
  out.table_ = table;
  out.rover_ = rover;
  out.table_crc_ = crc;
  out.correction_divisors_ = make_correction_divisors(table.correction);
  out.motor_divisors_ = make_motor_divisors(table.motor);
  out.traction_inverse_radius_ = inverse_radius(table.wheel_radius_m);
  out.rover_statics_ = make_rover_statics(rover);
  out.status_ = PrepareStatus::ok;
}

}  // namespace flight
}  // namespace sinkwatch
