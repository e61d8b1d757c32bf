// prepared_params.hpp: the parameters of the per-cycle step (rover_step.hpp),
// checked once per parameter load instead of once per control cycle.
//
// The step needs the parameter table (Eq. 15's wheel radius, the motor model,
// Table 2's corrections, the monitor's thresholds) and the rover's geometry
// (the wheel-load statics and the drawbar-pull balance of section 7). Both
// change only when the ground uploads a new table, so validate(table),
// validate_rover_params() and the wheel-radius consistency check run here,
// when the parameters are loaded, and the step only reads the outcome. So are
// the reciprocals of the table constants the step divides by (Table 2's
// breakpoint spacing, correction.hpp; the motor's N, eta and Kt, motor.hpp),
// and the rover's lengths and weight in the statics' format (rover_statics.hpp).
//
// A PreparedParameters is built only by prepare(); a default-constructed one
// holds no table and makes the step refuse every cycle (invalid_table, stop),
// the same fail-safe as an invalid table. It is a copy, not a reference: a
// later change to the table it came from does not reach the step until
// prepare() runs again.
#ifndef SINKWATCH_FLIGHT_PREPARED_PARAMS_HPP
#define SINKWATCH_FLIGHT_PREPARED_PARAMS_HPP

#include <cstdint>

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_statics.hpp"
#include "sinkwatch/flight/traction.hpp"

namespace sinkwatch {
namespace flight {

/// The outcome of prepare(), in the order the step reports it.
enum class PrepareStatus : std::uint8_t {
  ok = 0U,
  invalid_table = 1U,         ///< validate(table) failed: nothing is usable
  invalid_rover_params = 2U,  ///< the table is usable, the rover parameters are not
  radius_mismatch = 3U,       ///< both valid, but their wheel radii differ
};

class PreparedParameters {
 public:
  /// Holds no table: status() is invalid_table.
  constexpr PreparedParameters() noexcept = default;

  [[nodiscard]] constexpr PrepareStatus status() const noexcept { return status_; }
  /// True when the table passed validate() (whatever the rover parameters).
  [[nodiscard]] constexpr bool table_valid() const noexcept { return status_ != PrepareStatus::invalid_table; }
  /// True when the table, the rover parameters and their radii all agree.
  [[nodiscard]] constexpr bool ready() const noexcept { return status_ == PrepareStatus::ok; }
  /// The validated table; meaningful only when table_valid().
  [[nodiscard]] constexpr const ParameterTable& table() const& noexcept { return table_; }
  const ParameterTable& table() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// The rover parameters; validated only when ready().
  [[nodiscard]] constexpr const RoverParams& rover() const& noexcept { return rover_; }
  const RoverParams& rover() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// Table 2's segment widths and the motor's N, eta, Kt as reciprocals
  /// (correction.hpp, motor.hpp), for divisions without a division instruction.
  [[nodiscard]] constexpr const CorrectionDivisors& correction_divisors() const& noexcept {
    return correction_divisors_;
  }
  const CorrectionDivisors& correction_divisors() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  [[nodiscard]] constexpr const MotorDivisors& motor_divisors() const& noexcept { return motor_divisors_; }
  const MotorDivisors& motor_divisors() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// 1/r of the table's wheel radius for the motion-resistance check's
  /// thrust (traction.hpp): a product per cycle instead of a division.
  [[nodiscard]] constexpr InverseRadius traction_inverse_radius() const noexcept { return traction_inverse_radius_; }
  /// The rover's lengths and weight in the statics' Q6.25; meaningful only
  /// when ready().
  [[nodiscard]] constexpr const RoverStatics& rover_statics() const& noexcept { return rover_statics_; }
  const RoverStatics& rover_statics() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// CRC-32 of the bytes load() took the table from (0 for the built-in
  /// default and for prepare()).
  [[nodiscard]] constexpr std::uint32_t table_crc() const noexcept { return table_crc_; }

 private:
  friend PrepareStatus prepare(const ParameterTable& table, const RoverParams& rover,
                               PreparedParameters& out) noexcept;
  friend void prepare_validated(const ParameterTable& table, const RoverParams& rover, std::uint32_t crc,
                                PreparedParameters& out) noexcept;

  PrepareStatus status_{PrepareStatus::invalid_table};
  ParameterTable table_{};
  RoverParams rover_{};
  CorrectionDivisors correction_divisors_{};
  MotorDivisors motor_divisors_{};
  InverseRadius traction_inverse_radius_{};
  RoverStatics rover_statics_{};
  std::uint32_t table_crc_{0U};
};

/// Checks the table and the rover parameters and copies them into `out`
/// (also when only the rover parameters fail, so that the monitor still has
/// its thresholds and counts the refused cycles). Returns out.status().
PrepareStatus prepare(const ParameterTable& table, const RoverParams& rover, PreparedParameters& out) noexcept;

/// For load(): the table, the rover parameters and their radii have already
/// been checked (each once); copies them and prepares the reciprocals, status
/// ok. Not for other callers: prepare() is the checking entry point.
void prepare_validated(const ParameterTable& table, const RoverParams& rover, std::uint32_t crc,
                       PreparedParameters& out) noexcept;

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_PREPARED_PARAMS_HPP
