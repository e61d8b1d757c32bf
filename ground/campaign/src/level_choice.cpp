// The choice of the caution and stop levels for a false-stop target
// (level_choice.hpp, docs/campaign.md "Choosing the levels").
#include "sinkwatch/ground/level_choice.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/ground/campaign_report.hpp"
#include "sinkwatch/ground/strf.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

// P(X <= k) for X ~ Binomial(n, p), 0 < p < 1, summed in logs.
double binomial_cdf(std::size_t k, std::size_t n, double p) {
  const double nd = static_cast<double>(n);
  const double log_p = std::log(p), log_q = std::log1p(-p);
  double sum = 0.0;
  for (std::size_t i = 0; i <= k; ++i) {
    const double id = static_cast<double>(i);
    const double log_choose = std::lgamma(nd + 1.0) - std::lgamma(id + 1.0) - std::lgamma(nd - id + 1.0);
    sum += std::exp(log_choose + id * log_p + (nd - id) * log_q);
  }
  return std::min(sum, 1.0);
}

std::string number(double v, int digits) { return strf("%.*f", digits, v); }

std::string json_number(const std::optional<double>& v, int digits) { return v ? number(*v, digits) : "null"; }

double q_mm(const flight::SinkageM& level) { return 1000.0 * fx::to_double(level.q()); }

}  // namespace

double clopper_pearson_upper(std::size_t k, std::size_t n, double confidence) {
  if (n == 0 || k >= n) return 1.0;
  const double alpha = 1.0 - confidence;
  // The CDF falls with p: bisect for CDF(p) = alpha; 60 halvings reach 1e-18.
  double lo = 0.0, hi = 1.0;
  for (int step = 0; step < 60; ++step) {
    const double mid = 0.5 * (lo + hi);
    (binomial_cdf(k, n, mid) > alpha ? lo : hi) = mid;
  }
  return hi;
}

std::optional<std::size_t> certifiable_false_stops(std::size_t n, double target, double confidence) {
  std::optional<std::size_t> k_max;
  for (std::size_t k = 0; k < n && clopper_pearson_upper(k, n, confidence) <= target; ++k) k_max = k;
  return k_max;
}

std::size_t traverses_needed(double target, double confidence) {
  // With k = 0 the bound is 1 - alpha^(1/n); the closed form, then checked
  // against the bound itself (rounding at the boundary).
  auto n = static_cast<std::size_t>(std::ceil(std::log(1.0 - confidence) / std::log1p(-target)));
  while (n > 1 && clopper_pearson_upper(0, n - 1, confidence) <= target) --n;
  while (clopper_pearson_upper(0, n, confidence) > target) ++n;
  return n;
}

std::vector<double> choice_grid_mm(const flight::ParameterTable& table) {
  const double radius_mm = 1000.0 * fx::to_double(table.wheel_radius_m.q());
  std::vector<double> grid;
  for (int step = 0; step <= 4000; ++step) {  // 2.5 mm steps; 4000 covers a 10 m radius
    const double level_mm = 20.0 + 2.5 * step;
    if (level_mm > radius_mm + 1e-9) break;
    try {
      (void)table_at_stop_level(table, level_mm / 1000.0);
      grid.push_back(level_mm);
    } catch (const std::invalid_argument&) {
      // a level the flight code refuses for this table is not offered
    }
  }
  return grid;
}

std::vector<LevelPair> choice_grid(const flight::ParameterTable& table, const std::vector<double>& levels_mm,
                                   const std::vector<double>& traction_stops) {
  std::vector<std::optional<double>> coefficients{std::nullopt};
  if (flight::traction_check_on(table.traction)) {
    coefficients.insert(coefficients.end(), traction_stops.begin(), traction_stops.end());
  }
  std::vector<LevelPair> grid;
  for (const std::optional<double>& coefficient : coefficients) {
    for (const double level_mm : levels_mm) grid.push_back(LevelPair{level_mm, coefficient});
  }
  return grid;
}

const char* choice_basis_name(ChoiceBasis b) {
  return b == ChoiceBasis::certified ? "certified" : "fewest_false_stops";
}

LevelOutcome level_outcome(const CampaignResult& r, std::optional<std::size_t> level, bool held_out) {
  const std::vector<const TraverseResult*> group =
      select_traverses(r, [held_out](const TraverseResult& t) { return t.held_out == held_out; });
  const GroupStats g = group_stats(group, level, Sweep::choice);
  LevelOutcome o;
  o.traverses = g.traverses;
  o.embeddings = g.embeddings;
  o.clear_drives = clear_drives(g);
  o.near_misses = g.near_misses;
  o.near_miss_stops = g.outcomes[static_cast<std::size_t>(TraverseOutcome::near_miss_stop)];
  o.false_stops = g.outcomes[static_cast<std::size_t>(TraverseOutcome::false_stop)];
  o.false_stop_bound = clopper_pearson_upper(o.false_stops, o.clear_drives);
  o.stopped_ahead = g.outcomes[static_cast<std::size_t>(TraverseOutcome::stopped_ahead)];
  o.stopped_before = o.stopped_ahead + g.outcomes[static_cast<std::size_t>(TraverseOutcome::stopped_close)];
  o.lead_at_80pct_of_ideal = g.lead_at_80pct_of_ideal;
  o.median_lead_m = median(g.leads);
  o.median_ideal_lead_m = median(g.ideal_leads);
  std::vector<double> caution_leads;
  for (const TraverseResult* t : group) {
    const FlightVerdict& f = level ? t->choice.at(*level) : t->flight;
    const bool clear = !t->embedded && !(t->min_reserve_frac && *t->min_reserve_frac < kNearMissReserve);
    if (clear && f.caution_time_s) ++o.false_cautions;
    if (t->embedded && f.caution_x_m) caution_leads.push_back(t->embed_x_m - *f.caution_x_m);
  }
  o.median_caution_lead_m = median(caution_leads);
  return o;
}

namespace {

// True when grid point a is better for embeddings than b (level_choice.hpp,
// "The rule"): more stopped before, more >= 1 m ahead, longer median lead,
// fewer false stops, then the lower stop level and coefficient (off last).
bool better_for_embeddings(const CampaignResult& r, const LevelChoice& c, std::size_t a, std::size_t b) {
  const LevelOutcome& x = c.tuning[a];
  const LevelOutcome& y = c.tuning[b];
  if (x.stopped_before != y.stopped_before) return x.stopped_before > y.stopped_before;
  if (x.stopped_ahead != y.stopped_ahead) return x.stopped_ahead > y.stopped_ahead;
  const double lead_x = x.median_lead_m.value_or(-1e300), lead_y = y.median_lead_m.value_or(-1e300);
  if (lead_x != lead_y) return lead_x > lead_y;
  if (x.false_stops != y.false_stops) return x.false_stops < y.false_stops;
  const LevelPair& p = r.options.choice_grid[a];
  const LevelPair& q = r.options.choice_grid[b];
  if (p.stop_mm != q.stop_mm) return p.stop_mm < q.stop_mm;
  return p.traction_stop.value_or(1e300) < q.traction_stop.value_or(1e300);
}

// The best point, by better_for_embeddings(), of those `keep` accepts; none if none.
std::optional<std::size_t> best_point(const CampaignResult& r, const LevelChoice& c,
                                      const std::function<bool(std::size_t)>& keep) {
  std::optional<std::size_t> best;
  for (std::size_t k = 0; k < c.tuning.size(); ++k) {
    if (keep(k) && (!best || better_for_embeddings(r, c, k, *best))) best = k;
  }
  return best;
}

}  // namespace

LevelChoice choose_levels(const CampaignResult& r, double max_false_stop) {
  const std::size_t points = r.options.choice_grid.size();
  if (points == 0) throw std::invalid_argument("no stop level to choose from");
  LevelChoice c;
  c.max_false_stop = max_false_stop;
  for (std::size_t k = 0; k < points; ++k) c.tuning.push_back(level_outcome(r, k, false));
  const std::size_t n = c.tuning.front().clear_drives;  // the same traverses at every point
  if (n == 0) {
    throw std::invalid_argument("no traverse of the tuning families stays clear of embedding: no false-stop rate to "
                                "choose on (more traverses, or other families)");
  }
  c.certifiable = certifiable_false_stops(n, max_false_stop);
  c.needed_without_false_stop = traverses_needed(max_false_stop);
  const std::optional<std::size_t> certified = best_point(r, c, [&](std::size_t k) {
    return c.certifiable && c.tuning[k].false_stops <= *c.certifiable;
  });
  std::size_t fewest = c.tuning.front().false_stops;
  for (const LevelOutcome& o : c.tuning) fewest = std::min(fewest, o.false_stops);
  c.basis = certified ? ChoiceBasis::certified : ChoiceBasis::fewest_false_stops;
  c.level = certified ? *certified : *best_point(r, c, [&](std::size_t k) { return c.tuning[k].false_stops == fewest; });
  c.held_out = level_outcome(r, c.level, true);
  c.base_tuning = level_outcome(r, std::nullopt, false);
  c.base_held_out = level_outcome(r, std::nullopt, true);
  const flight::ParameterTable chosen = chosen_table(r, c);
  c.stop_mm = q_mm(chosen.monitor.stop_sinkage_m);
  c.caution_mm = q_mm(chosen.monitor.caution_sinkage_m);
  c.allowed_mm = q_mm(chosen.monitor.allowed_sinkage_m);
  if (flight::traction_check_on(chosen.traction)) {
    c.traction_stop = fx::to_double(chosen.traction.stop_coefficient.q());
    c.traction_caution = fx::to_double(chosen.traction.caution_coefficient.q());
  }
  return c;
}

flight::ParameterTable chosen_table(const CampaignResult& r, const LevelChoice& c) {
  return table_at_levels(r.options.table, r.options.choice_grid.at(c.level));
}

EncodedTable encode_chosen_table(const CampaignResult& r, const LevelChoice& c) {
  const flight::ParameterTable table = chosen_table(r, c);
  EncodedTable written = encode_table(table);
  const flight::MonitorParams& want = table.monitor;
  const flight::MonitorParams& got = written.table.monitor;
  const auto same = [](const flight::SinkageM& a, const flight::SinkageM& b) { return a.q().raw() == b.q().raw(); };
  const flight::TractionParams& want_t = table.traction;
  const flight::TractionParams& got_t = written.table.traction;
  const bool same_traction = want_t.stop_coefficient.q().raw() == got_t.stop_coefficient.q().raw() &&
                             want_t.caution_coefficient.q().raw() == got_t.caution_coefficient.q().raw() &&
                             flight::traction_check_on(want_t) == flight::traction_check_on(got_t);
  if (!same(want.stop_sinkage_m, got.stop_sinkage_m) || !same(want.caution_sinkage_m, got.caution_sinkage_m) ||
      !same(want.allowed_sinkage_m, got.allowed_sinkage_m) || !same_traction) {
    throw std::invalid_argument("the table loaded back does not carry the chosen levels");
  }
  return written;
}

namespace {

std::string share(std::size_t part, std::size_t whole) {
  return whole ? strf("%zu of %zu (%.0f %%)", part, whole, 100.0 * static_cast<double>(part) / static_cast<double>(whole))
               : std::string("–");
}

std::string median_text(const std::optional<double>& v) { return v ? number(*v, 2) : std::string("–"); }

std::string outcome_row(const char* group, const LevelOutcome& o) {
  std::ostringstream row;
  row << "| " << group << " | " << o.traverses << " | " << o.false_stops << " of " << o.clear_drives << " | "
      << (o.clear_drives ? number(100.0 * o.false_stop_bound, 1) + " %" : std::string("–")) << " | "
      << share(o.false_cautions, o.clear_drives) << " | " << o.near_miss_stops << " of " << o.near_misses << " | "
      << o.embeddings << " | " << share(o.stopped_before, o.embeddings)
      << " | " << share(o.stopped_ahead, o.embeddings) << " | " << median_text(o.median_lead_m) << " | "
      << median_text(o.median_ideal_lead_m) << " | " << share(o.lead_at_80pct_of_ideal, o.embeddings) << " | "
      << median_text(o.median_caution_lead_m) << " |\n";
  return row.str();
}

// The verdict in words: certified, or why not and what it would take.
std::string verdict_text(const LevelChoice& c, std::size_t n) {
  const LevelOutcome& at = c.tuning[c.level];
  std::ostringstream md;
  if (c.basis == ChoiceBasis::certified) {
    md << "**Certified**: " << at.false_stops << " false stops of " << n
       << " tuning clear drives; the one-sided 95 % upper bound on the false-stop rate, "
       << number(100.0 * at.false_stop_bound, 2) << " %, meets the target " << number(100.0 * c.max_false_stop, 2)
       << " %; of the grid's points that meet it, it stops the most embeddings before the embedding (then: ≥ 1 m "
          "ahead, median lead).\n";
    return md.str();
  }
  md << "**NOT CERTIFIED.** ";
  if (!c.certifiable) {
    md << "With " << n << " tuning clear drives, not even zero false stops would certify "
       << number(100.0 * c.max_false_stop, 2) << " % (bound at k = 0: "
       << number(100.0 * clopper_pearson_upper(0, n), 2) << " %); it takes at least " << c.needed_without_false_stop
       << " such traverses, none stopping falsely (each false stop raises the number). ";
  } else {
    md << "Up to " << *c.certifiable << " false stops of " << n << " would certify the target, but every level of "
       << "the grid has more. ";
  }
  md << "Fallback rule: of the points with the fewest false stops (" << at.false_stops << " of " << n
     << ", upper bound " << number(100.0 * at.false_stop_bound, 1) << " %), the best for embeddings";
  const double rate = static_cast<double>(at.false_stops) / static_cast<double>(n);
  if (rate >= c.max_false_stop) md << "; its observed rate is at or above the target: more traverses would not certify it";
  md << ".\n";
  return md.str();
}

std::string coefficient_text(const std::optional<double>& c) { return c ? number(*c, 2) : std::string("off"); }

std::string levels_rows(const CampaignResult& r, const LevelChoice& c) {
  std::ostringstream md;
  md << "| stop level [mm] | section 8 stop coefficient | false stops (tuning clear drives) | 95 % upper bound | meets "
        "the target | stopped before the embedding | median lead [m] |\n|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < c.tuning.size(); ++k) {
    const LevelOutcome& o = c.tuning[k];
    const LevelPair& p = r.options.choice_grid[k];
    md << "| " << number(p.stop_mm, 1) << (k == c.level ? " **(chosen)**" : "") << " | "
       << coefficient_text(p.traction_stop) << " | " << o.false_stops << " of " << o.clear_drives << " | "
       << number(100.0 * o.false_stop_bound, 1) << " % | " << (o.false_stop_bound <= c.max_false_stop ? "yes" : "no")
       << " | " << share(o.stopped_before, o.embeddings) << " | " << median_text(o.median_lead_m) << " |\n";
  }
  return md.str();
}

// The campaign's table's levels, in words.
std::string base_levels_text(const flight::ParameterTable& t) {
  const bool traction = flight::traction_check_on(t.traction);
  return "the campaign's table (stop " + number(q_mm(t.monitor.stop_sinkage_m), 1) + " mm, caution " +
         number(q_mm(t.monitor.caution_sinkage_m), 1) + " mm, section 8 " +
         (traction ? "stop coefficient " + number(fx::to_double(t.traction.stop_coefficient.q()), 2)
                   : std::string("off")) +
         ")";
}

}  // namespace

std::string level_choice_markdown(const CampaignResult& r, const LevelChoice& c, const std::string& table_path,
                                  std::uint32_t table_crc) {
  std::ostringstream md;
  const std::size_t n = c.tuning[c.level].clear_drives;
  const std::string base_levels = base_levels_text(r.options.table);
  md << "\n## Level choice (--choose-levels --max-false-stop " << number(c.max_false_stop, 4) << ")\n\n"
     << "Chosen on the tuning families only, over every pair of a sinkage stop level and a section-8 stop "
        "coefficient (or the motion-resistance check off; the sinkage levels alone when the table has no section 8): "
        "of the points whose one-sided 95 % Clopper–Pearson upper bound on the false-stop rate (over the tuning "
        "clear drives: traverses that never embed nor come within 5 % of the weight of it; near-miss stops apart) "
        "meets the target, the one that stops the most embeddings before the embedding (then ≥ 1 m ahead, median "
        "lead); if none meets it, the same order among the points with the fewest false stops, not certified. "
        "Cautions keep the base table's caution/stop ratios; the allowed sinkage (section 7) scales with the stop "
        "level, as in the sweep.\n\n"
     << "Stop level " << number(c.stop_mm, 2) << " mm, caution " << number(c.caution_mm, 2) << " mm, allowed sinkage "
     << number(c.allowed_mm, 2) << " mm; section 8 "
     << (c.traction_stop ? "stop coefficient " + number(*c.traction_stop, 3) + ", caution " +
                               number(c.traction_caution.value_or(0.0), 3)
                         : std::string("off"))
     << " (" << choice_basis_name(c.basis) << "); table written to " << table_path
     << " (CRC-32 " << strf("0x%08x", static_cast<unsigned>(table_crc)) << "; every other value from "
     << r.options.table_source << "; loaded back through flight::load()).\n\n"
     << verdict_text(c, n) << "\nThe price: at the chosen level " << share(c.tuning[c.level].stopped_before,
                                                                                 c.tuning[c.level].embeddings)
     << " tuning embeddings are stopped before the embedding, against "
     << share(c.base_tuning.stopped_before, c.base_tuning.embeddings) << " with " << base_levels << ".\n"
     << "\nExpected outcome at the chosen level (the held-out families are the check, never used to choose; false "
        "cautions: clear drives that reached CAUTION; near-miss stops: stops on traverses that came within 5 % of "
        "the weight of embedding without it; caution lead: embedding − first CAUTION):\n\n"
     << "| group | traverses | false stops (of the clear drives) | 95 % upper bound | false cautions | near-miss "
        "stops | embeddings | stopped before the embedding | stopped ≥ 1 m ahead | median lead [m] | median "
        "ideal-sensor lead [m] | lead ≥ 80 % of ideal | median caution lead [m] |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
     << outcome_row("tuning", c.tuning[c.level]) << outcome_row("held out", c.held_out)
     << outcome_row(("tuning, " + base_levels).c_str(), c.base_tuning)
     << outcome_row(("held out, " + base_levels).c_str(), c.base_held_out)
     << "\nEvery level of the choice's grid (tuning families):\n\n"
     << levels_rows(r, c);
  return md.str();
}

namespace {

std::string outcome_json(const LevelOutcome& o) {
  std::ostringstream j;
  j << "{\"traverses\": " << o.traverses << ", \"clear_drives\": " << o.clear_drives << ", \"near_misses\": "
    << o.near_misses << ", \"near_miss_stops\": " << o.near_miss_stops << ", \"false_stops\": "
    << o.false_stops << ", \"false_stop_upper_95\": " << number(o.false_stop_bound, 6) << ", \"false_cautions\": "
    << o.false_cautions << ", \"embeddings\": " << o.embeddings << ", \"stopped_before\": " << o.stopped_before
    << ", \"stopped_ahead_1m\": " << o.stopped_ahead << ", \"median_lead_m\": " << json_number(o.median_lead_m, 3)
    << ", \"median_ideal_lead_m\": " << json_number(o.median_ideal_lead_m, 3)
    << ", \"lead_at_80pct_of_ideal\": " << o.lead_at_80pct_of_ideal
    << ", \"median_caution_lead_m\": " << json_number(o.median_caution_lead_m, 3) << "}";
  return j.str();
}

}  // namespace

std::string level_choice_json(const CampaignResult& r, const LevelChoice& c, const std::string& table_path,
                              std::uint32_t table_crc) {
  std::ostringstream j;
  j << "{\"max_false_stop\": " << number(c.max_false_stop, 6) << ", \"confidence\": 0.95, \"basis\": \""
    << choice_basis_name(c.basis) << "\", \"certified\": " << (c.basis == ChoiceBasis::certified ? "true" : "false")
    << ",\n \"stop_mm\": " << number(c.stop_mm, 3) << ", \"caution_mm\": " << number(c.caution_mm, 3)
    << ", \"allowed_mm\": " << number(c.allowed_mm, 3) << ", \"traction_stop\": " << json_number(c.traction_stop, 4)
    << ", \"traction_caution\": " << json_number(c.traction_caution, 4)
    << ", \"caution_rule\": \"base table's caution/stop ratios\", \"table\": " << json_string(table_path) << ", \"table_crc\": " << table_crc << ",\n"
    << " \"certifiable_false_stops\": " << (c.certifiable ? std::to_string(*c.certifiable) : std::string("null"))
    << ", \"needed_without_false_stop\": " << c.needed_without_false_stop << ",\n"
    << " \"tuning\": " << outcome_json(c.tuning[c.level]) << ",\n \"held_out\": " << outcome_json(c.held_out)
    << ",\n \"base_table\": {\"stop_mm\": " << number(q_mm(r.options.table.monitor.stop_sinkage_m), 3)
    << ", \"traction_stop\": "
    << (flight::traction_check_on(r.options.table.traction)
            ? number(fx::to_double(r.options.table.traction.stop_coefficient.q()), 4)
            : std::string("null"))
    << ", \"tuning\": " << outcome_json(c.base_tuning) << ", \"held_out\": " << outcome_json(c.base_held_out) << "}"
    << ",\n \"levels\": [";
  for (std::size_t k = 0; k < c.tuning.size(); ++k) {
    const LevelPair& p = r.options.choice_grid[k];
    j << (k ? ",\n  " : "\n  ") << "{\"stop_mm\": " << number(p.stop_mm, 3)
      << ", \"traction_stop\": " << json_number(p.traction_stop, 4) << ", \"tuning\": " << outcome_json(c.tuning[k])
      << "}";
  }
  j << "]}\n";
  return j.str();
}

}  // namespace sinkwatch::ground
