// Benchmark (prints numbers; not a test): the flight code for a mission's
// length (issue 18). The shipped nominal drive tiled into a 24-hour log at
// 5 Hz (432,000 cycles, endurance_log.hpp), streamed through one OnboardLoop,
// then the same log started 12 h before the on-board clock wraps
// (4294967.295 s -> 0). Prints cycles per second, the peak resident memory
// (getrusage ru_maxrss) at the start and every 100,000 cycles, and whether the
// wrapped log decided the same as the unwrapped one, cycle for cycle.
#include "endurance_log.hpp"

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_command.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace sg = sinkwatch::ground;
namespace se = sinkwatch::ground::endurance;

namespace {

long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;  // KiB on Linux
}

struct Run {
  std::uint64_t digest = 14695981039346656037ULL;  // of every cycle's fingerprint, in order
  std::size_t stops = 0;
  std::size_t not_ok = 0;
  std::size_t not_finite = 0;
  std::size_t wraps = 0;
  double seconds = 0.0;
};

Run run(const char* name, const sg::TelemetryLog& base, std::uint64_t offset_ms, std::size_t cycles) {
  const se::TiledLog log(base, offset_ms);
  sg::ReplayConfig config;
  config.gravity_mps2 = sg::log_gravity(base);
  sg::OnboardLoop loop(config);
  Run r;
  const long rss0 = peak_rss_kib();
  long rss_prev = rss0;
  std::printf("%s: %zu cycles from %.3f s to %.3f s on the on-board clock\n", name, cycles,
              log.row(0).time_s, log.row(cycles - 1).time_s);
  std::printf("  %9s %14s %16s\n", "cycles", "peak RSS KiB", "growth KiB");
  std::printf("  %9d %14ld %16s\n", 0, rss0, "-");
  double prev_t = -1.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < cycles; ++i) {
    const sg::TelemetryRow row = log.row(i);
    if (row.time_s < prev_t) ++r.wraps;
    prev_t = row.time_s;
    const sg::CycleRecord c = loop.step(row, name, 0.0);
    const std::uint64_t fp = se::fingerprint(c);
    r.digest = (r.digest ^ fp) * 1099511628211ULL;
    if (c.decision == sinkwatch::flight::RoverDecision::stop_and_replan) ++r.stops;
    if (c.status != sinkwatch::flight::RoverStepStatus::ok) ++r.not_ok;
    if (!se::all_finite(c)) ++r.not_finite;
    if ((i + 1) % 100000 == 0 || i + 1 == cycles) {
      const long rss = peak_rss_kib();
      std::printf("  %9zu %14ld %16ld\n", i + 1, rss, rss - rss_prev);
      rss_prev = rss;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  %.0f cycles/s (%.2f us a cycle, %.1f s for the log); clock wraps: %zu; stop decisions: %zu; "
              "cycles not ok: %zu; cycles with a non-finite number: %zu\n",
              static_cast<double>(cycles) / r.seconds, 1e6 * r.seconds / static_cast<double>(cycles), r.seconds,
              r.wraps, r.stops, r.not_ok, r.not_finite);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  // Optional argument: the number of cycles (default 24 h at 5 Hz).
  const std::size_t cycles = argc > 1 ? static_cast<std::size_t>(std::strtoull(argv[1], nullptr, 10)) : 432000U;
  const sg::TelemetryLog base = sg::parse_telemetry_text(sg::embedded_scenario_text("nominal"), "nominal");
  std::printf("base: the shipped nominal drive, %zu cycles; sizeof(CycleRecord) = %zu B (run_replay keeps one per "
              "cycle; the stream below keeps none)\n",
              base.rows.size(), sizeof(sg::CycleRecord));
  const Run plain = run("24 h", base, 0U, cycles);
  // Started 12 h (216,000 cycles) before 2^32 ms: the wrap falls mid-log.
  const std::uint64_t offset_ms = se::kClockModulusMs - 43200000ULL;
  const Run wrap = run("24 h across the clock wrap", base, offset_ms, cycles);
  std::printf("same decisions and numbers, cycle for cycle, with and without the wrap: %s\n",
              plain.digest == wrap.digest ? "yes" : "NO");
  return plain.digest == wrap.digest ? 0 : 1;
}
