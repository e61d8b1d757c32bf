// The rover's stop record (flight/stop_record.hpp) under random cycles: at
// every stop its sinkage is the largest of the wheels' medians of their last
// kStopRecordSamples valid estimates, worked out here with a sort of doubles,
// and it is written only on the decision's edge.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/stop_record.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

struct Cycle {
  std::array<bool, kMaxWheels> valid{};
  std::array<std::int32_t, kMaxWheels> sinkage_raw{};  // Q7.24, any value the format holds
  bool stop = false;
};

rc::Gen<Cycle> cycle_gen() {
  return rc::gen::exec([] {
    Cycle c;
    for (std::size_t i = 0; i < kMaxWheels; ++i) {
      c.valid[i] = *rc::gen::inRange(0, 4) != 0;  // three in four samples usable
      c.sinkage_raw[i] = *rc::gen::arbitrary<std::int32_t>();
    }
    c.stop = *rc::gen::inRange(0, 6) == 0;
    return c;
  });
}

/// The deepest wheel's median of its recent samples [m], by plain sorting.
std::optional<double> reference_median(const std::array<std::deque<double>, kMaxWheels>& recent) {
  std::optional<double> deepest;
  for (const std::deque<double>& last : recent) {
    if (last.empty()) continue;
    std::vector<double> sorted(last.begin(), last.end());
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[(sorted.size() - 1) / 2];
    if (!deepest || median > *deepest) deepest = median;
  }
  return deepest;
}

RC_GTEST_PROP(StopRecordProps, EveryRecordIsTheDeepestRecentMedianWrittenOnTheEdge, ()) {
  const auto cycles = *rc::gen::container<std::vector<Cycle>>(*rc::gen::inRange<std::size_t>(1, 60), cycle_gen());
  StopRecorder recorder;
  std::array<std::deque<double>, kMaxWheels> recent;
  bool was_stopped = false;
  std::uint32_t records = 0U;
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    const Cycle& c = cycles[k];
    RoverOutput out{};
    for (std::size_t i = 0; i < kMaxWheels; ++i) {
      out.wheels[i].estimate_valid = c.valid[i];
      out.wheels[i].sinkage_m = SinkageM::from_raw(c.sinkage_raw[i]);
      if (c.valid[i]) {
        recent[i].push_back(fx::to_double(out.wheels[i].sinkage_m.q()));
        if (recent[i].size() > kStopRecordSamples) recent[i].pop_front();
      }
    }
    const auto now = TimeMs{static_cast<std::uint32_t>(k)};
    recorder.observe(out, false, c.stop ? RoverDecision::stop_and_replan : RoverDecision::continue_drive, now,
                     kMaxWheels);
    if (c.stop && !was_stopped) {
      ++records;
      RC_ASSERT(recorder.has_record());
      const RoverStopRecord& r = recorder.last_record();
      RC_ASSERT(r.time.ms == now.ms);
      const std::optional<double> expected = reference_median(recent);
      RC_ASSERT(r.sinkage_valid == expected.has_value());
      if (expected) {
        RC_ASSERT(fx::to_double(r.recent_sinkage_m.q()) == *expected);
        RC_ASSERT(r.samples == recent[r.deepest_wheel].size());
      }
    }
    RC_ASSERT(recorder.has_record() == (records > 0U));
    if (records > 0U) {
      RC_ASSERT(recorder.last_record().time.ms <= now.ms);
    }
    was_stopped = c.stop;
  }
}

}  // namespace
