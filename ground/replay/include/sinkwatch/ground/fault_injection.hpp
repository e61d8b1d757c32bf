// Sensor faults injected into a telemetry log, to see what the flight code's
// sensor health monitor (flight/sensor_health.hpp) and its decision make of
// them (issue 18; docs/fault-injection.md).
//
// A fault is written KIND:TARGET@START[+DURATION][=VALUE], several joined by
// commas, times in seconds (an optional trailing "s"):
//
//   stuck:LM_current@120s+30s     the current held at its value at START
//   dropout:imu@200s+5s           pitch and roll missing (empty cells)
//   spike:RR_current@130s=40      one sample, +40 A
//   jump:clock@100s=10            every time stamp from 100 s on 10 s later
//
// Without +DURATION a fault lasts to the end of the log. A fault changes only
// the measured columns of the rows whose (original) time lies in its window;
// it never adds or removes a row, so row k of the faulty log is row k of the
// clean one (the campaign compares them by index). Faults are applied in the
// order given; the noise of `noise` and `freewheel` is drawn from the seed,
// so a seed gives the same log bit for bit.
#pragma once

#include "sinkwatch/ground/telemetry_log.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sinkwatch::ground {

enum class FaultKind {
  stuck,      // the value held at its value at START
  zero,       // a current held at 0 A
  dropout,    // the sensor missing (empty cells)
  spike,      // one sample offset by VALUE
  bias,       // offset by VALUE from START on (a bias step)
  noise,      // gaussian noise of standard deviation VALUE added
  freeze,     // joint or attitude values held (as stuck)
  stall,      // a current forced to VALUE A (a stalled motor)
  freewheel,  // a current forced to about 0.02 A (no torque reaches the soil)
  repeat,     // the clock: every stamp repeats the last one before START
  jump,       // the clock: every stamp from START on VALUE s later
};
inline constexpr std::size_t kFaultKinds = 11;

/// What a fault acts on; the six currents first, in the flight code's wheel order.
enum class FaultTarget {
  current_lf, current_lm, current_lr, current_rf, current_rm, current_rr,
  left,    // the three left currents
  right,   // the three right currents
  imu,     // pitch and roll
  pitch,
  roll,
  joints,  // rocker and bogie angles
  clock,   // the time stamp
};
inline constexpr std::size_t kFaultTargets = 13;

const char* fault_kind_name(FaultKind k);
/// "LM_current", "left", "imu", ... as written in a spec.
const char* fault_target_name(FaultTarget t);

struct FaultSpec {
  FaultKind kind = FaultKind::stuck;
  FaultTarget target = FaultTarget::current_lf;
  double start_s = 0.0;
  std::optional<double> duration_s;  // empty: to the end of the log
  std::optional<double> value;       // A, deg or s by kind and target; empty: the kind's default
  /// The spec in its canonical form ("stuck:LM_current@120s+30s").
  std::string text() const;
};

/// A spec that cannot be read; the message names the spec and what is wrong.
class FaultSpecError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// One spec, e.g. "stuck:LM_current@120s+30s". Throws FaultSpecError.
FaultSpec parse_fault(const std::string& text);
/// A comma-separated list; empty items are refused. Throws FaultSpecError.
std::vector<FaultSpec> parse_faults(const std::string& list);

/// Defaults when a spec gives no VALUE (docs/fault-injection.md).
inline constexpr double kSpikeCurrentFactor = 10.0;   // spike: 10 x |the wheel's current| at START
inline constexpr double kSpikeCurrentMinA = 1.0;      // ... at least this
inline constexpr double kSpikeAngleDeg = 10.0;        // spike of pitch or roll
inline constexpr double kStallFactor = 3.0;           // stall: 3 x the log's highest |current|
inline constexpr double kFreewheelCurrentA = 0.02;    // freewheel: this, with ...
inline constexpr double kFreewheelNoiseA = 0.002;     // ... gaussian noise of this sd

/// What one fault did to the log.
struct AppliedFault {
  FaultSpec spec;
  std::size_t rows = 0;         // rows changed (0: the window lies outside the log)
  std::size_t first_row = 0;    // index of the first row changed
  double value = 0.0;           // the VALUE used (the default when none was given)
};

/// Applies the faults in order, records them in the log (metadata
/// "injected_faults" and "fault_seed", one comment per fault saying which rows
/// it changed), and returns what each did. Values are kept within the
/// reader's ranges (currents +-1000 A, angles +-90 deg) so that the faulty
/// log can be written and read back.
std::vector<AppliedFault> apply_faults(TelemetryLog& log, const std::vector<FaultSpec>& faults, std::uint64_t seed);

}  // namespace sinkwatch::ground
