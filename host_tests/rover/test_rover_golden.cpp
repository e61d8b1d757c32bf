// Golden vectors of the rover functions: the exact output bits of
// wheel_loads and drawbar_pulls for 72 fixed cases (24 with drive torques) (rover_golden_cases.hpp),
// recorded on the host. The same test runs on 32-bit ARM under qemu, so the
// fixed-point code must give the same bits on both.
#include <gtest/gtest.h>

#include <cstdint>

#include "rover_golden_cases.hpp"

namespace sinkwatch {
namespace {

const rover_golden::Expected kGolden[] = {
#include "rover_golden.inc"
};

TEST(RoverGolden, EveryCaseGivesTheRecordedBits) {
  static_assert(sizeof(kGolden) / sizeof(kGolden[0]) == rover_golden::kCaseCount, "one row per case");
  std::uint32_t stable = 0U;
  std::uint32_t tipped = 0U;
  for (std::uint32_t k = 0U; k < rover_golden::kCaseCount; ++k) {
    const rover_golden::Expected got = rover_golden::evaluate(rover_golden::make_case(k));
    const rover_golden::Expected& want = kGolden[k];
    EXPECT_EQ(got.load_status, want.load_status) << "case " << k;
    EXPECT_EQ(got.lifting_wheel, want.lifting_wheel) << "case " << k;
    EXPECT_EQ(got.weight_normal_raw, want.weight_normal_raw) << "case " << k;
    EXPECT_EQ(got.drawbar_status, want.drawbar_status) << "case " << k;
    EXPECT_EQ(got.capped_mask, want.capped_mask) << "case " << k;
    EXPECT_EQ(got.total_raw, want.total_raw) << "case " << k;
    for (std::uint32_t i = 0U; i < flight::kWheelCount; ++i) {
      EXPECT_EQ(got.load_raw[i], want.load_raw[i]) << "case " << k << " wheel " << i;
      EXPECT_EQ(got.dp_raw[i], want.dp_raw[i]) << "case " << k << " wheel " << i;
    }
    stable += (want.load_status == static_cast<std::uint8_t>(flight::WheelLoadStatus::ok)) ? 1U : 0U;
    tipped += (want.load_status == static_cast<std::uint8_t>(flight::WheelLoadStatus::tip_over)) ? 1U : 0U;
  }
  // The set exercises both sides of the stability limit.
  EXPECT_GE(stable, 10U);
  EXPECT_GE(tipped, 5U);
}

}  // namespace
}  // namespace sinkwatch
