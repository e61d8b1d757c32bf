// level_choice.hpp: `sinkwatch campaign --choose-levels --max-false-stop F`
// (issue 14; docs/campaign.md, "Choosing the levels"): the caution and stop
// levels for a target false-stop rate, chosen on the campaign's tuning
// families only, with the expected lead at the chosen level and the
// held-out families' outcomes at it reported apart as the check.
//
// The grid. With a table that has section 8 (the motion-resistance check,
// docs/traction.md) the rover stops when either rule says so, so the two
// levels are chosen together: the grid is every pair of a sinkage stop level
// (choice_grid_mm(), or --levels) and a section-8 stop coefficient
// (CampaignOptions::sweep_traction_stop, or the check off). Without section 8
// the grid is the sinkage levels alone. The campaign re-runs the flight code
// per point on the same open-loop rows (CampaignOptions::choice_grid), so
// each point's verdicts are exact for the table table_at_levels() makes.
//
// The rule. Over the n tuning clear drives (traverses that never embed nor
// come within kNearMissReserve of it, campaign.hpp; a stop on a near miss is
// counted apart, not as a false stop), a point with k false stops has a
// one-sided 95 % Clopper-Pearson upper bound on its false-stop rate; n is the
// same at every point, so the bound meets the target F exactly when
// k <= k_max(n, F). Among the points that meet it ("certified") the choice is
// the best for embeddings: the most tuning embeddings stopped before the
// embedding, then the most >= 1 m ahead, then the longest median lead, then
// the fewest false stops, then the lower stop level and coefficient. When no
// point meets F (too few traverses: n < ln 0.05 / ln(1 - F), or every point
// stops too often), the fallback is the best by the same order among the
// points with the fewest false stops, marked not certified, with the number
// of clear drives that would be needed. Either way a tighter target never
// gives a choice that is better for embeddings (the certified set only
// shrinks, and it holds the fewest-false-stop points while it is not empty).
// On a sinkage-only grid this is the lowest certified level: a lower level
// stops no later on the same rows.
//
// The caution levels keep the base table's caution/stop ratios (as every
// sweep point does): CAUTION stops nothing, and the ratio keeps its warning
// margin in proportion; its false-caution rate is reported.
#pragma once

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/rover_table.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sinkwatch::ground {

/// One-sided upper confidence bound (Clopper-Pearson) on a rate of which k of
/// n trials were seen: the p with P(X <= k | n, p) = 1 - confidence; 1 when
/// k >= n or n = 0.
double clopper_pearson_upper(std::size_t k, std::size_t n, double confidence = 0.95);

/// The largest k whose bound over n meets `target`; none when not even k = 0 does.
std::optional<std::size_t> certifiable_false_stops(std::size_t n, double target, double confidence = 0.95);

/// The smallest n whose bound with no false stop meets `target` (target in (0, 1)).
std::size_t traverses_needed(double target, double confidence = 0.95);

/// The default grid of the choice [mm]: 20 mm to the table's wheel radius in
/// 2.5 mm steps, the levels table_at_stop_level() accepts.
std::vector<double> choice_grid_mm(const flight::ParameterTable& table);

/// The choice's grid for `table`: every sinkage level of `levels_mm` with
/// each of section 8's stop coefficients `traction_stops` and with the check
/// off, when the table has section 8; else the sinkage levels alone (check off).
std::vector<LevelPair> choice_grid(const flight::ParameterTable& table, const std::vector<double>& levels_mm,
                                   const std::vector<double>& traction_stops);

/// How the stop level was chosen.
enum class ChoiceBasis {
  certified,           // the lowest level whose false-stop bound meets the target
  fewest_false_stops,  // not certified: the lowest level with the fewest false stops
};
const char* choice_basis_name(ChoiceBasis b);

/// A group of traverses (tuning or held out) at one sweep level.
struct LevelOutcome {
  std::size_t traverses = 0;
  std::size_t clear_drives = 0;         // never embed, never a near miss
  std::size_t false_stops = 0;          // of `clear_drives`
  std::size_t near_misses = 0, near_miss_stops = 0;  // reported apart
  double false_stop_bound = 1.0;        // Clopper-Pearson 95 % upper bound
  std::size_t false_cautions = 0;       // clear drives that reached CAUTION
  std::size_t embeddings = 0;
  std::size_t stopped_before = 0;       // stopped_ahead + stopped_close
  std::size_t stopped_ahead = 0;        // >= 1 m ahead
  std::size_t lead_at_80pct_of_ideal = 0;
  std::optional<double> median_lead_m, median_ideal_lead_m, median_caution_lead_m;
};

/// The tuning or held-out traverses' outcome at point `level` of the
/// choice's grid, or with the campaign's (base) table when `level` is empty.
LevelOutcome level_outcome(const CampaignResult& r, std::optional<std::size_t> level, bool held_out);

struct LevelChoice {
  double max_false_stop = 0.01;
  ChoiceBasis basis = ChoiceBasis::certified;
  std::size_t level = 0;  // index into CampaignOptions::choice_grid
  double stop_mm = 0.0, caution_mm = 0.0, allowed_mm = 0.0;
  std::optional<double> traction_stop, traction_caution;  // section 8's coefficients; none: off
  std::optional<std::size_t> certifiable;  // k_max(n, F) over the tuning traverses
  std::size_t needed_without_false_stop = 0;  // n with which k = 0 would certify F
  std::vector<LevelOutcome> tuning;        // every point of the grid
  LevelOutcome held_out;                   // at the chosen level only
  LevelOutcome base_tuning, base_held_out;  // with the campaign's table, for comparison
};

/// The choice on the tuning families of `r` (held-out traverses are not read
/// for it). Throws std::invalid_argument when the grid is empty or no tuning
/// traverse is ordinary (nothing to measure a false-stop rate on), and when
/// the chosen level's table is refused by the flight code.
LevelChoice choose_levels(const CampaignResult& r, double max_false_stop);

/// The base table at the chosen levels (table_at_levels()).
flight::ParameterTable chosen_table(const CampaignResult& r, const LevelChoice& c);

/// The chosen table written through the one table writer (encode_table():
/// flight::encode(), loaded back by flight::load()), and checked to carry the
/// chosen levels (sinkage and section 8) bit for bit. Throws (std::invalid_argument, RoverTableError)
/// when the flight code refuses it or the levels did not survive.
EncodedTable encode_chosen_table(const CampaignResult& r, const LevelChoice& c);

/// summary.md's section and the machine-readable choice.json.
std::string level_choice_markdown(const CampaignResult& r, const LevelChoice& c, const std::string& table_path,
                                  std::uint32_t table_crc);
std::string level_choice_json(const CampaignResult& r, const LevelChoice& c, const std::string& table_path,
                              std::uint32_t table_crc);

}  // namespace sinkwatch::ground
