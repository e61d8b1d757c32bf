// The rover's stop record (flight/stop_record.hpp): what it remembers of each
// wheel, when it is written, and which reason it names.
#include <gtest/gtest.h>

#include <cstdint>

#include "quantity_support.hpp"
#include "sinkwatch/flight/stop_record.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using test::d;
using test::q;

constexpr std::uint8_t kSix = 6U;

/// A cycle in which wheel `wheel` (only) gives `sinkage_mm`.
RoverOutput one_estimate(std::uint8_t wheel, double sinkage_mm) {
  RoverOutput out{};
  out.wheels[wheel].estimate_valid = true;
  out.wheels[wheel].sinkage_m = q<SinkageM>(sinkage_mm / 1000.0);
  return out;
}

void drive(StopRecorder& r, const RoverOutput& cycle, std::uint32_t time_ms) {
  r.observe(cycle, false, RoverDecision::continue_drive, TimeMs{time_ms}, kSix);
}

void stop(StopRecorder& r, std::uint32_t time_ms, bool traction_tripped = false) {
  r.observe(RoverOutput{}, traction_tripped, RoverDecision::stop_and_replan, TimeMs{time_ms}, kSix);
}

TEST(StopRecord, HoldsTheDeepestWheelsMedianOfItsLastNineEstimates) {
  StopRecorder r;
  for (std::uint32_t k = 1U; k <= 12U; ++k) {  // wheel 2: 1..12 mm; its last nine 4..12 mm
    drive(r, one_estimate(2U, static_cast<double>(k)), k);
  }
  for (std::uint32_t k = 0U; k < 9U; ++k) {  // wheel 5: 7 mm throughout
    drive(r, one_estimate(5U, 7.0), 20U + k);
  }
  stop(r, 40U);
  ASSERT_TRUE(r.has_record());
  const RoverStopRecord& rec = r.last_record();
  EXPECT_TRUE(rec.sinkage_valid);
  EXPECT_EQ(rec.deepest_wheel, 2U);
  EXPECT_EQ(rec.samples, kStopRecordSamples);
  EXPECT_EQ(rec.recent_sinkage_m.raw(), q<SinkageM>(0.008).raw());  // the median is one sample, unrounded
  EXPECT_EQ(rec.time.ms, 40U);
}

TEST(StopRecord, OneSpikeDoesNotSetTheRecordedSinkage) {
  StopRecorder r;
  for (std::uint32_t k = 0U; k < 8U; ++k) {
    drive(r, one_estimate(0U, 20.0), k);
  }
  drive(r, one_estimate(0U, 300.0), 8U);  // one wild sample, the newest
  stop(r, 9U);
  EXPECT_NEAR(d(r.last_record().recent_sinkage_m), 0.020, 1e-7);
}

TEST(StopRecord, FewerThanNineSamplesGiveTheirOwnMiddle) {
  StopRecorder r;
  drive(r, one_estimate(1U, 10.0), 1U);
  drive(r, one_estimate(1U, 30.0), 2U);
  drive(r, one_estimate(1U, 20.0), 3U);
  stop(r, 4U);
  EXPECT_EQ(r.last_record().samples, 3U);
  EXPECT_NEAR(d(r.last_record().recent_sinkage_m), 0.020, 1e-7);
}

TEST(StopRecord, CyclesWithoutAValidEstimateAreNotRemembered) {
  StopRecorder r;
  drive(r, one_estimate(3U, 15.0), 1U);
  RoverOutput blind{};
  blind.wheels[3].sinkage_m = q<SinkageM>(0.5);  // a number without estimate_valid: never read
  for (std::uint32_t k = 0U; k < 20U; ++k) {
    drive(r, blind, 2U + k);
  }
  stop(r, 30U);
  EXPECT_EQ(r.last_record().samples, 1U);
  EXPECT_NEAR(d(r.last_record().recent_sinkage_m), 0.015, 1e-7);
}

TEST(StopRecord, WithoutAnyEstimateTheRecordSaysSo) {
  StopRecorder r;
  stop(r, 5U, true);
  ASSERT_TRUE(r.has_record());
  EXPECT_FALSE(r.last_record().sinkage_valid);
  EXPECT_EQ(r.last_record().reason, StopReason::traction);
}

TEST(StopRecord, WrittenOncePerStopAndAgainAfterTheReplan) {
  StopRecorder r;
  EXPECT_FALSE(r.has_record());
  drive(r, one_estimate(0U, 10.0), 1U);
  stop(r, 2U);
  stop(r, 3U);  // the latched STOP holds the decision: the record stays the first cycle's
  EXPECT_EQ(r.last_record().time.ms, 2U);
  r.clear_stop();
  EXPECT_TRUE(r.has_record());  // readable until the next stop
  EXPECT_EQ(r.last_record().time.ms, 2U);
  drive(r, one_estimate(4U, 25.0), 4U);
  stop(r, 5U);
  EXPECT_EQ(r.last_record().time.ms, 5U);
  EXPECT_EQ(r.last_record().deepest_wheel, 4U);  // wheel 0's samples went with the re-plan
  EXPECT_EQ(r.last_record().samples, 1U);
}

TEST(StopRecord, AStopThatEndsWithoutAReplanIsRecordedAgainWhenItReturns) {
  StopRecorder r;  // a tip-over stop is not latched: the decision can turn back
  stop(r, 1U);
  drive(r, one_estimate(0U, 5.0), 2U);
  stop(r, 3U);
  EXPECT_EQ(r.last_record().time.ms, 3U);
  EXPECT_TRUE(r.last_record().sinkage_valid);
}

TEST(StopRecord, ReasonIsTheEpisodesFirstWheelToTripBeforeTheTractionCheck) {
  StopRecorder r;
  RoverOutput cycle = one_estimate(1U, 12.0);
  cycle.wheels[4].stop_tripped = true;  // a wheel in STOP; the rover needs more (rover_stop_k)
  cycle.wheels[4].stop_reason = StopReason::slip;
  drive(r, cycle, 1U);
  RoverOutput later{};
  later.wheels[0].stop_tripped = true;
  later.wheels[0].stop_reason = StopReason::sinkage;
  r.observe(later, true, RoverDecision::stop_and_replan, TimeMs{2U}, kSix);
  EXPECT_EQ(r.last_record().reason, StopReason::slip);
}

TEST(StopRecord, WheelsBeyondTheMonitoredCountAreIgnored) {
  StopRecorder r;
  r.observe(one_estimate(5U, 90.0), false, RoverDecision::continue_drive, TimeMs{1U}, 4U);
  r.observe(one_estimate(1U, 10.0), false, RoverDecision::stop_and_replan, TimeMs{2U}, 4U);
  EXPECT_EQ(r.last_record().deepest_wheel, 1U);
}

}  // namespace
}  // namespace flight
}  // namespace sinkwatch
