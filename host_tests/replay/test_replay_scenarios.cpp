// The shipped scenarios replayed through the flight code: the embedding
// scenario must stop the rover before the simulated embedding, the nominal
// traverse must never stop it. The generator's physics and determinism.
#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_command.hpp"
#include "sinkwatch/ground/replay_report.hpp"
#include "sinkwatch/ground/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fl = sinkwatch::flight;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

sg::TelemetryLog embedded(const std::string& name) {
  const std::string& text = sg::embedded_scenario_text(name);
  EXPECT_FALSE(text.empty()) << "no embedded scenario " << name;
  return sg::parse_telemetry_text(text, name);
}

/// The default table, or (`traction_check` false) the default without its
/// section 8, so that a test sees the wheel monitors' own rules.
sg::ReplayResult replay(const sg::TelemetryLog& log, bool traction_check = true) {
  sg::ReplayConfig config;
  config.gravity_mps2 = sg::log_gravity(log);
  if (!traction_check) config.table.traction = fl::TractionParams{};
  return sg::run_replay(log, config);
}

/// The embedding scenario generated with the wheels' own rules in the loop
/// (the default table without section 8): the shipped log follows the
/// default table, whose motion-resistance check stops the rover metres
/// before any wheel reaches the sinkage level, so the wheels' stop and an
/// escape from a sunk rover need a log of their own (generated once).
const sg::Scenario& wheels_alone_embedding() {
  static const sg::Scenario s = [] {
    sg::ScenarioSpec spec = sg::embedding_scenario();
    spec.flight.table.traction = fl::TractionParams{};
    return sg::generate_scenario(spec, "test");
  }();
  return s;
}

}  // namespace

TEST(ReplayScenarios, EmbeddedCopiesAreTheShippedFiles) {
  for (const std::string name : {"embedding", "nominal"}) {
    const std::string shipped = read_file(std::string(SINKWATCH_DATA_DIR) + "/telemetry/" + name + ".csv");
    ASSERT_FALSE(shipped.empty()) << name;
    EXPECT_EQ(sg::embedded_scenario_text(name), shipped) << name << ": rebuild after regenerating the data";
  }
}

// With section 8 (the default table) the motion-resistance check stops the
// rover first, at least the 2 m the issue asks for ahead of the embedding
// (docs/traction.md), before any wheel reaches the sinkage level; the
// escape then finds the wheels free.
TEST(ReplayScenarios, DefaultTractionCheckStopsTwoMetresBeforeTheEmbedding) {
  const sg::TelemetryLog log = embedded("embedding");
  const sg::ReplayResult r = replay(log);
  ASSERT_TRUE(r.first_stop.has_value()) << "the flight code never stopped the rover";
  const sg::CycleRecord& stop = r.cycles[*r.first_stop];
  EXPECT_TRUE(stop.traction_stop_tripped) << "the first stop is not the motion-resistance check's";
  EXPECT_TRUE(stop.new_events.empty()) << "a wheel tripped with it";
  EXPECT_EQ(stop.traction_state, fl::TractionState::stop);
  ASSERT_TRUE(stop.resistance_ahead.has_value());
  EXPECT_GE(*stop.resistance_ahead, 0.38);
  const std::optional<sg::Lead> lead = sg::stop_lead(log, r);
  ASSERT_TRUE(lead.has_value());
  EXPECT_GE(lead->distance_m, 2.0) << "stopped at x = " << stop.x_m << " m";
  ASSERT_TRUE(r.escape_end.has_value());
  EXPECT_EQ(r.cycles[*r.escape_end].escape_state, fl::EscapeState::freed);
  // The shipped log was made with this table in the loop: its escape is the
  // one the sequencer commands.
  EXPECT_EQ(r.direction_mismatches, 0U) << "the log's wheel directions differ from the sequencer's commands";
}

// The rover's stop record (flight/stop_record.hpp) on the shipped traverse:
// written on the stop's cycle, naming the motion-resistance check, with the
// largest of the wheels' medians of their last nine estimates, worked out
// here from the replayed cycles.
TEST(ReplayScenarios, StopRecordHoldsTheDeepestWheelsRecentMedianAtTheStop) {
  const sg::TelemetryLog log = embedded("embedding");
  const sg::ReplayResult r = replay(log);
  ASSERT_TRUE(r.first_stop.has_value());
  const sg::CycleRecord& stop = r.cycles[*r.first_stop];
  ASSERT_TRUE(stop.stop_decision.has_value()) << "no stop record on the stop's cycle";
  EXPECT_EQ(stop.stop_decision->reason, fl::StopReason::traction);
  EXPECT_NEAR(stop.stop_decision->time_s, stop.time_s, 1e-9);
  std::optional<double> deepest;
  std::size_t deepest_wheel = 0;
  for (std::size_t w = 0; w < stop.wheels.size(); ++w) {
    std::vector<double> last;
    for (std::size_t i = *r.first_stop + 1; i-- > 0 && last.size() < fl::kStopRecordSamples;) {
      if (r.cycles[i].wheels[w].estimate_valid) last.push_back(r.cycles[i].wheels[w].sinkage_m);
    }
    if (last.empty()) continue;
    std::sort(last.begin(), last.end());
    const double median = last[(last.size() - 1) / 2];
    if (!deepest || median > *deepest) {
      deepest = median;
      deepest_wheel = w;
    }
  }
  ASSERT_TRUE(deepest.has_value());
  ASSERT_TRUE(stop.stop_decision->recent_sinkage_m.has_value());
  EXPECT_EQ(*stop.stop_decision->recent_sinkage_m, *deepest);
  EXPECT_EQ(stop.stop_decision->deepest_wheel, deepest_wheel);
  EXPECT_EQ(stop.stop_decision->samples, fl::kStopRecordSamples);
  for (std::size_t i = 0; i < *r.first_stop; ++i) {
    EXPECT_FALSE(r.cycles[i].stop_decision.has_value()) << "a record before the stop, cycle " << i;
  }
}

// Without section 8 the default table's sinkage level stops the rover (the
// paper's rule alone; docs/scenarios.md finding 1).
TEST(ReplayScenarios, SinkageLevelAloneStopsBeforeTheSimulatedEmbedding) {
  const sg::TelemetryLog& log = wheels_alone_embedding().log;
  const std::optional<sg::EmbeddingTruth> embedding = sg::log_embedding(log);
  ASSERT_TRUE(embedding.has_value()) << "the embedding scenario must record where the rover embeds";
  const sg::ReplayResult r = replay(log, false);
  ASSERT_TRUE(r.first_stop.has_value()) << "the flight code never stopped the rover";
  const sg::CycleRecord& stop = r.cycles[*r.first_stop];
  EXPECT_EQ(stop.decision, fl::RoverDecision::stop_and_replan);
  const std::optional<sg::Lead> lead = sg::stop_lead(log, r);
  ASSERT_TRUE(lead.has_value());
  EXPECT_GT(lead->distance_m, 0.0) << "stopped at x = " << stop.x_m << " m, embedding at " << embedding->x_m;
  EXPECT_GT(lead->time_s, 0.0);
  // The stop comes from the sinkage monitor with an event record, not from a
  // telemetry fault: every cycle up to the stop was usable.
  ASSERT_FALSE(r.events.empty());
  EXPECT_EQ(r.events.front().reason, fl::StopReason::sinkage);
  for (std::size_t i = 0; i <= *r.first_stop; ++i) {
    EXPECT_EQ(r.cycles[i].status, fl::RoverStepStatus::ok) << "cycle " << i;
  }
  // At the stop the simulated rover is still driving, not already stuck
  // (its slip has not run away): the stop is not a late one in disguise.
  const sg::TelemetryRow& at_stop = log.rows[stop.row];
  EXPECT_EQ(at_stop.phase, "drive");
  ASSERT_TRUE(at_stop.true_slip.has_value());
  EXPECT_LT(*at_stop.true_slip, 0.5);
}

// The escape of a sunk rover: without section 8 the sinkage stop comes with
// the wheels sunk beyond the freed level.
TEST(ReplayScenarios, EscapeFollowsTheSequencerAndFreesTheRover) {
  const sg::ReplayResult r = replay(wheels_alone_embedding().log, false);
  ASSERT_TRUE(r.first_stop.has_value());
  EXPECT_TRUE(r.cycles[*r.first_stop].escape_started);
  EXPECT_EQ(r.direction_mismatches, 0U) << "the log's wheel directions differ from the sequencer's commands";
  ASSERT_TRUE(r.escape_end.has_value());
  const sg::CycleRecord& end = r.cycles[*r.escape_end];
  EXPECT_EQ(end.escape_state, fl::EscapeState::freed);
  EXPECT_GE(end.escape_cycles, 1U) << "freed without a single reversal";
  // The escape saw both directions.
  bool reverse = false;
  for (const sg::CycleRecord& c : r.cycles) reverse = reverse || c.escape_state == fl::EscapeState::reverse;
  EXPECT_TRUE(reverse);
}

TEST(ReplayScenarios, NominalTraverseNeverStops) {
  const sg::TelemetryLog log = embedded("nominal");
  const sg::ReplayResult r = replay(log);
  EXPECT_FALSE(r.first_stop.has_value()) << "false stop at " << r.cycles[r.first_stop.value_or(0)].time_s << " s";
  EXPECT_TRUE(r.events.empty());
  EXPECT_FALSE(sg::log_embedding(log).has_value());
  EXPECT_GT(r.distance_m, 19.0);
  for (const sg::CycleRecord& c : r.cycles) EXPECT_EQ(c.status, fl::RoverStepStatus::ok);
}

// docs/scenarios.md findings 2 and 3: on the steep soft flank the default
// table's sinkage level gives no lead (finding 2; closed by section 8, above), but once the wheels spin at
// or above the high-slip level the drawbar pull is only assumed (DP_max), so
// the rover must stop on slip and no wheel may go back to NOMINAL while it
// is stuck. Before the slip stop evidence the six wheels cleared to NOMINAL
// 1 s after the embedding and the rover drove on.
// Finding 2 closed by the motion-resistance check: the default table now
// stops the rover on the steep soft flank at least 1 m before it embeds.
TEST(ReplayScenarios, SteepRippleTractionCheckStopsAheadOfTheEmbedding) {
  const sg::Scenario s = sg::generate_scenario(sg::steep_ripple_scenario(), "test");
  ASSERT_TRUE(s.truth.embedded);
  const sg::ReplayResult r = replay(s.log);
  ASSERT_TRUE(r.first_stop.has_value()) << "the rover was never stopped";
  const sg::CycleRecord& stop = r.cycles[*r.first_stop];
  EXPECT_TRUE(stop.traction_stop_tripped);
  EXPECT_LE(stop.x_m, s.truth.embed_x_m - 1.0) << "embedding at x = " << s.truth.embed_x_m << " m";
}

TEST(ReplayScenarios, SteepRippleStuckRoverStopsOnSlipAndStaysStopped) {
  // The wheels' own rules, without section 8, in the generator's closed loop
  // too (with it the generated rover stops ahead and never gets stuck).
  sg::ScenarioSpec spec = sg::steep_ripple_scenario();
  spec.flight.table.traction = fl::TractionParams{};
  const sg::Scenario s = sg::generate_scenario(spec, "test");
  ASSERT_TRUE(s.truth.embedded);
  const sg::ReplayResult r = replay(s.log, false);
  ASSERT_TRUE(r.first_stop.has_value()) << "the stuck rover was never stopped";
  const sg::CycleRecord& stop = r.cycles[*r.first_stop];
  // Late, not early: finding 2 stands (no lead on this flank).
  EXPECT_GE(stop.time_s, s.truth.embed_time_s - 1.0);
  EXPECT_LE(stop.time_s, s.truth.embed_time_s + 2.0) << "embedding at " << s.truth.embed_time_s << " s";
  ASSERT_FALSE(r.events.empty());
  EXPECT_EQ(r.events.front().reason, fl::StopReason::slip);
  for (const sg::CycleRecord& c : r.cycles) {
    if (c.time_s >= s.truth.embed_time_s) {
      EXPECT_NE(c.worst_state(), fl::WheelState::nominal) << "a wheel back to NOMINAL while stuck at " << c.time_s;
    }
  }
}

TEST(ReplayScenarios, OnboardLoopRejectsValuesBeyondTheFlightFormats) {
  sg::OnboardLoop loop;
  sg::TelemetryRow row;
  row.line = 17;
  row.current_a[2] = 5000.0;  // beyond Q11.20
  row.accel_mps2 = 0.0;
  try {
    loop.step(row, "log.csv", 0.0);
    FAIL() << "no error";
  } catch (const sg::TelemetryError& e) {
    EXPECT_EQ(e.line(), 17U);
    EXPECT_NE(std::string(e.what()).find("log.csv:17:"), std::string::npos);
  }
}

// A short path: firm, then so soft that the rover cannot carry itself.
sg::ScenarioSpec short_spec(double soft_scale) {
  sg::ScenarioSpec s = sg::embedding_scenario();
  s.name = "short";
  s.terrain = {{0.0, 1.0, 0.0}, {0.3, 1.0, 0.0}, {0.9, soft_scale, 0.0}};
  s.end_x_m = 1.2;
  s.max_time_s = 80.0;
  s.stuck_tail_s = 2.0;
  s.settle_s = 1.0;
  return s;
}

TEST(ScenarioGenerator, FirmGroundDoesNotEmbedAndSlipIsSmall) {
  const sg::Scenario s = sg::generate_scenario(short_spec(1.0), "test");
  EXPECT_FALSE(s.truth.embedded);
  EXPECT_FALSE(s.truth.stop_time_s.has_value());
  for (const sg::TelemetryRow& r : s.log.rows) {
    ASSERT_TRUE(r.true_slip.has_value());
    EXPECT_LT(*r.true_slip, 0.2) << "t = " << r.time_s;
  }
  EXPECT_GE(*s.log.rows.back().x_m, 1.2);
}

TEST(ScenarioGenerator, VerySoftSoilEmbedsWhereNetTractionRunsOut) {
  const sg::Scenario s = sg::generate_scenario(short_spec(0.005), "test");
  ASSERT_TRUE(s.truth.embedded);
  EXPECT_GT(s.truth.embed_x_m, 0.3);
  EXPECT_LT(s.truth.embed_x_m, 0.9);
  EXPECT_FALSE(s.truth.embed_reason.empty());
  EXPECT_EQ(s.log.metadata.at("embedding_x_m").empty(), false);
}

TEST(ScenarioGenerator, SameSpecSameRows) {
  sg::ScenarioSpec spec = short_spec(0.3);
  spec.end_x_m = 0.4;
  std::ostringstream a;
  std::ostringstream b;
  sg::write_telemetry_csv(a, sg::generate_scenario(spec, "test").log);
  sg::write_telemetry_csv(b, sg::generate_scenario(spec, "test").log);
  EXPECT_EQ(a.str(), b.str());
  sg::ScenarioSpec other = spec;
  other.seed = spec.seed + 1;
  std::ostringstream c;
  sg::write_telemetry_csv(c, sg::generate_scenario(other, "test").log);
  EXPECT_NE(a.str(), c.str()) << "the seed does not reach the noise";
}
