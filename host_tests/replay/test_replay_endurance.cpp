// Endurance (issue 18): the flight code over a mission's length and across the
// on-board clock's wrap (4294967.295 s -> 0), through the replay's OnboardLoop.
//
// The long log is the shipped nominal drive tiled with its time continued
// (endurance_log.hpp). The full 24 h at 5 Hz (432,000 cycles) runs in
// bench_replay_endurance (2 s in the default build); this test runs 50,000
// cycles (2.8 h) so that the sanitizer build stays quick.
//
// "In pieces": OnboardLoop has no state to save and restore, so a piece is a
// fresh loop. The pieces are the tiles, each the shipped log replayed alone
// by a new OnboardLoop at its own time (0 ... 444.4 s); a tile starts and
// ends with the rover standing, so nothing the long run carries from one
// tile into the next may change a decision. The long run must decide (and
// compute) in every cycle exactly what the piece does in its cycle.
#include "endurance_log.hpp"

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_command.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace sg = sinkwatch::ground;
namespace se = sinkwatch::ground::endurance;
namespace fl = sinkwatch::flight;

namespace {

sg::TelemetryLog embedded(const std::string& name) {
  return sg::parse_telemetry_text(sg::embedded_scenario_text(name), name);
}

sg::ReplayConfig config_for(const sg::TelemetryLog& log) {
  sg::ReplayConfig config;
  config.gravity_mps2 = sg::log_gravity(log);
  return config;
}

/// Every cycle of `log` (tiled from offset_ms) through one fresh loop.
std::vector<sg::CycleRecord> replay_records(const sg::TelemetryLog& base, std::uint64_t offset_ms,
                                            std::size_t cycles) {
  const se::TiledLog log(base, offset_ms);
  sg::OnboardLoop loop(config_for(base));
  std::vector<sg::CycleRecord> out;
  out.reserve(cycles);
  for (std::size_t i = 0; i < cycles; ++i) out.push_back(loop.step(log.row(i), base.source, 0.0));
  return out;
}

/// The shipped log alone, as the replay runs it: one piece.
std::vector<std::uint64_t> piece_fingerprints(const sg::TelemetryLog& base) {
  const sg::ReplayResult r = sg::run_replay(base, config_for(base));
  std::vector<std::uint64_t> fp;
  for (const sg::CycleRecord& c : r.cycles) fp.push_back(se::fingerprint(c));
  return fp;
}

constexpr std::size_t kLongCycles = 50000;  // 2.8 h at 5 Hz; 432,000 in the benchmark

}  // namespace

TEST(ReplayEndurance, LongDriveDecidesAsTheLogInPieces) {
  const sg::TelemetryLog base = embedded("nominal");
  const std::vector<std::uint64_t> piece = piece_fingerprints(base);
  ASSERT_EQ(piece.size(), base.rows.size());
  const se::TiledLog log(base, 0U);
  sg::OnboardLoop loop(config_for(base));
  std::size_t mismatches = 0;
  std::size_t not_ok = 0;
  std::size_t stops = 0;
  std::size_t not_finite = 0;
  for (std::size_t i = 0; i < kLongCycles; ++i) {
    const sg::CycleRecord c = loop.step(log.row(i), base.source, 0.0);
    if (c.status != fl::RoverStepStatus::ok) ++not_ok;
    if (c.decision != fl::RoverDecision::continue_drive || c.escape_active) ++stops;
    if (!se::all_finite(c)) ++not_finite;
    if (se::fingerprint(c) != piece[i % piece.size()]) {
      if (mismatches++ < 5) ADD_FAILURE() << "cycle " << i << " (tile " << i / piece.size() << ", row "
                                          << i % piece.size() << ") differs from the piece";
    }
  }
  EXPECT_EQ(mismatches, 0U);
  EXPECT_EQ(not_ok, 0U) << "cycles whose status is not ok (the shipped drive has none)";
  EXPECT_EQ(stops, 0U) << "an ordinary drive must never stop the rover";
  EXPECT_EQ(not_finite, 0U);
  // The run reached beyond 2.7 h of on-board time.
  EXPECT_GT(log.row(kLongCycles - 1).time_s, 9999.0);
}

TEST(ReplayEndurance, LongDriveAcrossTheClockWrapDecidesAsWithoutIt) {
  const sg::TelemetryLog base = embedded("nominal");
  const std::vector<std::uint64_t> piece = piece_fingerprints(base);
  // Started 5,000 s before 2^32 ms: the clock wraps 25,000 cycles in, mid-drive.
  const std::uint64_t offset_ms = se::kClockModulusMs - 5000000U;
  const se::TiledLog log(base, offset_ms);
  sg::OnboardLoop loop(config_for(base));
  std::size_t mismatches = 0;
  std::size_t wraps = 0;
  double previous_s = -1.0;
  for (std::size_t i = 0; i < kLongCycles; ++i) {
    const sg::TelemetryRow row = log.row(i);
    if (row.time_s < previous_s) ++wraps;
    previous_s = row.time_s;
    const sg::CycleRecord c = loop.step(row, base.source, 0.0);
    if (se::fingerprint(c) != piece[i % piece.size()] && mismatches++ < 5) {
      ADD_FAILURE() << "cycle " << i << " at " << row.time_s << " s differs from the unwrapped drive";
    }
  }
  EXPECT_EQ(mismatches, 0U);
  EXPECT_EQ(wraps, 1U);
}

// The embedding scenario stops the rover and runs the escape sequencer: the
// clock wraps at each of many rows (around the stop, at every change of the
// escape's state, and across the drive), landing on 0 or on 4294967.295 s.
// Every cycle must decide as in the unshifted replay, and each event record's
// time must be the unshifted one plus the offset, modulo 2^32 ms.
TEST(ReplayEndurance, StopAndEscapeAcrossTheClockWrap) {
  const sg::TelemetryLog base = embedded("embedding");
  const std::size_t n = base.rows.size();
  const std::vector<sg::CycleRecord> plain = replay_records(base, 0U, n);
  std::size_t first_stop = n;
  std::set<std::size_t> wrap_rows;
  for (std::size_t i = 0; i < n; ++i) {
    if (plain[i].decision == fl::RoverDecision::stop_and_replan && first_stop == n) first_stop = i;
    if (i > 0 && (plain[i].escape_state != plain[i - 1].escape_state ||
                  plain[i].escape_cycles != plain[i - 1].escape_cycles)) {
      wrap_rows.insert(i);
    }
    if (i % 211 == 1) wrap_rows.insert(i);
  }
  ASSERT_LT(first_stop, n) << "the embedding scenario must stop the rover";
  ASSERT_GE(wrap_rows.size(), 5U) << "the escape must change state in the log";
  for (std::size_t k = first_stop > 20 ? first_stop - 20 : 1; k <= first_stop + 2 && k < n; ++k) wrap_rows.insert(k);

  EXPECT_EQ(plain.back().escape_state, fl::EscapeState::freed);
  RecordProperty("wrap_rows", static_cast<int>(wrap_rows.size()));
  const se::TiledLog unshifted(base, 0U);
  for (const std::size_t j : wrap_rows) {
    for (const std::uint64_t before : {0U, 1U}) {
      // Row j at 0 s (before = 0) or at 4294967.295 s (before = 1).
      const std::uint64_t offset_ms = se::kClockModulusMs - unshifted.unwrapped_ms(j) - before;
      const std::vector<sg::CycleRecord> shifted = replay_records(base, offset_ms, n);
      std::size_t mismatches = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (se::fingerprint(shifted[i]) != se::fingerprint(plain[i]) && mismatches++ < 3) {
          ADD_FAILURE() << "wrap at row " << j << (before ? " (4294967.295 s)" : " (0 s)") << ": cycle " << i
                        << " differs";
        }
        ASSERT_EQ(shifted[i].new_events.size(), plain[i].new_events.size());
        for (std::size_t e = 0; e < plain[i].new_events.size(); ++e) {
          const auto ms = [](double s) { return static_cast<std::uint64_t>(std::llround(s * 1000.0)); };
          EXPECT_EQ(ms(shifted[i].new_events[e].time_s), (ms(plain[i].new_events[e].time_s) + offset_ms) %
                                                              se::kClockModulusMs)
              << "wrap at row " << j << ", cycle " << i;
        }
      }
      EXPECT_EQ(mismatches, 0U) << "wrap at row " << j;
    }
  }
}

TEST(ReplayEndurance, TimeOutsideTheOnboardClockIsRefused) {
  const sg::TelemetryLog base = embedded("nominal");
  sg::OnboardLoop loop(config_for(base));
  sg::TelemetryRow row = base.rows.at(5);
  row.time_s = 4294967.295;
  EXPECT_NO_THROW(loop.step(row, "mem", 0.0));
  for (const double t : {4294967.296, 5e9, -0.001, std::nan("")}) {
    row.time_s = t;
    EXPECT_THROW(loop.step(row, "mem", 0.0), sg::TelemetryError) << t;
  }
}
