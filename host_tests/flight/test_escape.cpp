// The escape sequencer: every transition and outcome.
#include <gtest/gtest.h>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/escape.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

SinkageM z(double v) {
  fx::Status st;
  return SinkageM(fx::from_double<LengthQ>(v, st));
}

// Default: 5 s forward, 5 s reverse, at most 10 cycles, patience 2 cycles,
// progress = at least 2 mm less per cycle, freed at or below 20 mm.
class EscapeTest : public ::testing::Test {
 protected:
  EscapeParams params = default_parameter_table().escape;
  EscapeSequencer seq;
  std::uint32_t now = 0U;

  EscapeOutput at(std::uint32_t t_ms, double sinkage, bool valid = true) {
    now = t_ms;
    return seq.step(EscapeInput{TimeMs{t_ms}, valid, z(sinkage)}, params);
  }
  /// One full cycle starting at `now` with the given sinkage throughout.
  EscapeOutput cycle(double sinkage, bool valid = true) {
    const std::uint32_t start = now;
    at(start + 1000U, sinkage, valid);
    at(start + 5000U, sinkage, valid);   // forward -> reverse
    at(start + 7000U, sinkage, valid);
    return at(start + 10000U, sinkage, valid);  // end of the cycle
  }
};

TEST_F(EscapeTest, IdleCommandsStopAndIgnoresSteps) {
  const EscapeOutput o = at(100U, 0.05);
  EXPECT_EQ(o.state, EscapeState::idle);
  EXPECT_EQ(o.command, EscapeCommand::stop);
  EXPECT_FALSE(o.finished);
}

TEST_F(EscapeTest, AlternatesForwardAndReverse) {
  ASSERT_TRUE(seq.start(TimeMs{0U}, z(0.06)));
  EXPECT_FALSE(seq.start(TimeMs{0U}, z(0.06)));  // already running
  EXPECT_EQ(at(1000U, 0.06).command, EscapeCommand::drive_forward);
  EXPECT_EQ(at(4999U, 0.06).state, EscapeState::forward);
  EXPECT_EQ(at(5000U, 0.058).command, EscapeCommand::drive_reverse);
  EXPECT_EQ(at(9999U, 0.057).state, EscapeState::reverse);
  const EscapeOutput o = at(10000U, 0.055);  // 5 mm better than 60: progress
  EXPECT_EQ(o.state, EscapeState::forward);
  EXPECT_EQ(o.cycles_done, 1U);
  EXPECT_NEAR(fx::to_double(seq.best_sinkage_m().q()), 0.055, 1e-7);
}

TEST_F(EscapeTest, FreedAsSoonAsTheSinkageIsLowEnough) {
  seq.start(TimeMs{0U}, z(0.06));
  cycle(0.05);
  at(now + 2000U, 0.03);
  const EscapeOutput o = at(now + 1000U, 0.02);
  EXPECT_EQ(o.state, EscapeState::freed);
  EXPECT_EQ(o.command, EscapeCommand::stop);
  EXPECT_TRUE(o.finished);
  EXPECT_EQ(at(now + 1000U, 0.06).state, EscapeState::freed);  // final
}

TEST_F(EscapeTest, FreedDuringAReversePhase) {
  seq.start(TimeMs{0U}, z(0.06));
  EXPECT_EQ(at(5000U, 0.05).state, EscapeState::reverse);
  const EscapeOutput o = at(6000U, 0.019);
  EXPECT_EQ(o.state, EscapeState::freed);
  EXPECT_EQ(o.cycles_done, 0U);
}

TEST_F(EscapeTest, AbortsWhenTheSinkageStopsDecreasing) {
  seq.start(TimeMs{0U}, z(0.06));
  EXPECT_EQ(cycle(0.05).state, EscapeState::forward);    // progress
  EXPECT_EQ(cycle(0.049).state, EscapeState::forward);   // 1 mm: not enough (1 of 2)
  const EscapeOutput o = cycle(0.0495);                  // worse (2 of 2)
  EXPECT_EQ(o.state, EscapeState::aborted);
  EXPECT_EQ(o.command, EscapeCommand::stop);
  EXPECT_TRUE(o.finished);
  EXPECT_EQ(o.cycles_done, 3U);
}

TEST_F(EscapeTest, ProgressResetsThePatience) {
  seq.start(TimeMs{0U}, z(0.09));
  cycle(0.0895);                                        // no progress (1)
  cycle(0.08);                                          // progress: count reset
  EXPECT_EQ(cycle(0.0799).state, EscapeState::forward); // no progress (1)
  EXPECT_EQ(cycle(0.0799).state, EscapeState::aborted); // (2)
}

TEST_F(EscapeTest, CyclesWithoutAnEstimateAreNoProgress) {
  seq.start(TimeMs{0U}, z(0.06));
  cycle(0.0, false);
  EXPECT_EQ(cycle(0.0, false).state, EscapeState::aborted);
}

TEST_F(EscapeTest, GivesUpAfterMaxCycles) {
  params.max_cycles = 4U;
  seq.start(TimeMs{0U}, z(0.09));
  double s = 0.09;
  EscapeOutput o{};
  for (int i = 0; i < 4; ++i) {
    s -= 0.003;
    o = cycle(s);
  }
  EXPECT_EQ(o.state, EscapeState::gave_up);
  EXPECT_TRUE(o.finished);
  EXPECT_EQ(o.cycles_done, 4U);
}

TEST_F(EscapeTest, GroundAbortAndReset) {
  seq.start(TimeMs{0U}, z(0.06));
  at(1000U, 0.06);
  seq.abort();
  EXPECT_EQ(seq.state(), EscapeState::aborted);
  EXPECT_EQ(at(2000U, 0.06).command, EscapeCommand::stop);
  seq.reset();
  EXPECT_EQ(seq.state(), EscapeState::idle);
  seq.abort();  // abort when idle does nothing
  EXPECT_EQ(seq.state(), EscapeState::idle);
  EXPECT_TRUE(seq.start(TimeMs{5000U}, z(0.06)));
  EXPECT_EQ(seq.cycles_done(), 0U);
}

TEST_F(EscapeTest, PhaseTimingSurvivesClockWrap) {
  ASSERT_TRUE(seq.start(TimeMs{0xFFFFF000U}, z(0.06)));
  EXPECT_EQ(seq.step(EscapeInput{TimeMs{0x00000100U}, true, z(0.06)}, params).state, EscapeState::forward);
  // 0xFFFFF000 + 5000 ms wraps to 0x00000388.
  EXPECT_EQ(seq.step(EscapeInput{TimeMs{0x00000388U}, true, z(0.06)}, params).state, EscapeState::reverse);
}

}  // namespace
