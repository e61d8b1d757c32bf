// test_cov_escape.cpp: the escape sequencer's abort during the reverse
// phase, and its answer when the sinkage change of a cycle does not fit the
// sinkage format (parameters a validated table would refuse, given to the
// sequencer directly): not progress, so the patience rule ends the attempt.
#include <gtest/gtest.h>

#include "quantity_support.hpp"
#include "sinkwatch/flight/escape.hpp"
#include "sinkwatch/flight/param_table.hpp"

namespace {

using namespace sinkwatch::flight;
using sinkwatch::test::q;

EscapeInput sample(std::uint32_t t_ms, double sinkage_m) { return EscapeInput{TimeMs{t_ms}, true, q<SinkageM>(sinkage_m)}; }

TEST(EscapeAbort, AbortDuringTheReversePhaseEndsAborted) {
  const EscapeParams p = default_parameter_table().escape;
  EscapeSequencer seq;
  ASSERT_TRUE(seq.start(TimeMs{0U}, q<SinkageM>(0.04)));
  const EscapeOutput rev = seq.step(sample(p.forward_phase_ms, 0.04), p);
  ASSERT_EQ(rev.state, EscapeState::reverse);
  EXPECT_EQ(rev.command, EscapeCommand::drive_reverse);
  seq.abort();
  EXPECT_EQ(seq.state(), EscapeState::aborted);
  const EscapeOutput after = seq.step(sample(p.forward_phase_ms + 10U, 0.04), p);
  EXPECT_EQ(after.command, EscapeCommand::stop);
  EXPECT_TRUE(after.finished);
}

TEST(EscapeAbort, AbortWhenIdleChangesNothing) {
  EscapeSequencer seq;
  seq.abort();
  EXPECT_EQ(seq.state(), EscapeState::idle);
}

class EscapeUnvalidated : public ::testing::Test {
 protected:
  EscapeParams p = default_parameter_table().escape;
  void SetUp() override {
    p.freed_sinkage_m = SinkageM(LengthQ::min());  // nothing counts as freed
    p.patience_cycles = 1U;
  }
  // One forward+reverse cycle from `start` ending with `sinkage_m`.
  EscapeOutput cycle(EscapeSequencer& seq, std::uint32_t start, double sinkage_m) {
    static_cast<void>(seq.step(sample(start + p.forward_phase_ms, sinkage_m), p));
    return seq.step(sample(start + p.forward_phase_ms + p.reverse_phase_ms, sinkage_m), p);
  }
};

TEST_F(EscapeUnvalidated, DecreaseBeyondTheSinkageFormatIsNotProgress) {
  EscapeSequencer seq;
  ASSERT_TRUE(seq.start(TimeMs{0U}, q<SinkageM>(100.0)));
  // 100 m - (-100 m) = 200 m does not fit Q7.24 (max 128 m).
  const EscapeOutput out = cycle(seq, 0U, -100.0);
  EXPECT_EQ(out.state, EscapeState::aborted);
  EXPECT_EQ(out.cycles_done, 1U);
  EXPECT_EQ(seq.best_sinkage_m(), q<SinkageM>(100.0));
}

TEST_F(EscapeUnvalidated, LargeDecreaseThatFitsIsProgress) {
  EscapeSequencer seq;
  ASSERT_TRUE(seq.start(TimeMs{0U}, q<SinkageM>(100.0)));
  const EscapeOutput out = cycle(seq, 0U, -20.0);  // 120 m: fits
  EXPECT_EQ(out.state, EscapeState::forward);
  EXPECT_EQ(seq.best_sinkage_m(), q<SinkageM>(-20.0));
}

}  // namespace
