// The campaign's report files (campaign_report.hpp, docs/campaign.md).
#include "sinkwatch/ground/campaign_report.hpp"

#include "sinkwatch/ground/plot_style.hpp"
#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/flight/stop_record.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string opt(const std::optional<double>& v, int digits, const char* none = "") {
  return v ? fixed(*v, digits) : std::string(none);
}

std::string json_opt(const std::optional<double>& v, int digits) { return v ? fixed(*v, digits) : "null"; }

// One number of the traverse's calibration fit; empty without one.
std::optional<double> fitted(const TraverseResult& t, double SoilBinFit::*field) {
  return t.calibration ? std::optional<double>((*t.calibration).*field) : std::nullopt;
}

// One traverse's CSV fields, in traverse_csv_columns() order.
std::vector<std::string> csv_fields(const TraverseResult& t) {
  const TraverseDraw& d = t.draw;
  const FlightVerdict& f = t.flight;
  return {family_name(d.family), t.held_out ? "1" : "0", std::to_string(d.index), std::to_string(d.seed), d.soil,
          fixed(d.mass_kg, 1), fixed(d.slope_deg, 2), fixed(d.roll_deg, 2), fixed(d.min_soil_scale, 4),
          fixed(d.noise_scale, 3), d.effects, t.embedded ? "1" : "0", t.embedded ? fixed(t.embed_x_m, 3) : "",
          t.embedded ? fixed(t.embed_time_s, 1) : "", t.embed_reason, opt(f.caution_time_s, 1), opt(f.caution_x_m, 3),
          opt(f.stop_time_s, 1), opt(f.stop_x_m, 3), f.stop_time_s ? to_string(f.stop_reason) : "",
          opt(f.lead_m, 3), opt(f.lead_s, 1), outcome_name(f.outcome), opt(t.ideal.cross_time_s, 1),
          opt(t.ideal.cross_x_m, 3), opt(t.ideal.lead_m, 3), opt(t.ideal.lead_s, 1), fixed(t.max_true_sinkage_mm, 1),
          fixed(t.rear_load_excess, 4), fixed(t.front_load_excess, 4), opt(t.min_reserve_frac, 4),
          opt(t.reserve_ideal.cross_x_m, 3), opt(t.reserve_ideal.lead_m, 3),
          std::to_string(t.rows), opt(f.event_peak_sinkage_mm, 1), opt(f.event_max_estimate_mm, 1),
          opt(f.true_sinkage_at_stop_mm, 1), opt(f.recent_estimate_mm, 1), opt(fitted(t, &SoilBinFit::soil_scale), 4),
          opt(fitted(t, &SoilBinFit::c3_at_mean_load), 4), opt(fitted(t, &SoilBinFit::dp_max_at_mean_load), 4)};
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

bool is_embedding(const TraverseResult& t) { return t.embedded; }

// Never embeds, but its traction reserve fell below kNearMissReserve.
bool is_near_miss(const TraverseResult& t) {
  return !t.embedded && t.min_reserve_frac && *t.min_reserve_frac < kNearMissReserve;
}

}  // namespace

const std::vector<std::string>& traverse_csv_columns() {
  static const std::vector<std::string> columns = {
      "family", "held_out", "index", "seed", "soil", "mass_kg", "slope_deg", "roll_deg", "min_soil_scale",
      "noise_scale", "effects", "embedded", "embed_x_m", "embed_time_s", "embed_reason", "caution_time_s",
      "caution_x_m", "stop_time_s", "stop_x_m", "stop_reason", "lead_m", "lead_s", "outcome", "ideal_cross_time_s",
      "ideal_cross_x_m", "ideal_lead_m", "ideal_lead_s", "max_true_sinkage_mm", "rear_load_excess",
      "front_load_excess", "min_reserve_frac", "reserve_cross_x_m", "reserve_lead_m", "rows",
      "event_peak_sinkage_mm", "event_max_estimate_mm", "true_sinkage_at_stop_mm", "recent_estimate_mm",
      "calibration_soil_scale", "calibration_c3", "calibration_dp_max"};
  return columns;
}

std::string traverses_csv(const CampaignResult& r) {
  std::ostringstream out;
  const std::vector<std::string>& columns = traverse_csv_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << '\n';
  for (const TraverseResult& t : r.traverses) {
    const std::vector<std::string> fields = csv_fields(t);
    for (std::size_t i = 0; i < fields.size(); ++i) out << (i ? "," : "") << csv_field(fields[i]);
    out << '\n';
  }
  return out.str();
}

namespace {

std::string numbers_json(const std::vector<double>& values, int digits) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + fixed(values[i], digits);
  return out + "]";
}

/// A sweep's verdicts as a JSON array, with the ideal sensor's lead at each
/// level when `ideal` is given.
std::string verdicts_json(const std::vector<FlightVerdict>& verdicts, const std::vector<IdealVerdict>* ideal) {
  std::ostringstream out;
  out << "[";
  for (std::size_t i = 0; i < verdicts.size(); ++i) {
    out << (i ? ", " : "") << "{\"outcome\": " << json_string(outcome_name(verdicts[i].outcome))
        << ", \"stop_time_s\": " << json_opt(verdicts[i].stop_time_s, 1)
        << ", \"lead_m\": " << json_opt(verdicts[i].lead_m, 3);
    if (ideal) out << ", \"ideal_lead_m\": " << json_opt((*ideal)[i].lead_m, 3);
    out << "}";
  }
  out << "]";
  return out.str();
}

}  // namespace

std::string traverses_json(const CampaignResult& r) {
  std::ostringstream out;
  out << "{\"seed\": " << r.options.seed << ", \"table\": " << json_string(r.options.table_source)
      << ", \"flight_mass\": " << json_string(flight_mass_name(r.options.flight_mass))
      << ", \"calibration\": " << json_string(calibration_soil_name(r.options.calibration))
      << ", \"sweep_stop_mm\": " << numbers_json(r.options.sweep_stop_mm, 1)
      << ", \"sweep_traction_stop\": " << numbers_json(r.options.sweep_traction_stop, 2) << ",\n \"traverses\": [\n";
  const std::vector<std::string>& columns = traverse_csv_columns();
  for (std::size_t k = 0; k < r.traverses.size(); ++k) {
    const TraverseResult& t = r.traverses[k];
    const std::vector<std::string> fields = csv_fields(t);
    out << "  {";
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const bool number = !fields[i].empty() && fields[i].find_first_not_of("-0123456789.") == std::string::npos;
      out << (i ? ", " : "") << json_string(columns[i]) << ": "
          << (number ? fields[i] : (fields[i].empty() ? std::string("null") : json_string(fields[i])));
    }
    out << ", \"sweep\": " << verdicts_json(t.sweep, &t.sweep_ideal)
        << ", \"traction_sweep\": " << verdicts_json(t.traction_sweep, nullptr);
    out << "}" << (k + 1 < r.traverses.size() ? "," : "") << '\n';
  }
  out << " ]}\n";
  return out.str();
}

std::string json_string(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::optional<double> median(std::vector<double> values) {
  if (values.empty()) return std::nullopt;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

namespace {

const FlightVerdict& verdict_at(const TraverseResult& t, std::optional<std::size_t> level, Sweep sweep) {
  if (!level) return t.flight;
  switch (sweep) {
    case Sweep::traction_coefficient: return t.traction_sweep.at(*level);
    case Sweep::choice: return t.choice.at(*level);
    case Sweep::stop_level: break;
  }
  return t.sweep.at(*level);
}

const IdealVerdict& ideal_at(const TraverseResult& t, std::optional<std::size_t> level, Sweep sweep) {
  if (!level || sweep == Sweep::traction_coefficient) return t.ideal;
  return sweep == Sweep::choice ? t.choice_ideal.at(*level) : t.sweep_ideal.at(*level);
}

}  // namespace

GroupStats group_stats(const std::vector<const TraverseResult*>& group, std::optional<std::size_t> level,
                       Sweep sweep) {
  GroupStats g;
  for (const TraverseResult* t : group) {
    const FlightVerdict& f = verdict_at(*t, level, sweep);
    const IdealVerdict& ideal = ideal_at(*t, level, sweep);
    ++g.traverses;
    ++g.outcomes[static_cast<std::size_t>(f.outcome)];
    g.rear_excess.push_back(t->rear_load_excess);
    if (is_near_miss(*t)) ++g.near_misses;
    if (!is_embedding(*t)) continue;
    ++g.embeddings;
    if (f.lead_m) g.leads.push_back(*f.lead_m);
    if (ideal.lead_m) g.ideal_leads.push_back(*ideal.lead_m);
    if (t->reserve_ideal.lead_m) g.reserve_leads.push_back(*t->reserve_ideal.lead_m);
    if (f.lead_m && ideal.lead_m && *f.lead_m >= 0.8 * *ideal.lead_m) ++g.lead_at_80pct_of_ideal;
    if (embeds_at_start(*t)) {
      ++g.embeddings_at_start;
    } else if (f.outcome == TraverseOutcome::stopped_ahead || f.outcome == TraverseOutcome::stopped_close) {
      ++g.along_drive_stopped_before;
    }
  }
  return g;
}

bool embeds_at_start(const TraverseResult& t) { return t.embedded && t.embed_x_m < kStartEmbedM; }

std::size_t clear_drives(const GroupStats& g) { return g.traverses - g.embeddings - g.near_misses; }

std::vector<const TraverseResult*> select_traverses(const CampaignResult& r, const std::function<bool(const TraverseResult&)>& f) {
  std::vector<const TraverseResult*> out;
  for (const TraverseResult& t : r.traverses) {
    if (f(t)) out.push_back(&t);
  }
  return out;
}

namespace {

std::string percent(std::size_t part, std::size_t whole) {
  return whole ? fixed(100.0 * static_cast<double>(part) / static_cast<double>(whole), 0) + " %" : "–";
}

std::string family_row(const std::string& name, const GroupStats& g) {
  std::ostringstream row;
  row << "| " << name << " | " << g.traverses << " | " << g.embeddings;
  for (const std::size_t c : g.outcomes) row << " | " << c;
  const std::optional<double> rear = median(g.rear_excess);
  row << " | " << opt(median(g.leads), 2, "–") << " | " << opt(median(g.ideal_leads), 2, "–") << " | "
      << opt(median(g.reserve_leads), 2, "–") << " | " << percent(g.lead_at_80pct_of_ideal, g.embeddings) << " | "
      << (rear ? fixed(100.0 * *rear, 1) + " %" : "–") << " | " << g.embeddings_at_start << " | "
      << g.along_drive_stopped_before << " of " << g.embeddings - g.embeddings_at_start << " |\n";
  return row.str();
}

std::string outcome_table(const CampaignResult& r) {
  std::ostringstream md;
  md << "| family | traverses | embeddings | stopped ≥ 1 m ahead | stopped < 1 m ahead | late | missed | "
        "false stop | near-miss stop | ok, no stop | median lead [m] | median ideal-sensor lead [m] | "
        "median ideal-reserve lead [m] | lead ≥ 80 % of ideal | "
        "median rear-load excess | embeddings at the start (x < " << fixed(kStartEmbedM, 1)
     << " m) | the others: stopped before the embedding |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const bool held : {false, true}) {
    for (const CampaignFamily f : r.options.families) {
      const auto group = select_traverses(r, [&](const TraverseResult& t) { return t.draw.family == f && t.held_out == held; });
      if (!group.empty()) md << family_row(std::string(family_name(f)) + (held ? " (held out)" : ""), group_stats(group, {}));
    }
    const auto all = select_traverses(r, [&](const TraverseResult& t) { return t.held_out == held; });
    if (!all.empty()) {
      md << family_row(held ? "**all held-out families**" : "**all tuning families**", group_stats(all, {}));
    }
  }
  return md.str();
}

/// One sweep's table: per level and group, the false-stop rate, near-miss
/// stops, the share stopped before the embedding and the median leads.
std::string sweep_table(const CampaignResult& r, Sweep sweep) {
  const bool traction = sweep == Sweep::traction_coefficient;
  const std::vector<double>& levels = traction ? r.options.sweep_traction_stop : r.options.sweep_stop_mm;
  std::ostringstream md;
  md << (traction ? "| stop coefficient" : "| stop level [mm]")
     << " | group | false-stop rate (clear drives) | near-miss stops | stopped before embedding | "
        "median lead [m] | median ideal-sensor lead [m] |\n|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < levels.size(); ++k) {
    for (const bool held : {false, true}) {
      const auto group = select_traverses(r, [&](const TraverseResult& t) { return t.held_out == held; });
      if (group.empty()) continue;
      const GroupStats g = group_stats(group, k, sweep);
      const std::size_t before = g.outcomes[0] + g.outcomes[1];
      md << "| " << fixed(levels[k], traction ? 2 : 0) << " | " << (held ? "held out" : "tuning") << " | "
         << percent(g.outcomes[static_cast<std::size_t>(TraverseOutcome::false_stop)], clear_drives(g)) << " | "
         << g.outcomes[static_cast<std::size_t>(TraverseOutcome::near_miss_stop)] << " of " << g.near_misses << " | "
         << percent(before, g.embeddings) << " | " << opt(median(g.leads), 2, "–") << " | "
         << opt(median(g.ideal_leads), 2, "–") << " |\n";
    }
  }
  return md.str();
}

}  // namespace

const std::vector<std::string>& fault_csv_columns() {
  static const std::vector<std::string> columns = {
      "family", "held_out", "index", "seed", "embedded", "embed_time_s", "fault_class", "fault", "fault_seed",
      "clean_outcome", "outcome", "clean_stop_time_s", "stop_time_s", "stop_reason", "lead_m", "detected_time_s"};
  return columns;
}

std::string faults_csv(const CampaignResult& r) {
  std::ostringstream out;
  const std::vector<std::string>& columns = fault_csv_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << '\n';
  for (const TraverseResult& t : r.traverses) {
    for (const FaultVerdict& f : t.faults) {
      const std::vector<std::string> fields = {
          family_name(t.draw.family), t.held_out ? "1" : "0", std::to_string(t.draw.index),
          std::to_string(t.draw.seed), t.embedded ? "1" : "0", t.embedded ? fixed(t.embed_time_s, 1) : "",
          fault_class_name(f.fault_class), f.spec.text(), std::to_string(f.seed), outcome_name(t.flight.outcome),
          outcome_name(f.flight.outcome), opt(t.flight.stop_time_s, 1), opt(f.flight.stop_time_s, 1),
          f.flight.stop_time_s ? to_string(f.flight.stop_reason) : "", opt(f.flight.lead_m, 3),
          opt(f.detected_time_s, 1)};
      for (std::size_t i = 0; i < fields.size(); ++i) out << (i ? "," : "") << csv_field(fields[i]);
      out << '\n';
    }
  }
  return out.str();
}

namespace {

// One fault class over every traverse: outcomes without and with the fault,
// how the stop moved, and whether the flight code named the faulty channel.
struct FaultStats {
  std::size_t traverses = 0, embeddings = 0, earlier = 0, later = 0, detected = 0;
  std::size_t seen = 0;  // runs where the fault began before the stop (or there was none)
  std::array<std::size_t, kTraverseOutcomes> clean{}, faulty{};
  std::vector<double> detection_delays_s;
};

FaultStats fault_stats(const CampaignResult& r, std::size_t k) {
  FaultStats g;
  for (const TraverseResult& t : r.traverses) {
    const FaultVerdict& f = t.faults.at(k);
    ++g.traverses;
    g.embeddings += t.embedded ? 1U : 0U;
    ++g.clean[static_cast<std::size_t>(t.flight.outcome)];
    ++g.faulty[static_cast<std::size_t>(f.flight.outcome)];
    const std::optional<double>& a = t.flight.stop_time_s;
    const std::optional<double>& b = f.flight.stop_time_s;
    if (b && (!a || *b < *a - 1e-6)) ++g.earlier;
    if (a && (!b || *b > *a + 1e-6)) ++g.later;
    if (!b || f.spec.start_s <= *b + 1e-6) ++g.seen;
    if (f.detected_time_s) {
      ++g.detected;
      g.detection_delays_s.push_back(*f.detected_time_s - f.spec.start_s);
    }
  }
  return g;
}

std::string clean_to_faulty(const FaultStats& g, std::initializer_list<TraverseOutcome> outcomes) {
  std::size_t a = 0, b = 0;
  for (const TraverseOutcome o : outcomes) {
    a += g.clean[static_cast<std::size_t>(o)];
    b += g.faulty[static_cast<std::size_t>(o)];
  }
  return std::to_string(a) + " → " + std::to_string(b);
}

}  // namespace

std::string fault_table(const CampaignResult& r) {
  std::ostringstream md;
  md << "| fault class | traverses | embeddings | stopped before the embedding | late | missed | false stops "
        "| stop earlier | stop later or never | faulty channel named before the stop (of the runs that reached the "
        "fault) | median time to name it [s] |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  using O = TraverseOutcome;
  for (std::size_t k = 0; k < r.options.faults.size(); ++k) {
    const FaultStats g = fault_stats(r, k);
    md << "| " << fault_class_name(r.options.faults[k]) << " | " << g.traverses << " | " << g.embeddings << " | "
       << clean_to_faulty(g, {O::stopped_ahead, O::stopped_close}) << " | " << clean_to_faulty(g, {O::late}) << " | "
       << clean_to_faulty(g, {O::missed}) << " | " << clean_to_faulty(g, {O::false_stop}) << " (of "
       << g.traverses - g.embeddings << ") | " << g.earlier << " | " << g.later << " | "
       << g.detected << " of " << g.seen << " | " << opt(median(g.detection_delays_s), 1, "–") << " |\n";
  }
  return md.str();
}

namespace {

// One group's event records against the simulator's deepest wheel at the stop.
struct EventAccuracy {
  std::size_t stops = 0, with_record = 0;
  std::vector<double> peak_ratio, estimate_ratio;  // event sinkage / true deepest sinkage
  std::vector<double> recent_ratio;                // FlightVerdict::recent_estimate_mm / true, every stop
};

std::string accuracy_cells(const std::vector<double>& ratios, std::size_t of) {
  std::size_t within = 0;
  for (const double q : ratios) within += std::fabs(q - 1.0) <= 0.2 ? 1U : 0U;
  return opt(median(ratios), 2, "–") + " | " + std::to_string(within) + " of " + std::to_string(of);
}

std::string event_accuracy_table(const CampaignResult& r) {
  std::ostringstream md;
  md << "| group | stops | with a wheel's event record | peak-current sinkage / true: median | within 20 % | largest "
        "estimate / true: median | within 20 % | every stop: the rover's stop record (deepest wheel's recent median) / "
        "true: median | within 20 % |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const bool held : {false, true}) {
    EventAccuracy a;
    for (const TraverseResult& t : r.traverses) {
      const FlightVerdict& f = t.flight;
      if (t.held_out != held || !f.stop_time_s) continue;
      ++a.stops;
      const double truth = f.true_sinkage_at_stop_mm.value_or(0.0);
      if (truth > 0.0 && f.recent_estimate_mm) a.recent_ratio.push_back(*f.recent_estimate_mm / truth);
      if (!f.event_max_estimate_mm && !f.event_peak_sinkage_mm) continue;
      ++a.with_record;
      if (truth <= 0.0) continue;
      if (f.event_peak_sinkage_mm) a.peak_ratio.push_back(*f.event_peak_sinkage_mm / truth);
      if (f.event_max_estimate_mm) a.estimate_ratio.push_back(*f.event_max_estimate_mm / truth);
    }
    md << "| " << (held ? "held out" : "tuning") << " | " << a.stops << " | " << a.with_record << " | "
       << accuracy_cells(a.peak_ratio, a.with_record) << " | " << accuracy_cells(a.estimate_ratio, a.with_record)
       << " | " << accuracy_cells(a.recent_ratio, a.stops) << " |\n";
  }
  return md.str();
}

// With --calibrate: what the soil-bin fits gave, embeddings and the others apart.
std::string calibration_table(const CampaignResult& r) {
  if (r.options.calibration == CalibrationSoil::none) return {};
  std::ostringstream md;
  md << "Tables calibrated to each traverse's " << calibration_soil_name(r.options.calibration)
     << " soil (simulated soil bin, C1 = C2 = 1, C3 and DP_max/W per load; medians [min, max] at m g / 6):\n\n"
     << "| traverses | calibrated | soil scale | C3 | DP_max/W | not calibrated (no soil-bin pull at scale 1: run "
        "with the given table) |\n|---|---|---|---|---|---|\n";
  for (const bool embeds : {true, false}) {
    std::vector<double> scale, c3, dp;
    std::size_t failed = 0;
    for (const TraverseResult& t : r.traverses) {
      if (t.embedded != embeds) continue;
      if (!t.calibration) {
        ++failed;
        continue;
      }
      scale.push_back(t.calibration->soil_scale);
      c3.push_back(t.calibration->c3_at_mean_load);
      dp.push_back(t.calibration->dp_max_at_mean_load);
    }
    md << "| " << (embeds ? "embedding" : "never embedding") << " | " << scale.size();
    for (const std::vector<double>* v : {&scale, &c3, &dp}) {
      md << " | " << opt(median(*v), 3, "–");
      if (!v->empty()) {
        md << " [" << fixed(*std::min_element(v->begin(), v->end()), 3) << ", "
           << fixed(*std::max_element(v->begin(), v->end()), 3) << "]";
      }
    }
    md << " | " << failed << " |\n";
  }
  return md.str() + "\n";
}

}  // namespace

std::string campaign_summary(const CampaignResult& r, const std::string& command_line, bool plots) {
  std::ostringstream md;
  md << "# sinkwatch campaign\n\n`" << command_line << "`\n\n"
     << r.traverses.size() << " traverses (" << r.options.traverses_per_family << " per family), seed "
     << r.options.seed << ", table: " << r.options.table_source << ", path " << fixed(r.options.path_length_m, 1)
     << " m, " << fixed(r.seconds, 1) << " s wall time.\n\n"
     << "Flight mass: " << flight_mass_name(r.options.flight_mass)
     << (r.options.flight_mass == FlightMass::true_mass
             ? std::string(" (the flight code is given each traverse's drawn mass, 120–160 kg; geometry ") +
                   (r.options.rover ? "from the table's section 6" : "Yutu-like")
             : std::string(" (the flight code keeps its rover's mass whatever the drawn mass: ") +
                   (r.options.rover ? "the table's section 6" : "Yutu-like, 140 kg"))
     << ").\n\n"
     << calibration_table(r)
     << "Outcomes with the table (lead = embedding − stop along the path; the ideal sensor stops where the "
        "simulator's deepest wheel first reaches the table's stop level; the ideal reserve sensor where the "
        "traction reserve first falls below 5 % of the weight; a near miss is a drive that never embeds but "
        "whose reserve fell below that; medians over the embeddings that have one; rear-load excess = the fuller balance's rear loads over the flight statics', − 1; "
        "an embedding at the start comes within the first " << fixed(kStartEmbedM, 1) << " m, where the soil cannot carry the rover at all and no stop can "
        "come before it; the last column counts the other embeddings stopped before them):\n\n"
     << outcome_table(r)
     << "\nStop-level sweep (caution, stop and allowed sinkage scaled together; the flight code re-run on the same "
        "open-loop rows per level; false-stop rate over the clear drives, the traverses that never embed and "
        "never came within 5 % of the weight of it; near-miss stops apart):\n\n"
     << sweep_table(r, Sweep::stop_level)
     << (r.traverses.empty() || r.traverses.front().traction_sweep.empty()
             ? std::string()
             : "\nMotion-resistance sweep (section 8's stop coefficient, caution scaled with it; the sinkage levels "
               "as the table has them; docs/traction.md):\n\n" +
                   sweep_table(r, Sweep::traction_coefficient))
     << "\nThe event records at the stop against the simulator (the campaign's table; a stop by a wheel's rule "
        "leaves a wheel's event record, a stop by section 8 none; every stop leaves the rover's stop record, "
        "the deepest wheel's median of its last "
     << static_cast<unsigned>(flight::kStopRecordSamples)
     << " estimates; true = the simulator's deepest wheel at the stop; "
        "peak-current sinkage: section 7's Eq. 11 at the episode's peak current with DP = DP_max):\n\n"
     << event_accuracy_table(r)
     << (r.options.faults.empty()
             ? std::string()
             : "\nSensor faults (docs/fault-injection.md): one fault of each class per traverse, at the table's "
               "levels; each count is without the fault → with it, over the same traverses (tuning and held-out "
               "together); stop earlier / later: the first stop moved by the fault; named: the flight code's "
               "sensor health called a faulty channel not ok before its stop:\n\n" +
                   fault_table(r))
     << (plots ? "\nPlots: lead_by_family.svg, false_stop_vs_lead.svg.\n"
               : "\nNo plots (gnuplot not found, or it failed, e.g. with nothing to plot): leads.dat, levels.dat and "
                 "campaign.gp are here.\n");
  return md.str();
}

namespace {

// A single-quoted gnuplot string taken literally.
std::string q(std::string_view text) { return "'" + quote_gnuplot_string(text) + "'"; }

std::string leads_dat(const CampaignResult& r) {
  std::ostringstream dat;
  dat << "# family_index lead_m ideal_lead_m (embeddings only; NaN: none)\n";
  for (const TraverseResult& t : r.traverses) {
    if (!t.embedded) continue;
    const auto pos = std::find(r.options.families.begin(), r.options.families.end(), t.draw.family);
    const double jitter = 0.3 * (static_cast<double>(t.draw.index % 7) / 6.0 - 0.5);
    dat << fixed(static_cast<double>(pos - r.options.families.begin()) + jitter, 3) << ' '
        << opt(t.flight.lead_m, 3, "NaN") << ' ' << opt(t.ideal.lead_m, 3, "NaN") << '\n';
  }
  return dat.str();
}

std::string levels_dat(const CampaignResult& r) {
  std::ostringstream dat;
  dat << "# stop_mm false_stop_rate_tuning median_lead_tuning_m false_stop_rate_held_out median_lead_held_out_m\n";
  for (std::size_t k = 0; k < r.options.sweep_stop_mm.size(); ++k) {
    dat << fixed(r.options.sweep_stop_mm[k], 1);
    for (const bool held : {false, true}) {
      const GroupStats g = group_stats(select_traverses(r, [&](const TraverseResult& t) { return t.held_out == held; }), k);
      const std::size_t ordinary = clear_drives(g);
      const std::size_t fs = g.outcomes[static_cast<std::size_t>(TraverseOutcome::false_stop)];
      dat << ' ' << (ordinary ? fixed(static_cast<double>(fs) / static_cast<double>(ordinary), 4) : "NaN") << ' '
          << opt(median(g.leads), 3, "NaN");
    }
    dat << '\n';
  }
  return dat.str();
}

// The two scripts; `out_lead`/`out_levels` are where the SVGs go.
std::string plot_script(const CampaignResult& r, const std::string& leads, const std::string& levels,
                        const std::string& out_lead, const std::string& out_levels) {
  std::ostringstream gp;
  gp << "# gnuplot script written by sinkwatch campaign; run: gnuplot campaign.gp\n"
     << gnuplot_linetypes() << "set datafile missing 'NaN'\nset terminal svg size 900,500\n"
     << "set output " << q(out_lead) << "\nset title 'Lead per family (embeddings)'\n"
     << "set ylabel 'lead before the embedding [m]'\nset grid\nset xtics (";
  for (std::size_t i = 0; i < r.options.families.size(); ++i) {
    gp << (i ? ", " : "") << q(family_name(r.options.families[i])) << ' ' << i;
  }
  gp << ")\nset xrange [-0.5:" << r.options.families.size() - 0.5 << "]\n"
     << "plot " << q(leads) << " using 1:2 with points lt " << wheel_linetype(0)
     << " title 'flight code, table', '' using ($1+0.15):3 with points lt " << wheel_linetype(3)
     << " title 'ideal sinkage sensor, same stop level', 0 with lines lt " << level_linetype(PlotLevel::embedding)
     << " title 'embedding'\n"
     << "set output " << q(out_levels) << "\nset title 'False-stop rate vs median lead, stop level varied'\n"
     << "set xtics auto\nset autoscale x\nset xlabel 'median lead [m]'\nset ylabel 'false-stop rate'\n"
     << "plot " << q(levels) << " using 3:2:(stringcolumn(1)) with labels point lt "
     << wheel_linetype(0) << " offset 1,0.5 title 'tuning families (label: stop level, mm)', '' using 5:4 "
     << "with points lt " << wheel_linetype(3) << " title 'held-out families'\n";
  return gp.str();
}

std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (const char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string find_campaign_gnuplot() {
  const char* env = std::getenv("SINKWATCH_GNUPLOT");
  const std::string program = env != nullptr ? std::string(env) : std::string("gnuplot");
  if (program.empty()) return {};
  const std::string probe = shell_quote(program) + " -e exit >/dev/null 2>&1";
  return std::system(probe.c_str()) == 0 ? program : std::string();
}

struct CampaignReport::Files {
  OutputFileSet set;
  OutputFileSet plots;  // committed only when gnuplot drew them
  OutputFile* csv = nullptr;
  OutputFile* json = nullptr;
  OutputFile* summary = nullptr;
  OutputFile* leads = nullptr;
  OutputFile* levels = nullptr;
  OutputFile* script = nullptr;
  OutputFile* lead_svg = nullptr;
  OutputFile* levels_svg = nullptr;
  OutputFile* faults = nullptr;  // with --faults only
  OutputFile* choice = nullptr;  // with --choose-levels only
  OutputFile* table = nullptr;   // with --choose-levels only
  std::string table_path;
};

CampaignReport::CampaignReport(const std::string& dir, std::string gnuplot, bool faults,
                               const std::optional<std::string>& table_out)
    : dir_(dir), gnuplot_(std::move(gnuplot)), files_(std::make_unique<Files>()) {
  check_output_directory(dir);
  // A table outside the folder is checked before the folder is created.
  if (table_out && std::filesystem::path(*table_out).parent_path().lexically_normal() !=
                       std::filesystem::path(dir).lexically_normal()) {
    (void)check_output_path(*table_out);
  }
  create_output_directory(dir);
  const std::filesystem::path base(dir);
  const auto add = [&](const char* name) { return &files_->set.add((base / name).string()); };
  files_->csv = add("traverses.csv");
  files_->json = add("traverses.json");
  files_->summary = add("summary.md");
  files_->leads = add("leads.dat");
  files_->levels = add("levels.dat");
  files_->script = add("campaign.gp");
  if (faults) files_->faults = add("faults.csv");
  if (table_out) {
    files_->choice = add("choice.json");
    files_->table_path = *table_out;
    files_->table = &files_->set.add(*table_out);
  }
  if (!gnuplot_.empty()) {
    files_->lead_svg = &files_->plots.add((base / "lead_by_family.svg").string());
    files_->levels_svg = &files_->plots.add((base / "false_stop_vs_lead.svg").string());
  }
}

CampaignReport::~CampaignReport() = default;

// gnuplot draws into the SVGs' temporaries from the data's temporaries;
// true when it succeeded (then the SVGs are committed with the rest).
bool CampaignReport::draw(const CampaignResult& r) {
  Files& f = *files_;
  f.leads->close();
  f.levels->close();
  f.lead_svg->close();
  f.levels_svg->close();
  const std::string script = plot_script(r, f.leads->temporary_path(), f.levels->temporary_path(),
                                         f.lead_svg->temporary_path(), f.levels_svg->temporary_path());
  const std::string command = shell_quote(gnuplot_) + " >/dev/null 2>&1 <<'SINKWATCH_GP'\n" + script + "SINKWATCH_GP\n";
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::vector<std::string> CampaignReport::write(const CampaignResult& r, const std::string& command_line,
                                               const ChoiceFiles* choice) {
  Files& f = *files_;
  if ((choice != nullptr) != (f.table != nullptr)) {
    throw std::logic_error("campaign report: a level choice without its table file, or the reverse");
  }
  f.leads->write(leads_dat(r));
  f.levels->write(levels_dat(r));
  const bool plots = !gnuplot_.empty() && draw(r);
  f.csv->write(traverses_csv(r));
  f.json->write(traverses_json(r));
  f.summary->write(campaign_summary(r, command_line, plots) + (choice ? choice->markdown : std::string()));
  if (choice) {
    f.choice->write(choice->json);
    f.table->write(std::string(choice->table_bytes.begin(), choice->table_bytes.end()));
  }
  f.script->write(plot_script(r, "leads.dat", "levels.dat", "lead_by_family.svg", "false_stop_vs_lead.svg"));
  if (f.faults) f.faults->write(faults_csv(r));
  if (plots) f.plots.commit();
  f.set.commit();
  std::vector<std::string> written;
  for (const char* name : {"summary.md", "traverses.csv", "traverses.json", "leads.dat", "levels.dat", "campaign.gp"}) {
    written.push_back((std::filesystem::path(dir_) / name).string());
  }
  if (f.faults) written.push_back((std::filesystem::path(dir_) / "faults.csv").string());
  if (choice) {
    written.push_back((std::filesystem::path(dir_) / "choice.json").string());
    written.push_back(f.table_path);
  }
  for (const char* name : {"lead_by_family.svg", "false_stop_vs_lead.svg"}) {
    if (plots) written.push_back((std::filesystem::path(dir_) / name).string());
  }
  return written;
}

}  // namespace sinkwatch::ground
