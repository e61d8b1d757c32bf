// The alternating-reversal escape (escape.hpp).
#include "sinkwatch/flight/escape.hpp"

namespace sinkwatch {
namespace flight {

EscapeSequencer::EscapeSequencer() noexcept
    : state_(EscapeState::idle),
      phase_start_{0U},
      cycles_(0U),
      no_progress_(0U),
      best_(SinkageM::zero()),
      have_cycle_estimate_(false),
      cycle_last_(SinkageM::zero()) {}

bool EscapeSequencer::start(TimeMs now, SinkageM initial_sinkage_m) noexcept {
  if (state_ != EscapeState::idle) {
    return false;
  }
  state_ = EscapeState::forward;
  phase_start_ = now;
  cycles_ = 0U;
  no_progress_ = 0U;
  best_ = initial_sinkage_m;
  have_cycle_estimate_ = false;
  cycle_last_ = initial_sinkage_m;
  return true;
}

void EscapeSequencer::abort() noexcept {
  if ((state_ == EscapeState::forward) || (state_ == EscapeState::reverse)) {
    state_ = EscapeState::aborted;
  }
}

void EscapeSequencer::reset() noexcept { *this = EscapeSequencer(); }

EscapeOutput EscapeSequencer::output() const noexcept {
  EscapeOutput out{};
  out.state = state_;
  out.cycles_done = cycles_;
  switch (state_) {
    case EscapeState::forward:
      out.command = EscapeCommand::drive_forward;
      break;
    case EscapeState::reverse:
      out.command = EscapeCommand::drive_reverse;
      break;
    case EscapeState::idle:
    case EscapeState::freed:
    case EscapeState::aborted:
    case EscapeState::gave_up:
    default:
      out.command = EscapeCommand::stop;
      break;
  }
  out.finished =
      (state_ == EscapeState::freed) || (state_ == EscapeState::aborted) || (state_ == EscapeState::gave_up);
  return out;
}

EscapeOutput EscapeSequencer::step(const EscapeInput& input, const EscapeParams& params) noexcept {
  if ((state_ != EscapeState::forward) && (state_ != EscapeState::reverse)) {
    return output();
  }
  if (input.sinkage_valid) {
    have_cycle_estimate_ = true;
    cycle_last_ = input.sinkage_m;
    if (input.sinkage_m <= params.freed_sinkage_m) {
      state_ = EscapeState::freed;
      return output();
    }
  }
  const std::uint32_t in_phase = elapsed_ms(phase_start_, input.now);
  if (state_ == EscapeState::forward) {
    if (in_phase >= params.forward_phase_ms) {
      state_ = EscapeState::reverse;
      phase_start_ = input.now;
    }
    return output();
  }
  if (in_phase < params.reverse_phase_ms) {
    return output();
  }
  // End of a forward+reverse cycle: did the sinkage fall enough?
  if (cycles_ < 0xFFU) {
    ++cycles_;
  }
  bool progress = false;
  if (have_cycle_estimate_) {
    fx::Status st;
    const SinkageM decrease(fx::sub(best_.q(), cycle_last_.q(), st));
    progress = st.ok() && (decrease >= params.min_decrease_m);
  }
  if (progress) {
    best_ = cycle_last_;
    no_progress_ = 0U;
  } else if (no_progress_ < 0xFFU) {
    ++no_progress_;
  } else {
    // saturated; the patience check below has long fired
  }
  have_cycle_estimate_ = false;
  if (no_progress_ >= params.patience_cycles) {
    state_ = EscapeState::aborted;
  } else if (cycles_ >= params.max_cycles) {
    state_ = EscapeState::gave_up;
  } else {
    state_ = EscapeState::forward;
    phase_start_ = input.now;
  }
  return output();
}

}  // namespace flight
}  // namespace sinkwatch
