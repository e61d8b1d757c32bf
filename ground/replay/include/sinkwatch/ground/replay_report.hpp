// What `sinkwatch replay` prints and writes: the compact report, the full
// time series as CSV and the gnuplot plot (docs/replay.md, "Output").
#pragma once

#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <array>
#include <iosfwd>
#include <optional>
#include <string>

namespace sinkwatch::ground {

struct ReportOptions {
  bool verbose = false;     // one line per cycle
  double every_s = 30.0;    // a status line at least this often (besides changes)
  std::string title;        // e.g. "embedded default scenario 'embedding'"
};

/// The simulated embedding a scenario records, when it has one.
struct EmbeddingTruth {
  double x_m = 0.0;
  double time_s = 0.0;
  std::string reason;
};
std::optional<EmbeddingTruth> log_embedding(const TelemetryLog& log);

/// How far before the embedding the rover stopped (negative: after it).
struct Lead {
  double distance_m = 0.0;
  double time_s = 0.0;
};
std::optional<Lead> stop_lead(const TelemetryLog& log, const ReplayResult& result);

/// One telemetry channel's health over a replay (the flight code's own
/// verdicts, sensor_health.hpp).
struct ChannelHealthSummary {
  std::array<std::size_t, flight::kSensorHealthCount> cycles{};  // by SensorHealth
  std::array<std::optional<double>, flight::kSensorHealthCount> first_s{};  // first report of each health
  std::size_t episodes = 0;             // ok (or the start) -> not ok
  std::optional<double> back_to_ok_s;   // the last return to ok after a fault
  bool ok_at_end = true;
};
std::array<ChannelHealthSummary, flight::kSensorChannelCount> channel_health(const ReplayResult& result);

void print_report(std::ostream& out, const TelemetryLog& log, const ReplayConfig& config,
                  const ReplayResult& result, const ReportOptions& options);

/// Every cycle: time, position, status, decision, slip, and per wheel W, DP,
/// I, I_max, T, z and state, the escape and the simulator's truth, then each
/// channel's health (health_<channel>), wheels_blind and degraded.
void write_series_csv(std::ostream& out, const TelemetryLog& log, const ReplayResult& result);

/// The gnuplot script that draws currents against limits, sinkage and the
/// decisions over time into `image_path` (.png or .svg).
std::string plot_script(const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& result,
                        const std::string& image_path);

/// Checks, before any work, that the plot can be written to `image_path`
/// and its script to IMAGE.gp (docs/output-files.md); "-" is refused.
/// Throws OutputError naming the path.
void check_plot_path(const std::string& image_path);

/// Runs gnuplot on plot_script() into a temporary beside the image, and
/// renames it into place when gnuplot exited 0 and the image is not empty.
/// Returns an empty string on success, or, when gnuplot is not installed, a
/// note for the user: the script is then written next to the image as
/// IMAGE.gp so it can be drawn later. Throws (naming the path, with gnuplot's
/// messages) when the path cannot be written or gnuplot fails; nothing is
/// left behind then.
std::string draw_plot(const TelemetryLog& log, const ReplayConfig& config, const ReplayResult& result,
                      const std::string& image_path);

}  // namespace sinkwatch::ground
