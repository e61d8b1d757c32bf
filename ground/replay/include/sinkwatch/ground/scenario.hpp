// Telemetry scenarios made with the reference wheel–soil simulator
// (docs/scenarios.md): a Yutu-like rover drives a path whose soil and slope
// change along x; each cycle the simulator gives every wheel's sinkage, torque
// and drawbar pull at the wheel's load and the rover's slip, and the torque
// becomes a motor current through the inverse of the flight motor model.
//
// The rover's slip is the one at which the six simulated drawbar pulls carry
// the rover: sum_i DP_sim(W_i, s) = m (g sin(slope) + a). Embedding, in the
// simulator's world, is the first point of the path where no slip up to
// kEmbedMaxSlip gives that much net traction (the rover can no longer balance
// its resistance and its slip runs away to 100 %), or where the soil can no
// longer carry a wheel's load above the axle.
//
// The flight software is in the loop (OnboardLoop, replay.hpp): the rover
// drives until the flight code decides to stop, then follows the escape
// sequencer's commands. The open-loop drive is continued without telemetry
// to find where and when the rover would have embedded had it not stopped.
#pragma once

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sinkwatch::ground {

inline constexpr double kEmbedMaxSlip = 0.95;

/// The path: soil softness, slope and roll, linear between knots, held beyond.
struct TerrainKnot {
  double x_m = 0.0;
  double soil_scale = 1.0;  // multiplies kc, kphi and the cohesion of the base soil (< 1: softer)
  double slope_deg = 0.0;   // path slope, positive uphill
  double roll_deg = 0.0;    // cross slope, positive right side down
  double right_soil_factor = 1.0;  // the right wheels' soil_scale is soil_scale times this (one-side softening)
};

/// How the bracketed slip is refined: bisection (the shipped scenarios) or
/// false position with the Illinois modification (the campaign: fewer
/// simulator calls for the same slip resolution).
enum class SlipRefine { bisection, illinois };

struct ScenarioNoise {
  double current_abs_a = 0.004;   // motor-current sensor: sigma = hypot(abs, rel * |I|)
  double current_rel = 0.01;
  double attitude_deg = 0.05;     // IMU pitch and roll
  double joint_deg = 0.05;        // rocker and bogie potentiometers
  double accel_mps2 = 0.003;      // IMU along the path
  double speed_mps = 0.001;       // visual odometry
};

struct ScenarioSpec {
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  std::string soil = "hit-lss1";   // base soil preset of the simulator
  double gravity_mps2 = 1.62;      // the Moon
  double cycle_s = 0.2;            // 5 Hz
  double speed_mps = 0.05;         // commanded rim speed (Yutu: 200 m/h = 0.056 m/s)
  double ramp_s = 1.0;             // speed ramps at starts and reversals
  double end_x_m = 20.0;           // the drive's goal
  double max_time_s = 1500.0;
  double stuck_tail_s = 20.0;      // rows logged after an embedding (no stop)
  double settle_s = 5.0;           // rows logged after the escape ends
  double escape_soil_gain = 1.5;   // soil_scale factor per direction reversal (assumption)
  std::vector<TerrainKnot> terrain;
  ScenarioNoise noise;
  ReplayConfig flight;             // the flight software in the loop
  // Campaign extensions (docs/campaign.md); the defaults are the shipped scenarios' world.
  double mass_kg = 140.0;                       // the simulated rover's mass, written as the log's mass_kg
                                                // (the flight code in the loop runs with it too)
  std::optional<SoilParameters> soil_parameters;  // a drawn soil in place of the preset `soil`
  std::optional<EffectSettings> effects;        // the simulator's effects; none: slip_sinkage only
  // The wheel loads are always the fuller balance (docs/rover-loads.md
  // section 11: each wheel's drawbar pull and drive-torque reaction), iterated
  // with the simulator up to this many passes per cycle.
  int load_iterations = 4;
  double quadrature_rel_tol = kDefaultQuadratureRelTol;  // the simulator's quadrature goal
  int slip_bisections = 14;          // refinement steps of the rover's slip (at most, for illinois)
  double slip_step_down = 0.04;      // bracketing the slip: steps down from the last slip, then up
  double slip_step_up = 0.02;
  SlipRefine slip_refine = SlipRefine::bisection;
  // The open-loop drive's traction reserve (CycleLoads::reserve_n) on every
  // this-many-th driving row; 0: not computed (the shipped scenarios).
  int reserve_every_rows = 0;
};

/// The simulator's parameters of the spec's soil at `soil_scale` (kc, kphi
/// and the cohesion of the base soil times the scale), with the spec's
/// gravity, quadrature goal and effects: what the generator evaluates a
/// wheel with on that soil, and what a soil-bin test of it would be run on.
SimParameters scenario_soil(const ScenarioSpec& spec, double soil_scale);

/// From firm ground into a soft ripple until the wheels would embed
/// (after Opportunity at Purgatory, sol 446), then the escape.
ScenarioSpec embedding_scenario();
/// Firm and moderately soft ground with gentle slopes: must not stop.
ScenarioSpec nominal_scenario();
/// The embedding scenario with a steep soft flank: a documented miss of the
/// default table (not shipped; docs/scenarios.md, finding 2).
ScenarioSpec steep_ripple_scenario();
/// By name: "embedding", "nominal" or "steep-ripple"; throws
/// std::invalid_argument otherwise.
ScenarioSpec scenario_by_name(const std::string& name);

struct ScenarioTruth {
  bool embedded = false;        // the open-loop drive embeds before the goal
  double embed_x_m = 0.0;
  double embed_time_s = 0.0;
  std::string embed_reason;
  std::optional<double> stop_time_s;  // the flight code's stop in the loop
  std::optional<double> stop_x_m;
  /// The smallest traction reserve (CycleLoads::reserve_n) of the open-loop
  /// drive before the embedding, over the rover's weight m g; empty when no
  /// row has a reserve (ScenarioSpec::reserve_every_rows = 0).
  std::optional<double> min_reserve_frac;
};

/// One cycle's wheel loads in the simulated world and what the flight
/// code's statics give there: wheel_loads() at the same mass, the true
/// attitude and joints, with each wheel's drive torque from the row's logged
/// current through the flight motor model, as the per-cycle step takes them
/// (docs/rover-loads.md 12.8; the sensor-health gate is not replayed).
struct CycleLoads {
  std::array<double, kTelemetryWheels> true_n{};
  std::array<double, kTelemetryWheels> flight_statics_n{};
  /// The traction reserve (docs/campaign.md): the largest total drawbar pull
  /// of the six wheels at any slip up to kEmbedMaxSlip, at this row's soil and
  /// loads, minus the pull the slope needs [N]. Below zero the rover embeds.
  /// Only on the rows ScenarioSpec::reserve_every_rows asks for.
  std::optional<double> reserve_n;
};

struct Scenario {
  TelemetryLog log;
  ScenarioTruth truth;
  std::vector<CycleLoads> cycle_loads;  // generate_open_loop_drive only, one per row
};

/// Deterministic: the same spec gives the same rows on any machine with
/// IEEE doubles (own Box–Muller on mt19937_64). `command_line` is recorded.
/// `progress` (may be empty) gets the simulated time in seconds.
Scenario generate_scenario(const ScenarioSpec& spec, const std::string& command_line,
                           const std::function<void(double)>& progress = {});

/// The open-loop drive alone (docs/campaign.md): forward at the commanded
/// speed, never stopping, until the goal or the embedding (then
/// stuck_tail_s of rows with the wheels spinning); the flight code is not
/// in the loop. Up to any stop of the flight code the closed-loop drive is
/// this drive (same rows, same noise draws), so replaying these rows through
/// OnboardLoop gives the flight code's first stop exactly, for any table.
/// `truth.stop_*` stay empty; `cycle_loads` has one entry per row.
Scenario generate_open_loop_drive(const ScenarioSpec& spec);

}  // namespace sinkwatch::ground
