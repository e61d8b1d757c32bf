// campaign_report.hpp: what `sinkwatch campaign --out DIR` writes
// (docs/campaign.md): traverses.csv and traverses.json (one record per
// traverse), summary.md (per family: outcomes, median lead, the ideal
// sensor's lead; tuning and held-out families apart; the stop-level sweep),
// leads.dat/levels.dat with their gnuplot scripts, and, when gnuplot is
// installed, lead_by_family.svg and false_stop_vs_lead.svg; with --faults,
// faults.csv and a table per fault class in summary.md.
#pragma once

#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/output_file.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sinkwatch::ground {

/// The CSV columns, in order.
const std::vector<std::string>& traverse_csv_columns();
std::string traverses_csv(const CampaignResult& r);
std::string traverses_json(const CampaignResult& r);
std::string campaign_summary(const CampaignResult& r, const std::string& command_line, bool plots);
/// faults.csv: one line per traverse and fault class (docs/fault-injection.md).
const std::vector<std::string>& fault_csv_columns();
std::string faults_csv(const CampaignResult& r);
/// summary.md's table of the fault classes against the same traverses without faults.
std::string fault_table(const CampaignResult& r);

/// `s` as a JSON string, quotes and backslashes escaped.
std::string json_string(const std::string& s);

/// Median of the values (nothing when empty).
std::optional<double> median(std::vector<double> values);

/// Counts and medians of a group of traverses at one verdict per traverse.
struct GroupStats {
  std::size_t traverses = 0, embeddings = 0;
  std::size_t near_misses = 0;  // never embed, but the reserve fell below kNearMissReserve
  std::array<std::size_t, kTraverseOutcomes> outcomes{};  // by TraverseOutcome
  std::vector<double> leads, ideal_leads, rear_excess;
  std::vector<double> reserve_leads;  // the ideal traction-reserve sensor's, embeddings only
  std::size_t lead_at_80pct_of_ideal = 0;  // embeddings whose stop lead >= 0.8 ideal lead
  // Embeddings at the start (embeds_at_start()), and of the others, those
  // stopped before the embedding.
  std::size_t embeddings_at_start = 0, along_drive_stopped_before = 0;
};

/// A traverse that embeds within its first kStartEmbedM (the soil cannot
/// carry the rover from the start: the `effects` traverses with bulldozing
/// on, docs/scenarios.md finding 9): no stop can come before it, the ideal
/// sensor's neither. Counted apart in summary.md's outcome table.
inline constexpr double kStartEmbedM = 0.1;
bool embeds_at_start(const TraverseResult& t);

/// Which sweep a level indexes: the sinkage level's, section 8's stop
/// coefficient's (the ideal sensor stays at the table's stop level then) or
/// the level choice's grid of pairs (CampaignOptions::choice_grid).
enum class Sweep { stop_level, traction_coefficient, choice };

/// The group at the campaign table's verdict, or at level `level` of `sweep`.
GroupStats group_stats(const std::vector<const TraverseResult*>& group, std::optional<std::size_t> level,
                       Sweep sweep = Sweep::stop_level);

/// Drives that never embed and never came near it (no near miss): what a
/// false stop is counted against.
std::size_t clear_drives(const GroupStats& g);

/// The traverses `keep` accepts, in order.
std::vector<const TraverseResult*> select_traverses(const CampaignResult& r, const std::function<bool(const TraverseResult&)>& keep);

/// The report folder: every file checked (and its temporary made) when this
/// is constructed, before the campaign runs; written by write() through
/// temporaries and renamed into place only when all are complete. When
/// gnuplot fails (e.g. nothing to plot), the plots are left out and
/// summary.md says so; the data and scripts are still written.
/// What --choose-levels adds to the report: its section of summary.md,
/// choice.json, and the chosen flight table's bytes.
struct ChoiceFiles {
  std::string markdown;
  std::string json;
  std::vector<std::uint8_t> table_bytes;
};

class CampaignReport {
 public:
  /// `gnuplot`: the program to draw with, empty for none (scripts only);
  /// `faults`: the campaign injects faults (faults.csv is written too);
  /// `table_out`: with --choose-levels, where the chosen table goes
  /// (choice.json is written too).
  CampaignReport(const std::string& dir, std::string gnuplot, bool faults = false,
                 const std::optional<std::string>& table_out = std::nullopt);
  CampaignReport(const CampaignReport&) = delete;
  CampaignReport& operator=(const CampaignReport&) = delete;
  ~CampaignReport();
  /// Writes every file; returns the paths written. `choice` must be given
  /// exactly when the report was made with a `table_out`.
  std::vector<std::string> write(const CampaignResult& r, const std::string& command_line,
                                 const ChoiceFiles* choice = nullptr);

 private:
  bool draw(const CampaignResult& r);
  struct Files;
  std::string dir_;
  std::string gnuplot_;
  std::unique_ptr<Files> files_;
};

/// The gnuplot program (SINKWATCH_GNUPLOT, else "gnuplot") when it runs, else empty.
std::string find_campaign_gnuplot();

}  // namespace sinkwatch::ground
