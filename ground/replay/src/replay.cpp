// The onboard loop and the replay (replay.hpp).
#include "sinkwatch/ground/replay.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/load.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/text_input.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

template <typename QType>
QType to_q(double v, const TelemetryRow& row, const std::string& source, const char* what) {
  fx::Status st;
  const QType q = fx::from_double<QType>(v, st);
  if (!st.ok()) {
    throw TelemetryError(source, row.line, 1,
                         std::string(what) + " = " + text_input::format_number(v) + " does not fit the flight code's format");
  }
  return q;
}

template <typename Quantity>
double to_d(Quantity q) {
  return fx::to_double(q.q());
}

StopRecord convert(const flight::EventRecord& e) {
  StopRecord r;
  r.wheel = e.wheel;
  r.time_s = static_cast<double>(e.time.ms) / 1000.0;
  r.reason = e.reason;
  r.peak_current_a = to_d(e.peak_current_a);
  r.load_at_peak_n = to_d(e.load_at_peak_n);
  if (e.peak_sinkage_valid) r.peak_sinkage_m = to_d(e.peak_sinkage_m);
  if (e.max_estimate_valid) r.max_estimated_sinkage_m = to_d(e.max_estimated_sinkage_m);
  return r;
}

StopDecision convert(const flight::RoverStopRecord& s) {
  StopDecision d;
  d.time_s = static_cast<double>(s.time.ms) / 1000.0;
  d.reason = s.reason;
  d.deepest_wheel = s.deepest_wheel;
  d.samples = s.samples;
  if (s.sinkage_valid) d.recent_sinkage_m = to_d(s.recent_sinkage_m);
  return d;
}

}  // namespace

std::optional<double> CycleRecord::max_sinkage_m() const {
  std::optional<double> m;
  for (const WheelCycle& w : wheels) {
    if (w.estimate_valid && (!m || w.sinkage_m > *m)) m = w.sinkage_m;
  }
  return m;
}

std::optional<double> CycleRecord::max_current_ratio() const {
  std::optional<double> m;
  for (const WheelCycle& w : wheels) {
    if (w.limit_valid && w.current_limit_a > 0.0) {
      const double r = std::fabs(w.current_a) / w.current_limit_a;
      if (!m || r > *m) m = r;
    }
  }
  return m;
}

flight::WheelState CycleRecord::worst_state() const {
  flight::WheelState s = flight::WheelState::nominal;
  for (const WheelCycle& w : wheels) {
    if (static_cast<int>(w.state) > static_cast<int>(s)) s = w.state;
  }
  return s;
}

OnboardLoop::OnboardLoop(ReplayConfig config) : config_(config) {
  fx::Status st;
  const flight::AccelMps2 g{fx::from_double<flight::AccelQ>(config_.gravity_mps2, st)};
  if (!st.ok() || config_.gravity_mps2 <= 0.0) {
    throw std::invalid_argument("gravity " + text_input::format_number(config_.gravity_mps2) + " m/s^2 is not usable");
  }
  rover_ = config_.rover ? *config_.rover : flight::yutu_like_rover_params(g);
  if (flight::validate_rover_params(rover_) != flight::RoverParamStatus::ok) {
    throw std::invalid_argument("gravity " + text_input::format_number(config_.gravity_mps2) +
                                " m/s^2 is outside the rover model's range (0, 10]");
  }
  if (config_.mass_kg) {
    rover_.mass_kg = flight::MassKg{fx::from_double<flight::MassQ>(*config_.mass_kg, st)};
    if (!st.ok() || flight::validate_rover_params(rover_) != flight::RoverParamStatus::ok) {
      throw std::invalid_argument("rover mass " + text_input::format_number(*config_.mass_kg) +
                                  " kg is outside the flight code's range (0, 1000] kg");
    }
  }
  // Once, as the rover does at a table load; a table or rover the flight code
  // refuses is reported by every step's status, as on board.
  static_cast<void>(flight::prepare(config_.table, rover_, prepared_));
}

void resolve_rover_mass(const TelemetryLog& log, std::optional<double> option_kg, ReplayConfig& config) {
  if (option_kg) {
    if (!(std::isfinite(*option_kg) && *option_kg > 0.0 && *option_kg <= flight::limits::kMaxMassKg)) {
      throw std::invalid_argument("--mass-kg " + text_input::format_number(*option_kg) +
                                  " is outside the flight code's range (0, 1000] kg");
    }
    config.mass_kg = option_kg;
    config.mass_source = MassSource::option;
    return;
  }
  if (const std::optional<double> header = log.number("mass_kg")) {
    config.mass_kg = header;
    config.mass_source = MassSource::log_header;
    const auto at = log.metadata_at.find("mass_kg");
    config.mass_line = at != log.metadata_at.end() ? at->second.line : 0;
  }
}

double replay_mass_kg(const ReplayConfig& config) {
  if (config.mass_kg) return *config.mass_kg;
  if (config.rover) return to_d(config.rover->mass_kg);
  return flight::limits::YutuLike::kMassKg;
}

std::string describe_mass_source(const ReplayConfig& config) {
  switch (config.mass_source) {
    case MassSource::option: return "--mass-kg";
    case MassSource::log_header:
      return "the log's mass_kg" + (config.mass_line > 0 ? " (line " + std::to_string(config.mass_line) + ")" : "");
    case MassSource::table: return "the table's section 6";
    case MassSource::yutu_default: break;
  }
  return "the Yutu-like default: no --mass-kg, no mass_kg in the log, no rover section in the table";
}

double OnboardLoop::escape_best_sinkage_m() const { return to_d(escape_.best_sinkage_m()); }

namespace {

// The row in the flight code's fixed-point formats; a value that does not fit
// is a TelemetryError on the row's line.
flight::RoverTelemetry telemetry_of(const TelemetryRow& row, const std::string& source) {
  using namespace flight;
  RoverTelemetry t{};
  // The on-board clock is uint32 milliseconds: a time outside 0 ... 4294967.295 s
  // (possible in a row built in memory; the reader refuses it) has no clock
  // value, and converting it would be undefined behaviour.
  const double ms = std::round(row.time_s * 1000.0);
  if (!(ms >= 0.0 && ms <= 4294967295.0)) {
    throw TelemetryError(source, row.line, 1,
                         "time " + text_input::format_number(row.time_s) +
                             " s is outside the on-board clock (0 ... 4294967.295 s)");
  }
  t.time = TimeMs{static_cast<std::uint32_t>(ms)};
  t.valid = row.valid;
  // Dropouts reach the flight code as absence flags; the 0 beside each is
  // never a reading (the health monitor calls the channel missing).
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) t.presence.current_missing[i] = row.current_missing[i];
  t.presence.attitude_missing = row.attitude_missing;
  t.presence.joints_missing = row.joints_missing;
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    t.current_a[i] = CurrentA{to_q<CurrentQ>(row.current_a[i], row, source, "motor current")};
    t.direction[i] = row.reverse ? DriveDirection::reverse : DriveDirection::forward;
  }
  t.attitude.pitch_rad = AngleRad{to_q<AngleQ>(row.pitch_deg * kDegToRad, row, source, "pitch")};
  t.attitude.roll_rad = AngleRad{to_q<AngleQ>(row.roll_deg * kDegToRad, row, source, "roll")};
  for (std::size_t s = 0; s < 2; ++s) {
    t.joints.rocker_rad[s] = AngleRad{to_q<AngleQ>(row.rocker_deg[s] * kDegToRad, row, source, "rocker angle")};
    t.joints.bogie_rad[s] = AngleRad{to_q<AngleQ>(row.bogie_deg[s] * kDegToRad, row, source, "bogie angle")};
  }
  t.accel_valid = row.accel_mps2.has_value();
  if (t.accel_valid) t.accel_mps2 = AccelMps2{to_q<AccelQ>(*row.accel_mps2, row, source, "acceleration")};
  t.speed_valid = row.speed_mps.has_value();
  if (t.speed_valid) t.speed_mps = SpeedMps{to_q<SpeedQ>(*row.speed_mps, row, source, "speed")};
  t.rim_speed_valid = row.rim_speed_mps.has_value();
  if (t.rim_speed_valid) t.rim_speed_mps = SpeedMps{to_q<SpeedQ>(*row.rim_speed_mps, row, source, "rim speed")};
  return t;
}

// The cycle's record of the flight step's output, in SI units; the events
// of the wheels that tripped this cycle come from the monitor.
CycleRecord record_of(const flight::RoverStepOutput& out, const TelemetryRow& row, double x_m,
                      const flight::RoverStep& step) {
  using namespace flight;
  CycleRecord rec;
  rec.time_s = row.time_s;
  rec.x_m = x_m;
  rec.status = out.status;
  rec.decision = out.decision;
  if (out.slip_known) rec.slip = to_d(out.slip);
  if (out.accel_valid) rec.accel_mps2 = to_d(out.accel_mps2);
  rec.drawbar_saturated = out.drawbar_status == DrawbarStatus::saturated;
  for (std::size_t c = 0; c < kSensorChannelCount; ++c) rec.health[c] = out.health.channel[c];
  rec.wheels_blind = out.monitor.wheels_blind;
  rec.degraded = out.monitor.degraded;
  rec.traction_state = out.traction.state;
  rec.traction_stop_tripped = out.traction.stop_tripped;
  if (out.traction.rho_valid) {
    rec.resistance = to_d(out.traction.resistance_median);
    rec.resistance_ahead = to_d(out.traction.resistance_ahead);
  }
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    const WheelOutput& w = out.monitor.wheels[i];
    WheelCycle& c = rec.wheels[i];
    c.current_a = row.current_a[i];
    c.load_valid = out.loads_valid;
    c.load_n = to_d(out.load_n[i]);
    c.drawbar_pull_n = out.drawbar_valid ? to_d(out.drawbar_pull_n[i]) : 0.0;
    c.estimate_valid = w.estimate_valid;
    c.torque_nm = to_d(w.torque_nm);
    c.sinkage_m = to_d(w.sinkage_m);
    c.limit_valid = w.limit_valid;
    c.current_limit_a = to_d(w.current_limit_a);
    c.state = w.state;
    c.sample = w.sample_status;
    c.stop_reason = w.stop_reason;
    c.stop_tripped = w.stop_tripped;
    if (w.stop_tripped) {
      rec.new_events.push_back(convert(step.monitor().wheel(static_cast<std::uint8_t>(i)).last_event()));
    }
  }
  return rec;
}

// Where the escape starts: the deepest estimate of this cycle or of the
// events that stopped the rover, whichever is deeper.
flight::SinkageM escape_start_sinkage(const CycleRecord& rec) {
  double start_m = rec.max_sinkage_m().value_or(0.0);
  for (const StopRecord& e : rec.new_events) {
    if (e.max_estimated_sinkage_m) start_m = std::max(start_m, *e.max_estimated_sinkage_m);
  }
  fx::Status st;
  return flight::SinkageM{fx::from_double<flight::LengthQ>(start_m, st)};
}

// The escape sequencer's input for a cycle: the deepest estimate, only while
// driving forward at rim speed and not saturated (a reverse or slow cycle
// says nothing about getting out).
flight::EscapeInput escape_input(flight::TimeMs now, const TelemetryRow& row, CycleRecord& rec) {
  flight::EscapeInput in{};
  in.now = now;
  const std::optional<double> deepest = rec.max_sinkage_m();
  const bool driving_forward = !row.reverse && row.rim_speed_mps.has_value() &&
                               *row.rim_speed_mps >= kEscapeMinRimSpeedMps &&
                               !rec.drawbar_saturated;
  in.sinkage_valid = driving_forward && deepest.has_value();
  if (in.sinkage_valid) {
    fx::Status st;
    in.sinkage_m = flight::SinkageM{fx::from_double<flight::LengthQ>(*deepest, st)};
    in.sinkage_valid = st.ok();
    if (in.sinkage_valid) rec.escape_input_m = *deepest;
  }
  return in;
}

}  // namespace

CycleRecord OnboardLoop::step(const TelemetryRow& row, const std::string& source, double x_m) {
  using namespace flight;
  const RoverTelemetry t = telemetry_of(row, source);
  RoverStepOutput out{};
  step_.step(t, t.time, prepared_, out);
  CycleRecord rec = record_of(out, row, x_m, step_);
  // The flight code writes its stop record on the decision's edge.
  if (out.decision == RoverDecision::stop_and_replan && last_decision_ != out.decision &&
      step_.stops().has_record()) {
    rec.stop_decision = convert(step_.stops().last_record());
  }
  last_decision_ = out.decision;

  // The escape: started on the first stop, then fed forward-driving estimates.
  if (out.decision == RoverDecision::stop_and_replan && !stopped_) {
    stopped_ = true;
    if (config_.run_escape) {
      rec.escape_started = escape_.start(t.time, escape_start_sinkage(rec));
    }
  } else if (escape_.state() == EscapeState::forward || escape_.state() == EscapeState::reverse) {
    const EscapeCommand expected =
        escape_.state() == EscapeState::forward ? EscapeCommand::drive_forward : EscapeCommand::drive_reverse;
    rec.direction_mismatch = (expected == EscapeCommand::drive_reverse) != row.reverse;
    const EscapeOutput eo = escape_.step(escape_input(t.time, row, rec), config_.table.escape);
    rec.escape_finished_now = eo.finished;
  }
  rec.escape_active = escape_.state() != EscapeState::idle;
  rec.escape_state = escape_.state();
  rec.escape_cycles = escape_.cycles_done();
  switch (escape_.state()) {
    case EscapeState::forward: rec.escape_command = EscapeCommand::drive_forward; break;
    case EscapeState::reverse: rec.escape_command = EscapeCommand::drive_reverse; break;
    default: rec.escape_command = EscapeCommand::stop; break;
  }
  return rec;
}

void set_loss_policy(const std::string& name, flight::ParameterTable& table, std::string& table_source) {
  if (name == "stop") {
    table.health.policy = flight::LossPolicy::stop;
  } else if (name == "continue-degraded") {
    table.health.policy = flight::LossPolicy::continue_degraded;
  } else {
    throw std::invalid_argument("--loss-policy: '" + name + "' is not stop or continue-degraded");
  }
  const flight::RejectReason reason = flight::validate(table);
  if (reason != flight::RejectReason::ok) {
    throw std::invalid_argument("--loss-policy " + name + ": the flight code refuses the table (" +
                                reject_reason_name(reason) + ")");
  }
  table_source += ", loss policy " + name;
}

void load_parameter_table(const std::string& path, ReplayConfig& config) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the parameter table");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // load(): the flight module's one path from bytes to prepared parameters
  // (framing, CRC, the table's and the rover section's checks, each once).
  flight::PreparedParameters loaded;
  const flight::RejectReason reason = flight::load(bytes.data(), bytes.size(), loaded);
  if (reason != flight::RejectReason::ok) {
    throw std::runtime_error(path + ": the flight code rejects this parameter table: " +
                             reject_reason_name(reason));
  }
  config.table = loaded.table();
  config.table_source = path;
  if (loaded.table().rover_geometry.present) {
    config.rover = loaded.rover();
    config.gravity_mps2 = fx::to_double(loaded.rover().gravity_mps2.q());
    if (!config.mass_kg) config.mass_source = MassSource::table;
  }
}

double log_gravity(const TelemetryLog& log) { return log.number("gravity_mps2").value_or(1.62); }

ReplayResult run_replay(const TelemetryLog& log, const ReplayConfig& config,
                        const std::function<void(double)>& progress) {
  OnboardLoop loop(config);
  ReplayResult result;
  result.cycles.reserve(log.rows.size());
  double x = 0.0;
  double x0 = 0.0;
  for (std::size_t i = 0; i < log.rows.size(); ++i) {
    const TelemetryRow& row = log.rows[i];
    if (row.x_m) {
      x = *row.x_m;
    } else if (i > 0) {
      const double dt = row.time_s - log.rows[i - 1].time_s;
      const std::optional<double>& v = row.speed_mps ? row.speed_mps : row.rim_speed_mps;
      if (v && dt > 0.0) x += *v * dt;
    }
    if (i == 0) x0 = x;
    CycleRecord rec = loop.step(row, log.source, x);
    rec.row = i;
    result.status_counts.at(static_cast<std::size_t>(rec.status))++;
    for (const StopRecord& e : rec.new_events) result.events.push_back(e);
    if (rec.decision == flight::RoverDecision::stop_and_replan && !result.first_stop) {
      result.first_stop = result.cycles.size();
    }
    if (rec.escape_finished_now) result.escape_end = result.cycles.size();
    if (rec.direction_mismatch) ++result.direction_mismatches;
    result.cycles.push_back(std::move(rec));
    if (progress && (i % 64 == 0 || i + 1 == log.rows.size())) {
      progress(static_cast<double>(i + 1) / static_cast<double>(log.rows.size()));
    }
  }
  result.distance_m = x - x0;
  return result;
}

const char* to_string(flight::WheelState s) {
  switch (s) {
    case flight::WheelState::nominal: return "NOMINAL";
    case flight::WheelState::caution: return "CAUTION";
    case flight::WheelState::stop: return "STOP";
  }
  return "?";
}

const char* to_string(flight::RoverDecision d) {
  return d == flight::RoverDecision::stop_and_replan ? "STOP AND RE-PLAN" : "continue";
}

const char* to_string(flight::RoverStepStatus s) {
  using S = flight::RoverStepStatus;
  switch (s) {
    case S::ok: return "ok";
    case S::invalid_table: return "invalid parameter table";
    case S::invalid_rover_params: return "invalid rover parameters";
    case S::telemetry_invalid: return "telemetry flagged invalid";
    case S::telemetry_stale: return "telemetry stale";
    case S::telemetry_repeated: return "repeated time stamp";
    case S::motion_out_of_range: return "motion out of range";
    case S::loads_failed: return "wheel loads failed";
    case S::tip_over: return "tip-over limit";
    case S::no_acceleration: return "no acceleration";
    case S::drawbar_failed: return "drawbar pull failed";
    case S::radius_mismatch: return "wheel radius differs between rover and table";
    case S::sensor_lost: return "IMU or joint sensor lost";
  }
  return "?";
}

const char* to_string(flight::StopReason r) {
  switch (r) {
    case flight::StopReason::none: return "none";
    case flight::StopReason::current: return "current at its limit";
    case flight::StopReason::sinkage: return "sinkage at the stop level";
    case flight::StopReason::telemetry: return "unusable telemetry";
    case flight::StopReason::slip: return "slip at or above the high-slip level";
    case flight::StopReason::traction: return "motion resistance rising to the stop coefficient";
  }
  return "?";
}

const char* to_string(flight::EscapeState s) {
  switch (s) {
    case flight::EscapeState::idle: return "idle";
    case flight::EscapeState::forward: return "forward";
    case flight::EscapeState::reverse: return "reverse";
    case flight::EscapeState::freed: return "FREED";
    case flight::EscapeState::aborted: return "ABORTED";
    case flight::EscapeState::gave_up: return "GAVE UP";
  }
  return "?";
}

const char* to_string(flight::EscapeCommand c) {
  switch (c) {
    case flight::EscapeCommand::stop: return "stop";
    case flight::EscapeCommand::drive_forward: return "forward";
    case flight::EscapeCommand::drive_reverse: return "reverse";
  }
  return "?";
}

const char* to_string(flight::SampleStatus s) {
  using S = flight::SampleStatus;
  switch (s) {
    case S::ok: return "ok";
    case S::flagged_invalid: return "flagged invalid";
    case S::stale: return "stale";
    case S::repeated_time: return "repeated time";
    case S::current_out_of_range: return "current out of range";
    case S::load_out_of_range: return "load out of range";
    case S::direction_invalid: return "direction invalid";
    case S::estimate_failed: return "estimate failed";
    case S::sensor_fault: return "sensor fault";
  }
  return "?";
}

}  // namespace sinkwatch::ground
