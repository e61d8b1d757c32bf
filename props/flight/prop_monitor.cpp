// The monitor and the escape sequencer under random sample sequences: the
// allowed transitions only, STOP latched, unusable samples never estimated,
// the sequencer always finishes within its bound.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <vector>

#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/escape.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/reference.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
namespace ref = sinkwatch::ground::reference;

template <typename Qty>
Qty q(double v) {
  fx::Status st;
  return Qty(fx::from_double<typename Qty::q_type>(v, st));
}

struct Kind {
  double current;
  double sinkage;
  bool valid;
  bool clear;  // below both clear levels
};
// Levels of the default table at W = 98.1 N (see host_tests/flight/test_monitor.cpp).
const Kind kKinds[] = {{1.0, 0.01, true, true},   {1.0, 0.035, true, false}, {1.0, 0.05, true, false},
                       {2.2, 0.01, true, false},  {2.5, 0.01, true, false},  {1.0, 0.027, true, false},
                       {1.0, 0.01, false, false}, {0.5, 0.0, true, true}};

RC_GTEST_PROP(MonitorProps, OnlyAllowedTransitionsAndUnusableNeverEstimated, ()) {
  const ParameterTable table = default_parameter_table();
  const ref::Parameters p = ref::from_flight(table);
  const auto seq = *rc::gen::container<std::vector<int>>(*rc::gen::inRange<std::size_t>(1, 80),
                                                          rc::gen::inRange(0, 8));
  WheelMonitor wheel;
  WheelState previous = WheelState::nominal;
  std::uint32_t t = 1000U;
  bool all_clear = true;
  for (int k : seq) {
    const Kind& kind = kKinds[k];
    all_clear = all_clear && kind.clear;
    t += 100U;
    const double torque = ref::torque_nm(p.motor, kind.current, DriveDirection::forward);
    const double dp = 98.1 * ((torque / 98.1 - kind.sinkage) / p.wheel_radius_m - 0.13);
    const WheelInput in = test::with_drive_torque(WheelInput{TimeMs{t}, q<CurrentA>(kind.current), q<WheelLoadN>(98.1),
                                                             q<DrawbarPullN>(dp), DriveDirection::forward, kind.valid},
                                                  table.motor);
    WheelOutput o{};
    wheel.step(in, TimeMs{t}, test::prepared_of(table), o);
    if (!kind.valid) {
      RC_ASSERT(!o.estimate_valid);
      RC_ASSERT(o.sinkage_m == SinkageM::zero());
      RC_ASSERT(o.sample_status == SampleStatus::flagged_invalid);
    } else {
      RC_ASSERT(o.estimate_valid);
    }
    if (previous == WheelState::stop) {
      RC_ASSERT(o.state == WheelState::stop);
      RC_ASSERT(!o.stop_tripped);
    }
    RC_ASSERT(o.stop_tripped == ((previous != WheelState::stop) && (o.state == WheelState::stop)));
    if (all_clear) {
      RC_ASSERT(o.state == WheelState::nominal);
    }
    previous = o.state;
  }
  const WheelCounters& c = wheel.counters();
  RC_ASSERT(c.samples == seq.size());
}

RC_GTEST_PROP(EscapeProps, AlwaysFinishesWithinMaxCycles, ()) {
  EscapeParams params = default_parameter_table().escape;
  params.max_cycles = static_cast<std::uint8_t>(*rc::gen::inRange(1, 20));
  params.patience_cycles = static_cast<std::uint8_t>(*rc::gen::inRange(1, static_cast<int>(params.max_cycles) + 1));
  EscapeSequencer seq;
  RC_ASSERT(seq.start(TimeMs{0U}, q<SinkageM>(0.06)));
  const std::uint32_t cycle_ms = params.forward_phase_ms + params.reverse_phase_ms;
  const std::uint32_t limit_ms = cycle_ms * params.max_cycles + 2U * cycle_ms;
  EscapeOutput o{};
  std::uint32_t t = 0U;
  while (!o.finished && t <= limit_ms) {
    t += *rc::gen::inRange<std::uint32_t>(1U, 2000U);
    const bool valid = *rc::gen::inRange(0, 10) != 0;
    const double z = *rc::gen::inRange(0, 80) / 1000.0;
    o = seq.step(EscapeInput{TimeMs{t}, valid, q<SinkageM>(z)}, params);
    RC_ASSERT(o.cycles_done <= params.max_cycles);
    RC_ASSERT((o.command == EscapeCommand::stop) == o.finished);
  }
  RC_ASSERT(o.finished);
}

}  // namespace
