// campaign.hpp: a Monte Carlo evaluation of the flight code in the loop over
// families of simulated traverses (issue 14; docs/campaign.md).
//
// Each traverse is a ScenarioSpec drawn from a family (soil, softening
// profile, slope, roll, bumps, mass, sensor noise, simulator effects) and a
// seed. The simulator makes the open-loop drive (generate_open_loop_drive:
// forward at the commanded speed until the goal or the embedding, wheel loads
// from the fuller force balance); the flight code (OnboardLoop) reads its rows.
// Up to the flight code's first stop the closed-loop drive is this drive, so
// the first STOP found on these rows is the stop the rover would have made,
// for the given table and for every stop level of the sweep (the loop re-run
// per level on the same rows, exact). The embedding point is the scenario
// generator's (docs/scenarios.md). Per traverse: first CAUTION, first STOP and
// its reason, lead, outcome, and the lead an ideal sinkage sensor (the
// simulator's deepest wheel against the same stop level) would have had.
//
// Deterministic per seed: traverse k of family f depends only on (seed, f, k),
// results are stored by index, so any thread count gives the same numbers.
#pragma once

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/fault_injection.hpp"
#include "sinkwatch/ground/scenario.hpp"
#include "sinkwatch/ground/soil_calibration.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sinkwatch::ground {

enum class CampaignFamily {
  gradual,     // a preset soil softening gradually over 3-8 m
  abrupt,      // an abrupt soft patch (0.3 m transition)
  stepwise,    // three steps of softening, 2 m apart
  one_side,    // only the right wheels' soil softens
  slope,       // gradual softening on an uphill slope of 0-12 deg
  roll,        // gradual softening at a roll of 0-10 deg
  bumps,       // gradual softening with short bumps (slope features up to ~14 deg)
  drawn_soil,  // a soil drawn within published ranges of kc, kphi, n, c, phi, K
  effects,     // a preset soil with the simulator's effects switched on at random
};
inline constexpr std::array<CampaignFamily, 9> kAllCampaignFamilies{
    CampaignFamily::gradual, CampaignFamily::abrupt,  CampaignFamily::stepwise,
    CampaignFamily::one_side, CampaignFamily::slope,  CampaignFamily::roll,
    CampaignFamily::bumps,    CampaignFamily::drawn_soil, CampaignFamily::effects};

const char* family_name(CampaignFamily f);
/// Throws std::invalid_argument naming the families when `name` is unknown.
CampaignFamily family_from_name(const std::string& name);
/// Kept out of any tuning by default, reported apart: drawn soils, one-side softening.
std::vector<CampaignFamily> default_held_out_families();

enum class TraverseOutcome {
  stopped_ahead,  // embeds; the flight code stopped >= 1 m before the embedding point
  stopped_close,  // embeds; stopped before it, by less than 1 m
  late,           // embeds; stopped at or after the embedding
  missed,         // embeds; never stopped
  false_stop,     // never embeds, never came near it (min reserve >= kNearMissReserve), but stopped
  near_miss_stop, // never embeds, came within kNearMissReserve of it, and stopped
  ok_no_stop,     // never embeds, never stopped
};
inline constexpr std::size_t kTraverseOutcomes = 7;
/// A drive that never embeds but whose traction reserve (the largest pull
/// the six wheels could give, minus what the slope needs) fell below this
/// share of the rover's weight is a near miss: 0.05 m g is the pull of a
/// 2.9 degree rise, so the next gentle rise or slightly softer patch would
/// have embedded it. A stop there is not a stop for nothing (docs/campaign.md).
inline constexpr double kNearMissReserve = 0.05;
const char* outcome_name(TraverseOutcome o);

inline constexpr double kCloseLeadM = 1.0;  // stopped_ahead vs stopped_close

/// Sensor-fault classes of `--faults` (docs/fault-injection.md): each a
/// fault kind on a kind of channel with a fixed duration and value; the
/// wheel or side, the sign and the start are drawn per traverse.
enum class FaultClass {
  stuck_current,      // stuck:<wheel>_current, to the end
  zero_current,       // zero:<wheel>_current, to the end
  dropout_current,    // dropout:<wheel>_current, 5 s
  dropout_side,       // dropout:left|right, 5 s
  dropout_imu,        // dropout:imu, 5 s
  dropout_joints,     // dropout:joints, 5 s
  spike_current,      // spike:<wheel>_current, the default value
  bias_pitch,         // bias:pitch, +-5 deg, to the end
  noise_imu,          // noise:imu, sd 3 deg, 5 s
  freeze_joints,      // freeze:joints, to the end
  stall_current,      // stall:<wheel>_current, the default value, to the end
  freewheel_current,  // freewheel:<wheel>_current, to the end
  repeat_clock,       // repeat:clock, 2 s
  jump_clock,         // jump:clock, +10 s
};
inline constexpr std::size_t kFaultClasses = 14;
const char* fault_class_name(FaultClass c);
/// Throws std::invalid_argument naming the classes when `name` is unknown.
FaultClass fault_class_from_name(const std::string& name);
std::vector<FaultClass> all_fault_classes();

/// The fault of class `c` for the traverse of seed `traverse_seed`: a pure
/// function of the two and of `window_end_s` (the embedding's time, else the
/// drive's end): it starts uniformly within 10-90 % of the window, on 0.1 s.
FaultSpec draw_fault(FaultClass c, std::uint64_t traverse_seed, double window_end_s);

/// What was drawn for one traverse, with the spec the simulator runs.
struct TraverseDraw {
  CampaignFamily family = CampaignFamily::gradual;
  std::size_t index = 0;
  std::uint64_t seed = 0;        // the traverse's own seed (noise and draws)
  std::string soil;              // preset name, or "drawn"
  double mass_kg = 140.0;
  double slope_deg = 0.0;        // the uphill slope after the start (0 outside `slope`)
  double roll_deg = 0.0;
  double min_soil_scale = 1.0;   // the softest soil_scale of the path
  double noise_scale = 1.0;      // multiplies every sensor noise sigma
  std::string effects;           // effects switched on, '+'-joined
  ScenarioSpec spec;
};

/// Traverse `index` of `family` for `seed`: a pure function of the three.
/// `path_length_m` is the drive's goal (docs/campaign.md: 16 m by default).
TraverseDraw draw_traverse(CampaignFamily family, std::uint64_t seed, std::size_t index, double path_length_m = 16.0);

/// The flight code's first stop and caution on one traverse's rows, for one table.
struct FlightVerdict {
  std::optional<double> caution_time_s, caution_x_m;
  std::optional<double> stop_time_s, stop_x_m;
  flight::StopReason stop_reason = flight::StopReason::none;
  std::optional<double> lead_m, lead_s;  // embedding minus stop, when both exist
  TraverseOutcome outcome = TraverseOutcome::ok_no_stop;
  // At the stop, when a wheel's event record stopped the rover: its sinkage at
  // the episode's peak current (section 7: Eq. 11 with DP = DP_max) and its
  // largest per-cycle estimate; and the simulator's deepest wheel then.
  std::optional<double> event_peak_sinkage_mm, event_max_estimate_mm, true_sinkage_at_stop_mm;
  // At any stop: the rover's stop record (flight/stop_record.hpp), the
  // deepest wheel's median over its last kStopRecordSamples valid estimates.
  std::optional<double> recent_estimate_mm;
};

/// One injected fault's effect on a traverse (the campaign's table).
struct FaultVerdict {
  FaultClass fault_class = FaultClass::stuck_current;
  FaultSpec spec;
  std::uint64_t seed = 0;  // of the fault's own noise
  FlightVerdict flight;    // on the faulty rows, timed and placed by the clean ones
  /// The first cycle, up to the stop, where the flight code's health named a
  /// faulted channel not ok; empty: never (before the stop).
  std::optional<double> detected_time_s;
};

/// The ideal sensor: the first row whose true deepest-wheel sinkage reaches the level.
struct IdealVerdict {
  std::optional<double> cross_time_s, cross_x_m;
  std::optional<double> lead_m, lead_s;  // embedding minus crossing (negative: after it)
};

struct TraverseResult {
  TraverseDraw draw;
  bool held_out = false;
  bool embedded = false;
  double embed_x_m = 0.0, embed_time_s = 0.0;
  std::string embed_reason;
  double max_true_sinkage_mm = 0.0;  // deepest wheel before the embedding (or over the drive)
  FlightVerdict flight;              // the campaign's table
  IdealVerdict ideal;                // at the table's stop level
  IdealVerdict reserve_ideal;        // the ideal traction-reserve sensor (reserve_verdict)
  // The fuller balance against the flight statics, mean over the driving
  // rows: true load / statics load - 1 of the rear and of the front wheels.
  double rear_load_excess = 0.0, front_load_excess = 0.0;
  std::optional<double> min_reserve_frac;  // ScenarioTruth::min_reserve_frac of the open-loop drive
  std::vector<FlightVerdict> sweep;  // one per CampaignOptions::sweep_stop_mm
  std::vector<IdealVerdict> sweep_ideal;
  // One per CampaignOptions::sweep_traction_stop; empty when the table has
  // no section 8 (the motion-resistance check off).
  std::vector<FlightVerdict> traction_sweep;
  // One per CampaignOptions::choice_grid (--choose-levels); empty otherwise.
  std::vector<FlightVerdict> choice;
  std::vector<IdealVerdict> choice_ideal;  // the ideal sinkage sensor at each point's stop level
  std::vector<FaultVerdict> faults;  // one per CampaignOptions::faults
  std::size_t rows = 0;
  // With CampaignOptions::calibration: the soil the traverse's table was
  // calibrated on and what the fit gave at m g / 6 (soil_calibration.hpp);
  // empty when no table could be fitted (the traverse ran with the
  // campaign's table) or without --calibrate.
  std::optional<SoilBinFit> calibration;
};

/// The mass the flight code in the loop is given (--flight-mass).
enum class FlightMass {
  true_mass,     // "true": each traverse's drawn mass (120-160 kg), as an operator who
                 // sets the rover's mass (rover-table, --mass-kg, the log's mass_kg) has it
  default_mass,  // "default": the table's section 6, else the Yutu-like 140 kg, whatever
                 // the drawn mass (the campaign before issue 14's mass bullet)
};
const char* flight_mass_name(FlightMass m);
/// Throws std::invalid_argument for a name other than "true" or "default".
FlightMass flight_mass_from_name(const std::string& name);

/// One point of the level choice's grid (--choose-levels): the sinkage stop
/// level and section 8's stop coefficient; no coefficient: the
/// motion-resistance check off (section 8 removed from the table).
struct LevelPair {
  double stop_mm = 45.0;
  std::optional<double> traction_stop;
};

struct CampaignOptions {
  std::size_t traverses_per_family = 8;
  std::uint64_t seed = 14;
  std::vector<CampaignFamily> families{kAllCampaignFamilies.begin(), kAllCampaignFamilies.end()};
  std::vector<CampaignFamily> held_out = default_held_out_families();
  flight::ParameterTable table = flight::default_parameter_table();
  std::string table_source = "built-in default";
  /// Each traverse's table calibrated to its soil (soil_calibration.hpp):
  /// `table`'s correction rows replaced, its other sections kept.
  CalibrationSoil calibration = CalibrationSoil::none;
  /// The table's section 6 (its rover geometry), when it has one; else the Yutu-like rover.
  std::optional<flight::RoverParams> rover;
  FlightMass flight_mass = FlightMass::true_mass;
  unsigned threads = 0;  // 0: all cores
  double path_length_m = 16.0;
  /// Stop levels of the sweep [mm]: caution, stop and allowed (z_max) levels
  /// scaled together from the table's (docs/campaign.md).
  std::vector<double> sweep_stop_mm{25, 30, 35, 40, 45, 50, 55, 60, 70};
  /// Stop coefficients of the motion-resistance check's sweep (section 8;
  /// caution scaled with it, docs/traction.md); run only when the table has
  /// section 8.
  std::vector<double> sweep_traction_stop{0.30, 0.34, 0.38, 0.42, 0.46, 0.50};
  /// The level choice's grid (--choose-levels, level_choice.hpp): the flight
  /// code re-run per point with table_at_levels(); empty: not run.
  std::vector<LevelPair> choice_grid;
  /// Per traverse, one run with one fault of each class (at the table's levels).
  std::vector<FaultClass> faults;
  /// Called from worker threads (serialised) with (done, total).
  std::function<void(std::size_t, std::size_t)> progress;
};

/// The table with its caution, stop and allowed sinkage levels scaled so that
/// the stop level is `stop_m` (caution/stop and allowed/stop kept; the
/// hysteresis capped below the caution). Throws std::invalid_argument when the
/// flight code's validate() refuses the result.
flight::ParameterTable table_at_stop_level(const flight::ParameterTable& table, double stop_m);

/// The table with section 8's stop coefficient at `stop_coefficient` and its
/// caution coefficient scaled with it (caution/stop kept; the hysteresis
/// capped below the caution). Throws std::invalid_argument when the table has
/// no section 8 or validate() refuses the result.
flight::ParameterTable table_at_traction_level(const flight::ParameterTable& table, double stop_coefficient);

/// The table at a point of the level choice's grid: table_at_stop_level(),
/// then section 8 at the pair's coefficient (table_at_traction_level()) or
/// removed when it has none. Throws std::invalid_argument as those do.
flight::ParameterTable table_at_levels(const flight::ParameterTable& table, const LevelPair& levels);

/// The flight code's configuration for a traverse with `table`: the drawn
/// gravity, the options' rover (the table's section 6, else Yutu-like) and,
/// with FlightMass::true_mass, the drawn mass.
ReplayConfig traverse_flight_config(const TraverseDraw& draw, const CampaignOptions& options,
                                    const flight::ParameterTable& table);

/// The flight code's verdict on an open-loop traverse's rows.
FlightVerdict flight_verdict(const Scenario& drive, const ReplayConfig& config);
/// The same with the Yutu-like rover (140 kg) at `gravity_mps2`.
FlightVerdict flight_verdict(const Scenario& drive, const flight::ParameterTable& table, double gravity_mps2);
/// The flight code's verdict on `seen` (the drive's rows with faults; row k
/// for row k), with the stop's time and place taken from the clean rows so
/// that a clock fault does not move them. `watch` (one bit per
/// flight::SensorChannel) selects the channels whose first non-ok health
/// up to the stop is reported in `detected_time_s`.
FlightVerdict flight_verdict_of(const TelemetryLog& seen, const Scenario& drive, const ReplayConfig& config,
                                unsigned watch = 0U, std::optional<double>* detected_time_s = nullptr);
/// The verdict with one fault injected (draw_fault, apply_faults).
FaultVerdict fault_verdict(FaultClass c, const TraverseDraw& draw, const Scenario& drive, const ReplayConfig& config);
/// The ideal sensor's verdict at `level_m` on the same rows.
IdealVerdict ideal_verdict(const Scenario& drive, double level_m);
/// The ideal traction-reserve sensor: the first row of the open-loop drive
/// whose reserve (CycleLoads::reserve_n) is below kNearMissReserve of the
/// weight, and its lead. What knowing the soil's present reserve exactly
/// would allow without stopping a clear drive (docs/campaign.md).
IdealVerdict reserve_verdict(const Scenario& drive, double weight_n);

/// One traverse: the simulator's drive, then the verdicts.
TraverseResult evaluate_traverse(const TraverseDraw& draw, const CampaignOptions& options);

struct CampaignResult {
  CampaignOptions options;
  std::vector<TraverseResult> traverses;  // family by family, index order
  double seconds = 0.0;                   // wall time of the run
};

CampaignResult run_campaign(const CampaignOptions& options);

}  // namespace sinkwatch::ground
