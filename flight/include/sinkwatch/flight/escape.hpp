// escape.hpp: the escape manoeuvre of section 7 as a bounded state machine.
//
// The paper's ground simulation (Fig. 11) frees an embedded wheel by
// alternating its direction: each reversal carries soil under the wheel and
// the sinkage falls step by step. The sequencer drives forward for
// forward_phase_ms, then reverse for reverse_phase_ms (one cycle), and at the
// end of each cycle compares the sinkage estimate with the best so far:
//
//   IDLE --start--> FORWARD --phase time--> REVERSE --phase time--> (cycle end)
//   cycle end: z <= freed level            -> FREED
//              z fell by >= min_decrease   -> FORWARD (progress; best = z)
//              else, patience_cycles in a row without progress -> ABORTED
//              cycles == max_cycles        -> GAVE_UP
//   any running state: z <= freed level    -> FREED;  abort()  -> ABORTED
//
// A cycle without one valid sinkage estimate is a cycle without progress
// (fail-safe: the sequencer never credits progress it did not see). FREED,
// ABORTED and GAVE_UP are final until reset(); every step is O(1).
#ifndef SINKWATCH_FLIGHT_ESCAPE_HPP
#define SINKWATCH_FLIGHT_ESCAPE_HPP

#include <cstdint>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/units.hpp"

namespace sinkwatch {
namespace flight {

enum class EscapeState : std::uint8_t {
  idle = 0U,
  forward = 1U,
  reverse = 2U,
  freed = 3U,    ///< outcome: sinkage at or below the freed level
  aborted = 4U,  ///< outcome: the sinkage stopped decreasing, or abort()
  gave_up = 5U,  ///< outcome: max_cycles without being freed
};

enum class EscapeCommand : std::uint8_t { stop = 0U, drive_forward = 1U, drive_reverse = 2U };

// Defaults are the fail-safe values: no estimate, and the wheel stopped.
struct EscapeInput {
  TimeMs now{};
  bool sinkage_valid{false};  ///< false: no estimate this cycle (the monitor said why)
  SinkageM sinkage_m{};
};

struct EscapeOutput {
  EscapeState state{EscapeState::idle};
  EscapeCommand command{EscapeCommand::stop};
  std::uint8_t cycles_done{0U};
  bool finished{false};  ///< state is freed, aborted or gave_up
};

class EscapeSequencer {
 public:
  EscapeSequencer() noexcept;

  /// Starts from IDLE with the sinkage at the embedding; false (and no
  /// change) when not IDLE.
  bool start(TimeMs now, SinkageM initial_sinkage_m) noexcept;

  EscapeOutput step(const EscapeInput& input, const EscapeParams& params) noexcept;

  /// The ground's abort: a running sequence ends ABORTED.
  void abort() noexcept;
  /// Back to IDLE from any state.
  void reset() noexcept;

  [[nodiscard]] EscapeState state() const noexcept { return state_; }
  [[nodiscard]] std::uint8_t cycles_done() const noexcept { return cycles_; }
  [[nodiscard]] SinkageM best_sinkage_m() const noexcept { return best_; }

 private:
  EscapeOutput output() const noexcept;

  EscapeState state_;
  TimeMs phase_start_;
  std::uint8_t cycles_;
  std::uint8_t no_progress_;
  SinkageM best_;
  bool have_cycle_estimate_;
  SinkageM cycle_last_;
};

}  // namespace flight
}  // namespace sinkwatch

#endif  // SINKWATCH_FLIGHT_ESCAPE_HPP
