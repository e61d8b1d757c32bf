// Replay of rover telemetry through the exact fixed-point flight code.
//
// OnboardLoop is what the rover's computer runs each control cycle: it turns
// one telemetry row into the flight types (fx::from_double, the only rounding),
// calls flight::RoverStep::step (wheel loads, drawbar pulls, Eq. 11 sinkage,
// section 7 current limit, N-of-M monitor, decision) and, once the rover has
// stopped, the escape sequencer of section 7 (flight::EscapeSequencer). The
// replay and the scenario generator (scenario.hpp, closed loop) use this one
// loop, so a shipped scenario replays to the same decisions it was made with.
//
// Integration choices (docs/replay.md, "What the replay runs"):
//   * the monitor's clock `now` is the sample's own time (a log has no
//     separate receive time, so nothing is stale unless the log says so);
//   * the escape starts in the cycle the rover decides stop_and_replan, from
//     the deepest wheel's sinkage estimate;
//   * the sequencer is fed the deepest wheel's estimate only from samples
//     driving forward with the wheels turning (rim speed >= 0.01 m/s) and
//     below the high-slip level: Eq. 11 and the drawbar-pull balance describe
//     a wheel driving forward, and at high slip every drawbar pull is the
//     table's soil-bin DP_max rather than this wheel's, so its sinkage is not
//     a measurement the escape may read freedom from. Such a sample is "no
//     estimate" (the sequencer's fail-safe path), never a number.
#pragma once

#include "sinkwatch/flight/escape.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/sensor_health.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sinkwatch::ground {

/// Below this rim speed the wheels are taken as standing (no escape sample).
inline constexpr double kEscapeMinRimSpeedMps = 0.01;

/// Where the replay's rover mass comes from. The first that exists decides,
/// in this order (docs/replay.md, "The rover's mass"): an explicit --mass-kg,
/// the log's "# mass_kg:" line (the rover that made the log), the table's
/// section 6, the Yutu-like default's 140 kg.
enum class MassSource { option, log_header, table, yutu_default };

struct ReplayConfig {
  flight::ParameterTable table = flight::default_parameter_table();
  double gravity_mps2 = 1.62;  // the rover's body: feeds RoverParams (Yutu-like geometry)
  bool run_escape = true;      // start the escape sequencer when the rover stops
  /// The rover from a table's section 6; empty: the Yutu-like rover at gravity_mps2.
  std::optional<flight::RoverParams> rover;
  std::string table_source = "built-in default";  // for the report
  /// A mass given apart from the rover (--mass-kg, the log's mass_kg): it
  /// replaces the mass of `rover` (or of the Yutu-like rover). Empty: the
  /// rover's own. OnboardLoop refuses one the flight code's check refuses.
  std::optional<double> mass_kg;
  MassSource mass_source = MassSource::yutu_default;
  std::size_t mass_line = 0;  // the log's mass_kg line (MassSource::log_header)
};

/// Sets `config.mass_kg` and `mass_source` by the order of MassSource:
/// `option_kg` (--mass-kg), else the log's mass_kg metadata (the reader has
/// range-checked it at its line), else leaves the table's or the default
/// rover's mass. Call after load_parameter_table(). Throws
/// std::invalid_argument for an option outside (0, 1000] kg.
void resolve_rover_mass(const TelemetryLog& log, std::optional<double> option_kg, ReplayConfig& config);

/// The mass the flight code runs with under `config`, in kg.
double replay_mass_kg(const ReplayConfig& config);

/// "--mass-kg", "the log's mass_kg (line 12)", "the table's section 6",
/// "the Yutu-like default": for the report.
std::string describe_mass_source(const ReplayConfig& config);

/// Reads an uploaded parameter table (the bytes `sinkwatch calibrate --table`
/// writes) into `config`: flight::decode() with the rover section checked;
/// the rover geometry too when the table carries section 6. Throws
/// std::runtime_error naming the file and the flight code's reject reason.
void load_parameter_table(const std::string& path, ReplayConfig& config);

/// --loss-policy: the table's section-7 loss policy (docs/fault-tolerance.md)
/// by name, "stop" or "continue-degraded"; `table_source` says so. Throws
/// std::invalid_argument for another name or a table the flight code would
/// then refuse (its reject reason named).
void set_loss_policy(const std::string& name, flight::ParameterTable& table, std::string& table_source);

/// One wheel's flight outputs for one cycle, converted to double for display.
struct WheelCycle {
  double current_a = 0.0;  // the telemetry's current
  bool load_valid = false;
  double load_n = 0.0;
  double drawbar_pull_n = 0.0;
  bool estimate_valid = false;
  double torque_nm = 0.0;
  double sinkage_m = 0.0;
  bool limit_valid = false;
  double current_limit_a = 0.0;
  flight::WheelState state = flight::WheelState::nominal;
  flight::SampleStatus sample = flight::SampleStatus::ok;
  flight::StopReason stop_reason = flight::StopReason::none;
  bool stop_tripped = false;
};

/// A wheel's event record (monitor.hpp), in double.
struct StopRecord {
  std::size_t wheel = 0;
  double time_s = 0.0;
  flight::StopReason reason = flight::StopReason::none;
  double peak_current_a = 0.0;
  double load_at_peak_n = 0.0;
  std::optional<double> peak_sinkage_m;       // Eq. 11 at the peak current, DP = DP_max
  std::optional<double> max_estimated_sinkage_m;
};

/// The rover's record of a stop-and-replan decision (flight/stop_record.hpp),
/// in SI units.
struct StopDecision {
  double time_s = 0.0;
  flight::StopReason reason = flight::StopReason::none;  // none: the step's own stop (tip-over)
  std::size_t deepest_wheel = 0;
  std::size_t samples = 0;                    // in the deepest wheel's median
  std::optional<double> recent_sinkage_m;     // the deepest wheel's median recent estimate
};

struct CycleRecord {
  std::size_t row = 0;  // index into the log's rows
  double time_s = 0.0;
  double x_m = 0.0;     // truth x_m when the log has it, else integrated speed
  flight::RoverStepStatus status = flight::RoverStepStatus::ok;
  flight::RoverDecision decision = flight::RoverDecision::continue_drive;
  std::optional<double> slip;  // the flight code's slip, when it had one
  std::optional<double> accel_mps2;
  bool drawbar_saturated = false;  // high slip: every DP taken at the table's DP_max
  std::array<WheelCycle, kTelemetryWheels> wheels{};
  std::vector<StopRecord> new_events;  // wheels that entered STOP this cycle
  std::optional<StopDecision> stop_decision;  // the rover's stop record, when written this cycle
  // Escape sequencer.
  bool escape_active = false;  // started (running or finished)
  flight::EscapeState escape_state = flight::EscapeState::idle;
  flight::EscapeCommand escape_command = flight::EscapeCommand::stop;
  std::uint8_t escape_cycles = 0;
  std::optional<double> escape_input_m;  // what the sequencer was given
  bool escape_started = false;           // started in this cycle
  bool escape_finished_now = false;      // reached its outcome in this cycle
  bool direction_mismatch = false;       // the log's direction differs from the sequencer's command
  // The flight code's sensor health (sensor_health.hpp): each channel's
  // health this cycle, the wheels whose current was not evidence, and
  // whether the rover drove on without them (LossPolicy::continue_degraded).
  std::array<flight::SensorHealth, flight::kSensorChannelCount> health{};
  std::uint8_t wheels_blind = 0;
  bool degraded = false;
  // The motion-resistance check (flight/traction.hpp): its state, whether it
  // stopped the rover this cycle, and its median and carried-ahead
  // coefficients when the cycle had them.
  flight::TractionState traction_state = flight::TractionState::off;
  bool traction_stop_tripped = false;
  std::optional<double> resistance;
  std::optional<double> resistance_ahead;

  /// Deepest valid sinkage estimate of the cycle.
  std::optional<double> max_sinkage_m() const;
  /// Largest |I| / I_max of the cycle.
  std::optional<double> max_current_ratio() const;
  flight::WheelState worst_state() const;
};

/// The flight software of one rover, cycle by cycle.
class OnboardLoop {
 public:
  explicit OnboardLoop(ReplayConfig config = ReplayConfig{});

  /// One control cycle. `x_m` is recorded as given. Throws TelemetryError
  /// (with the row's line) when a value does not fit its flight format, or
  /// the time is outside the on-board clock's 0 ... 4294967.295 s. The clock
  /// wraps to 0 after 4294967.295 s: rows may follow it across the wrap
  /// (the flight code's time differences are modulo 2^32 ms).
  CycleRecord step(const TelemetryRow& row, const std::string& source, double x_m);

  const ReplayConfig& config() const { return config_; }
  const flight::RoverParams& rover() const { return rover_; }
  bool stopped() const { return stopped_; }
  flight::EscapeState escape_state() const { return escape_.state(); }
  double escape_best_sinkage_m() const;

 private:
  ReplayConfig config_;
  flight::RoverParams rover_;
  flight::PreparedParameters prepared_;  // config_.table and rover_, prepared once
  flight::RoverStep step_;
  flight::EscapeSequencer escape_;
  bool stopped_ = false;
  flight::RoverDecision last_decision_ = flight::RoverDecision::continue_drive;
};

struct ReplayResult {
  std::vector<CycleRecord> cycles;
  std::vector<StopRecord> events;  // every event record, in order
  std::optional<std::size_t> first_stop;  // index into cycles
  std::optional<std::size_t> escape_end;  // cycle where the sequencer finished
  std::size_t direction_mismatches = 0;
  std::array<std::size_t, 16> status_counts{};  // by RoverStepStatus
  double distance_m = 0.0;                      // x at the end minus x at the start
};

/// Replays every row. `progress` (may be empty) is called with the fraction done.
ReplayResult run_replay(const TelemetryLog& log, const ReplayConfig& config,
                        const std::function<void(double)>& progress = {});

/// The gravity a log asks for: metadata "gravity_mps2", else the Moon's.
double log_gravity(const TelemetryLog& log);

const char* to_string(flight::WheelState s);
const char* to_string(flight::RoverDecision d);
const char* to_string(flight::RoverStepStatus s);
const char* to_string(flight::StopReason r);
const char* to_string(flight::EscapeState s);
const char* to_string(flight::EscapeCommand c);
const char* to_string(flight::SampleStatus s);

}  // namespace sinkwatch::ground
