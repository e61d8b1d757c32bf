// The replay's report, time-series CSV and plot (replay_report.hpp).
#include "sinkwatch/ground/strf.hpp"
#include "sinkwatch/ground/replay_report.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/plot_style.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sinkwatch::ground {
namespace {

template <typename Quantity>
double to_d(Quantity q) {
  return fx::to_double(q.q());
}

// Negative estimates (the data above the fitted plane) are shown as "<0":
// the monitor treats them as no sinkage; the CSV keeps the raw number.
std::string mm(std::optional<double> m) {
  if (!m) return "    -   ";
  return *m < 0.0 ? std::string("   <0 mm") : strf("%5.1f mm", *m * 1000.0);
}

std::string ratio(std::optional<double> r) { return r ? strf("%4.2f", *r) : std::string("  - "); }

std::string states(const CycleRecord& c) {
  std::size_t count[3] = {0, 0, 0};
  for (const WheelCycle& w : c.wheels) count[static_cast<int>(w.state)]++;
  if (count[0] == kTelemetryWheels) return "all NOMINAL";
  std::string s;
  if (count[2] > 0) s += strf("%zu STOP", count[2]);
  if (count[1] > 0) s += strf("%s%zu CAUTION", s.empty() ? "" : ", ", count[1]);
  if (count[0] > 0) s += strf("%s%zu NOMINAL", s.empty() ? "" : ", ", count[0]);
  return s;
}

std::string status_line(const CycleRecord& c) {
  std::string line = strf("%8.1f s %7.2f m  %5s  %s   %s   %-20s %s", c.time_s, c.x_m,
                          c.slip ? strf("%4.2f", *c.slip).c_str() : "  - ", mm(c.max_sinkage_m()).c_str(),
                          ratio(c.max_current_ratio()).c_str(), states(c).c_str(), to_string(c.decision));
  if (c.status != flight::RoverStepStatus::ok) line += std::string("  [") + to_string(c.status) + "]";
  return line;
}

std::string verbose_line(const CycleRecord& c) {
  std::string line = strf("%8.1f s %7.2f m slip %5s |", c.time_s, c.x_m, c.slip ? strf("%4.2f", *c.slip).c_str() : "-");
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    const WheelCycle& w = c.wheels[i];
    line += strf(" %s %s %5.3f/%s %c |", kWheelNames[i],
                 w.estimate_valid ? strf("%5.1f", w.sinkage_m * 1000.0).c_str() : "  -  ", w.current_a,
                 w.limit_valid ? strf("%5.3f", w.current_limit_a).c_str() : "  -  ", to_string(w.state)[0]);
  }
  line += std::string(" ") + to_string(c.decision);
  if (c.status != flight::RoverStepStatus::ok) line += std::string(" [") + to_string(c.status) + "]";
  if (c.escape_active) line += std::string(" escape:") + to_string(c.escape_state);
  return line;
}

void wheel_table(std::ostream& out, const CycleRecord& c) {
  out << "       wheel   W [N]   DP [N]  T [N m]   I [A]  I_max [A]  z est [mm]  state\n";
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    const WheelCycle& w = c.wheels[i];
    out << strf("       %-4s %7.2f  %7.2f  %7.3f  %6.3f   %8s  %10s  %s\n", kWheelNames[i], w.load_n,
                w.drawbar_pull_n, w.torque_nm, w.current_a,
                w.limit_valid ? strf("%6.3f", w.current_limit_a).c_str() : "-",
                w.estimate_valid ? strf("%5.1f", w.sinkage_m * 1000.0).c_str() : "-", to_string(w.state));
  }
}

std::string event_text(const StopRecord& e) {
  std::string s = strf("%s at %.1f s: %s; peak current %.3f A at W = %.1f N", kWheelNames[e.wheel], e.time_s,
                       to_string(e.reason), e.peak_current_a, e.load_at_peak_n);
  if (e.peak_sinkage_m) s += strf("; Eq. 11 at that current and DP_max: %.1f mm", *e.peak_sinkage_m * 1000.0);
  if (e.max_estimated_sinkage_m) s += strf("; deepest estimate of the episode %.1f mm", *e.max_estimated_sinkage_m * 1000.0);
  return s;
}

std::string stop_decision_text(const StopDecision& s) {
  const std::string reason = s.reason == flight::StopReason::none ? "the step's own stop" : to_string(s.reason);
  if (!s.recent_sinkage_m) return strf("%s; no wheel had a valid estimate", reason.c_str());
  return strf("%s; deepest wheel %s, median of its last %zu estimates %.1f mm", reason.c_str(),
              kWheelNames[s.deepest_wheel], s.samples, *s.recent_sinkage_m * 1000.0);
}

std::optional<double> truth_sinkage_mm(const TelemetryLog& log, const CycleRecord& c) {
  return log.rows[c.row].true_sinkage_mm;
}

}  // namespace

std::optional<EmbeddingTruth> log_embedding(const TelemetryLog& log) {
  const auto it = log.metadata.find("embedding_x_m");
  if (it == log.metadata.end() || it->second == "none") return std::nullopt;
  EmbeddingTruth e;
  e.x_m = *log.number("embedding_x_m");
  const std::optional<double> t = log.number("embedding_time_s");
  if (!t) throw TelemetryError(log.source, 0, 0, "metadata 'embedding_x_m' without 'embedding_time_s'");
  e.time_s = *t;
  const auto reason = log.metadata.find("embedding_reason");
  if (reason != log.metadata.end()) e.reason = reason->second;
  return e;
}

std::optional<Lead> stop_lead(const TelemetryLog& log, const ReplayResult& result) {
  const std::optional<EmbeddingTruth> e = log_embedding(log);
  if (!e || !result.first_stop) return std::nullopt;
  const CycleRecord& stop = result.cycles[*result.first_stop];
  return Lead{e->x_m - stop.x_m, e->time_s - stop.time_s};
}

namespace {

// The title, the log's first comment (wrapped at about 100 columns), the
// rover and the flight code's stop rule, and the timeline's column heads.
void print_heading(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& r,
                   const std::string& title, double duration) {
  const flight::MonitorParams& mp = config.table.monitor;
  out << "sinkwatch replay: " << title << '\n';
  if (!log.comments.empty()) {
    std::istringstream words(log.comments.front());
    std::string word;
    std::string line = " ";
    while (words >> word) {
      if (line.size() + 1 + word.size() > 100) {
        out << line << '\n';
        line = " ";
      }
      line += " " + word;
    }
    out << line << '\n';
  }
  out << strf("  rover: %s geometry, %.1f kg (from %s), g = %.2f m/s^2; %zu cycles over %.1f s\n",
              config.rover ? "the table's section 6" : "Yutu-like", replay_mass_kg(config),
              describe_mass_source(config).c_str(), config.gravity_mps2, r.cycles.size(), duration);
  out << strf("  flight code: RoverStep (fixed point), parameter table: %s, version %u.\n"
              "  Stop at an estimated sinkage >= %.1f mm or a current >= I_max in %u of %u samples; %u wheel(s) in "
              "STOP stop the rover.\n",
              config.table_source.c_str(), static_cast<unsigned>(config.table.table_version),
              to_d(mp.stop_sinkage_m) * 1000.0,
              static_cast<unsigned>(mp.trip_n), static_cast<unsigned>(mp.window_m),
              static_cast<unsigned>(mp.rover_stop_k));
  const flight::TractionParams& tp = config.table.traction;
  if (flight::traction_check_on(tp)) {
    out << strf("  Stop also when the motion-resistance coefficient, carried %.1f m ahead along its rise over the "
                "last %.1f m, reaches %.2f (section 8).\n",
                to_d(tp.lookahead_m), to_d(tp.trend_span_m), to_d(tp.stop_coefficient));
  } else {
    out << "  The motion-resistance check is off (no section 8 in the table).\n";
  }
  out << "\n      time       x   slip   deepest z  I/Imax  wheels               decision\n";
}

// What the timeline carries from one cycle to the next.
struct Timeline {
  double next_line = -1e300;
  const CycleRecord* previous = nullptr;
  flight::EscapeState escape_before = flight::EscapeState::idle;
  std::optional<double> last_escape_input;
};

// The wheels whose state changed since the previous cycle ("FL -> CAUTION").
std::string wheel_changes(const CycleRecord& c, const CycleRecord& previous) {
  std::string changes;
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    if (c.wheels[i].state != previous.wheels[i].state) {
      changes += strf("%s%s -> %s", changes.empty() ? "" : ", ", kWheelNames[i], to_string(c.wheels[i].state));
    }
  }
  return changes;
}

// Every cycle with --verbose; otherwise a line when the rover-level picture
// changes (each wheel's own transitions are in --verbose and the CSV), every
// --every seconds and at the end.
void print_cycle_line(std::ostream& out, const CycleRecord& c, bool last, const ReportOptions& options,
                      Timeline& timeline) {
  const CycleRecord* previous = timeline.previous;
  const std::string changes = previous ? wheel_changes(c, *previous) : std::string();
  const bool changed = previous == nullptr || c.worst_state() != previous->worst_state() ||
                       c.decision != previous->decision || c.status != previous->status;
  if (options.verbose) {
    out << verbose_line(c) << '\n';
  } else if (changed || c.time_s >= timeline.next_line || last) {
    out << status_line(c) << (changes.empty() ? "" : "   <- " + changes) << '\n';
    timeline.next_line = c.time_s + options.every_s;
  }
}

// The rover's stop (the wheels and event records), or the wheels that trip
// after it has stopped (one short line).
void print_stop_events(std::ostream& out, const TelemetryLog& log, const CycleRecord& c,
                       const CycleRecord* previous) {
  const bool stop_now =
      c.decision == flight::RoverDecision::stop_and_replan && (!previous || previous->decision != c.decision);
  if (stop_now) {
    const std::optional<double> truth = truth_sinkage_mm(log, c);
    out << strf("\n  >>> STOP AND RE-PLAN at %.1f s, x = %.2f m%s. The wheels at the stop:\n", c.time_s, c.x_m,
                truth ? strf(" (simulator: deepest wheel %.1f mm)", *truth).c_str() : "");
    wheel_table(out, c);
    for (const StopRecord& e : c.new_events) out << "      event record: " << event_text(e) << '\n';
    if (c.stop_decision) out << "      stop record: " << stop_decision_text(*c.stop_decision) << '\n';
    if (c.traction_stop_tripped) {
      out << strf("      the motion-resistance check stopped the rover: coefficient %.3f, carried ahead %.3f\n",
                  c.resistance.value_or(0.0), c.resistance_ahead.value_or(0.0));
    }
    out << '\n';
  } else if (!c.new_events.empty()) {
    std::string names;
    for (const StopRecord& e : c.new_events) names += std::string(names.empty() ? "" : ", ") + kWheelNames[e.wheel];
    out << strf("%8.1f s %7.2f m  event records: %s (%s)\n", c.time_s, c.x_m, names.c_str(),
                to_string(c.new_events.front().reason));
  }
}

// The escape's start and each change of its phase.
void print_escape_progress(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config,
                           const CycleRecord& c, Timeline& timeline) {
  if (c.escape_started) {
    out << strf("  >>> escape sequence started (section 7: alternate forward and reverse, %.0f s + %.0f s per "
                "cycle)\n",
                config.table.escape.forward_phase_ms / 1000.0, config.table.escape.reverse_phase_ms / 1000.0);
  }
  if (c.escape_input_m) timeline.last_escape_input = c.escape_input_m;
  if (c.escape_active && c.escape_state != timeline.escape_before && !c.escape_started) {
    std::optional<double> truth = truth_sinkage_mm(log, c);
    out << strf("%8.1f s %7.2f m  escape: %-8s cycles done %u, last forward estimate of the deepest wheel %s%s\n",
                c.time_s, c.x_m, to_string(c.escape_state), static_cast<unsigned>(c.escape_cycles),
                timeline.last_escape_input ? strf("%.1f mm", *timeline.last_escape_input * 1000.0).c_str() : "-",
                truth ? strf(" (simulator: %.1f mm)", *truth).c_str() : "");
  }
  timeline.escape_before = c.escape_state;
}

void print_timeline(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& r,
                    const ReportOptions& options) {
  Timeline timeline;
  for (const CycleRecord& c : r.cycles) {
    print_cycle_line(out, c, &c == &r.cycles.back(), options, timeline);
    print_stop_events(out, log, c, timeline.previous);
    print_escape_progress(out, log, config, c, timeline);
    timeline.previous = &c;
  }
}

// Summary: the cycles the flight code could not use, and the stops.
void print_cycles_and_stops(std::ostream& out, const ReplayResult& r, double duration) {
  std::size_t bad = 0;
  std::string issues;
  for (std::size_t s = 1; s < r.status_counts.size(); ++s) {
    if (r.status_counts[s] == 0) continue;
    bad += r.status_counts[s];
    issues += strf("%s%zu %s", issues.empty() ? "" : ", ", r.status_counts[s],
                   to_string(static_cast<flight::RoverStepStatus>(s)));
  }
  out << strf("  cycles     %zu over %.1f s, %.2f m driven; cycles the flight code could not use: %s\n", r.cycles.size(),
              duration, r.distance_m, bad == 0 ? "none" : issues.c_str());
  std::size_t stops = 0;
  for (std::size_t i = 0; i < r.cycles.size(); ++i) {
    if (r.cycles[i].decision == flight::RoverDecision::stop_and_replan &&
        (i == 0 || r.cycles[i - 1].decision != flight::RoverDecision::stop_and_replan)) {
      ++stops;
    }
  }
  if (r.first_stop) {
    const CycleRecord& s = r.cycles[*r.first_stop];
    out << strf("  stops      %zu; the first at %.1f s, x = %.2f m\n", stops, s.time_s, s.x_m);
  } else {
    out << "  stops      none: the rover was never stopped\n";
  }
}

// Summary: where the simulator's rover would embed and how far ahead of it
// the flight code stopped; then the event records.
void print_embedding_and_events(std::ostream& out, const TelemetryLog& log, const ReplayResult& r) {
  const std::optional<EmbeddingTruth> emb = log_embedding(log);
  if (emb) {
    out << strf("  embedding  the simulator's rover would embed at x = %.2f m, %.1f s (%s)\n", emb->x_m, emb->time_s,
                emb->reason.c_str());
    const std::optional<Lead> lead = stop_lead(log, r);
    if (lead && lead->distance_m > 0.0) {
      out << strf("  lead       stopped %.2f m and %.1f s BEFORE the embedding\n", lead->distance_m, lead->time_s);
    } else if (lead) {
      out << strf("  lead       stopped %.2f m and %.1f s AFTER the embedding: too late\n", -lead->distance_m,
                  -lead->time_s);
    } else {
      out << "  lead       none: the rover drove into the embedding without stopping\n";
    }
  } else if (log.metadata.count("embedding_x_m")) {
    out << "  embedding  none in this scenario (the simulator's rover never embeds on this path)\n";
  }
  if (r.first_stop && r.cycles[*r.first_stop].stop_decision) {
    const CycleRecord& stop = r.cycles[*r.first_stop];
    const std::optional<double> truth = truth_sinkage_mm(log, stop);
    out << "  record     the rover's stop record: " << stop_decision_text(*stop.stop_decision)
        << (truth ? strf(" (simulator: %.1f mm)", *truth) : std::string()) << '\n';
  }
  if (r.events.empty()) {
    out << "  events     none\n";
  } else {
    out << strf("  events     %zu event record(s), the first: %s at %.1f s, %s\n", r.events.size(),
                kWheelNames[r.events.front().wheel], r.events.front().time_s, to_string(r.events.front().reason));
  }
}

// Summary: how the escape ended, when the first stop started one.
void print_escape_summary(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config,
                          const ReplayResult& r) {
  if (!r.first_stop || !r.cycles[*r.first_stop].escape_active) {
    return;
  }
  const CycleRecord& start = r.cycles[*r.first_stop];
  if (r.escape_end) {
    const CycleRecord& end = r.cycles[*r.escape_end];
    std::optional<double> t0 = truth_sinkage_mm(log, start);
    std::optional<double> t1 = truth_sinkage_mm(log, end);
    out << strf("  escape     %s after %u forward/reverse cycle(s), %.1f s", to_string(end.escape_state),
                static_cast<unsigned>(end.escape_cycles), end.time_s - start.time_s);
    if (end.escape_input_m) out << strf("; last estimate %.1f mm", *end.escape_input_m * 1000.0);
    out << strf(" (freed at <= %.1f mm)", to_d(config.table.escape.freed_sinkage_m) * 1000.0);
    if (t0 && t1) out << strf("; simulator's deepest wheel %.1f -> %.1f mm", *t0, *t1);
    out << '\n';
  } else {
    out << strf("  escape     still %s when the log ends\n", to_string(r.cycles.back().escape_state));
  }
  if (r.direction_mismatches > 0) {
    out << strf("  warning    %zu escape cycle(s) where the log's wheel direction differs from the sequencer's "
                "command\n             (the log was made with other parameters or by another sequencer)\n",
                r.direction_mismatches);
  }
}

// "stuck at 62.0 s (1250 cycles), recovering at ..." for one channel.
std::string channel_health_text(const ChannelHealthSummary& h) {
  // The healths in the order they were first reported.
  std::vector<std::size_t> order;
  for (std::size_t k = 1; k < flight::kSensorHealthCount; ++k) {
    if (h.first_s[k]) order.push_back(k);
  }
  std::stable_sort(order.begin(), order.end(), [&h](std::size_t a, std::size_t b) { return *h.first_s[a] < *h.first_s[b]; });
  std::string text;
  for (const std::size_t k : order) {
    text += strf("%s%s at %.1f s (%zu cycle%s)", text.empty() ? "" : ", ",
                 flight::health_name(static_cast<flight::SensorHealth>(k)), *h.first_s[k], h.cycles[k],
                 h.cycles[k] == 1 ? "" : "s");
  }
  if (h.episodes > 1) text += strf("; %zu episodes", h.episodes);
  if (!h.ok_at_end) {
    text += "; not ok at the end";
  } else if (h.back_to_ok_s) {
    text += strf("; ok again at %.1f s", *h.back_to_ok_s);
  }
  return text;
}

// Cycles driven degraded and with blind wheels, and since when.
void print_degraded(std::ostream& out, const ReplayConfig& config, const ReplayResult& r) {
  std::size_t degraded = 0, blind = 0;
  unsigned most_blind = 0;
  std::optional<double> first_degraded, first_blind;
  for (const CycleRecord& c : r.cycles) {
    if (c.degraded && ++degraded == 1) first_degraded = c.time_s;
    if (c.wheels_blind > 0 && ++blind == 1) first_blind = c.time_s;
    most_blind = std::max(most_blind, static_cast<unsigned>(c.wheels_blind));
  }
  const bool continue_policy = config.table.health.policy == flight::LossPolicy::continue_degraded;
  out << "  policy     " << (continue_policy ? "continue degraded" : "stop") << " on lost evidence (table section 7";
  if (continue_policy) out << strf(", at most %u blind wheel(s)", static_cast<unsigned>(config.table.health.max_blind_wheels));
  out << ")\n";
  out << (blind == 0 ? std::string("  blind      no wheel was ever blind\n")
                     : strf("  blind      %zu cycle(s) with blind wheels, the first at %.1f s, up to %u at once\n",
                            blind, *first_blind, most_blind));
  out << (degraded == 0 ? std::string("  degraded   never: the rover never drove on without evidence\n")
                        : strf("  degraded   %zu cycle(s) driven degraded, the first at %.1f s\n", degraded,
                               *first_degraded));
}

// The section "Sensor health": what was injected, each channel's health as
// the flight code reported it, the decision, blind wheels and degraded driving.
void print_sensor_health(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config,
                         const ReplayResult& r) {
  out << "\nSensor health\n";
  const std::string prefix = "injected fault ";
  for (const std::string& c : log.comments) {
    if (c.compare(0, prefix.size(), prefix) == 0) out << "  injected   " << c.substr(prefix.size()) << '\n';
  }
  const auto health = channel_health(r);
  std::size_t quiet = 0;
  for (std::size_t ch = 0; ch < health.size(); ++ch) {
    if (health[ch].episodes == 0) {
      ++quiet;
      continue;
    }
    out << strf("  %-10s %s\n", flight::channel_name(static_cast<flight::SensorChannel>(ch)),
                channel_health_text(health[ch]).c_str());
  }
  out << (quiet == health.size() ? "  channels   every channel ok throughout\n"
                                 : quiet > 0 ? "  channels   the others ok throughout\n" : "");
  if (r.first_stop) {
    const CycleRecord& s = r.cycles[*r.first_stop];
    out << strf("  decision   STOP AND RE-PLAN at %.1f s", s.time_s)
        << (r.events.empty() ? std::string()
                             : strf(" (first event: %s, %s)", kWheelNames[r.events.front().wheel],
                                    to_string(r.events.front().reason)))
        << '\n';
  } else {
    out << "  decision   continue throughout: the rover was never stopped\n";
  }
  print_degraded(out, config, r);
}

}  // namespace

std::array<ChannelHealthSummary, flight::kSensorChannelCount> channel_health(const ReplayResult& r) {
  std::array<ChannelHealthSummary, flight::kSensorChannelCount> out{};
  for (std::size_t ch = 0; ch < out.size(); ++ch) {
    ChannelHealthSummary& h = out[ch];
    bool ok_before = true;
    for (const CycleRecord& c : r.cycles) {
      const std::size_t k = static_cast<std::size_t>(c.health[ch]);
      const bool ok = c.health[ch] == flight::SensorHealth::ok;
      ++h.cycles[k];
      if (!h.first_s[k]) h.first_s[k] = c.time_s;
      if (ok_before && !ok) ++h.episodes;
      if (!ok_before && ok) h.back_to_ok_s = c.time_s;
      ok_before = ok;
    }
    h.ok_at_end = ok_before;
  }
  return out;
}

void print_report(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& r,
                  const ReportOptions& options) {
  const double duration = r.cycles.empty() ? 0.0 : r.cycles.back().time_s - r.cycles.front().time_s;
  print_heading(out, log, config, r, options.title, duration);
  print_timeline(out, log, config, r, options);
  out << "\nSummary\n";
  print_cycles_and_stops(out, r, duration);
  print_embedding_and_events(out, log, r);
  print_escape_summary(out, log, config, r);
  print_sensor_health(out, log, config, r);
}

void write_series_csv(std::ostream& out, const TelemetryLog& log, const ReplayResult& r) {
  out << "time_s,x_m,status,decision,slip,accel_mps2";
  for (const char* w : kWheelNames) {
    out << ",W_" << w << "_n,DP_" << w << "_n,I_" << w << "_a,Imax_" << w << "_a,T_" << w << "_nm,z_" << w
        << "_mm,state_" << w;
  }
  out << ",escape_state,escape_command,escape_input_mm,true_slip,true_sinkage_mm";
  for (std::uint8_t ch = 0; ch < flight::kSensorChannelCount; ++ch) {
    out << ",health_" << flight::channel_name(static_cast<flight::SensorChannel>(ch));
  }
  out << ",wheels_blind,degraded\n";
  const auto opt = [](const std::optional<double>& v, const char* f) { return v ? strf(f, *v) : std::string(); };
  for (const CycleRecord& c : r.cycles) {
    out << strf("%.3f,%.4f,", c.time_s, c.x_m) << to_string(c.status) << ','
        << (c.decision == flight::RoverDecision::stop_and_replan ? "stop" : "continue") << ',' << opt(c.slip, "%.5f")
        << ',' << opt(c.accel_mps2, "%.5f");
    for (const WheelCycle& w : c.wheels) {
      out << ',' << (w.load_valid ? strf("%.4f", w.load_n) : "") << ',' << (w.load_valid ? strf("%.4f", w.drawbar_pull_n) : "")
          << ',' << strf("%.5f", w.current_a) << ',' << (w.limit_valid ? strf("%.5f", w.current_limit_a) : "") << ','
          << (w.estimate_valid ? strf("%.5f", w.torque_nm) : "") << ','
          << (w.estimate_valid ? strf("%.3f", w.sinkage_m * 1000.0) : "") << ',' << to_string(w.state);
    }
    const TelemetryRow& row = log.rows[c.row];
    out << ',' << to_string(c.escape_state) << ',' << to_string(c.escape_command) << ','
        << (c.escape_input_m ? strf("%.3f", *c.escape_input_m * 1000.0) : "") << ',' << opt(row.true_slip, "%.4f")
        << ',' << opt(row.true_sinkage_mm, "%.3f");
    for (const flight::SensorHealth h : c.health) out << ',' << flight::health_name(h);
    out << ',' << static_cast<unsigned>(c.wheels_blind) << ',' << (c.degraded ? 1 : 0) << '\n';
  }
}

namespace {

// Every line is drawn with `lt N` of the palette (plot_style.hpp) and
// nothing else, so a legend key looks like the line it names.
std::string lt(int linetype) { return " lt " + std::to_string(linetype); }
std::string level(PlotLevel l) { return lt(level_linetype(l)); }

// The data block $D, one line per cycle: time, |I| and I_max of each wheel,
// the estimates, the simulator's deepest wheel, the worst state, the stop
// and the escape command (columns 1 to 23). Sets `truth` when the log has
// the simulator's sinkage.
void plot_data(std::ostream& s, const TelemetryLog& log, const ReplayResult& r, bool& truth) {
  s << "$D << EOD\n";
  for (const CycleRecord& c : r.cycles) {
    s << strf("%.3f", c.time_s);
    for (const WheelCycle& w : c.wheels) s << strf(" %.5f", std::fabs(w.current_a));
    for (const WheelCycle& w : c.wheels) s << (w.limit_valid ? strf(" %.5f", w.current_limit_a) : " NaN");
    for (const WheelCycle& w : c.wheels) s << (w.estimate_valid ? strf(" %.3f", w.sinkage_m * 1000.0) : " NaN");
    const std::optional<double>& tz = log.rows[c.row].true_sinkage_mm;
    truth = truth || tz.has_value();
    s << (tz ? strf(" %.3f", *tz) : " NaN");
    s << ' ' << static_cast<int>(c.worst_state()) << ' '
      << (c.decision == flight::RoverDecision::stop_and_replan ? 1 : 0) << ' ';
    const int esc = c.escape_command == flight::EscapeCommand::drive_forward   ? 1
                    : c.escape_command == flight::EscapeCommand::drive_reverse ? -1
                                                                               : 0;
    s << esc << '\n';
  }
  s << "EOD\n";
}

// Vertical markers at the first stop and at the simulated embedding.
void plot_markers(std::ostream& s, const TelemetryLog& log, const ReplayResult& r) {
  if (r.first_stop) {
    s << strf("set arrow 1 from %.3f, graph 0 to %.3f, graph 1 nohead", r.cycles[*r.first_stop].time_s,
              r.cycles[*r.first_stop].time_s)
      << level(PlotLevel::stop) << '\n';
    s << strf("set label 1 'stop' at %.3f, graph 0.95 right offset -0.5,0 tc", r.cycles[*r.first_stop].time_s)
      << level(PlotLevel::stop) << '\n';
  }
  const std::optional<EmbeddingTruth> emb = log_embedding(log);
  if (emb) {
    // A rover stopped well ahead ends its log before the embedding's time:
    // widen the time axis so that the marker lies on the panels, not on the
    // key, and write its label on the marker's left.
    const bool after_log = !log.rows.empty() && (emb->time_s > log.rows.back().time_s);
    if (after_log) {
      s << strf("set xrange [*:%.3f]\n", emb->time_s + 0.02 * (emb->time_s - log.rows.front().time_s));
    }
    s << strf("set arrow 2 from %.3f, graph 0 to %.3f, graph 1 nohead", emb->time_s, emb->time_s)
      << level(PlotLevel::embedding) << '\n';
    s << strf("set label 2 'simulated embedding' at %.3f, graph 0.85 %s tc", emb->time_s,
              after_log ? "right offset -0.5,0" : "left offset 0.5,0")
      << level(PlotLevel::embedding) << '\n';
  }
}

// Top panel: each wheel's |I| and the limits I_max.
void plot_currents(std::ostream& s) {
  s << "set ylabel 'current [A]'\nset format x ''\n";
  s << "plot ";
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    s << (i ? ", " : "") << "$D u 1:" << 2 + i << " w l" << lt(wheel_linetype(i)) << " t '|I| " << kWheelNames[i]
      << "'";
  }
  // I_max of all six wheels in one style, titled once.
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    s << ", $D u 1:" << 8 + i << " w l" << level(PlotLevel::current_limit)
      << (i == 0 ? " t 'I_{max} (each wheel)'" : " notitle");
  }
  s << "\n";
}

// Middle panel: each wheel's estimate, the stop and caution levels and,
// when the log has it, the simulator's deepest wheel.
void plot_sinkage(std::ostream& s, const ReplayConfig& config, bool truth) {
  const double stop_mm = fx::to_double(config.table.monitor.stop_sinkage_m.q()) * 1000.0;
  const double caution_mm = fx::to_double(config.table.monitor.caution_sinkage_m.q()) * 1000.0;
  s << "unset label 1\nunset label 2\n";
  s << "set ylabel 'sinkage [mm]'\nset yrange [-10:*]\n";
  s << "plot ";
  for (std::size_t i = 0; i < kTelemetryWheels; ++i) {
    s << (i ? ", " : "") << "$D u 1:" << 14 + i << " w l" << lt(wheel_linetype(i)) << " t 'z est " << kWheelNames[i]
      << "'";
  }
  s << strf(", %.3f w l", stop_mm) << level(PlotLevel::stop) << " t 'stop level'";
  s << strf(", %.3f w l", caution_mm) << level(PlotLevel::caution) << " t 'caution level'";
  if (truth) s << ", $D u 1:20 w l" << level(PlotLevel::truth) << " t 'simulator: deepest wheel'";
  s << "\n";
}

// Bottom panel: the worst wheel state, the rover's stop and the escape command.
void plot_decisions(std::ostream& s) {
  s << "set format x '%g'\nset xlabel 'time [s]'\nset ylabel 'decision'\nset yrange [-1.5:2.5]\n";
  s << "set ytics ('reverse' -1, 'nominal' 0, 'caution, fwd' 1, 'stop' 2)\n";
  s << "plot $D u 1:21 w steps" << level(PlotLevel::state) << " t 'worst wheel state', "
    << "$D u 1:($22*2) w steps" << level(PlotLevel::stop) << " t 'rover: stop and re-plan', "
    << "$D u 1:23 w steps" << level(PlotLevel::escape) << " t 'escape command'\n";
}

}  // namespace

std::string plot_script(const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& r,
                        const std::string& image_path) {
  const bool svg = image_path.size() >= 4 && image_path.compare(image_path.size() - 4, 4, ".svg") == 0;
  std::ostringstream s;
  s << "# gnuplot script written by sinkwatch replay for " << quote_gnuplot_string(log.source) << "\n";
  s << (svg ? "set terminal svg size 1100,900 dynamic enhanced font 'sans,11'\n"
            : "set terminal pngcairo size 1100,900 enhanced font 'sans,10'\n");
  s << "set output '" << quote_gnuplot_string(image_path) << "'\n";
  s << gnuplot_linetypes();
  bool truth = false;
  plot_data(s, log, r, truth);
  // The log's name is user text: escaped, so that x_y.csv is not drawn as x
  // with a subscript y.
  s << "set multiplot layout 3,1 title '" << escape_gnuplot_text(log.source) << ": sinkwatch flight code replay'\n";
  s << "set grid\nset key outside right\nset lmargin 14\nset rmargin 28\n";
  plot_markers(s, log, r);
  plot_currents(s);
  plot_sinkage(s, config, truth);
  plot_decisions(s);
  s << "unset multiplot\n";
  return s.str();
}

namespace {

// `text` as one single-quoted shell word.
std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return q + "'";
}

}  // namespace

void check_plot_path(const std::string& image_path) {
  if (is_standard_output(image_path)) {
    throw OutputError("-: the plot is drawn into a file; standard output cannot take it");
  }
  (void)check_output_path(image_path);
  (void)check_output_path(image_path + ".gp");
}

std::string draw_plot(const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& result,
                      const std::string& image_path) {
  check_plot_path(image_path);
  const std::string script_path = image_path + ".gp";
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    write_output_file(script_path, plot_script(log, config, result, image_path));
    return "gnuplot was not found, so the plot was not drawn (Debian: apt-get install gnuplot-nox); the script is " +
           script_path + " (run: gnuplot " + shell_quote(script_path) + ")";
  }
  // gnuplot draws into a temporary beside the image (same extension, so the
  // same terminal), from a temporary script naming it; the image is renamed
  // into place only when gnuplot exited 0 and the image is not empty
  // (output_file.hpp). The script and the log are temporaries too, removed
  // at the end either way.
  OutputFile image(image_path);
  image.close();
  OutputFile script(script_path);
  script.write(plot_script(log, config, result, image.temporary_path()));
  script.close();
  OutputFile messages(script_path + ".log");
  messages.close();
  const int status = std::system(("gnuplot " + shell_quote(script.temporary_path()) + " 2>" +
                                  shell_quote(messages.temporary_path()))
                                     .c_str());
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream in(messages.temporary_path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.size() > 2000) text = text.substr(0, 2000) + " ...";
    throw std::runtime_error(image_path + ": gnuplot failed drawing the plot" +
                             (text.empty() ? std::string() : ":\n" + text));
  }
  image.commit();  // throws when gnuplot wrote nothing
  return "";
}

}  // namespace sinkwatch::ground
