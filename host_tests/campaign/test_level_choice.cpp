// `sinkwatch campaign --choose-levels --max-false-stop F` (level_choice.hpp,
// docs/campaign.md "Choosing the levels"): the confidence bound, the rule on
// made-up sweeps whose answer is known, and the command on a small campaign
// (the choice meets its target on its own data, a tighter target never
// lowers the level, held-out families do not move it, the written table
// loads and carries the levels, the not-certifiable path, determinism).
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/level_choice.hpp"
#include "sinkwatch/ground/rover_table.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace {

using namespace sinkwatch::ground;
namespace fx = sinkwatch::fx;

TEST(ClopperPearson, MatchesTheClosedFormAndTabulatedBounds) {
  EXPECT_NEAR(clopper_pearson_upper(0, 10), 1.0 - std::pow(0.05, 0.1), 1e-12);
  EXPECT_NEAR(clopper_pearson_upper(0, 299), 1.0 - std::pow(0.05, 1.0 / 299.0), 1e-12);
  EXPECT_NEAR(clopper_pearson_upper(1, 10), 0.3942, 1e-4);  // exact one-sided 95 % bound for 1 of 10
  EXPECT_NEAR(clopper_pearson_upper(5, 100), 0.1023, 1e-4);
  EXPECT_EQ(clopper_pearson_upper(3, 3), 1.0);
  EXPECT_EQ(clopper_pearson_upper(0, 0), 1.0);
  EXPECT_LT(clopper_pearson_upper(2, 50), clopper_pearson_upper(3, 50));  // rises with k
}

TEST(ClopperPearson, TellsHowManyTraversesATargetNeeds) {
  EXPECT_EQ(traverses_needed(0.01), 299U);  // ln 0.05 / ln 0.99 = 298.07
  EXPECT_EQ(traverses_needed(0.05), 59U);
  EXPECT_FALSE(certifiable_false_stops(298, 0.01));
  EXPECT_EQ(certifiable_false_stops(299, 0.01), std::optional<std::size_t>(0));
  EXPECT_EQ(certifiable_false_stops(1000, 0.01), std::optional<std::size_t>(4));  // bound(4) 0.98 %, bound(5) 1.15 %
}

// A made-up campaign: `ordinary` tuning traverses that never embed, of which
// false_stops[k] stop at sweep level k, and 10 embeddings stopped ahead; the
// same numbers of held-out traverses, held_out_false_stops[k] stopping at
// level k (none when empty).
CampaignResult made_up(const std::vector<double>& levels_mm, std::size_t ordinary,
                       const std::vector<std::size_t>& false_stops,
                       const std::vector<std::size_t>& held_out_false_stops = {}) {
  CampaignResult r;
  for (const double level_mm : levels_mm) r.options.choice_grid.push_back(LevelPair{level_mm, std::nullopt});
  const auto add = [&](bool held_out, bool embedded, const std::vector<bool>& stops) {
    TraverseResult t;
    t.draw.family = held_out ? CampaignFamily::one_side : CampaignFamily::gradual;
    t.held_out = held_out;
    t.embedded = embedded;
    t.embed_x_m = 8.0;
    for (std::size_t k = 0; k < levels_mm.size(); ++k) {
      FlightVerdict f;
      IdealVerdict ideal;
      if (embedded) {
        f.outcome = TraverseOutcome::stopped_ahead;
        f.lead_m = 3.0 - levels_mm[k] / 50.0;
        ideal.lead_m = *f.lead_m;
      } else if (stops[k]) {
        f.outcome = TraverseOutcome::false_stop;
      }
      t.choice.push_back(f);
      t.choice_ideal.push_back(ideal);
    }
    r.traverses.push_back(t);
  };
  for (const bool held_out : {false, true}) {
    for (std::size_t i = 0; i < ordinary; ++i) {
      std::vector<bool> stops;
      for (std::size_t k = 0; k < levels_mm.size(); ++k) {
        const std::size_t stopping = held_out ? (held_out_false_stops.empty() ? 0 : held_out_false_stops[k])
                                              : false_stops[k];
        stops.push_back(i < stopping);
      }
      add(held_out, false, stops);
    }
    for (std::size_t i = 0; i < 10; ++i) add(held_out, true, {});
  }
  return r;
}

TEST(LevelChoiceRule, TakesTheLowestLevelWhoseBoundMeetsTheTarget) {
  // 1000 ordinary drives: k_max(1000, 1 %) = 4. Levels 30..60 mm.
  const CampaignResult r = made_up({30, 40, 50, 60}, 1000, {40, 9, 4, 0});
  const LevelChoice c = choose_levels(r, 0.01);
  EXPECT_EQ(c.basis, ChoiceBasis::certified);
  EXPECT_EQ(c.level, 2U);
  EXPECT_NEAR(c.stop_mm, 50.0, 1e-4);
  EXPECT_LE(c.tuning[c.level].false_stop_bound, 0.01);
  EXPECT_GT(c.tuning[1].false_stop_bound, 0.01);
  // Caution keeps the default table's ratio (30/45), allowed sinkage scales with the stop level.
  EXPECT_NEAR(c.caution_mm, 50.0 * 30.0 / 45.0, 1e-4);
  EXPECT_NEAR(c.allowed_mm, 50.0, 1e-4);
}

TEST(LevelChoiceRule, TighterTargetNeverGivesALowerStopLevel) {
  // False stops not monotone in the level, on purpose.
  const CampaignResult r = made_up({25, 30, 35, 40, 45, 50, 55}, 800, {60, 12, 3, 7, 1, 0, 2});
  double last_mm = 0.0;
  for (const double target : {0.2, 0.05, 0.02, 0.012, 0.008, 0.005, 0.003, 0.001}) {
    const LevelChoice c = choose_levels(r, target);
    EXPECT_GE(c.stop_mm, last_mm) << "target " << target;
    last_mm = c.stop_mm;
  }
}

TEST(LevelChoiceRule, HeldOutTraversesDoNotMoveTheChoice) {
  // Were the held-out drives counted, 40 mm would have 400 false stops of 800
  // and the choice would move to 30 mm (20 of 800, the fewest).
  const LevelChoice clean = choose_levels(made_up({30, 40, 50}, 400, {20, 0, 0}), 0.01);
  const LevelChoice noisy = choose_levels(made_up({30, 40, 50}, 400, {20, 0, 0}, {0, 400, 400}), 0.01);
  EXPECT_EQ(clean.level, 1U);
  EXPECT_EQ(clean.basis, ChoiceBasis::certified);
  EXPECT_EQ(clean.level, noisy.level);
  EXPECT_EQ(clean.basis, noisy.basis);
  EXPECT_EQ(clean.tuning[clean.level].false_stops, noisy.tuning[noisy.level].false_stops);
  // They are reported, at the chosen level.
  EXPECT_EQ(clean.held_out.false_stops, 0U);
  EXPECT_EQ(noisy.held_out.false_stops, 400U);
}

TEST(LevelChoiceRule, TooFewTraversesFallBackToTheFewestFalseStopsNotCertified) {
  const CampaignResult r = made_up({30, 40, 50, 60}, 40, {6, 0, 0, 0});
  const LevelChoice c = choose_levels(r, 0.01);
  EXPECT_EQ(c.basis, ChoiceBasis::fewest_false_stops);
  EXPECT_FALSE(c.certifiable);
  EXPECT_EQ(c.level, 1U);  // the lowest level with zero false stops
  EXPECT_EQ(c.needed_without_false_stop, 299U);
  const std::string md = level_choice_markdown(r, c, "t.tbl", 0U);
  EXPECT_NE(md.find("NOT CERTIFIED"), std::string::npos) << md;
  EXPECT_NE(md.find("at least 299"), std::string::npos) << md;
  EXPECT_NE(level_choice_json(r, c, "t.tbl", 0U).find("\"certified\": false"), std::string::npos);
  // Enough traverses for certificate, but every level stops falsely too often.
  const LevelChoice many = choose_levels(made_up({30, 40}, 400, {50, 20}), 0.01);
  EXPECT_EQ(many.basis, ChoiceBasis::fewest_false_stops);
  EXPECT_EQ(many.level, 1U);
}

TEST(LevelChoiceRule, StopsOnNearMissesAreNotFalseStops) {
  // 400 clear drives without a false stop at 40 mm, and 50 drives that came
  // within kNearMissReserve of embedding and stop at every level: counted
  // apart, they neither enter n nor k.
  CampaignResult r = made_up({30, 40}, 400, {9, 0});
  for (std::size_t i = 0; i < 50; ++i) {
    TraverseResult t = r.traverses.front();
    ASSERT_FALSE(t.embedded);
    t.min_reserve_frac = 0.5 * kNearMissReserve;
    for (FlightVerdict& f : t.choice) f.outcome = TraverseOutcome::near_miss_stop;
    r.traverses.push_back(t);
  }
  const LevelChoice c = choose_levels(r, 0.01);
  EXPECT_EQ(c.level, 1U);
  EXPECT_EQ(c.basis, ChoiceBasis::certified);
  EXPECT_EQ(c.tuning[c.level].clear_drives, 400U);
  EXPECT_EQ(c.tuning[c.level].false_stops, 0U);
  EXPECT_EQ(c.tuning[c.level].near_misses, 50U);
  EXPECT_EQ(c.tuning[c.level].near_miss_stops, 50U);
}

TEST(LevelChoiceRule, RefusesAChoiceWithNothingToMeasureOn) {
  CampaignResult r = made_up({30, 40}, 0, {0, 0});  // only embeddings
  EXPECT_THROW((void)choose_levels(r, 0.01), std::invalid_argument);
}

// A made-up campaign over pairs of a sinkage level and a section-8 stop
// coefficient: at point k, false_stops[k] of `ordinary` tuning clear drives
// stop falsely, and stopped_before[k] of 10 embeddings are stopped 2 m ahead
// (the others late).
struct MadeUpPoint {
  LevelPair levels;
  std::size_t false_stops = 0, stopped_before = 0;
};

CampaignResult made_up_pairs(const std::vector<MadeUpPoint>& points, std::size_t ordinary) {
  CampaignResult r;
  for (const MadeUpPoint& p : points) r.options.choice_grid.push_back(p.levels);
  const auto add = [&](bool embedded, std::size_t index) {
    TraverseResult t;
    t.draw.family = CampaignFamily::gradual;
    t.embedded = embedded;
    t.embed_x_m = 8.0;
    for (const MadeUpPoint& p : points) {
      FlightVerdict f;
      if (embedded) {
        const bool before = index < p.stopped_before;
        f.outcome = before ? TraverseOutcome::stopped_ahead : TraverseOutcome::late;
        f.lead_m = before ? 2.0 : -0.5;
      } else if (index < p.false_stops) {
        f.outcome = TraverseOutcome::false_stop;
      }
      t.choice.push_back(f);
      t.choice_ideal.push_back(IdealVerdict{});
    }
    r.traverses.push_back(t);
  };
  for (std::size_t i = 0; i < ordinary; ++i) add(false, i);
  for (std::size_t i = 0; i < 10; ++i) add(true, i);
  return r;
}

TEST(LevelChoiceRule, PairsTakeTheCertifiedPointThatStopsTheMostEmbeddingsBeforeThem) {
  // 1000 clear drives: k_max(1000, 1 %) = 4, k_max(1000, 0.5 %) = 1.
  const std::vector<MadeUpPoint> points = {
      {LevelPair{45.0, std::nullopt}, 2, 6},  // sinkage rule alone
      {LevelPair{45.0, 0.38}, 4, 9},          // both rules: more embeddings, more false stops
      {LevelPair{45.0, 0.30}, 30, 10},        // too many false stops
      {LevelPair{60.0, 0.38}, 3, 9},          // as good for embeddings, fewer false stops
  };
  const CampaignResult r = made_up_pairs(points, 1000);
  const LevelChoice c = choose_levels(r, 0.01);
  EXPECT_EQ(c.basis, ChoiceBasis::certified);
  EXPECT_EQ(c.level, 3U);
  EXPECT_NEAR(c.stop_mm, 60.0, 1e-4);
  ASSERT_TRUE(c.traction_stop);
  EXPECT_NEAR(*c.traction_stop, 0.38, 1e-6);
  // Tighter: every point has more than 1 false stop, so none is certified;
  // the fallback is the fewest false stops: the sinkage rule alone.
  const LevelChoice tight = choose_levels(r, 0.005);
  EXPECT_EQ(tight.basis, ChoiceBasis::fewest_false_stops);
  EXPECT_EQ(tight.level, 0U);
  EXPECT_FALSE(tight.traction_stop);
  EXPECT_LE(tight.tuning[tight.level].stopped_before, c.tuning[c.level].stopped_before);
  // Looser: the point that stops every embedding before it.
  EXPECT_EQ(choose_levels(r, 0.05).level, 2U);
}

TEST(LevelChoiceTable, TheChosenPairIsWhatTheTableCarries) {
  const CampaignResult r = made_up_pairs({{LevelPair{40.0, std::nullopt}, 0, 5}, {LevelPair{50.0, 0.42}, 0, 8}}, 400);
  const LevelChoice c = choose_levels(r, 0.01);
  ASSERT_EQ(c.level, 1U);
  const EncodedTable written = encode_chosen_table(r, c);
  ASSERT_TRUE(sinkwatch::flight::traction_check_on(written.table.traction));
  EXPECT_NEAR(fx::to_double(written.table.traction.stop_coefficient.q()), 0.42, 1e-6);
  EXPECT_NEAR(1000.0 * fx::to_double(written.table.monitor.stop_sinkage_m.q()), 50.0, 1e-4);
  // Caution keeps the default table's section-8 ratio (0.30 / 0.38).
  EXPECT_NEAR(fx::to_double(written.table.traction.caution_coefficient.q()), 0.42 * 0.30 / 0.38, 1e-6);
  // The other point: section 8 removed, the rest as the default table.
  LevelChoice off = c;
  off.level = 0;
  const EncodedTable without = encode_chosen_table(r, off);
  EXPECT_FALSE(sinkwatch::flight::traction_check_on(without.table.traction));
  EXPECT_LT(without.bytes.size(), written.bytes.size());
}

TEST(LevelChoiceTable, TheGridPairsEverySinkageLevelWithEveryCoefficientAndWithTheCheckOff) {
  const auto table = sinkwatch::flight::default_parameter_table();
  const std::vector<LevelPair> grid = choice_grid(table, {30, 45}, {0.34, 0.42});
  ASSERT_EQ(grid.size(), 6U);
  EXPECT_FALSE(grid[0].traction_stop);
  EXPECT_EQ(grid[1].stop_mm, 45.0);
  EXPECT_EQ(grid[5].traction_stop, std::optional<double>(0.42));
  auto without = table;
  without.traction = sinkwatch::flight::TractionParams{};
  EXPECT_EQ(choice_grid(without, {30, 45}, {0.34, 0.42}).size(), 2U);  // the sinkage levels alone
}

TEST(LevelChoiceTable, ALevelTheFlightCodeRefusesIsNotWritten) {
  CampaignResult r = made_up({30, 40}, 400, {0, 0});
  LevelChoice c = choose_levels(r, 0.01);
  r.options.choice_grid[c.level].stop_mm = 400.0;  // beyond the 0.15 m wheel radius
  EXPECT_THROW((void)encode_chosen_table(r, c), std::invalid_argument);
}

TEST(LevelChoiceTable, GridRunsFromTwentyMillimetresToTheWheelRadius) {
  const std::vector<double> grid = choice_grid_mm(sinkwatch::flight::default_parameter_table());
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(grid.front(), 20.0);
  EXPECT_LE(grid.back(), 150.0);
  EXPECT_GE(grid.size(), 40U);
}

// The command on a small real campaign: 3 tuning families, one held out.
std::string read(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// choice.json without its "table" (the path differs between runs).
std::string without_table_path(std::string json) {
  const std::size_t start = json.find("\"table\": \"");
  const std::size_t end = json.find("\", ", start);
  if (start != std::string::npos && end != std::string::npos) json.erase(start, end - start);
  return json;
}

class ChooseLevelsCommand : public ::testing::Test {
 protected:
  static std::filesystem::path dir(const std::string& name) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("sinkwatch_choose_levels_" + std::string(info->name())) / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d.parent_path());
    return d;
  }
  static int run(const std::vector<std::string>& extra, const std::filesystem::path& out, std::string* text = nullptr,
                 const std::string& jobs = "2") {
    // One section-8 coefficient besides "off" keeps the grid (and the sanitizer build's time) small.
    std::vector<std::string> args = {"--families", "gradual,abrupt,stepwise,one-side", "--held-out", "one-side",
                                     "--traverses", "2", "--seed", "5", "--path-length", "7", "-j", jobs, "-q",
                                     "--traction-levels", "0.38", "--choose-levels", "--out", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    std::ostringstream o, e;
    const int rc = run_campaign_command(args, o, e);
    if (text) *text = o.str() + e.str();
    return rc;
  }
};

TEST_F(ChooseLevelsCommand, WritesATableThatLoadsAndCarriesTheChosenLevels) {
  const std::filesystem::path out = dir("a");
  std::string text;
  ASSERT_EQ(run({"--max-false-stop", "0.2", "--levels", "20,30,45,60,90,140"}, out, &text), 0) << text;
  const std::string json = read(out / "choice.json");
  const LoadedTable table = read_table_file((out / "chosen.tbl").string());
  const double stop_mm = 1000.0 * fx::to_double(table.table.monitor.stop_sinkage_m.q());
  const double caution_mm = 1000.0 * fx::to_double(table.table.monitor.caution_sinkage_m.q());
  char want[64];
  std::snprintf(want, sizeof want, "\"stop_mm\": %.3f, \"caution_mm\": %.3f", stop_mm, caution_mm);
  EXPECT_NE(json.find(want), std::string::npos) << want << "\n" << json;
  // Section 8's coefficient was chosen with them: the table carries the one choice.json names.
  const std::size_t at = json.find("\"traction_stop\": ");
  ASSERT_NE(at, std::string::npos) << json;
  if (json.compare(at + 17, 4, "null") == 0) {
    EXPECT_FALSE(sinkwatch::flight::traction_check_on(table.table.traction));
  } else {
    ASSERT_TRUE(sinkwatch::flight::traction_check_on(table.table.traction));
    EXPECT_NEAR(std::stod(json.substr(at + 17)), fx::to_double(table.table.traction.stop_coefficient.q()), 1e-4);
  }
  // The grid: the 6 sinkage levels with the check off and with run()'s one coefficient.
  std::size_t points = 0;
  for (std::size_t p = json.find("{\"stop_mm\": "); p != std::string::npos; p = json.find("{\"stop_mm\": ", p + 1)) ++points;
  EXPECT_EQ(points, 6U * 2U + 1U) << json;  // + the base table's block
  // Everything but the levels is the base (default) table's.
  const auto base = sinkwatch::flight::default_parameter_table();
  EXPECT_EQ(table.table.correction.rows[0].c3.q().raw(), base.correction.rows[0].c3.q().raw());
  EXPECT_EQ(table.table.monitor.window_m, base.monitor.window_m);
  EXPECT_FALSE(table.rover);
  EXPECT_NE(json.find("\"base_table\": {\"stop_mm\": 45.000"), std::string::npos) << json;  // the comparison
  EXPECT_NE(text.find("Level choice"), std::string::npos);
  EXPECT_NE(read(out / "summary.md").find("Level choice"), std::string::npos);
}

TEST_F(ChooseLevelsCommand, MeetsItsTargetOnItsOwnDataAndTighterTargetsNeverGoLower) {
  // A 7-traverse tuning set cannot certify 1 %: the fallback, said so.
  const std::filesystem::path loose = dir("loose"), tight = dir("tight");
  ASSERT_EQ(run({"--max-false-stop", "0.5", "--levels", "20,30,45,60,90,140"}, loose), 0);
  ASSERT_EQ(run({"--max-false-stop", "0.01", "--levels", "20,30,45,60,90,140", "--table-out",
                 (tight.parent_path() / "tight.tbl").string()},
                tight),
            0);
  const std::string a = read(loose / "choice.json"), b = read(tight / "choice.json");
  EXPECT_NE(b.find("\"certified\": false"), std::string::npos) << b;
  EXPECT_NE(read(tight / "summary.md").find("NOT CERTIFIED"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(tight.parent_path() / "tight.tbl"));
  // A tighter target never stops more tuning embeddings before the embedding
  // (the tuning block comes first in choice.json).
  const auto stopped_before = [](const std::string& json) {
    return std::stoul(json.substr(json.find("\"stopped_before\": ") + 18));
  };
  EXPECT_LE(stopped_before(b), stopped_before(a));
  if (a.find("\"certified\": true") != std::string::npos) {
    const auto bound = [](const std::string& json) {
      return std::stod(json.substr(json.find("\"false_stop_upper_95\": ") + 23));
    };
    EXPECT_LE(bound(a), 0.5);  // the tuning block comes first
  }
}

TEST_F(ChooseLevelsCommand, HeldOutFamiliesDoNotChangeTheChoiceAndTheSameSeedGivesTheSameFiles) {
  const std::filesystem::path one = dir("one"), two = dir("two"), other = dir("other");
  ASSERT_EQ(run({"--max-false-stop", "0.3", "--levels", "30,45,90"}, one), 0);
  ASSERT_EQ(run({"--max-false-stop", "0.3", "--levels", "30,45,90"}, two, nullptr, "1"), 0);
  EXPECT_EQ(without_table_path(read(one / "choice.json")), without_table_path(read(two / "choice.json")));
  EXPECT_EQ(read(one / "chosen.tbl"), read(two / "chosen.tbl"));
  // Another held-out family in place of one-side: same tuning traverses, same choice and table.
  std::vector<std::string> args = {"--families", "gradual,abrupt,stepwise,drawn-soil", "--held-out", "drawn-soil",
                                   "--traverses", "2", "--seed", "5", "--path-length", "7", "-q",
                                   "--traction-levels", "0.38", "--choose-levels",
                                   "--max-false-stop", "0.3", "--levels", "30,45,90", "--out", other.string()};
  std::ostringstream o, e;
  ASSERT_EQ(run_campaign_command(args, o, e), 0) << e.str();
  const auto tuning = [](const std::string& json) {
    return without_table_path(json.substr(0, json.find("\"held_out\":")));
  };
  EXPECT_EQ(tuning(read(one / "choice.json")), tuning(read(other / "choice.json")));
  EXPECT_EQ(read(one / "chosen.tbl"), read(other / "chosen.tbl"));
}

TEST(ChooseLevelsOptions, AreCheckedBeforeAnyWork) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "sinkwatch_choose_levels_options";
  std::filesystem::remove_all(out);
  std::ostringstream o, e;
  const auto rc = [&](std::vector<std::string> args) {
    args.insert(args.end(), {"--out", out.string(), "--traverses", "1"});
    return run_campaign_command(args, o, e);
  };
  const int usage = exit_status(ExitCode::usage_error);
  EXPECT_EQ(rc({"--max-false-stop", "0.01"}), usage);  // without --choose-levels
  EXPECT_EQ(rc({"--choose-levels"}), usage);           // without a target
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "1"}), usage);
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "0"}), usage);
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "0.01", "--table-out", "-"}), usage);
  EXPECT_EQ(rc({"--table-out", "x.tbl"}), usage);
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "0.01", "--traction-levels", "0.4,5"}), usage);  // > 4
  EXPECT_EQ(rc({"--traction-levels", "0"}), usage);
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "0.01", "--families", "one-side"}), usage);  // all held out
  EXPECT_EQ(rc({"--choose-levels", "--max-false-stop", "0.01", "--table-out", "/nonexistent/dir/t.tbl"}),
            exit_status(ExitCode::data_error));
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
