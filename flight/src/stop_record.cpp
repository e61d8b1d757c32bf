// stop_record.cpp: the rover's stop record (stop_record.hpp).
#include "sinkwatch/flight/stop_record.hpp"

#include "median.hpp"

#include "sinkwatch/fixedpoint/inline.hpp"

namespace sinkwatch {
namespace flight {

namespace {

/// The samples in wheel i's median: the window once it has filled, else
/// the slots used.
std::uint8_t samples_of(std::uint8_t next, std::uint8_t full, std::uint8_t i) noexcept {
  return (((static_cast<std::uint32_t>(full) >> i) & 1U) != 0U) ? kStopRecordSamples : next;
}

}  // namespace

StopRecorder::StopRecorder() noexcept = default;

void StopRecorder::clear_stop() noexcept {
  const bool had_record = has_record_;
  const RoverStopRecord kept = record_;
  *this = StopRecorder();
  has_record_ = had_record;
  record_ = kept;
}

SW_FX_INLINE void StopRecorder::remember(const RoverOutput& monitor, std::uint8_t wheels) noexcept {
  // The bound once, and the episode's first reason and the filled windows
  // in locals stored once:
  // the byte stores into the histories may alias any member as far as the
  // compiler knows, so a member read in the loop is read again per wheel.
  const std::uint32_t count = (wheels < kMaxWheels) ? wheels : kMaxWheels;
  StopReason first = first_reason_;
  std::uint32_t full = full_;
  for (std::uint32_t i = 0U; i < count; ++i) {
    const WheelOutput& w = monitor.wheels[i];
    if (w.estimate_valid) {
      std::uint32_t slot = next_[i];
      recent_m_[i][slot] = w.sinkage_m;
      ++slot;
      if (slot >= kStopRecordSamples) {
        // The window has filled: from here on the next slot is the oldest's.
        slot = 0U;
        full |= 1U << i;
      }
      next_[i] = static_cast<std::uint8_t>(slot);
    }
    // The wheel's trip first: it is rare, and the usual cycle's first
    // reason is none, so this way one test per wheel, not two (round 16).
    if (w.stop_tripped && (first == StopReason::none)) {
      first = w.stop_reason;
    }
  }
  first_reason_ = first;
  full_ = static_cast<std::uint8_t>(full);
}

RoverStopRecord StopRecorder::record(TimeMs now, std::uint8_t wheels) const noexcept {
  RoverStopRecord r{};
  r.time = now;
  r.reason = first_reason_;
  for (std::uint8_t i = 0U; (i < wheels) && (i < kMaxWheels); ++i) {
    const std::uint8_t count = samples_of(next_[i], full_, i);
    if (count > 0U) {
      const SinkageM z = detail::median_of(recent_m_[i], count);
      if (!r.sinkage_valid || (r.recent_sinkage_m < z)) {
        r.sinkage_valid = true;
        r.deepest_wheel = i;
        r.samples = count;
        r.recent_sinkage_m = z;
      }
    }
  }
  return r;
}

void StopRecorder::observe(const RoverOutput& monitor, bool traction_stop_tripped, RoverDecision decision,
                           TimeMs now, std::uint8_t wheels) noexcept {
  remember(monitor, wheels);
  if ((first_reason_ == StopReason::none) && traction_stop_tripped) {
    first_reason_ = StopReason::traction;
  }
  // One record per stop: on the decision's edge. A latched STOP holds the
  // decision until clear_stop(); a tip-over's stop can end without one.
  const bool stop = (decision == RoverDecision::stop_and_replan);
  if (stop && !stopped_) {
    has_record_ = true;
    record_ = record(now, wheels);
  }
  stopped_ = stop;
}

}  // namespace flight
}  // namespace sinkwatch
