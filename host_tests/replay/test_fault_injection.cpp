// Fault injection (fault_injection.hpp, docs/fault-injection.md): the spec
// grammar (every kind, every error) and the applier (each kind changes
// exactly the rows and columns it should, and records itself in the log).
#include "sinkwatch/ground/fault_injection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace sg = sinkwatch::ground;
using sg::FaultKind;
using sg::FaultTarget;

namespace {

// The message of the FaultSpecError `list` raises (fails the test if none).
std::string error_of(const std::string& list) {
  try {
    (void)sg::parse_faults(list);
  } catch (const sg::FaultSpecError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << list;
  return "";
}

// 100 rows, one per second; every measured number differs from row to row
// and from column to column, so that a held value is seen as such.
sg::TelemetryLog test_log() {
  sg::TelemetryLog log;
  log.source = "test";
  for (int i = 0; i < 100; ++i) {
    sg::TelemetryRow r;
    r.line = static_cast<std::size_t>(i) + 2;
    r.time_s = i;
    for (std::size_t w = 0; w < 6; ++w) r.current_a[w] = 0.1 * static_cast<double>(w + 1) + 0.001 * i;
    r.pitch_deg = 1.0 + 0.01 * i;
    r.roll_deg = -0.5 + 0.01 * i;
    r.rocker_deg = {0.2 + 0.01 * i, -0.2 - 0.01 * i};
    r.bogie_deg = {0.3 + 0.01 * i, -0.3 - 0.01 * i};
    r.accel_mps2 = 0.0;
    log.rows.push_back(r);
  }
  return log;
}

// Every measured cell of a row by name ("" for a missing one), and the time.
std::vector<std::pair<std::string, std::string>> cells(const sg::TelemetryRow& r) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto num = [](double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
  };
  for (std::size_t w = 0; w < 6; ++w) {
    out.emplace_back(std::string(sg::kWheelNames[w]) + "_current", r.current_missing[w] ? "" : num(r.current_a[w]));
  }
  out.emplace_back("pitch", r.attitude_missing ? "" : num(r.pitch_deg));
  out.emplace_back("roll", r.attitude_missing ? "" : num(r.roll_deg));
  const char* joints[] = {"rocker_l", "rocker_r", "bogie_l", "bogie_r"};
  const double values[] = {r.rocker_deg[0], r.rocker_deg[1], r.bogie_deg[0], r.bogie_deg[1]};
  for (int j = 0; j < 4; ++j) out.emplace_back(joints[j], r.joints_missing ? "" : num(values[j]));
  out.emplace_back("time", num(r.time_s));
  return out;
}

// The (row, column) cells that differ between the logs.
std::set<std::pair<std::size_t, std::string>> changes(const sg::TelemetryLog& a, const sg::TelemetryLog& b) {
  std::set<std::pair<std::size_t, std::string>> out;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    const auto ca = cells(a.rows[i]);
    const auto cb = cells(b.rows[i]);
    for (std::size_t k = 0; k < ca.size(); ++k) {
      if (ca[k] != cb[k]) out.emplace(i, ca[k].first);
    }
  }
  return out;
}

std::set<std::pair<std::size_t, std::string>> expected(std::size_t first, std::size_t last,
                                                       const std::vector<std::string>& columns) {
  std::set<std::pair<std::size_t, std::string>> out;
  for (std::size_t i = first; i <= last; ++i) {
    for (const std::string& c : columns) out.emplace(i, c);
  }
  return out;
}

// The log after one fault, and that fault's record.
struct Faulted {
  sg::TelemetryLog log;
  sg::AppliedFault applied;
};

Faulted inject(const std::string& spec, std::uint64_t seed = 1) {
  Faulted f{test_log(), {}};
  f.applied = sg::apply_faults(f.log, sg::parse_faults(spec), seed).at(0);
  return f;
}

}  // namespace

TEST(FaultSpec, EveryKindParses) {
  struct Case {
    const char* text;
    FaultKind kind;
    FaultTarget target;
    double start;
    std::optional<double> duration, value;
  };
  const Case cases[] = {
      {"stuck:LM_current@120s+30s", FaultKind::stuck, FaultTarget::current_lm, 120, 30, {}},
      {"zero:LF_current@5", FaultKind::zero, FaultTarget::current_lf, 5, {}, {}},
      {"dropout:LM_current@120s+5s", FaultKind::dropout, FaultTarget::current_lm, 120, 5, {}},
      {"dropout:imu@200s+5s", FaultKind::dropout, FaultTarget::imu, 200, 5, {}},
      {"dropout:joints@1.5s", FaultKind::dropout, FaultTarget::joints, 1.5, {}, {}},
      {"dropout:left@3s+1s", FaultKind::dropout, FaultTarget::left, 3, 1, {}},
      {"dropout:right@3s", FaultKind::dropout, FaultTarget::right, 3, {}, {}},
      {"spike:RR_current@130s=40", FaultKind::spike, FaultTarget::current_rr, 130, {}, 40},
      {"spike:RF_current@130s", FaultKind::spike, FaultTarget::current_rf, 130, {}, {}},
      {"bias:pitch@200s=5", FaultKind::bias, FaultTarget::pitch, 200, {}, 5},
      {"bias:roll@200s+10s=-2.5", FaultKind::bias, FaultTarget::roll, 200, 10, -2.5},
      {"noise:imu@200s+5s=3", FaultKind::noise, FaultTarget::imu, 200, 5, 3},
      {"freeze:joints@150s+60s", FaultKind::freeze, FaultTarget::joints, 150, 60, {}},
      {"stall:LM_current@10s=4", FaultKind::stall, FaultTarget::current_lm, 10, {}, 4},
      {"stall:RM_current@10s+2s", FaultKind::stall, FaultTarget::current_rm, 10, 2, {}},
      {"freewheel:LR_current@10s", FaultKind::freewheel, FaultTarget::current_lr, 10, {}, {}},
      {"repeat:clock@100s+2s", FaultKind::repeat, FaultTarget::clock, 100, 2, {}},
      {"jump:clock@100s=10", FaultKind::jump, FaultTarget::clock, 100, {}, 10},
  };
  for (const Case& c : cases) {
    const sg::FaultSpec f = sg::parse_fault(c.text);
    EXPECT_EQ(f.kind, c.kind) << c.text;
    EXPECT_EQ(f.target, c.target) << c.text;
    EXPECT_EQ(f.start_s, c.start) << c.text;
    EXPECT_EQ(f.duration_s, c.duration) << c.text;
    EXPECT_EQ(f.value, c.value) << c.text;
    // The canonical text reads back as the same spec.
    const sg::FaultSpec back = sg::parse_fault(f.text());
    EXPECT_EQ(back.text(), f.text());
    EXPECT_EQ(back.start_s, f.start_s);
  }
  EXPECT_EQ(sg::parse_fault(" stuck:LM_current@120+30 ").text(), "stuck:LM_current@120s+30s");
  EXPECT_EQ(sg::parse_fault("spike:RR_current@130.25s=40").text(), "spike:RR_current@130.25s=40");
}

TEST(FaultSpec, AListIsCommaSeparated) {
  const std::vector<sg::FaultSpec> f = sg::parse_faults("stuck:LM_current@60s,dropout:imu@200s+5s");
  ASSERT_EQ(f.size(), 2U);
  EXPECT_EQ(f[0].kind, FaultKind::stuck);
  EXPECT_EQ(f[1].target, FaultTarget::imu);
}

TEST(FaultSpec, EveryErrorNamesTheSpecAndTheProblem) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "an empty fault"},
      {"stuck:LM_current@1,,zero:LF_current@2", "an empty fault"},
      {"stuck", "expected KIND:TARGET@START"},
      {"stuck:LM_current", "fault 'stuck:LM_current': expected KIND:TARGET@START"},
      {"stuck@1:LM_current", "expected KIND:TARGET@START"},
      {"melt:LM_current@1", "fault 'melt:LM_current@1': unknown kind 'melt'; known: stuck, zero, dropout"},
      {"stuck:XX_current@1", "unknown target 'XX_current'; known: LF_current"},
      {"stuck:lm_current@1", "unknown target 'lm_current'"},
      {"stuck:LM_current@soon", "START: expected a finite number of s, got 'soon'"},
      {"stuck:LM_current@", "START: expected a finite number"},
      {"stuck:LM_current@-1s", "START must be >= 0 s, got -1 s"},
      {"stuck:LM_current@nan", "START: expected a finite number"},
      {"stuck:LM_current@1s+", "DURATION: expected a finite number"},
      {"stuck:LM_current@1s+0s", "DURATION must be > 0 s, got 0 s"},
      {"stuck:LM_current@1s+-3", "DURATION must be > 0 s"},
      {"stuck:LM_current@1s+2x", "DURATION: expected a finite number of s, got '2x'"},
      {"bias:pitch@1s=", "VALUE: expected a finite number, got ''"},
      {"bias:pitch@1s=inf", "VALUE: expected a finite number"},
      {"bias:pitch@1s=5deg", "VALUE: expected a finite number, got '5deg'"},
      {"stuck:LM_current@1s=3", "stuck takes no =VALUE"},
      {"dropout:imu@1s=3", "dropout takes no =VALUE"},
      {"repeat:clock@1s+1s=3", "repeat takes no =VALUE"},
      {"bias:pitch@1s", "bias needs =VALUE"},
      {"noise:imu@1s+5s", "noise needs =VALUE"},
      {"jump:clock@1s", "jump needs =VALUE"},
      {"noise:imu@1s+5s=0", "noise: VALUE must be > 0, got 0"},
      {"noise:imu@1s+5s=-1", "noise: VALUE must be > 0"},
      {"jump:clock@1s=-10", "jump: VALUE must be > 0"},
      {"stall:LM_current@1s=-2", "stall: VALUE must be > 0"},
      {"bias:pitch@1s=0", "bias: VALUE 0 changes nothing"},
      {"spike:LM_current@1s=0", "spike: VALUE 0 changes nothing"},
      {"spike:LM_current@1s+2s", "spike is one sample: it takes no +DURATION"},
      {"jump:clock@1s+2s=3", "jump lasts from START on: it takes no +DURATION"},
      {"zero:imu@1s", "zero does not apply to imu; its targets: LF_current, LM_current, LR_current, RF_current, "
                      "RM_current, RR_current, left, right"},
      {"dropout:pitch@1s", "dropout does not apply to pitch"},
      {"stuck:clock@1s", "stuck does not apply to clock"},
      {"repeat:imu@1s", "repeat does not apply to imu; its targets: clock"},
      {"freewheel:joints@1s", "freewheel does not apply to joints"},
      {"freeze:LM_current@1s", "freeze does not apply to LM_current"},
  };
  for (const auto& [spec, message] : cases) {
    const std::string e = error_of(spec);
    EXPECT_NE(e.find(message), std::string::npos) << spec << " -> " << e;
  }
}

TEST(FaultApply, StuckHoldsTheValueAtStartForItsWindowOnly) {
  const Faulted f = inject("stuck:LM_current@20s+10s");
  EXPECT_EQ(changes(test_log(), f.log), expected(21, 29, {"LM_current"}));  // row 20 keeps its own value
  for (std::size_t i = 20; i < 30; ++i) EXPECT_EQ(f.log.rows[i].current_a[1], test_log().rows[20].current_a[1]);
  EXPECT_EQ(f.applied.rows, 10U);
  EXPECT_EQ(f.applied.first_row, 20U);
}

TEST(FaultApply, WithoutADurationAFaultLastsToTheEnd) {
  const Faulted f = inject("zero:right@90s");
  EXPECT_EQ(changes(test_log(), f.log), expected(90, 99, {"RF_current", "RM_current", "RR_current"}));
  EXPECT_EQ(f.log.rows[99].current_a[4], 0.0);
  EXPECT_FALSE(f.log.rows[99].current_missing[4]);
}

TEST(FaultApply, DropoutMarksTheSensorMissing) {
  EXPECT_EQ(changes(test_log(), inject("dropout:LM_current@10s+5s").log), expected(10, 14, {"LM_current"}));
  EXPECT_EQ(changes(test_log(), inject("dropout:left@10s+2s").log),
            expected(10, 11, {"LF_current", "LM_current", "LR_current"}));
  const Faulted imu = inject("dropout:imu@50s+3s");
  EXPECT_EQ(changes(test_log(), imu.log), expected(50, 52, {"pitch", "roll"}));
  EXPECT_TRUE(imu.log.rows[50].attitude_missing);
  EXPECT_EQ(imu.log.rows[50].pitch_deg, 0.0);
  EXPECT_FALSE(imu.log.rows[53].attitude_missing);
  EXPECT_EQ(changes(test_log(), inject("dropout:joints@98s").log),
            expected(98, 99, {"rocker_l", "rocker_r", "bogie_l", "bogie_r"}));
}

TEST(FaultApply, SpikeIsOneSample) {
  const Faulted given = inject("spike:RR_current@30.5s=40");
  EXPECT_EQ(changes(test_log(), given.log), expected(31, 31, {"RR_current"}));  // the first row at or after START
  EXPECT_DOUBLE_EQ(given.log.rows[31].current_a[5], test_log().rows[31].current_a[5] + 40.0);
  // The default: 10 x the wheel's |current| at START, at least 1 A.
  const Faulted dflt = inject("spike:RR_current@30s");
  EXPECT_DOUBLE_EQ(dflt.applied.value, 10.0 * test_log().rows[30].current_a[5]);
  EXPECT_DOUBLE_EQ(inject("spike:LF_current@0s").applied.value, 1.0);  // 10 x 0.1 A: the 1 A floor
  const Faulted pitch = inject("spike:pitch@30s");
  EXPECT_EQ(changes(test_log(), pitch.log), expected(30, 30, {"pitch"}));
  EXPECT_DOUBLE_EQ(pitch.log.rows[30].pitch_deg, test_log().rows[30].pitch_deg + sg::kSpikeAngleDeg);
}

TEST(FaultApply, BiasIsAStepFromStartOn) {
  const Faulted f = inject("bias:pitch@40s=5");
  EXPECT_EQ(changes(test_log(), f.log), expected(40, 99, {"pitch"}));
  EXPECT_DOUBLE_EQ(f.log.rows[70].pitch_deg, test_log().rows[70].pitch_deg + 5.0);
  EXPECT_EQ(changes(test_log(), inject("bias:imu@40s+1s=-1").log), expected(40, 40, {"pitch", "roll"}));
}

TEST(FaultApply, NoiseIsSeededAndOnlyInItsWindow) {
  const Faulted a = inject("noise:imu@20s+5s=3", 7);
  EXPECT_EQ(changes(test_log(), a.log), expected(20, 24, {"pitch", "roll"}));
  EXPECT_EQ(changes(a.log, inject("noise:imu@20s+5s=3", 7).log).size(), 0U);   // same seed, same log
  EXPECT_EQ(changes(a.log, inject("noise:imu@20s+5s=3", 8).log).size(), 10U);  // another seed, other draws
  double sum2 = 0.0;
  Faulted big = inject("noise:roll@0s=3", 7);
  for (std::size_t i = 0; i < 100; ++i) sum2 += std::pow(big.log.rows[i].roll_deg - test_log().rows[i].roll_deg, 2);
  EXPECT_NEAR(std::sqrt(sum2 / 100.0), 3.0, 0.8);
}

TEST(FaultApply, FreezeHoldsTheJointAngles) {
  const Faulted f = inject("freeze:joints@60s+20s");
  EXPECT_EQ(changes(test_log(), f.log), expected(61, 79, {"rocker_l", "rocker_r", "bogie_l", "bogie_r"}));
  EXPECT_EQ(f.log.rows[79].bogie_deg, test_log().rows[60].bogie_deg);
}

TEST(FaultApply, StallAndFreewheelForceTheCurrent) {
  const Faulted stall = inject("stall:LM_current@10s+5s");
  EXPECT_EQ(changes(test_log(), stall.log), expected(10, 14, {"LM_current"}));
  // The default: 3 x the log's highest |current| (RR at the last row, 0.699 A).
  EXPECT_DOUBLE_EQ(stall.applied.value, 3.0 * test_log().rows[99].current_a[5]);
  EXPECT_DOUBLE_EQ(stall.log.rows[12].current_a[1], stall.applied.value);
  EXPECT_DOUBLE_EQ(inject("stall:LM_current@10s=4").log.rows[12].current_a[1], 4.0);
  sg::TelemetryLog reverse = test_log();
  for (sg::TelemetryRow& r : reverse.rows) r.reverse = true;
  sg::apply_faults(reverse, sg::parse_faults("stall:LM_current@10s=4"), 1);
  EXPECT_DOUBLE_EQ(reverse.rows[12].current_a[1], -4.0);  // a motor stalls in the commanded direction
  const Faulted fw = inject("freewheel:RF_current@50s");
  EXPECT_EQ(changes(test_log(), fw.log), expected(50, 99, {"RF_current"}));
  for (std::size_t i = 50; i < 100; ++i) EXPECT_NEAR(fw.log.rows[i].current_a[3], 0.02, 0.01);
}

TEST(FaultApply, RepeatAndJumpMoveOnlyTheClock) {
  const Faulted rep = inject("repeat:clock@40s+3s");
  EXPECT_EQ(changes(test_log(), rep.log), expected(40, 42, {"time"}));
  for (std::size_t i = 40; i < 43; ++i) EXPECT_EQ(rep.log.rows[i].time_s, 39.0);
  EXPECT_EQ(rep.log.rows[43].time_s, 43.0);
  const Faulted jump = inject("jump:clock@40s=10");
  EXPECT_EQ(changes(test_log(), jump.log), expected(40, 99, {"time"}));
  EXPECT_EQ(jump.log.rows[40].time_s, 50.0);
  EXPECT_EQ(jump.log.rows[99].time_s, 109.0);
}

TEST(FaultApply, AWindowOutsideTheLogChangesNothingAndSaysSo) {
  const Faulted f = inject("stuck:LM_current@500s");
  EXPECT_EQ(f.applied.rows, 0U);
  EXPECT_TRUE(changes(test_log(), f.log).empty());
  EXPECT_NE(f.log.comments.back().find("no rows"), std::string::npos) << f.log.comments.back();
}

TEST(FaultApply, TheLogRecordsWhatWasInjectedAndReadsBack) {
  sg::TelemetryLog log = test_log();
  sg::apply_faults(log, sg::parse_faults("dropout:imu@10s+2s,spike:RR_current@20s=40,stall:LM_current@30s+1s"), 42);
  EXPECT_EQ(log.metadata.at("injected_faults"),
            "dropout:imu@10s+2s,spike:RR_current@20s=40,stall:LM_current@30s+1s");
  EXPECT_EQ(log.metadata.at("fault_seed"), "42");
  ASSERT_EQ(log.comments.size(), 3U);
  EXPECT_NE(log.comments[0].find("injected fault dropout:imu@10s+2s: rows 11-12 of 100 (10.000-11.000 s)"),
            std::string::npos)
      << log.comments[0];
  EXPECT_NE(log.comments[2].find("(value 2.097)"), std::string::npos) << log.comments[2];
  std::ostringstream out;
  sg::write_telemetry_csv(out, log);
  const sg::TelemetryLog back = sg::parse_telemetry_text(out.str(), "back");
  EXPECT_EQ(back.metadata.at("injected_faults"), log.metadata.at("injected_faults"));
  EXPECT_EQ(back.comments, log.comments);
  EXPECT_TRUE(back.rows[10].attitude_missing);
  EXPECT_FALSE(back.rows[12].attitude_missing);
}
