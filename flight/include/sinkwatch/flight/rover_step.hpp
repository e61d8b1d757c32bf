// rover_step.hpp: one control cycle of the on-board sinkage monitor, from raw
// telemetry to each wheel's load, drawbar pull, torque, sinkage estimate,
// current limit and state, and the rover's decision (the paper's section 7
// chain: key technologies 2 and 4 feeding Eq. 15 and the current threshold).
//
//   telemetry -> validate (flag, age, repeated stamp, ranges)
//             -> wheel loads W_i          (wheel_load.hpp, rocker-bogie statics)
//             -> acceleration a           (measured, else the speed difference)
//             -> slip s = 1 - v / (r w)   (when ground and rim speed are known)
//             -> DP_max/W at each load    (corrections_at, Table 2's table)
//             -> drawbar pulls DP_i       (drawbar_pull.hpp, force balance)
//             -> RoverMonitor::step       (monitor.hpp: T, z, I_max, states, decision)
//             -> TractionMonitor::step    (traction.hpp: the motion-resistance check)
//
// One bounded call: no allocation, no recursion, loops over the six wheels.
// Every input is validated. A cycle whose loads or pulls cannot be computed
// still reaches the monitor, with its samples marked invalid, so the monitor
// counts it and, after invalid_to_stop such cycles, stops the rover: blind
// never means "continue". Attitudes beyond the stability limit stop the rover
// in the same cycle. docs/rover-loads.md, section 8, gives the details.
// Between stages 1 and 2 the sensor health monitor (sensor_health.hpp)
// judges every channel: a faulty current makes its wheel's sample unusable,
// a faulty IMU or joint sensor is bridged by its last good value and then
// leaves the rover without loads (docs/fault-tolerance.md).
//
// Sign convention: drawbar pulls are along body +x, the convention of the
// torque (positive drives the rover forward).
#ifndef SINKWATCH_FLIGHT_ROVER_STEP_HPP
#define SINKWATCH_FLIGHT_ROVER_STEP_HPP

#include <cstdint>

#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/sensor_health.hpp"
#include "sinkwatch/flight/stop_record.hpp"
#include "sinkwatch/flight/traction.hpp"
#include "sinkwatch/flight/units.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sinkwatch {
namespace flight {

/// Accepted magnitude of the ground and rim speeds: a sensor reading beyond
/// it is a fault (Yutu drives at 0.055 m/s).
constexpr SpeedMps kMaxAbsSpeed{fx::constant<SpeedQ>(5.0)};
/// Below this commanded rim speed the slip ratio is not defined.
constexpr SpeedMps kMinRimSpeedForSlip{fx::constant<SpeedQ>(0.001)};

namespace detail {
/// The slip s = 1 - v / v_rim limited to [-1, 1], in Q7.24, for |v| and
/// |v_rim| at most kMaxAbsSpeed and |v_rim| above kMinRimSpeedForSlip (the
/// step's checks), bit for bit the Q31.32 chain it replaced in round 15,
///   fx::rescale<Q7.24>(fx::clamp(1 - fx::div<Q31.32>(v, v_rim), -1, 1)),
/// which raises no flag there (docs/coverage.md): that chain's 64-bit
/// library division by a 64-bit divisor becomes one 64 / 32-bit quotient
/// (fx::wide::quotient_64_by_32) of the part of |v| / |v_rim| below one:
///  * v and v_rim of opposite signs (or v = 0 with v_rim < 0, which fx::div
///    also calls negative): the ratio is <= 0, s >= 1, clamped to 1;
///  * |v| >= 2 |v_rim|: the ratio is at least 2, s <= -1, clamped to -1;
///  * otherwise the ratio's magnitude m = round(|v| 2^32 / |v_rim|) (half
///    up, as fx::div rounds a magnitude) is at most 2^33: the whole part
///    (0 or 1) by a comparison, the rest r 2^32 / |v_rim| (r < |v_rim|) by
///    the quotient of the divisor normalised to bit 31 and its remainder
///    from the quotient's low word (a tie, r 2^32 / |v_rim| = n + 1/2,
///    would need 2^33 to divide |v_rim|: none occurs); then s = 2^32 - m
///    lies in [-2^32, 2^32] (no clamp), rescaled to Q7.24 by rounding its
///    magnitude half up.
/// host_tests/rover/test_rover_step.cpp compares it with the chain.
[[nodiscard]] Ratio slip_in_range(SpeedMps speed, SpeedMps rim) noexcept;
}  // namespace detail

/// One cycle's raw telemetry.
struct RoverTelemetry {
  TimeMs time{0U};                          ///< when the sample was taken
  bool valid{false};                        ///< the telemetry source's own flag
  CurrentA current_a[kWheelCount];          ///< signed; positive drives forward
  DriveDirection direction[kWheelCount]{};  ///< commanded direction per wheel
  RoverAttitude attitude;                   ///< IMU pitch and roll
  JointAnglesRad joints;                    ///< rocker and bogie angles
  bool accel_valid{false};                  ///< accel_mps2 holds a measurement
  AccelMps2 accel_mps2;                     ///< along the path (IMU / VO)
  bool speed_valid{false};                  ///< speed_mps holds a measurement
  SpeedMps speed_mps;                       ///< over the ground (odometry / VO), signed
  bool rim_speed_valid{false};              ///< rim_speed_mps holds a value
  SpeedMps rim_speed_mps;                   ///< mean r w of the driven wheels, signed
  SensorPresence presence{};                ///< per-sensor dropouts (all present by default)
};

enum class RoverStepStatus : std::uint8_t {
  ok = 0U,
  invalid_table = 1U,          ///< the parameter table failed validate() (prepare()): monitor not run
  invalid_rover_params = 2U,   ///< RoverParams failed validate_rover_params() (prepare())
  telemetry_invalid = 3U,      ///< the source flagged the sample invalid
  telemetry_stale = 4U,        ///< older than the stale timeout, or from the future
  telemetry_repeated = 5U,     ///< the same time stamp as the previous cycle
  motion_out_of_range = 6U,    ///< acceleration or a speed beyond its accepted range
  loads_failed = 7U,           ///< wheel_loads() gave no loads (see load_status)
  tip_over = 8U,               ///< beyond the stability limit: stop and re-plan now
  no_acceleration = 9U,        ///< no measured acceleration and no previous speed
  drawbar_failed = 10U,        ///< drawbar_pulls() or DP_max/W gave no number
  radius_mismatch = 11U,       ///< RoverParams and the table disagree on the wheel radius
  sensor_lost = 12U,           ///< the IMU or the joints unusable beyond bridge_ms: no loads
};

struct RoverStepOutput {
  RoverStepStatus status{RoverStepStatus::ok};
  WheelLoadStatus load_status{WheelLoadStatus::invalid_params};
  DrawbarStatus drawbar_status{DrawbarStatus::invalid_loads};
  bool loads_valid{false};                 ///< load_n holds this cycle's loads
  WheelLoadN load_n[kWheelCount];
  bool drawbar_valid{false};               ///< drawbar_pull_n holds this cycle's pulls
  DrawbarPullN drawbar_pull_n[kWheelCount];
  bool accel_valid{false};
  AccelMps2 accel_mps2;                    ///< the acceleration used (measured or differenced)
  bool slip_known{false};
  Ratio slip;                              ///< limited to [-1, 1]
  std::uint32_t lifting_wheel{kWheelCount};  ///< with tip_over: the wheel that lifts
  /// Bit i: wheel i's current gave no usable torque, so the loads took its
  /// free-rolling couple (wheel_load.hpp DriveTorques). All set until the loads run.
  std::uint8_t torque_fallback_mask{kEveryTorqueFallsBack};
  bool torque_overload{false};  ///< WheelLoadResult::torque_overload: loads taken without torques
  SensorHealthReport health{};             ///< every channel's health (sensor_health.hpp)
  RoverOutput monitor{};                   ///< per wheel: torque, sinkage, I_max, state
  TractionOutput traction{};               ///< the motion-resistance check (traction.hpp)
  /// The monitor's, or stop on tip_over / bad table / the motion-resistance
  /// check in STOP.
  RoverDecision decision{RoverDecision::stop_and_replan};
};

class RoverStep {
 public:
  RoverStep() noexcept;

  /// One control cycle into `out`. `now` is the monitor's clock. `prepared`
  /// holds the parameter table and the rover parameters (the table's
  /// section 6, read and validated by decode() when the table is loaded),
  /// checked once per load by load() or prepare(): the step does no
  /// validation of its own. `out` is reset and then written, so a record
  /// reused from the previous cycle holds this cycle's result only; taking
  /// it by reference lets the caller keep it in its own storage (the C
  /// interface keeps it in the context), not on the step's stack.
  void step(const RoverTelemetry& telemetry, TimeMs now, const PreparedParameters& prepared,
            RoverStepOutput& out) noexcept;

  /// The ground's acknowledgement after a re-plan (RoverMonitor::clear_stop,
  /// TractionMonitor::clear_stop); the sensor health takes the next sample as every channel's reference
  /// (SensorHealthMonitor::accept_levels).
  void clear_stop() noexcept;


  [[nodiscard]] const RoverMonitor& monitor() const& noexcept { return monitor_; }
  const RoverMonitor& monitor() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary
  /// The record of the last stop-and-replan decision (stop_record.hpp).
  [[nodiscard]] const StopRecorder& stops() const& noexcept { return stops_; }
  const StopRecorder& stops() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary

 private:
  /// Stage 1: flagged, stale, repeated, or ok (then remembered as the last).
  RoverStepStatus classify(const RoverTelemetry& t, TimeMs now, const ParameterTable& table) noexcept;
  /// Stage 3: the acceleration (measured or differenced) and the slip.
  void motion(const RoverTelemetry& t, const ParameterTable& table, RoverStepOutput& out) noexcept;
  /// Stage 1 and the prepared parameters' own refusal, for a fresh sample.
  RoverStepStatus admit(const RoverTelemetry& t, TimeMs now, const PreparedParameters& prepared) noexcept;
  /// What stages 2 and 4 evaluate once per wheel and the monitor reuses.
  /// Kept in the object, not on the step's stack; stage 5 reads them only
  /// for a usable sample, whose stages 2 and 4 wrote every wheel's.
  struct WheelTerms {
    TorqueResult torque[kWheelCount];     ///< from the currents: the loads' and the monitor's
    DriveTorques drive;                   ///< the loads' view of `torque` (wheel_load.hpp)
    CorrectionResult corr[kWheelCount];   ///< C(W) at each load: DP_max/W, Eq. 11, I_max
  };
  /// Stages 2 to 4 of an admitted sample: torques and loads, motion, C(W),
  /// drawbar pulls, into `terms_` and `out`.
  RoverStepStatus compute(const RoverTelemetry& t, const PreparedParameters& prepared, RoverStepOutput& out) noexcept;
  /// Stage 5: every wheel's monitor, fed this cycle's numbers or an invalid
  /// sample, and the rover's decision.
  void monitor_stage(const RoverTelemetry& t, TimeMs now, const PreparedParameters& prepared,
                     RoverStepOutput& out) noexcept;

  /// Stage 6: the motion-resistance check on this cycle's loads, pulls and
  /// the wheel monitors' torques (their sums in `traction_in_`).
  void traction_stage(const RoverTelemetry& t, const PreparedParameters& prepared, RoverStepOutput& out) noexcept;

  /// Stage 1b: the channels' health for an admitted sample, or the clock's
  /// for a refused one (the other channels as last assessed).
  void assess(const RoverTelemetry& t, const PreparedParameters& prepared, bool clock_jump,
              RoverStepOutput& out) noexcept;

  WheelTerms terms_{};
  /// Stage 6's input: the sums of this cycle's wheels, rebuilt every cycle
  /// with loads.
  TractionCycle traction_in_{};
  RoverMonitor monitor_;
  TractionMonitor traction_;
  StopRecorder stops_;
  SensorHealthMonitor health_;
  SensorHealthReport last_health_{};
  bool have_time_{false};
  TimeMs last_time_{0U};
  bool have_speed_{false};
  SpeedMps last_speed_{};
  TimeMs last_speed_time_{0U};
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ROVER_STEP_HPP
