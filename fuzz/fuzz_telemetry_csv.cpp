// libFuzzer harness: the replay tool's telemetry CSV reader
// (ground/replay telemetry_log.hpp, parse_telemetry_text).
//
// Input: the CSV text. Besides "no crash, no sanitizer finding":
//   * the only exception is TelemetryError (the header's contract); any other
//     escapes and libFuzzer reports it as a crash;
//   * a TelemetryError's line is 0 or within the text;
//   * an accepted log has rows, in non-decreasing time on the flight clock's
//     range (0 .. 4294967.295 s), every measured number finite, a missing
//     sensor's values 0 (an empty cell is a dropout, never a reading), and
//     the metadata's numbers either parse or throw TelemetryError.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sinkwatch/ground/telemetry_log.hpp"

namespace sg = sinkwatch::ground;

namespace {
void check(bool condition) {
  if (!condition) {
    std::abort();
  }
}
bool finite_or_empty(const std::optional<double>& v) { return !v.has_value() || std::isfinite(*v); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::size_t lines = 1U;
  for (char ch : text) {
    lines += (ch == '\n') ? 1U : 0U;
  }
  try {
    const sg::TelemetryLog log = sg::parse_telemetry_text(text, "fuzz.csv");
    check(!log.rows.empty());
    double previous_time = 0.0;
    for (const sg::TelemetryRow& row : log.rows) {
      check(row.line >= 1U && row.line <= lines);
      check(std::isfinite(row.time_s) && row.time_s >= 0.0 && row.time_s <= 4294967.295);
      check(row.time_s >= previous_time);
      previous_time = row.time_s;
      for (std::size_t w = 0U; w < row.current_a.size(); ++w) {
        check(std::isfinite(row.current_a[w]));
        check(!row.current_missing[w] || row.current_a[w] == 0.0);
      }
      check(!row.attitude_missing || (row.pitch_deg == 0.0 && row.roll_deg == 0.0));
      check(!row.joints_missing || (row.rocker_deg[0] == 0.0 && row.rocker_deg[1] == 0.0 &&
                                    row.bogie_deg[0] == 0.0 && row.bogie_deg[1] == 0.0));
      check(std::isfinite(row.pitch_deg) && std::isfinite(row.roll_deg));
      for (std::size_t s = 0U; s < 2U; ++s) {
        check(std::isfinite(row.rocker_deg[s]) && std::isfinite(row.bogie_deg[s]));
      }
      check(finite_or_empty(row.accel_mps2) && finite_or_empty(row.speed_mps) && finite_or_empty(row.rim_speed_mps));
    }
    for (const auto& entry : log.metadata) {
      try {
        (void)log.number(entry.first);
      } catch (const sg::TelemetryError&) {
        // documented: present but not a number
      }
    }
  } catch (const sg::TelemetryError& e) {
    check(e.line() <= lines);
  }
  return 0;
}
