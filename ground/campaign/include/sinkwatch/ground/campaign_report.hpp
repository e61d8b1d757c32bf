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

#include <memory>
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

/// Median of the values (nothing when empty).
std::optional<double> median(std::vector<double> values);

/// The report folder: every file checked (and its temporary made) when this
/// is constructed, before the campaign runs; written by write() through
/// temporaries and renamed into place only when all are complete. When
/// gnuplot fails (e.g. nothing to plot), the plots are left out and
/// summary.md says so; the data and scripts are still written.
class CampaignReport {
 public:
  /// `gnuplot`: the program to draw with, empty for none (scripts only);
  /// `faults`: the campaign injects faults (faults.csv is written too).
  CampaignReport(const std::string& dir, std::string gnuplot, bool faults = false);
  CampaignReport(const CampaignReport&) = delete;
  CampaignReport& operator=(const CampaignReport&) = delete;
  ~CampaignReport();
  /// Writes every file; returns the paths written.
  std::vector<std::string> write(const CampaignResult& r, const std::string& command_line);

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
