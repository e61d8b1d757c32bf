// `sinkwatch replay --inject`: faults injected into the embedded default,
// what the flight code's sensor health reports of them (the report's "Sensor
// health" section and the CSV's health columns), and the option's errors.
#include "sinkwatch/ground/replay_command.hpp"

#include "sinkwatch/flight/param_table.hpp"

#include <gtest/gtest.h>

#include "replay_command_run.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fs = std::filesystem;

namespace {

using sinkwatch::ground::test::CommandRun;
using sinkwatch::ground::test::run;

// The embedded default's control period.
constexpr double kCycleS = 0.2;

// The time in "<channel> ... <health> at T s" of the report's Sensor health
// section; -1 when the channel never reported that health.
double first_report_s(const std::string& report, const std::string& channel, const std::string& health) {
  const std::size_t section = report.find("\nSensor health\n");
  if (section == std::string::npos) return -1.0;
  const std::size_t line = report.find("\n  " + channel + " ", section);
  if (line == std::string::npos) return -1.0;
  const std::size_t end = report.find('\n', line + 1);
  const std::size_t at = report.find(health + " at ", line);
  if (at == std::string::npos || at > end) return -1.0;
  return std::atof(report.c_str() + at + health.size() + 4);
}

/// The clean run's decision line up to its time ("  decision   STOP AND
/// RE-PLAN at 231.6 s"): where a fault that changes nothing must stop too.
std::string clean_decision() {
  const CommandRun clean = run({});
  const std::size_t at = clean.out.find("  decision   STOP AND RE-PLAN at ");
  if (at == std::string::npos) return "no decision line in the clean run";
  return clean.out.substr(at, clean.out.find(" s", at + 33) + 2 - at);
}

}  // namespace

TEST(ReplayFaults, TheCleanDefaultHasEveryChannelOk) {
  const CommandRun r = run({});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\nSensor health\n  channels   every channel ok throughout\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  blind      no wheel was ever blind"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  degraded   never"), std::string::npos) << r.out;
}

TEST(ReplayFaults, AStuckCurrentIsNamedWithinStuckCyclesOfItsStart) {
  const CommandRun r = run({"--inject", "stuck:LM_current@60s"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  injected   stuck:LM_current@60s: rows 301-1228 of 1228"), std::string::npos) << r.out;
  const double stuck_cycles = sinkwatch::flight::default_parameter_table().health.stuck_cycles;
  const double t = first_report_s(r.out, "LM_current", "stuck");
  EXPECT_GE(t, 60.0) << r.out;
  EXPECT_LE(t, 60.0 + (stuck_cycles + 1) * kCycleS) << r.out;
  // Only the faulty channel is named.
  EXPECT_NE(r.out.find("  channels   the others ok throughout"), std::string::npos) << r.out;
  EXPECT_LT(first_report_s(r.out, "LF_current", "stuck"), 0.0);
}

TEST(ReplayFaults, DropoutsAreReportedMissingAtOnce) {
  const CommandRun imu = run({"--inject", "dropout:imu@200s+5s"});
  ASSERT_EQ(imu.code, 0) << imu.err;
  EXPECT_DOUBLE_EQ(first_report_s(imu.out, "imu", "missing"), 200.0) << imu.out;
  const CommandRun side = run({"--inject", "dropout:left@100s+1s"});
  ASSERT_EQ(side.code, 0) << side.err;
  for (const char* ch : {"LF_current", "LM_current", "LR_current"}) {
    EXPECT_DOUBLE_EQ(first_report_s(side.out, ch, "missing"), 100.0) << ch << side.out;
  }
  EXPECT_LT(first_report_s(side.out, "RF_current", "missing"), 0.0);
}

TEST(ReplayFaults, ASpikeIsOneSampleOfOneChannel) {
  const CommandRun r = run({"--inject", "spike:RR_current@130s=40"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_DOUBLE_EQ(first_report_s(r.out, "RR_current", "spike"), 130.0) << r.out;
  // A single bad sample must not stop the rover earlier than the clean run.
  EXPECT_NE(r.out.find(clean_decision()), std::string::npos) << r.out;
}

TEST(ReplayFaults, RepeatedTimeStampsAreTheClocksFault) {
  const CommandRun r = run({"--inject", "repeat:clock@100s+4s"});
  ASSERT_EQ(r.code, 0) << r.err;
  // Reported at the repeated stamp itself (99.8 s, the last one before the
  // fault), within stuck_cycles repeats.
  const double stuck_cycles = sinkwatch::flight::default_parameter_table().health.stuck_cycles;
  const double t = first_report_s(r.out, "clock", "stuck");
  EXPECT_GE(t, 100.0 - kCycleS) << r.out;
  EXPECT_LE(t, 100.0 + (stuck_cycles + 1) * kCycleS) << r.out;
}

TEST(ReplayFaults, CsvHasEachChannelsHealthAndTheBlindWheels) {
  const fs::path dir = fs::temp_directory_path() / "sinkwatch_replay_test_faults_csv";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path csv = dir / "series.csv";
  const CommandRun r = run({"--inject", "stuck:LM_current@60s", "--csv", csv.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find(",true_sinkage_mm,health_LF_current,health_LM_current,health_LR_current,health_RF_current,"
                        "health_RM_current,health_RR_current,health_imu,health_joints,health_clock,wheels_blind,"
                        "degraded"),
            std::string::npos)
      << header;
  std::string line;
  std::size_t stuck_rows = 0;
  while (std::getline(in, line)) {
    if (line.find(",ok,stuck,ok,ok,ok,ok,ok,ok,ok,1,") != std::string::npos) ++stuck_rows;
  }
  EXPECT_GT(stuck_rows, 100U);
}

TEST(ReplayFaults, BadSpecsAreUsageErrorsNamingTheSpec) {
  const CommandRun bad = run({"--inject", "stuck:LM_current@60s,melt:LM_current@1s"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("sinkwatch replay: "), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("fault 'melt:LM_current@1s': unknown kind 'melt'"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("--help"), std::string::npos) << bad.err;
  EXPECT_EQ(run({"--inject", ""}).code, 2);
  EXPECT_EQ(run({"--inject", "spike:LM_current@1s+2s"}).code, 2);
  EXPECT_EQ(run({"--inject-seed", "3"}).code, 2) << "--inject-seed needs --inject";
  EXPECT_EQ(run({"--inject", "noise:imu@1s+2s=1", "--inject-seed", "-3"}).code, 2);
}

TEST(ReplayFaults, AFaultOutsideTheLogIsANoteNotAnError) {
  const CommandRun r = run({"--inject", "stuck:LM_current@900s"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: fault 'stuck:LM_current@900s' changes no row"), std::string::npos) << r.err;
  EXPECT_TRUE(run({"-q", "--inject", "stuck:LM_current@900s"}).err.empty());
}

TEST(ReplayFaults, TheSameSeedGivesTheSameReport) {
  const std::vector<std::string> args{"--inject", "noise:imu@150s+5s=3,freewheel:RM_current@200s", "--inject-seed", "5"};
  EXPECT_EQ(run(args).out, run(args).out);
}

TEST(ReplayFaults, TheContinuePolicyDrivesOnABlindWheelThatTheStopPolicyStopsFor) {
  // A 5 s LM dropout: under the default stop policy the rover stops 2 s in
  // (invalid_to_stop samples); under continue-degraded it drives on blind
  // and stops where the clean run does.
  ASSERT_NE(clean_decision().find("STOP AND RE-PLAN at 2"), std::string::npos);  // after the dropout
  const CommandRun stop = run({"--inject", "dropout:LM_current@120s+5s"});
  ASSERT_EQ(stop.code, 0) << stop.err;
  EXPECT_NE(stop.out.find("  decision   STOP AND RE-PLAN at 121.8 s"), std::string::npos) << stop.out;
  const CommandRun go = run({"--inject", "dropout:LM_current@120s+5s", "--loss-policy", "continue-degraded"});
  ASSERT_EQ(go.code, 0) << go.err;
  EXPECT_NE(go.out.find(clean_decision()), std::string::npos) << go.out;
  EXPECT_EQ(go.out.find("  degraded   never"), std::string::npos) << go.out;
  const CommandRun bad = run({"--loss-policy", "carry-on"});
  EXPECT_NE(bad.code, 0);
}
