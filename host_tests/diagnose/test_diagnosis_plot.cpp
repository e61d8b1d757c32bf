// The diagnosis report's residual plots (issue 17): every panel, base and
// base + top effect side by side and channel under channel, on one y-range
// that holds every residual of residuals.dat; the points in the palette's
// linetypes (plot_style.hpp). The script text comes from
// residuals_plot_script(), which write_report() writes as residuals.gp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/diagnosis_data.hpp"
#include "sinkwatch/ground/diagnosis_report.hpp"
#include "sinkwatch/ground/plot_style.hpp"

namespace sinkwatch {
namespace ground {
namespace {

namespace fs = std::filesystem;

// Two channels on very different scales (in noise units): the base fit's
// residuals of channel 0 reach 12, those of channel 1 stay below 1; the top
// effect shrinks both. Autoscaled panels would each get their own range.
DiagnosisResult two_channel_result() {
  DiagnosisResult r;
  r.model = "test";
  r.source = "synthetic_rows.csv";
  r.channels = {{"traction_coeff", "DP/W"}, {"sinkage_m", "m"}};
  r.noise = {{"traction_coeff", 0.01, "replicates", 4, 0.01, 0.0}, {"sinkage_m", 0.002, "replicates", 4, 0.002, 0.0}};
  const std::size_t n = 12;
  for (std::size_t i = 0; i < n; ++i) {
    DiagnosisRow row;
    row.slip = 0.05 + 0.05 * static_cast<double>(i);
    row.load_n = i < 8 ? 30.0 : 60.0;
    r.rows.push_back(row);
    (i < 8 ? r.train : r.heldout).push_back(i);
    r.row_noise.push_back({0.01, 0.002});
    const double t = static_cast<double>(i) / static_cast<double>(n - 1);
    r.base.residuals.push_back({0.01 * (12.0 * t - 3.0), 0.002 * 0.8 * std::sin(7.0 * t)});
  }
  r.base.label = "base";
  RankedEffect top;
  top.effect = "grouser_effect";
  top.identifiable = true;
  top.fit.label = "grouser_effect";
  top.channel_before = {1.0, 1.0};  // read by the summary write_report() writes too
  top.channel_after = {0.5, 0.5};
  top.channel_shrink_pct = {50.0, 50.0};
  for (std::size_t i = 0; i < n; ++i) {
    top.fit.residuals.push_back({0.01 * (1.5 * std::cos(3.0 * static_cast<double>(i))), i == 5 ? std::nan("") : 0.0002});
  }
  r.ranking.push_back(top);
  return r;
}

std::vector<std::vector<double>> read_dat(const fs::path& path) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream cells(line);
    std::vector<double> row;
    std::string cell;
    while (cells >> cell) row.push_back(cell == "NaN" ? std::nan("") : std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST(DiagnosisPlot, EveryPanelHasTheSameYRangeHoldingEveryResidual) {
  const DiagnosisResult r = two_channel_result();
  const std::string script = residuals_plot_script(r);

  // Which y-range each `plot` (one panel) is drawn on: the last `set yrange`
  // before it; none, or an autoscaled one, fails.
  const std::regex yrange(R"(^set yrange \[([-+0-9.eE]+):([-+0-9.eE]+)\]$)");
  std::istringstream in(script);
  std::string line;
  std::string current;
  std::set<std::string> ranges;
  double low = std::nan("");
  double high = std::nan("");
  std::size_t panels = 0;
  while (std::getline(in, line)) {
    std::smatch m;
    if (line.rfind("set yrange", 0) == 0 || line.rfind("set autoscale", 0) == 0 || line.rfind("unset yrange", 0) == 0) {
      ASSERT_TRUE(std::regex_match(line, m, yrange)) << "not a fixed y-range: " << line;
      current = line;
      low = std::stod(m[1]);
      high = std::stod(m[2]);
    }
    if (line.rfind("plot ", 0) == 0) {
      ++panels;
      EXPECT_FALSE(current.empty()) << "panel " << panels << " is autoscaled";
      ranges.insert(current);
    }
  }
  EXPECT_EQ(panels, 2U * 2U * 2U);  // against slip and load; 2 channels; base and base + effect
  ASSERT_EQ(ranges.size(), 1U) << "the panels are on different y-ranges";

  // The range holds every value the panels draw (residuals.dat, columns 5 on).
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_diag_plot_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  write_report(r, dir.string(), "");
  {
    std::ifstream gp(dir / "residuals.gp");
    std::stringstream written;
    written << gp.rdbuf();
    EXPECT_EQ(written.str(), script) << "residuals.gp is residuals_plot_script()";
  }
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const std::vector<double>& row : read_dat(dir / "residuals.dat")) {
    ASSERT_EQ(row.size(), 4U + 2U * r.channels.size());
    for (std::size_t c = 4; c < row.size(); ++c) {
      if (!std::isfinite(row[c])) continue;
      lo = std::min(lo, row[c]);
      hi = std::max(hi, row[c]);
    }
  }
  fs::remove_all(dir);
  EXPECT_NEAR(hi, 9.0, 1e-9);
  EXPECT_LE(low, lo);
  EXPECT_GE(high, hi);
  EXPECT_LT(high, 1.2 * hi) << "the range is not much wider than the data";
  EXPECT_DOUBLE_EQ(low, -high) << "symmetric about zero";
  const ResidualRange range = residual_plot_range(r);
  EXPECT_DOUBLE_EQ(range.low, low);
  EXPECT_DOUBLE_EQ(range.high, high);
}

TEST(DiagnosisPlot, PointsUseThePaletteAndChannelNamesAreNotSubscripted) {
  const std::string script = residuals_plot_script(two_channel_result());
  EXPECT_NE(script.find(gnuplot_linetypes()), std::string::npos);
  EXPECT_NE(script.find("set termoption noenhanced\n"), std::string::npos);
  EXPECT_NE(script.find("set title 'traction_coeff: base + grouser_effect'\n"), std::string::npos);
  const std::string train = "with points lt " + std::to_string(sample_linetype(PlotSample::training)) + " title 'train'";
  const std::string held = "with points lt " + std::to_string(sample_linetype(PlotSample::held_out)) + " title 'held out'";
  std::size_t plots = 0;
  std::istringstream in(script);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("plot ", 0) != 0) continue;
    ++plots;
    EXPECT_NE(line.find(train), std::string::npos) << line;
    EXPECT_NE(line.find(held), std::string::npos) << line;
    EXPECT_EQ(line.find(" pt "), std::string::npos) << "the point type is the linetype's: " << line;
  }
  EXPECT_EQ(plots, 8U);
  EXPECT_NE(std::string(sample_plot_style(PlotSample::training).colour),
            std::string(sample_plot_style(PlotSample::held_out).colour));
}

TEST(DiagnosisPlot, NoFiniteResidualGivesAUnitRange) {
  DiagnosisResult r = two_channel_result();
  for (auto& row : r.base.residuals) row = {std::nan(""), std::nan("")};
  r.ranking.clear();
  const ResidualRange range = residual_plot_range(r);
  EXPECT_DOUBLE_EQ(range.low, -1.0);
  EXPECT_DOUBLE_EQ(range.high, 1.0);
}

}  // namespace ground
}  // namespace sinkwatch
