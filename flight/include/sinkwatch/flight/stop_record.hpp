// stop_record.hpp: the rover's record of a stop-and-replan decision, whatever
// made it: a wheel's rule of section 7 (current, sinkage, slip, telemetry),
// the motion-resistance check (traction.hpp, the table's section 8) or the
// step's own stop (tip-over).
//
// Section 7 records the sinkage at the stop so that the ground can reproduce
// it. A wheel's EventRecord (monitor.hpp) holds Eq. 11 at the episode's peak
// current with DP = DP_max, which is a sinkage only when the table's DP_max
// fits the soil (docs/campaign.md: with the paper's DP_max/W = 0.5 it reads
// negative in soft soil), and the motion-resistance check, the most common
// stop, leaves no wheel record at all. This record holds, for every stop,
// the deepest wheel's recent sinkage:
//
//   z_recent(i) = median of wheel i's last kStopRecordSamples valid Eq. 11
//                 estimates (WheelOutput::sinkage_m; one noisy sample cannot
//                 set it)
//   deepest     = the wheel with the largest z_recent (the lowest index of equals)
//
// The median moves no bit (detail::median_of: a sort, no arithmetic), so the
// recorded sinkage is one of the monitor's own estimates, with their error
// budget (docs/flight.md). Like Eq. 11 itself it is physical when Table 2
// fits the soil (docs/campaign.md, "The rover's stop record").
//
// The record is written once per stop: on a cycle whose decision is
// stop_and_replan after one that was not (or after construction or
// clear_stop()). Its reason is the
// first STOP of the episode: the first wheel to trip (lowest index within a
// cycle), else the motion-resistance check (StopReason::traction), else none
// (the step's own stop: RoverStepOutput::status says which).
#ifndef SINKWATCH_FLIGHT_STOP_RECORD_HPP
#define SINKWATCH_FLIGHT_STOP_RECORD_HPP

#include <cstdint>

#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

/// Samples per wheel in the recent-sinkage median: about 2 s at the shipped
/// 5 Hz telemetry. Odd, so the median is one sample.
constexpr std::uint8_t kStopRecordSamples = 9U;

/// Written when the rover's decision turns to stop_and_replan.
struct RoverStopRecord {
  TimeMs time{0U};                       ///< the monitor's clock at the decision
  StopReason reason{StopReason::none};   ///< the episode's first STOP (see above)
  std::uint8_t deepest_wheel{0U};        ///< meaningful when sinkage_valid
  std::uint8_t samples{0U};              ///< the deepest wheel's samples in its median (1..kStopRecordSamples)
  bool sinkage_valid{false};             ///< some wheel had a valid estimate since the last clear
  SinkageM recent_sinkage_m;             ///< z_recent of the deepest wheel
};

class StopRecorder {
 public:
  StopRecorder() noexcept;

  /// One cycle, after the monitor and the motion-resistance check:
  /// remembers each wheel's valid estimate and, on the cycle the decision
  /// turns to stop_and_replan, writes the record. `wheels`: the monitored
  /// wheels (the table's monitor.wheel_count).
  void observe(const RoverOutput& monitor, bool traction_stop_tripped, RoverDecision decision, TimeMs now,
               std::uint8_t wheels) noexcept;

  /// The ground's re-plan: empty histories, the next stop writes a new record
  /// (the last one stays readable until then).
  void clear_stop() noexcept;

  [[nodiscard]] bool has_record() const noexcept { return has_record_; }
  [[nodiscard]] const RoverStopRecord& last_record() const& noexcept { return record_; }
  const RoverStopRecord& last_record() const&& = delete;  // MISRA C++:2023 6.8.4: no reference into a temporary

 private:
  // observe()'s first stage, inline (defined and used only in
  // stop_record.cpp, forced inline there): no call per cycle.
  inline void remember(const RoverOutput& monitor, std::uint8_t wheels) noexcept;
  [[nodiscard]] RoverStopRecord record(TimeMs now, std::uint8_t wheels) const noexcept;

  SinkageM recent_m_[kMaxWheels][kStopRecordSamples]{};
  std::uint8_t next_[kMaxWheels]{};  ///< per wheel, the ring's next slot
  /// Bit i: wheel i's window has filled (its median takes every slot). Set
  /// once per episode, where a count per wheel was read and written per
  /// estimate; the count is only needed for a record.
  std::uint8_t full_{0U};
  StopReason first_reason_{StopReason::none};
  bool stopped_{false};  ///< the last observed decision was stop_and_replan
  bool has_record_{false};
  RoverStopRecord record_{};
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_STOP_RECORD_HPP
