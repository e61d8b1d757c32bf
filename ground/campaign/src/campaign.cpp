// The campaign's families, draws, verdicts and the threaded run (campaign.hpp,
// docs/campaign.md).
#include "sinkwatch/ground/campaign.hpp"

#include "sinkwatch/ground/calibration.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/soil_presets.hpp"

#include <algorithm>
#include <functional>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <exception>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>

namespace sinkwatch::ground {
namespace {

constexpr double kDegRad = 3.14159265358979323846 / 180.0;

// A row's time is the telemetry's (rounded through the CSV format); the
// embedding time is the simulator's double. Within this they are one cycle.
constexpr double kSameTimeS = 1e-3;

// Portable draws: the engine is specified bit for bit, the conversion is ours.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0));
  }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  std::size_t pick(std::size_t n) { return std::min(n - 1, static_cast<std::size_t>(uniform(0.0, 1.0) * n)); }

 private:
  std::mt19937_64 engine_;
};

// SplitMix64: one well-mixed seed per (campaign seed, family, index).
std::uint64_t mix(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// A piecewise-linear function of x, held beyond its ends (0 when empty).
struct Profile {
  std::vector<std::pair<double, double>> knots;
  double at(double x) const {
    if (knots.empty()) return 0.0;
    if (x <= knots.front().first) return knots.front().second;
    for (std::size_t i = 1; i < knots.size(); ++i) {
      if (x <= knots[i].first) {
        const double f = (x - knots[i - 1].first) / (knots[i].first - knots[i - 1].first);
        return knots[i - 1].second + f * (knots[i].second - knots[i - 1].second);
      }
    }
    return knots.back().second;
  }
};

// The softening along the path, from 1 at x0 down to `min_scale`.
Profile softening(CampaignFamily family, Draws& r, double x0, double min_scale) {
  Profile p;
  p.knots = {{0.0, 1.0}, {x0, 1.0}};
  if (family == CampaignFamily::abrupt) {
    p.knots.push_back({x0 + 0.3, min_scale});
  } else if (family == CampaignFamily::stepwise) {
    for (int k = 1; k <= 3; ++k) {
      const double level = std::pow(min_scale, k / 3.0);
      p.knots.push_back({x0 + 2.0 * (k - 1) + 0.3, level});
      if (k < 3) p.knots.push_back({x0 + 2.0 * k, level});
    }
  } else {
    const double length = r.uniform(3.0, 8.0);  // geometric fall over 3-8 m
    for (int k = 1; k <= 4; ++k) p.knots.push_back({x0 + length * k / 4.0, std::pow(min_scale, k / 4.0)});
  }
  return p;
}

// Short bumps: slope features of 0.8-2 m length and 3-10 cm height.
Profile bumps(Draws& r, double end_x) {
  Profile p;
  p.knots.push_back({0.0, 0.0});
  double x = r.uniform(2.0, 4.0);
  while (x + 2.0 < end_x) {
    const double length = r.uniform(0.8, 2.0);
    const double slope_deg = std::atan(r.uniform(0.03, 0.10) / (0.5 * length)) / kDegRad;
    p.knots.insert(p.knots.end(), {{x, 0.0}, {x + 0.25 * length, slope_deg}, {x + 0.75 * length, -slope_deg},
                                   {x + length, 0.0}});
    x += length + r.uniform(1.0, 4.0);
  }
  return p;
}

// A soil within the published ranges (../shared/reference/terramechanics.md 2.7).
SoilParameters drawn_soil(Draws& r) {
  SoilParameters s;
  s.name = "drawn";
  s.kc = r.log_uniform(0.9e3, 16e3);
  s.kphi = r.log_uniform(800e3, 2500e3);
  s.n = r.uniform(0.7, 1.2);
  s.cohesion_pa = r.log_uniform(170.0, 1700.0);
  s.friction_angle_rad = r.uniform(28.0, 37.0) * kDegRad;
  s.shear_modulus_m = r.uniform(0.010, 0.025);
  s.density_kg_m3 = 1600.0;
  return s;
}

// Every effect but slip_sinkage (always on) with probability 1/2.
EffectSettings random_effects(Draws& r, std::string& names) {
  EffectSettings e;
  e.slip_sinkage.enabled = true;
  names = "slip_sinkage";
  for (const Effect effect : kAllEffects) {
    if (effect == Effect::slip_sinkage || !r.chance(0.5)) continue;
    e.set_enabled(effect, true);
    names += "+" + std::string(effect_name(effect));
  }
  return e;
}

// The knots: every x where a profile changes, each knot with all profiles' values.
std::vector<TerrainKnot> knots_of(const Profile& scale, bool one_side, const Profile& slope, const Profile& roll) {
  std::vector<double> xs;
  for (const Profile* p : {&scale, &slope, &roll}) {
    for (const auto& k : p->knots) xs.push_back(k.first);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::vector<TerrainKnot> knots;
  for (const double x : xs) {
    const double s = scale.at(x);
    knots.push_back(TerrainKnot{x, one_side ? 1.0 : s, slope.at(x), roll.at(x), one_side ? s : 1.0});
  }
  return knots;
}

void scale_noise(ScenarioNoise& n, double f) {
  n.current_abs_a *= f;
  n.current_rel *= f;
  n.attitude_deg *= f;
  n.joint_deg *= f;
  n.accel_mps2 *= f;
  n.speed_mps *= f;
}

// The simulator settings of every campaign traverse (docs/campaign.md, "Speed").
void campaign_settings(ScenarioSpec& s, double path_length_m) {
  s.end_x_m = path_length_m;
  s.stuck_tail_s = 10.0;
  s.max_time_s = 60.0 * path_length_m / s.speed_mps;
  s.quadrature_rel_tol = 1e-6;
  s.slip_refine = SlipRefine::illinois;
  s.slip_bisections = 12;
  s.slip_step_down = 0.01;
  s.slip_step_up = 0.01;
  s.reserve_every_rows = 5;  // 1 s, 5 cm of travel: the traction reserve's resolution
}

}  // namespace

const char* family_name(CampaignFamily f) {
  switch (f) {
    case CampaignFamily::gradual: return "gradual";
    case CampaignFamily::abrupt: return "abrupt";
    case CampaignFamily::stepwise: return "stepwise";
    case CampaignFamily::one_side: return "one-side";
    case CampaignFamily::slope: return "slope";
    case CampaignFamily::roll: return "roll";
    case CampaignFamily::bumps: return "bumps";
    case CampaignFamily::drawn_soil: return "drawn-soil";
    case CampaignFamily::effects: return "effects";
  }
  return "unknown";
}

CampaignFamily family_from_name(const std::string& name) {
  std::string known;
  for (const CampaignFamily f : kAllCampaignFamilies) {
    if (name == family_name(f)) return f;
    known += std::string(" ") + family_name(f);
  }
  throw std::invalid_argument("unknown family '" + name + "'; known:" + known);
}

const char* flight_mass_name(FlightMass m) { return m == FlightMass::true_mass ? "true" : "default"; }

FlightMass flight_mass_from_name(const std::string& name) {
  if (name == "true") return FlightMass::true_mass;
  if (name == "default") return FlightMass::default_mass;
  throw std::invalid_argument("--flight-mass: '" + name + "' is not true or default");
}

std::vector<CampaignFamily> default_held_out_families() {
  return {CampaignFamily::one_side, CampaignFamily::drawn_soil};
}

const char* outcome_name(TraverseOutcome o) {
  switch (o) {
    case TraverseOutcome::stopped_ahead: return "stopped_ahead";
    case TraverseOutcome::stopped_close: return "stopped_close";
    case TraverseOutcome::late: return "late";
    case TraverseOutcome::missed: return "missed";
    case TraverseOutcome::false_stop: return "false_stop";
    case TraverseOutcome::near_miss_stop: return "near_miss_stop";
    case TraverseOutcome::ok_no_stop: return "ok_no_stop";
  }
  return "unknown";
}

namespace {

constexpr std::array<const char*, kFaultClasses> kFaultClassNames{
    "stuck-current", "zero-current", "dropout-current", "dropout-side",  "dropout-imu",       "dropout-joints",
    "spike-current", "bias-pitch",   "noise-imu",       "freeze-joints", "stall-current",     "freewheel-current",
    "repeat-clock",  "jump-clock"};

// A fault class's kind, its fixed duration (0: to the end) and value (0: the
// kind's default), and what its target is drawn from.
enum class TargetDraw { wheel, side, imu, pitch, joints, clock };
struct FaultClassRule {
  FaultKind kind;
  TargetDraw target;
  double duration_s;
  double value;
};
constexpr std::array<FaultClassRule, kFaultClasses> kFaultClassRules{{
    {FaultKind::stuck, TargetDraw::wheel, 0.0, 0.0},
    {FaultKind::zero, TargetDraw::wheel, 0.0, 0.0},
    {FaultKind::dropout, TargetDraw::wheel, 5.0, 0.0},
    {FaultKind::dropout, TargetDraw::side, 5.0, 0.0},
    {FaultKind::dropout, TargetDraw::imu, 5.0, 0.0},
    {FaultKind::dropout, TargetDraw::joints, 5.0, 0.0},
    {FaultKind::spike, TargetDraw::wheel, 0.0, 0.0},
    {FaultKind::bias, TargetDraw::pitch, 0.0, 5.0},  // the sign drawn
    {FaultKind::noise, TargetDraw::imu, 5.0, 3.0},
    {FaultKind::freeze, TargetDraw::joints, 0.0, 0.0},
    {FaultKind::stall, TargetDraw::wheel, 0.0, 0.0},
    {FaultKind::freewheel, TargetDraw::wheel, 0.0, 0.0},
    {FaultKind::repeat, TargetDraw::clock, 2.0, 0.0},
    {FaultKind::jump, TargetDraw::clock, 0.0, 10.0},
}};

FaultTarget drawn_target(TargetDraw t, Draws& r) {
  switch (t) {
    case TargetDraw::wheel: return static_cast<FaultTarget>(r.pick(kTelemetryWheels));
    case TargetDraw::side: return r.chance(0.5) ? FaultTarget::left : FaultTarget::right;
    case TargetDraw::imu: return FaultTarget::imu;
    case TargetDraw::pitch: return FaultTarget::pitch;
    case TargetDraw::joints: return FaultTarget::joints;
    case TargetDraw::clock: return FaultTarget::clock;
  }
  return FaultTarget::clock;
}

// The flight code's health channels a fault target feeds (one bit each).
unsigned watched_channels(FaultTarget t) {
  const auto bit = [](flight::SensorChannel c) { return 1U << static_cast<unsigned>(c); };
  switch (t) {
    case FaultTarget::left: return 0x07U;
    case FaultTarget::right: return 0x38U;
    case FaultTarget::imu:
    case FaultTarget::pitch:
    case FaultTarget::roll: return bit(flight::SensorChannel::imu);
    case FaultTarget::joints: return bit(flight::SensorChannel::joints);
    case FaultTarget::clock: return bit(flight::SensorChannel::clock);
    default: return 1U << static_cast<unsigned>(t);  // the six currents, in the same order
  }
}

}  // namespace

const char* fault_class_name(FaultClass c) { return kFaultClassNames.at(static_cast<std::size_t>(c)); }

FaultClass fault_class_from_name(const std::string& name) {
  std::string known;
  for (std::size_t i = 0; i < kFaultClasses; ++i) {
    if (name == kFaultClassNames[i]) return static_cast<FaultClass>(i);
    known += std::string(" ") + kFaultClassNames[i];
  }
  throw std::invalid_argument("unknown fault class '" + name + "'; known:" + known + " (or all)");
}

std::vector<FaultClass> all_fault_classes() {
  std::vector<FaultClass> all;
  for (std::size_t i = 0; i < kFaultClasses; ++i) all.push_back(static_cast<FaultClass>(i));
  return all;
}

FaultSpec draw_fault(FaultClass c, std::uint64_t traverse_seed, double window_end_s) {
  const FaultClassRule& rule = kFaultClassRules.at(static_cast<std::size_t>(c));
  Draws r(mix(traverse_seed ^ ((static_cast<std::uint64_t>(c) + 1U) << 40U)));
  FaultSpec f;
  f.kind = rule.kind;
  f.target = drawn_target(rule.target, r);
  f.start_s = std::round(10.0 * r.uniform(0.1, 0.9) * window_end_s) / 10.0;
  if (rule.duration_s > 0.0) f.duration_s = rule.duration_s;
  if (rule.value > 0.0) f.value = (f.kind == FaultKind::bias && r.chance(0.5)) ? -rule.value : rule.value;
  return f;
}

FaultVerdict fault_verdict(FaultClass c, const TraverseDraw& draw, const Scenario& drive, const ReplayConfig& config) {
  FaultVerdict v;
  v.fault_class = c;
  const double window_end_s = drive.truth.embedded ? drive.truth.embed_time_s
                                                   : (drive.log.rows.empty() ? 0.0 : drive.log.rows.back().time_s);
  v.spec = draw_fault(c, draw.seed, window_end_s);
  v.seed = mix(draw.seed ^ 0xFA17ULL);
  TelemetryLog seen = drive.log;
  (void)apply_faults(seen, {v.spec}, v.seed);
  v.flight = flight_verdict_of(seen, drive, config, watched_channels(v.spec.target), &v.detected_time_s);
  return v;
}

TraverseDraw draw_traverse(CampaignFamily family, std::uint64_t seed, std::size_t index, double path_length_m) {
  TraverseDraw d;
  d.family = family;
  d.index = index;
  d.seed = mix(mix(seed) ^ (static_cast<std::uint64_t>(family) << 32U) ^ index);
  Draws r(d.seed);
  ScenarioSpec& s = d.spec;
  s.name = std::string(family_name(family)) + "-" + std::to_string(index);
  s.seed = d.seed;
  campaign_settings(s, path_length_m);
  // Drawn for every family in the same order, so a family's own draws come after.
  d.mass_kg = r.uniform(120.0, 160.0);
  d.noise_scale = r.uniform(0.5, 2.0);
  const bool ordinary = r.chance(0.4);
  d.min_soil_scale = ordinary ? r.log_uniform(0.15, 1.0) : r.log_uniform(0.005, 0.1);
  const double x0 = r.uniform(3.0, 6.0);
  const std::vector<std::string> presets = soil_preset_names();
  d.soil = presets[r.pick(presets.size())];
  s.mass_kg = d.mass_kg;
  scale_noise(s.noise, d.noise_scale);
  const Profile scale = softening(family, r, x0, d.min_soil_scale);
  Profile slope, roll;
  if (family == CampaignFamily::slope) d.slope_deg = r.uniform(0.0, 12.0);
  if (family == CampaignFamily::roll) d.roll_deg = r.uniform(0.0, 10.0);
  if (d.slope_deg != 0.0) slope.knots = {{1.0, 0.0}, {2.0, d.slope_deg}};
  if (d.roll_deg != 0.0) roll.knots = {{1.0, 0.0}, {2.0, d.roll_deg}};
  if (family == CampaignFamily::bumps) slope = bumps(r, path_length_m);
  if (family == CampaignFamily::drawn_soil) {
    d.soil = "drawn";
    s.soil_parameters = drawn_soil(r);
  }
  s.soil = d.soil == "drawn" ? std::string("hit-lss1") : d.soil;
  d.effects = "slip_sinkage";
  if (family == CampaignFamily::effects) s.effects = random_effects(r, d.effects);
  s.terrain = knots_of(scale, family == CampaignFamily::one_side, slope, roll);
  s.description = std::string("campaign family ") + family_name(family);
  return d;
}

flight::ParameterTable table_at_traction_level(const flight::ParameterTable& table, double stop_coefficient) {
  if (!flight::traction_check_on(table.traction)) {
    throw std::invalid_argument("table_at_traction_level: the table has no section 8");
  }
  flight::ParameterTable t = table;
  flight::TractionParams& p = t.traction;
  const double caution =
      fx::to_double(p.caution_coefficient.q()) * stop_coefficient / fx::to_double(p.stop_coefficient.q());
  const double hysteresis = std::min(fx::to_double(p.hysteresis.q()), 0.5 * caution);
  fx::Status st;
  p.stop_coefficient = flight::Ratio{fx::from_double<flight::RatioQ>(stop_coefficient, st)};
  p.caution_coefficient = flight::Ratio{fx::from_double<flight::RatioQ>(caution, st)};
  p.hysteresis = flight::Ratio{fx::from_double<flight::RatioQ>(hysteresis, st)};
  if (!st.ok() || flight::validate(t) != flight::RejectReason::ok) {
    throw std::invalid_argument("table_at_traction_level: the flight code refuses stop coefficient " +
                                std::to_string(stop_coefficient));
  }
  return t;
}

flight::ParameterTable table_at_stop_level(const flight::ParameterTable& table, double stop_m) {
  flight::ParameterTable t = table;
  flight::MonitorParams& m = t.monitor;
  const double stop = fx::to_double(m.stop_sinkage_m.q());
  const double f = stop_m / stop;
  const double radius = fx::to_double(t.wheel_radius_m.q());
  const double caution = fx::to_double(m.caution_sinkage_m.q()) * f;
  const double allowed = std::min(radius, fx::to_double(m.allowed_sinkage_m.q()) * f);
  const double hysteresis = std::min(fx::to_double(m.sinkage_hysteresis_m.q()), 0.5 * caution);
  fx::Status st;
  m.stop_sinkage_m = flight::SinkageM{fx::from_double<flight::LengthQ>(stop_m, st)};
  m.caution_sinkage_m = flight::SinkageM{fx::from_double<flight::LengthQ>(caution, st)};
  m.allowed_sinkage_m = flight::SinkageM{fx::from_double<flight::LengthQ>(allowed, st)};
  m.sinkage_hysteresis_m = flight::SinkageM{fx::from_double<flight::LengthQ>(hysteresis, st)};
  // The escape's "freed" level must stay below the stop level (not used by
  // the campaign, which never runs the escape, but part of a valid table).
  const double freed = std::min(fx::to_double(t.escape.freed_sinkage_m.q()), 0.5 * stop_m);
  t.escape.freed_sinkage_m = flight::SinkageM{fx::from_double<flight::LengthQ>(freed, st)};
  const flight::RejectReason reason = flight::validate(t);
  if (!st.ok() || reason != flight::RejectReason::ok) {
    char level[32];
    std::snprintf(level, sizeof level, "%.1f", stop_m * 1000.0);
    throw std::invalid_argument(std::string("a stop level of ") + level + " mm gives a table the flight code refuses (" +
                                (st.ok() ? reject_reason_name(reason) : std::string("out of range")) + ")");
  }
  return t;
}

namespace {

// Outcome and lead from the stop and the simulator's embedding.
void classify(const ScenarioTruth& truth, FlightVerdict& v) {
  if (!truth.embedded) {
    const bool near_miss = truth.min_reserve_frac && *truth.min_reserve_frac < kNearMissReserve;
    v.outcome = !v.stop_time_s ? TraverseOutcome::ok_no_stop
                : near_miss    ? TraverseOutcome::near_miss_stop
                               : TraverseOutcome::false_stop;
    return;
  }
  if (!v.stop_time_s) {
    v.outcome = TraverseOutcome::missed;
    return;
  }
  v.lead_m = truth.embed_x_m - *v.stop_x_m;
  v.lead_s = truth.embed_time_s - *v.stop_time_s;
  if (*v.stop_time_s >= truth.embed_time_s - kSameTimeS) {
    v.outcome = TraverseOutcome::late;
  } else {
    v.outcome = *v.lead_m >= kCloseLeadM ? TraverseOutcome::stopped_ahead : TraverseOutcome::stopped_close;
  }
}

}  // namespace

ReplayConfig traverse_flight_config(const TraverseDraw& draw, const CampaignOptions& options,
                                    const flight::ParameterTable& table) {
  ReplayConfig config;
  config.table = table;
  config.gravity_mps2 = draw.spec.gravity_mps2;
  config.rover = options.rover;
  config.mass_source = options.rover ? MassSource::table : MassSource::yutu_default;
  if (options.flight_mass == FlightMass::true_mass) {
    config.mass_kg = draw.mass_kg;
    config.mass_source = MassSource::option;
  }
  return config;
}

namespace {

// The event record's sinkages at the stop, beside the simulator's deepest wheel.
void record_event(const std::optional<StopRecord>& event, const TelemetryRow& stop_row, FlightVerdict& v) {
  v.true_sinkage_at_stop_mm = stop_row.true_sinkage_mm;
  if (!event) return;
  if (event->peak_sinkage_m) v.event_peak_sinkage_mm = 1000.0 * *event->peak_sinkage_m;
  if (event->max_estimated_sinkage_m) v.event_max_estimate_mm = 1000.0 * *event->max_estimated_sinkage_m;
}

}  // namespace

FlightVerdict flight_verdict_of(const TelemetryLog& seen, const Scenario& drive, const ReplayConfig& flight_config,
                                unsigned watch, std::optional<double>* detected_time_s) {
  ReplayConfig config = flight_config;
  config.run_escape = false;
  OnboardLoop loop(config);
  FlightVerdict v;
  std::optional<StopRecord> first_event;
  const std::size_t rows = std::min(seen.rows.size(), drive.log.rows.size());
  for (std::size_t i = 0; i < rows; ++i) {
    const TelemetryRow& clean = drive.log.rows[i];
    const CycleRecord rec = loop.step(seen.rows[i], seen.source, clean.x_m.value_or(0.0));
    for (std::size_t ch = 0; ch < flight::kSensorChannelCount; ++ch) {
      const bool watched = ((watch >> ch) & 1U) != 0U;
      if (watched && detected_time_s && !*detected_time_s && rec.health[ch] != flight::SensorHealth::ok) {
        *detected_time_s = clean.time_s;
      }
    }
    const bool traction_caution = rec.traction_state == flight::TractionState::caution ||
                                  rec.traction_state == flight::TractionState::stop;
    if (!v.caution_time_s && (rec.worst_state() != flight::WheelState::nominal || traction_caution)) {
      v.caution_time_s = clean.time_s;
      v.caution_x_m = rec.x_m;
    }
    if (v.stop_reason == flight::StopReason::none && !rec.new_events.empty()) {
      v.stop_reason = rec.new_events.front().reason;
      first_event = rec.new_events.front();
    }
    if (v.stop_reason == flight::StopReason::none && rec.traction_stop_tripped) {
      v.stop_reason = flight::StopReason::traction;
    }
    if (rec.decision == flight::RoverDecision::stop_and_replan) {
      v.stop_time_s = clean.time_s;
      v.stop_x_m = rec.x_m;
      record_event(first_event, clean, v);
      if (rec.stop_decision && rec.stop_decision->recent_sinkage_m) {
        v.recent_estimate_mm = 1000.0 * *rec.stop_decision->recent_sinkage_m;
      }
      break;
    }
  }
  classify(drive.truth, v);
  return v;
}

FlightVerdict flight_verdict(const Scenario& drive, const ReplayConfig& config) {
  return flight_verdict_of(drive.log, drive, config);
}

FlightVerdict flight_verdict(const Scenario& drive, const flight::ParameterTable& table, double gravity_mps2) {
  ReplayConfig config;
  config.table = table;
  config.gravity_mps2 = gravity_mps2;
  return flight_verdict_of(drive.log, drive, config);
}

namespace {

// The first row of the drive that `crossed` accepts, and its lead on the
// simulator's embedding: the ideal sensors' common verdict.
IdealVerdict first_crossing(const Scenario& drive, const std::function<bool(std::size_t row)>& crossed) {
  IdealVerdict v;
  for (std::size_t i = 0; i < drive.log.rows.size(); ++i) {
    if (crossed(i)) {
      v.cross_time_s = drive.log.rows[i].time_s;
      v.cross_x_m = drive.log.rows[i].x_m.value_or(0.0);
      break;
    }
  }
  if (v.cross_time_s && drive.truth.embedded) {
    v.lead_m = drive.truth.embed_x_m - *v.cross_x_m;
    v.lead_s = drive.truth.embed_time_s - *v.cross_time_s;
  }
  return v;
}

}  // namespace

IdealVerdict ideal_verdict(const Scenario& drive, double level_m) {
  return first_crossing(drive, [&](std::size_t i) {
    const std::optional<double>& z_mm = drive.log.rows[i].true_sinkage_mm;
    return z_mm && *z_mm >= level_m * 1000.0;
  });
}

IdealVerdict reserve_verdict(const Scenario& drive, double weight_n) {
  return first_crossing(drive, [&](std::size_t i) {
    if (i >= drive.cycle_loads.size()) return false;
    const std::optional<double>& reserve = drive.cycle_loads[i].reserve_n;
    return reserve && *reserve < kNearMissReserve * weight_n;
  });
}

namespace {

// The simulator's deepest wheel before the embedding, and the mean load
// excess of the fuller balance over the flight statics while driving.
void truth_statistics(const Scenario& drive, TraverseResult& out) {
  double rear_true = 0.0, rear_statics = 0.0, front_true = 0.0, front_statics = 0.0;
  for (std::size_t i = 0; i < drive.log.rows.size(); ++i) {
    const TelemetryRow& row = drive.log.rows[i];
    if (drive.truth.embedded && row.time_s >= drive.truth.embed_time_s - kSameTimeS) break;
    out.max_true_sinkage_mm = std::max(out.max_true_sinkage_mm, row.true_sinkage_mm.value_or(0.0));
    if (row.phase != "drive" || i >= drive.cycle_loads.size()) continue;
    const CycleLoads& l = drive.cycle_loads[i];
    rear_true += l.true_n[2] + l.true_n[5];
    rear_statics += l.flight_statics_n[2] + l.flight_statics_n[5];
    front_true += l.true_n[0] + l.true_n[3];
    front_statics += l.flight_statics_n[0] + l.flight_statics_n[3];
  }
  out.rear_load_excess = rear_statics > 0.0 ? rear_true / rear_statics - 1.0 : 0.0;
  out.front_load_excess = front_statics > 0.0 ? front_true / front_statics - 1.0 : 0.0;
}

}  // namespace

flight::ParameterTable table_at_levels(const flight::ParameterTable& table, const LevelPair& levels) {
  const flight::ParameterTable at_stop = table_at_stop_level(table, levels.stop_mm / 1000.0);
  if (!levels.traction_stop) {
    flight::ParameterTable off = at_stop;
    off.traction = flight::TractionParams{};
    return off;
  }
  return table_at_traction_level(at_stop, *levels.traction_stop);
}

namespace {

// The traverse's table: the options' table, or that table calibrated to the
// traverse's soil (recorded in `out`).
flight::ParameterTable traverse_table(const TraverseDraw& draw, const CampaignOptions& options, TraverseResult& out) {
  if (options.calibration == CalibrationSoil::none) return options.table;
  SoilCalibration c;
  try {
    c = calibrate_to_soil(draw.spec, draw.min_soil_scale, options.calibration, options.table,
                          mix(draw.seed ^ 0x5011B1CULL));
  } catch (const CalibrationError&) {
    // No soil-bin pull even at scale 1 (bulldozing effects traverses that
    // cannot start, docs/scenarios.md finding 9): no table can be fitted,
    // the traverse runs with the given one and is counted in the summary.
    return options.table;
  }
  out.calibration = c.fit;
  return c.table;
}

}  // namespace

TraverseResult evaluate_traverse(const TraverseDraw& draw, const CampaignOptions& options) {
  TraverseResult out;
  out.draw = draw;
  out.held_out = std::find(options.held_out.begin(), options.held_out.end(), draw.family) != options.held_out.end();
  const Scenario drive = generate_open_loop_drive(draw.spec);
  out.rows = drive.log.rows.size();
  out.embedded = drive.truth.embedded;
  out.embed_x_m = drive.truth.embed_x_m;
  out.embed_time_s = drive.truth.embed_time_s;
  out.embed_reason = drive.truth.embed_reason;
  out.min_reserve_frac = drive.truth.min_reserve_frac;
  truth_statistics(drive, out);
  const flight::ParameterTable table = traverse_table(draw, options, out);
  const ReplayConfig config = traverse_flight_config(draw, options, table);
  out.flight = flight_verdict(drive, config);
  out.ideal = ideal_verdict(drive, fx::to_double(table.monitor.stop_sinkage_m.q()));
  out.reserve_ideal = reserve_verdict(drive, draw.spec.mass_kg * draw.spec.gravity_mps2);
  for (const double level_mm : options.sweep_stop_mm) {
    const flight::ParameterTable level = table_at_stop_level(table, level_mm / 1000.0);
    out.sweep.push_back(flight_verdict(drive, traverse_flight_config(draw, options, level)));
    out.sweep_ideal.push_back(ideal_verdict(drive, level_mm / 1000.0));
  }
  if (flight::traction_check_on(table.traction)) {
    for (const double coefficient : options.sweep_traction_stop) {
      const flight::ParameterTable level = table_at_traction_level(table, coefficient);
      out.traction_sweep.push_back(flight_verdict(drive, traverse_flight_config(draw, options, level)));
    }
  }
  for (const LevelPair& point : options.choice_grid) {
    out.choice.push_back(flight_verdict(drive, traverse_flight_config(draw, options, table_at_levels(table, point))));
    out.choice_ideal.push_back(ideal_verdict(drive, point.stop_mm / 1000.0));
  }
  for (const FaultClass c : options.faults) out.faults.push_back(fault_verdict(c, draw, drive, config));
  return out;
}

CampaignResult run_campaign(const CampaignOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CampaignResult result;
  result.options = options;
  std::vector<TraverseDraw> draws;
  for (const CampaignFamily f : options.families) {
    for (std::size_t k = 0; k < options.traverses_per_family; ++k) {
      draws.push_back(draw_traverse(f, options.seed, k, options.path_length_m));
    }
  }
  result.traverses.resize(draws.size());
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex mutex;
  std::exception_ptr failure;
  const auto worker = [&]() {
    for (std::size_t i = next++; i < draws.size(); i = next++) {
      try {
        result.traverses[i] = evaluate_traverse(draws[i], options);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = draws.size();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (options.progress) options.progress(done, draws.size());
    }
  };
  unsigned threads = options.threads != 0 ? options.threads : std::max(1U, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, draws.size())));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace sinkwatch::ground
