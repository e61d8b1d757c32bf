// Mission-length telemetry for the endurance test and benchmark (issue 18):
// the shipped nominal drive (data/telemetry/nominal.csv, 2,223 cycles at
// 5 Hz, the rover standing at its start and end) tiled end to end with the
// time continued, made row by row so the log itself takes no memory, and a
// fingerprint of what the flight code decided in a cycle.
//
// Times are kept in whole milliseconds of the on-board clock (uint32) and
// wrap at 2^32 ms = 4294967.296 s like the flight clock: a log started
// `offset_ms` late crosses the wrap when the clock passes 4294967.295 s.
// Such a log cannot be a file (the reader accepts 0 ... 4294967.295 s and
// never a time that goes backwards), so it is fed to OnboardLoop directly.
#pragma once

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace sinkwatch::ground::endurance {

inline constexpr std::uint64_t kClockModulusMs = 4294967296ULL;  // the uint32 ms clock

class TiledLog {
 public:
  /// `base`: one drive; its rows are repeated every tile, the next tile
  /// starting one cycle (cycle_ms) after the base's last row.
  TiledLog(const TelemetryLog& base, std::uint64_t offset_ms, std::uint64_t cycle_ms = 200U)
      : base_(base), offset_ms_(offset_ms) {
    tile_ms_ = ms_of(base.rows.back().time_s) + cycle_ms;
  }

  std::size_t tile_rows() const { return base_.rows.size(); }
  std::uint64_t tile_ms() const { return tile_ms_; }

  /// Row i of the endless log (the base's row i mod tile_rows(), its time
  /// continued and wrapped like the on-board clock).
  TelemetryRow row(std::size_t i) const {
    const std::size_t n = base_.rows.size();
    TelemetryRow r = base_.rows[i % n];
    const std::uint64_t t = ms_of(r.time_s) + static_cast<std::uint64_t>(i / n) * tile_ms_ + offset_ms_;
    r.time_s = static_cast<double>(t % kClockModulusMs) / 1000.0;
    r.line = 0;
    return r;
  }

  /// The row's time on the unwrapped clock, ms.
  std::uint64_t unwrapped_ms(std::size_t i) const {
    const std::size_t n = base_.rows.size();
    return ms_of(base_.rows[i % n].time_s) + static_cast<std::uint64_t>(i / n) * tile_ms_ + offset_ms_;
  }

 private:
  static std::uint64_t ms_of(double time_s) { return static_cast<std::uint64_t>(std::llround(time_s * 1000.0)); }

  const TelemetryLog& base_;
  std::uint64_t offset_ms_;
  std::uint64_t tile_ms_ = 0;
};

/// FNV-1a over everything the flight code decided and computed in a cycle,
/// except the time (which a shifted log changes) and the replay's own
/// bookkeeping (row, x_m): status, decision, slip, acceleration, every
/// wheel's load, pull, estimate, limit, state, sample status and stop
/// reason, the event records but their times, and the escape sequencer.
class Fingerprint {
 public:
  void add_bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t k = 0; k < n; ++k) {
      h_ ^= b[k];
      h_ *= 1099511628211ULL;
    }
  }
  void add(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    add_bytes(&bits, sizeof bits);
  }
  void add(bool v) { add_int(v ? 1 : 0); }
  void add_int(std::int64_t v) { add_bytes(&v, sizeof v); }
  void add(const std::optional<double>& v) {
    add(v.has_value());
    if (v) add(*v);
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 14695981039346656037ULL;
};

inline std::uint64_t fingerprint(const CycleRecord& c) {
  Fingerprint f;
  f.add_int(static_cast<int>(c.status));
  f.add_int(static_cast<int>(c.decision));
  f.add(c.slip);
  f.add(c.accel_mps2);
  f.add(c.drawbar_saturated);
  for (const WheelCycle& w : c.wheels) {
    f.add(w.current_a);
    f.add(w.load_valid);
    f.add(w.load_n);
    f.add(w.drawbar_pull_n);
    f.add(w.estimate_valid);
    f.add(w.torque_nm);
    f.add(w.sinkage_m);
    f.add(w.limit_valid);
    f.add(w.current_limit_a);
    f.add_int(static_cast<int>(w.state));
    f.add_int(static_cast<int>(w.sample));
    f.add_int(static_cast<int>(w.stop_reason));
    f.add(w.stop_tripped);
  }
  for (const StopRecord& e : c.new_events) {
    f.add_int(static_cast<std::int64_t>(e.wheel));
    f.add_int(static_cast<int>(e.reason));
    f.add(e.peak_current_a);
    f.add(e.load_at_peak_n);
    f.add(e.peak_sinkage_m);
    f.add(e.max_estimated_sinkage_m);
  }
  f.add(c.escape_active);
  f.add_int(static_cast<int>(c.escape_state));
  f.add_int(static_cast<int>(c.escape_command));
  f.add_int(c.escape_cycles);
  f.add(c.escape_input_m);
  f.add(c.escape_started);
  f.add(c.escape_finished_now);
  f.add(c.direction_mismatch);
  return f.value();
}

/// Every number of the cycle is finite.
inline bool all_finite(const CycleRecord& c) {
  auto fin = [](const std::optional<double>& v) { return !v || std::isfinite(*v); };
  bool ok = std::isfinite(c.time_s) && fin(c.slip) && fin(c.accel_mps2) && fin(c.escape_input_m);
  for (const WheelCycle& w : c.wheels) {
    ok = ok && std::isfinite(w.load_n) && std::isfinite(w.drawbar_pull_n) && std::isfinite(w.torque_nm) &&
         std::isfinite(w.sinkage_m) && std::isfinite(w.current_limit_a);
  }
  return ok;
}

}  // namespace sinkwatch::ground::endurance
