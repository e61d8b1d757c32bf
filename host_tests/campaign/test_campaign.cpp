// The campaign (campaign.hpp, docs/campaign.md): its draws are a pure
// function of the seed, its files do not depend on the thread count, every
// outcome class is reachable by a constructed traverse, its files carry the
// documented columns, and bad options are refused before any work.
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/campaign_report.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <sstream>

namespace {

using namespace sinkwatch::ground;
using sinkwatch::flight::default_parameter_table;

// A campaign traverse's simulator settings on a hand-made path.
ScenarioSpec constructed(const std::string& name, std::vector<TerrainKnot> terrain, double end_x_m) {
  ScenarioSpec s = draw_traverse(CampaignFamily::gradual, 1, 0, end_x_m).spec;
  s.name = name;
  s.seed = 7;
  s.mass_kg = 140.0;
  s.noise = ScenarioNoise{};
  s.terrain = std::move(terrain);
  return s;
}

// Firm ground, then a soft ripple that embeds the wheels within 9 m.
ScenarioSpec embedding_path() {
  return constructed("embeds", {{0, 1, 0}, {1, 1, 0}, {3, 0.1, 0}, {6, 0.02, 0}, {9, 0.008, 0}}, 9.0);
}

// Firm and moderately soft ground: never embeds.
ScenarioSpec ordinary_path() { return constructed("ordinary", {{0, 1, 0}, {2, 1, 2}, {4, 0.4, 3}, {6, 0.6, 0}}, 6.0); }

// Firm ground, then a patch just firm enough to carry the rover through
// (min reserve 0.024 m g at scale 0.07; 0.05 embeds, 0.1 keeps 0.069).
ScenarioSpec near_miss_path() {
  return constructed("near-miss", {{0, 1, 0}, {1, 1, 0}, {3, 0.07, 0}, {6, 0.07, 0}}, 6.0);
}

class CampaignCases : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    embedding_ = std::make_unique<Scenario>(generate_open_loop_drive(embedding_path()));
    ordinary_ = std::make_unique<Scenario>(generate_open_loop_drive(ordinary_path()));
    ScenarioSpec no_tail = embedding_path();
    no_tail.stuck_tail_s = 0.0;
    no_tail_ = std::make_unique<Scenario>(generate_open_loop_drive(no_tail));
  }
  static void TearDownTestSuite() {
    embedding_.reset();
    ordinary_.reset();
    no_tail_.reset();
  }
  static std::unique_ptr<Scenario> embedding_, ordinary_, no_tail_;
};
std::unique_ptr<Scenario> CampaignCases::embedding_, CampaignCases::ordinary_, CampaignCases::no_tail_;

constexpr double kMoon = 1.62;

TEST_F(CampaignCases, ConstructedPathsEmbedOrNot) {
  EXPECT_TRUE(embedding_->truth.embedded);
  EXPECT_FALSE(ordinary_->truth.embedded);
  EXPECT_EQ(embedding_->cycle_loads.size(), embedding_->log.rows.size());
}

// The claim is the rover's decision as a whole, the default table with its
// section 8: since the step puts the drive torques in the wheel loads
// (docs/rover-loads.md 12.8) the rear wheels' sinkage no longer reads high
// from loads that were too low, so the wheels' sinkage rule alone, with the
// default C3 that reads low in soft soil, stops this path only 0.08 m ahead;
// the motion-resistance check stops it 2.06 m ahead, first.
TEST_F(CampaignCases, DefaultTableStopsTheEmbeddingAhead) {
  const FlightVerdict v = flight_verdict(*embedding_, default_parameter_table(), kMoon);
  EXPECT_EQ(v.outcome, TraverseOutcome::stopped_ahead);
  ASSERT_TRUE(v.lead_m && v.caution_time_s && v.stop_time_s);
  EXPECT_GE(*v.lead_m, kCloseLeadM);
  EXPECT_LE(*v.caution_time_s, *v.stop_time_s);
  EXPECT_EQ(v.stop_reason, sinkwatch::flight::StopReason::traction);
}

/// The default table with its sinkage stop at the wheel radius (it never
/// trips) and without section 8: the wheels' slip rule alone.
sinkwatch::flight::ParameterTable stops_disabled() {
  sinkwatch::flight::ParameterTable table = table_at_stop_level(default_parameter_table(), 0.15);
  table.traction = sinkwatch::flight::TractionParams{};
  return table;
}

TEST_F(CampaignCases, DisabledStopMissesTheEmbedding) {
  // The stop level at the wheel radius: the sinkage never trips; without a
  // stuck tail the slip rule has no rows to trip on either.
  const auto table = stops_disabled();
  EXPECT_EQ(flight_verdict(*no_tail_, table, kMoon).outcome, TraverseOutcome::missed);
}

TEST_F(CampaignCases, DisabledStopIsLateWhenTheWheelsSpin) {
  // The same, with the stuck tail: the high-slip rule stops the rover after the embedding.
  const auto table = stops_disabled();
  const FlightVerdict v = flight_verdict(*embedding_, table, kMoon);
  EXPECT_EQ(v.outcome, TraverseOutcome::late);
  ASSERT_TRUE(v.lead_s);
  EXPECT_LE(*v.lead_s, 0.0);
}

TEST_F(CampaignCases, AbsurdlyLowStopLevelStopsAnOrdinaryDrive) {
  const auto table = table_at_stop_level(default_parameter_table(), 0.010);
  EXPECT_EQ(flight_verdict(*ordinary_, table, kMoon).outcome, TraverseOutcome::false_stop);
}

TEST_F(CampaignCases, AHigherTractionStopCoefficientNeverStopsEarlier) {
  // Section 8's sweep (docs/traction.md): the same drive at rising stop
  // coefficients; the sinkage levels as the default has them.
  std::optional<double> previous;
  bool any_stop = false;
  for (const double c : {0.30, 0.34, 0.38, 0.42, 0.46, 0.50}) {
    const auto table = table_at_traction_level(default_parameter_table(), c);
    EXPECT_NEAR(sinkwatch::fx::to_double(table.traction.stop_coefficient.q()), c, 1e-7);
    const FlightVerdict v = flight_verdict(*embedding_, table, kMoon);
    ASSERT_TRUE(v.stop_time_s) << c;  // the sinkage level stops it at the latest
    any_stop = true;
    if (previous) {
      EXPECT_GE(*v.stop_time_s, *previous) << "coefficient " << c;
    }
    previous = v.stop_time_s;
  }
  EXPECT_TRUE(any_stop);
}

TEST(CampaignTractionSweep, NeedsSection8AndAValidLevel) {
  sinkwatch::flight::ParameterTable off = default_parameter_table();
  off.traction = sinkwatch::flight::TractionParams{};
  EXPECT_THROW(table_at_traction_level(off, 0.4), std::invalid_argument);
  EXPECT_THROW(table_at_traction_level(default_parameter_table(), 5.0), std::invalid_argument);
  const auto t = table_at_traction_level(default_parameter_table(), 0.50);
  // caution / stop kept (0.30 / 0.38 in the default).
  EXPECT_NEAR(sinkwatch::fx::to_double(t.traction.caution_coefficient.q()), 0.50 * 0.30 / 0.38, 1e-7);
}

TEST_F(CampaignCases, DefaultTableLetsAnOrdinaryDriveThrough) {
  const FlightVerdict v = flight_verdict(*ordinary_, default_parameter_table(), kMoon);
  EXPECT_EQ(v.outcome, TraverseOutcome::ok_no_stop);
  EXPECT_FALSE(v.stop_time_s);
}

TEST_F(CampaignCases, FlightStaticsWithTheLoggedTorquesCarryTheSimulatedRoversLoads) {
  // The generator's loads are the fuller balance (each wheel's pull and
  // drive-torque reaction); the flight statics with each wheel's torque
  // from its logged current describe that world (docs/rover-loads.md 12.6:
  // a mean rear error of about 0.1 %, against 15-25 % without the torques).
  for (const Scenario* drive : {ordinary_.get(), embedding_.get()}) {
    double rear_true = 0.0, rear_statics = 0.0, front_true = 0.0, front_statics = 0.0;
    for (std::size_t i = 0; i < drive->log.rows.size(); ++i) {
      const TelemetryRow& row = drive->log.rows[i];
      if (row.phase != "drive" || (drive->truth.embedded && row.time_s >= drive->truth.embed_time_s)) continue;
      const CycleLoads& l = drive->cycle_loads.at(i);
      rear_true += l.true_n[2] + l.true_n[5];
      rear_statics += l.flight_statics_n[2] + l.flight_statics_n[5];
      front_true += l.true_n[0] + l.true_n[3];
      front_statics += l.flight_statics_n[0] + l.flight_statics_n[3];
    }
    ASSERT_GT(rear_statics, 0.0);
    EXPECT_NEAR(rear_true / rear_statics - 1.0, 0.0, 0.01);
    EXPECT_NEAR(front_true / front_statics - 1.0, 0.0, 0.01);
  }
}

TEST_F(CampaignCases, IdealSensorCrossesTheStopLevelBeforeTheEmbedding) {
  const IdealVerdict v = ideal_verdict(*embedding_, 0.045);
  ASSERT_TRUE(v.lead_m && v.cross_time_s);
  EXPECT_GT(*v.lead_m, 0.0);
  EXPECT_LT(*v.cross_time_s, embedding_->truth.embed_time_s);
  EXPECT_FALSE(ideal_verdict(*ordinary_, 0.045).cross_time_s);  // 45 mm is never reached there
}

TEST_F(CampaignCases, TractionReserveRunsOutOnlyWhereTheRoverEmbeds) {
  // The ordinary path keeps a wide reserve; on the embedding path the reserve
  // falls towards zero just before the simulator's embedding point.
  ASSERT_TRUE(ordinary_->truth.min_reserve_frac && embedding_->truth.min_reserve_frac);
  EXPECT_GT(*ordinary_->truth.min_reserve_frac, 2.0 * kNearMissReserve);
  EXPECT_LT(*embedding_->truth.min_reserve_frac, kNearMissReserve);
  EXPECT_GT(*embedding_->truth.min_reserve_frac, -kNearMissReserve);
  std::size_t rows_with_reserve = 0;
  for (const CycleLoads& c : ordinary_->cycle_loads) rows_with_reserve += c.reserve_n ? 1U : 0U;
  EXPECT_GT(rows_with_reserve, ordinary_->log.rows.size() / 6);  // every 5th driving row
  EXPECT_LT(rows_with_reserve, ordinary_->log.rows.size() / 4);
}

TEST_F(CampaignCases, IdealReserveSensorCrossesBeforeTheEmbeddingAndNeverOnAClearDrive) {
  const double weight_n = 140.0 * kMoon;
  const IdealVerdict v = reserve_verdict(*embedding_, weight_n);
  ASSERT_TRUE(v.lead_m && v.cross_time_s);
  EXPECT_GT(*v.lead_m, 0.0);
  EXPECT_LT(*v.cross_time_s, embedding_->truth.embed_time_s);
  EXPECT_FALSE(reserve_verdict(*ordinary_, weight_n).cross_time_s);
}

TEST_F(CampaignCases, ShippedScenarioSettingsComputeNoReserve) {
  ScenarioSpec s = ordinary_path();
  s.reserve_every_rows = 0;
  const Scenario drive = generate_open_loop_drive(s);
  EXPECT_FALSE(drive.truth.min_reserve_frac);
  for (const CycleLoads& c : drive.cycle_loads) EXPECT_FALSE(c.reserve_n);
}

TEST(CampaignOutcomes, AStopOnADriveThatNearlyEmbedsIsANearMissNotAFalseStop) {
  // A soft patch the rover just gets through: it never embeds, but its
  // reserve falls below kNearMissReserve; a low stop level stops it there.
  const Scenario drive = generate_open_loop_drive(near_miss_path());
  ASSERT_FALSE(drive.truth.embedded);
  ASSERT_TRUE(drive.truth.min_reserve_frac);
  ASSERT_LT(*drive.truth.min_reserve_frac, kNearMissReserve);
  const auto table = table_at_stop_level(default_parameter_table(), 0.010);
  EXPECT_EQ(flight_verdict(drive, table, kMoon).outcome, TraverseOutcome::near_miss_stop);
}

TEST(CampaignOutcomes, AnEmbeddingAtTheStartIsCountedApartFromTheOthers) {
  // Three embeddings: one at x = 0.05 m (late: nothing could stop before it),
  // one stopped 2 m ahead, one late at 6 m; and a clear drive.
  std::vector<TraverseResult> ts(4);
  ts[0].embedded = true;
  ts[0].embed_x_m = 0.05;
  ts[0].flight.outcome = TraverseOutcome::late;
  ts[1].embedded = true;
  ts[1].embed_x_m = 8.0;
  ts[1].flight.outcome = TraverseOutcome::stopped_ahead;
  ts[2].embedded = true;
  ts[2].embed_x_m = 6.0;
  ts[2].flight.outcome = TraverseOutcome::late;
  ts[3].flight.outcome = TraverseOutcome::ok_no_stop;
  EXPECT_TRUE(embeds_at_start(ts[0]));
  EXPECT_FALSE(embeds_at_start(ts[2]));
  EXPECT_FALSE(embeds_at_start(ts[3]));
  const GroupStats g = group_stats({&ts[0], &ts[1], &ts[2], &ts[3]}, {});
  EXPECT_EQ(g.embeddings, 3U);
  EXPECT_EQ(g.embeddings_at_start, 1U);
  EXPECT_EQ(g.along_drive_stopped_before, 1U);  // of the 2 along the drive
}

TEST(CampaignDraws, AreAPureFunctionOfSeedFamilyAndIndex) {
  const TraverseDraw a = draw_traverse(CampaignFamily::bumps, 5, 3);
  const TraverseDraw b = draw_traverse(CampaignFamily::bumps, 5, 3);
  const TraverseDraw c = draw_traverse(CampaignFamily::bumps, 6, 3);
  EXPECT_EQ(a.seed, b.seed);
  ASSERT_EQ(a.spec.terrain.size(), b.spec.terrain.size());
  for (std::size_t i = 0; i < a.spec.terrain.size(); ++i) {
    EXPECT_EQ(a.spec.terrain[i].x_m, b.spec.terrain[i].x_m);
    EXPECT_EQ(a.spec.terrain[i].slope_deg, b.spec.terrain[i].slope_deg);
  }
  EXPECT_NE(a.seed, c.seed);
  EXPECT_NE(a.mass_kg, c.mass_kg);
}

TEST(CampaignDraws, FamiliesShapeTheirPaths) {
  for (std::size_t k = 0; k < 4; ++k) {
    const TraverseDraw one_side = draw_traverse(CampaignFamily::one_side, 1, k);
    const auto& t = one_side.spec.terrain;
    EXPECT_TRUE(std::all_of(t.begin(), t.end(), [](const TerrainKnot& n) { return n.soil_scale == 1.0; }));
    EXPECT_LT(t.back().right_soil_factor, 1.0);
    const TraverseDraw slope = draw_traverse(CampaignFamily::slope, 1, k);
    EXPECT_GE(slope.slope_deg, 0.0);
    EXPECT_LE(slope.slope_deg, 12.0);
    EXPECT_EQ(slope.spec.terrain.back().slope_deg, slope.slope_deg);
    const TraverseDraw drawn = draw_traverse(CampaignFamily::drawn_soil, 1, k);
    ASSERT_TRUE(drawn.spec.soil_parameters);
    EXPECT_GE(drawn.spec.soil_parameters->n, 0.7);
    EXPECT_LE(drawn.spec.soil_parameters->n, 1.2);
    EXPECT_GE(draw_traverse(CampaignFamily::roll, 1, k).mass_kg, 120.0);
    EXPECT_LE(draw_traverse(CampaignFamily::roll, 1, k).mass_kg, 160.0);
  }
}

// Fields of a CSV line, quoted fields (with commas) counted once.
std::size_t csv_field_count(const std::string& line) {
  std::size_t fields = 1;
  bool quoted = false;
  for (const char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) ++fields;
  }
  return fields;
}

CampaignOptions small_campaign(unsigned threads) {
  CampaignOptions o;
  o.families = {CampaignFamily::abrupt, CampaignFamily::one_side};
  o.traverses_per_family = 1;
  o.seed = 3;
  o.path_length_m = 7.0;
  o.threads = threads;
  o.sweep_stop_mm = {30, 45};
  return o;
}

TEST(CampaignRun, SameSeedGivesTheSameFilesWhateverTheThreadCount) {
  const CampaignResult one = run_campaign(small_campaign(1));
  const CampaignResult two = run_campaign(small_campaign(2));
  EXPECT_EQ(traverses_csv(one), traverses_csv(two));
  EXPECT_EQ(traverses_json(one), traverses_json(two));
  ASSERT_EQ(one.traverses.size(), 2U);
  EXPECT_FALSE(one.traverses[0].held_out);
  EXPECT_TRUE(one.traverses[1].held_out);  // one-side is held out by default
  // The CSV: the documented header, and every row with as many fields.
  std::istringstream csv(traverses_csv(one));
  std::string line;
  std::getline(csv, line);
  std::string header;
  for (const std::string& c : traverse_csv_columns()) header += (header.empty() ? "" : ",") + c;
  EXPECT_EQ(line, header);
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(csv_field_count(line), traverse_csv_columns().size()) << line;
  }
  EXPECT_EQ(rows, 2U);
  const std::string json = traverses_json(one);
  EXPECT_NE(json.find("\"outcome\": \""), std::string::npos);
  EXPECT_EQ(std::count(json.begin(), json.end(), '{'), std::count(json.begin(), json.end(), '}'));
  EXPECT_EQ(one.traverses[0].sweep.size(), 2U);
}

int campaign(const std::vector<std::string>& args, std::string* err_text = nullptr) {
  std::ostringstream out, err;
  const int rc = run_campaign_command(args, out, err);
  if (err_text) *err_text = err.str();
  return rc;
}

TEST(CampaignCommand, RefusesBadOptionsBeforeAnyWork) {
  const std::string dir = (std::filesystem::temp_directory_path() / "sinkwatch_campaign_test_out").string();
  std::string err;
  EXPECT_EQ(campaign({"--traverses", "0", "--out", dir}, &err), exit_status(ExitCode::usage_error));
  EXPECT_NE(err.find("sinkwatch campaign: "), std::string::npos) << err;
  EXPECT_EQ(campaign({"--families", "gradual,nowhere", "--out", dir}, &err), exit_status(ExitCode::usage_error));
  EXPECT_NE(err.find("nowhere"), std::string::npos) << err;
  EXPECT_EQ(campaign({"--traverses", "1"}), exit_status(ExitCode::usage_error));  // --out is required
  EXPECT_EQ(campaign({"--levels", "-5", "--out", dir}), exit_status(ExitCode::usage_error));
  EXPECT_EQ(campaign({"--levels", "200", "--out", dir}), exit_status(ExitCode::usage_error));  // beyond the radius
  EXPECT_EQ(campaign({"--jobs", "x", "--out", dir}), exit_status(ExitCode::usage_error));
  EXPECT_EQ(campaign({"--table", "/nonexistent/table.bin", "--out", dir}, &err), exit_status(ExitCode::data_error));
  EXPECT_NE(err.find("/nonexistent/table.bin"), std::string::npos) << err;
  EXPECT_EQ(campaign({"--out", "/nonexistent/dir/report"}, &err), exit_status(ExitCode::data_error));
  EXPECT_FALSE(std::filesystem::exists(dir));  // nothing ran, nothing was created
}

}  // namespace
