// Rover telemetry logs for `sinkwatch replay`: the CSV format, its reader and
// its writer (docs/replay.md, "Columns").
//
// One row per control cycle. The flight code sees only the measured columns
// (time, validity, six motor currents, direction, attitude, joint angles,
// acceleration, speeds); the optional truth columns (x_m, true_slip,
// true_sinkage_mm, phase) come from a simulator and are used for the report and
// the plot, never by the flight code. Lines starting with '#' before the header
// are comments; "# key: value" comments are kept as metadata (a scenario
// records its gravity, seed and simulated embedding there).
//
// The input rules (docs/input-files.md) are those of every ground CSV reader:
// "-" reads standard input, a directory or a binary file is refused, a leading
// UTF-8 byte-order mark is skipped, an unknown column is an error unless its
// name starts with "note", and every number must lie in its column's physical
// range (gravity_mps2, mass_kg, embedding_x_m and embedding_time_s metadata
// too; mass_kg within the flight code's (0, 1000] kg).
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sinkwatch::ground {

inline constexpr std::size_t kTelemetryWheels = 6;
/// Wheel names in the flight code's order (left front, middle, rear, then right).
inline constexpr std::array<const char*, kTelemetryWheels> kWheelNames{"LF", "LM", "LR", "RF", "RM", "RR"};

/// One control cycle of telemetry, in engineering units (double, host side).
struct TelemetryRow {
  std::size_t line = 0;  // 1-based line in the source file (0: not from a file)
  double time_s = 0.0;
  bool valid = true;
  std::array<double, kTelemetryWheels> current_a{};  // signed: positive drives forward
  // A dropout: the sensor delivered nothing this cycle (an empty cell in the
  // CSV). The value beside a missing flag is 0 and means nothing; the flight
  // code gets the flag (RoverTelemetry::presence), never the 0 as a reading.
  std::array<bool, kTelemetryWheels> current_missing{};
  bool reverse = false;                              // commanded direction of all six wheels
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
  std::array<double, 2> rocker_deg{};  // left, right
  std::array<double, 2> bogie_deg{};
  // One flag for pitch and roll, one for the four joint angles, as the flight
  // code has (SensorPresence): an empty cell in either group marks its whole
  // group missing, all its values 0.
  bool attitude_missing = false;
  bool joints_missing = false;
  std::optional<double> accel_mps2;     // along the path (IMU); empty: not measured
  std::optional<double> speed_mps;      // over the ground (VO / odometry)
  std::optional<double> rim_speed_mps;  // mean r*omega of the driven wheels
  // Simulator truth (optional, never given to the flight code).
  std::optional<double> x_m;
  std::optional<double> true_slip;
  std::optional<double> true_sinkage_mm;  // deepest wheel
  std::string phase;                      // e.g. "drive", "escape-fwd"
};

/// Where a metadata value stands in its file (1-based; 0: not from a file).
struct MetadataPosition {
  std::size_t line = 0;
  std::size_t column = 0;
};

struct TelemetryLog {
  std::string source;                          // file name, or "<embedded default>"
  std::vector<std::string> comments;          // every '#' line, without the '#'
  std::map<std::string, std::string> metadata;  // "# key: value" lines
  std::map<std::string, MetadataPosition> metadata_at;  // where each value was read
  std::vector<TelemetryRow> rows;

  /// metadata[key] as a number, or nullopt when absent.
  /// Throws TelemetryError when present but not a number.
  std::optional<double> number(const std::string& key) const;
};

/// A problem in a telemetry file, with its position ("file:line:column: ...";
/// a line or column of 0, not tied to one, is left out).
class TelemetryError : public std::runtime_error {
 public:
  TelemetryError(const std::string& source, std::size_t line, std::size_t column, const std::string& message);
  std::size_t line() const { return line_; }
  std::size_t column() const { return column_; }

 private:
  std::size_t line_;
  std::size_t column_;
};

/// The column names the reader knows, in the order the writer uses.
const std::vector<std::string>& telemetry_columns();

/// Parses a whole log. `source` names the input in error messages.
/// Throws TelemetryError on the first bad line (unknown, missing or
/// conflicting column, a cell that is not a number or outside its column's
/// physical range, wrong cell count, time going backwards, binary bytes).
TelemetryLog read_telemetry_csv(std::istream& in, const std::string& source);
/// Opens and reads a file; "-" reads standard input (named "<stdin>").
/// A missing file or a directory is a TelemetryError too.
TelemetryLog read_telemetry_file(const std::string& path);
TelemetryLog parse_telemetry_text(const std::string& text, const std::string& source);

/// Writes comments ("# " + line), metadata ("# key: value"), the header and
/// the rows; numbers with enough digits that reading them back gives the same
/// doubles.
void write_telemetry_csv(std::ostream& out, const TelemetryLog& log);

/// One row as the writer formats it (no newline), and back: used by the
/// scenario generator so that the flight code in the loop sees exactly the
/// numbers the file will hold.
std::string format_telemetry_row(const TelemetryRow& row);
TelemetryRow parse_telemetry_row(const std::string& line);

}  // namespace sinkwatch::ground
