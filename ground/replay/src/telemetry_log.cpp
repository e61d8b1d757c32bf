// Telemetry CSV reader and writer (telemetry_log.hpp, docs/replay.md).
#include "sinkwatch/ground/telemetry_log.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <istream>
#include <ostream>
#include <sstream>

#include "sinkwatch/flight/rover_limits.hpp"
#include "sinkwatch/ground/text_input.hpp"

namespace sinkwatch::ground {
namespace {

// Column identifiers; the writer's order.
enum Col : int {
  kTimeS, kTimeMs, kValid,
  kI0, kI1, kI2, kI3, kI4, kI5,
  kDirection, kPitch, kRoll, kRockerL, kRockerR, kBogieL, kBogieR,
  kAccel, kSpeed, kRimSpeed,
  kX, kTrueSlip, kTrueSinkage, kPhase,
  kColCount
};

const std::vector<std::string> kNames = {
    "time_s",     "time_ms",     "valid",       "i_lf_a",       "i_lm_a",        "i_lr_a",
    "i_rf_a",     "i_rm_a",      "i_rr_a",      "direction",    "pitch_deg",     "roll_deg",
    "rocker_l_deg", "rocker_r_deg", "bogie_l_deg", "bogie_r_deg", "accel_mps2",   "speed_mps",
    "rim_speed_mps", "x_m",       "true_slip",   "true_sinkage_mm", "phase"};

using text_input::Range;

// The physical range of each numeric column: generous enough for any real
// rover, narrow enough to refuse nonsense such as 1e300 (docs/input-files.md).
const Range kTimeSRange{0.0, 4294967.295, false, false, "s"};  // the flight clock, in ms in 32 bits
const Range kTimeMsRange{0.0, 4294967295.0, false, false, "ms"};
const Range kCurrentRange{-1000.0, 1000.0, false, false, "A"};
const Range kAngleRange{-90.0, 90.0, false, false, "deg"};
const Range kAccelRange{-100.0, 100.0, false, false, "m/s^2"};
const Range kSpeedRange{-100.0, 100.0, false, false, "m/s"};
const Range kPositionRange{-1e6, 1e6, false, false, "m"};
const Range kSlipRange{-1.0, 1.0, false, false, ""};
const Range kSinkageMmRange{-1000.0, 10000.0, false, false, "mm"};
const Range kGravityRange{0.0, 30.0, true, false, "m/s^2"};
// The rover's mass: the flight code's own bound (validate_rover_params).
const Range kMassRange{0.0, flight::limits::kMaxMassKg, true, false, "kg"};

const Range& range_of(int col) {
  switch (col) {
    case kTimeS: return kTimeSRange;
    case kTimeMs: return kTimeMsRange;
    case kI0: case kI1: case kI2: case kI3: case kI4: case kI5: return kCurrentRange;
    case kAccel: return kAccelRange;
    case kSpeed: case kRimSpeed: return kSpeedRange;
    case kX: return kPositionRange;
    case kTrueSlip: return kSlipRange;
    case kTrueSinkage: return kSinkageMmRange;
    default: return kAngleRange;  // pitch, roll, rocker, bogie
  }
}

std::string known_columns() {
  std::string list;
  for (const std::string& name : kNames) list += (list.empty() ? "" : ", ") + name;
  return list;
}

struct Cell {
  std::string text;
  std::size_t column;  // 1-based character column
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<Cell> split(const std::string& line) {
  std::vector<Cell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string raw = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t lead = raw.find_first_not_of(" \t");
    cells.push_back(Cell{trim(raw), start + 1 + (lead == std::string::npos ? 0 : lead)});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

class RowParser {
 public:
  RowParser(std::string source, const std::vector<Cell>& header, std::size_t header_line) : source_(std::move(source)) {
    index_.fill(-1);
    std::vector<std::string> notes;
    for (std::size_t i = 0; i < header.size(); ++i) {
      int id = -1;
      for (int c = 0; c < kColCount; ++c) {
        if (kNames[static_cast<std::size_t>(c)] == header[i].text) id = c;
      }
      if (id < 0 && text_input::is_note_column(header[i].text)) {
        if (std::find(notes.begin(), notes.end(), header[i].text) != notes.end()) {
          throw TelemetryError(source_, header_line, header[i].column,
                               "column " + text_input::quoted(header[i].text) + " appears twice");
        }
        notes.push_back(header[i].text);
        continue;  // annotation: free text, ignored
      }
      if (id < 0) {
        throw TelemetryError(source_, header_line, header[i].column,
                             "unknown column " + text_input::quoted(header[i].text) + "; the known columns are " +
                                 known_columns() + " (a column whose name starts with 'note' is ignored; "
                                 "docs/replay.md)");
      }
      if (index_[static_cast<std::size_t>(id)] >= 0) {
        throw TelemetryError(source_, header_line, header[i].column,
                             "column " + text_input::quoted(header[i].text) + " appears twice");
      }
      if ((id == kTimeS && has(kTimeMs)) || (id == kTimeMs && has(kTimeS))) {
        throw TelemetryError(source_, header_line, header[i].column,
                             "conflicting columns time_s and time_ms: give the time in one of them");
      }
      index_[static_cast<std::size_t>(id)] = static_cast<int>(i);
    }
    columns_ = header.size();
    const auto missing = [&](const std::string& what) {
      throw TelemetryError(source_, header_line, 1, "missing column " + what);
    };
    if (!has(kTimeS) && !has(kTimeMs)) missing("time_s or time_ms (one of them)");
    for (int c : {kI0, kI1, kI2, kI3, kI4, kI5, kPitch, kRoll, kRockerL, kRockerR, kBogieL, kBogieR}) {
      if (!has(c)) missing("'" + kNames[static_cast<std::size_t>(c)] + "'");
    }
    if (!has(kAccel) && !has(kSpeed)) missing("accel_mps2 or speed_mps (the flight code needs an acceleration)");
  }

  TelemetryRow parse(const std::vector<Cell>& cells, std::size_t line) const {
    if (cells.size() != columns_) {
      throw TelemetryError(source_, line, 1,
                           "expected " + std::to_string(columns_) + " cells, found " + std::to_string(cells.size()));
    }
    TelemetryRow r;
    r.line = line;
    if (has(kTimeS)) {
      r.time_s = required(cells, kTimeS, line);
    } else {
      r.time_s = required(cells, kTimeMs, line) / 1000.0;
    }
    if (has(kValid)) {
      const Cell& c = cell(cells, kValid);
      if (c.text == "1") {
        r.valid = true;
      } else if (c.text == "0") {
        r.valid = false;
      } else {
        throw TelemetryError(source_, line, c.column, "column 'valid': expected 0 or 1, got " + text_input::quoted(c.text));
      }
    }
    read_currents(cells, line, r);
    if (has(kDirection)) {
      const Cell& c = cell(cells, kDirection);
      if (c.text == "F") {
        r.reverse = false;
      } else if (c.text == "R") {
        r.reverse = true;
      } else {
        throw TelemetryError(source_, line, c.column,
                             "column 'direction': expected F or R, got " + text_input::quoted(c.text));
      }
    }
    read_attitude_and_joints(cells, line, r);
    r.accel_mps2 = optional(cells, kAccel, line);
    r.speed_mps = optional(cells, kSpeed, line);
    r.rim_speed_mps = optional(cells, kRimSpeed, line);
    r.x_m = optional(cells, kX, line);
    r.true_slip = optional(cells, kTrueSlip, line);
    r.true_sinkage_mm = optional(cells, kTrueSinkage, line);
    if (has(kPhase)) r.phase = cell(cells, kPhase).text;
    return r;
  }

  /// Column of the time cell of a row that parse() accepted.
  std::size_t time_column(const std::vector<Cell>& cells) const {
    return cell(cells, has(kTimeS) ? kTimeS : kTimeMs).column;
  }

 private:
  bool has(int c) const { return index_[static_cast<std::size_t>(c)] >= 0; }
  const Cell& cell(const std::vector<Cell>& cells, int c) const {
    return cells[static_cast<std::size_t>(index_[static_cast<std::size_t>(c)])];
  }
  double number(const Cell& c, int col, std::size_t line) const {
    const std::string& name = kNames[static_cast<std::size_t>(col)];
    if (c.text.empty()) {
      throw TelemetryError(source_, line, c.column, "column '" + name + "': empty cell where a number is required");
    }
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(c.text.c_str(), &end);
    if (end != c.text.c_str() + c.text.size() || errno == ERANGE || !std::isfinite(v)) {
      throw TelemetryError(source_, line, c.column,
                           "column '" + name + "': expected a finite number, got " + text_input::quoted(c.text));
    }
    const Range& range = range_of(col);
    if (!range.contains(v)) {
      if (col == kTimeS || col == kTimeMs) {
        throw TelemetryError(source_, line, c.column,
                             "column '" + name + "': time out of range: " + text_input::out_of_range_message(v, range) +
                                 " (the flight clock)");
      }
      throw TelemetryError(source_, line, c.column, "column '" + name + "': " + text_input::out_of_range_message(v, range));
    }
    return v;
  }
  double required(const std::vector<Cell>& cells, int col, std::size_t line) const {
    return number(cell(cells, col), col, line);
  }
  // A sensor's value, or nothing for an empty cell: a dropout (docs/replay.md).
  std::optional<double> measured(const std::vector<Cell>& cells, int col, std::size_t line) const {
    if (cell(cells, col).text.empty()) return std::nullopt;
    return number(cell(cells, col), col, line);
  }
  void read_currents(const std::vector<Cell>& cells, std::size_t line, TelemetryRow& r) const {
    for (std::size_t w = 0; w < kTelemetryWheels; ++w) {
      const std::optional<double> i = measured(cells, kI0 + static_cast<int>(w), line);
      r.current_missing[w] = !i.has_value();
      r.current_a[w] = i.value_or(0.0);
    }
  }
  // Pitch and roll, and the four joints, are each one sensor to the flight
  // code (one presence flag): a group with an empty cell is missing as a
  // whole, every value of it 0, so that writing the row back gives the same row.
  void read_attitude_and_joints(const std::vector<Cell>& cells, std::size_t line, TelemetryRow& r) const {
    const std::optional<double> pitch = measured(cells, kPitch, line);
    const std::optional<double> roll = measured(cells, kRoll, line);
    r.attitude_missing = !pitch || !roll;
    r.pitch_deg = r.attitude_missing ? 0.0 : *pitch;
    r.roll_deg = r.attitude_missing ? 0.0 : *roll;
    std::array<std::optional<double>, 4> joint{};
    bool all = true;
    for (std::size_t j = 0; j < joint.size(); ++j) {
      joint[j] = measured(cells, kRockerL + static_cast<int>(j), line);
      all = all && joint[j].has_value();
    }
    r.joints_missing = !all;
    r.rocker_deg = {all ? *joint[0] : 0.0, all ? *joint[1] : 0.0};
    r.bogie_deg = {all ? *joint[2] : 0.0, all ? *joint[3] : 0.0};
  }
  std::optional<double> optional(const std::vector<Cell>& cells, int col, std::size_t line) const {
    if (!has(col) || cell(cells, col).text.empty()) return std::nullopt;
    return number(cell(cells, col), col, line);
  }

  std::string source_;
  std::array<int, kColCount> index_{};
  std::size_t columns_ = 0;
};

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string opt(const char* format, const std::optional<double>& v) { return v ? fmt(format, *v) : std::string(); }

std::vector<std::string> writer_header() {
  std::vector<std::string> h;
  for (int c = 0; c < kColCount; ++c) {
    if (c != kTimeMs) h.push_back(kNames[static_cast<std::size_t>(c)]);
  }
  return h;
}

}  // namespace

TelemetryError::TelemetryError(const std::string& source, std::size_t line, std::size_t column,
                               const std::string& message)
    : std::runtime_error(source + (line > 0 ? ":" + std::to_string(line) : std::string()) +
                         (line > 0 && column > 0 ? ":" + std::to_string(column) : std::string()) + ": " + message),
      line_(line),
      column_(column) {}

std::optional<double> TelemetryLog::number(const std::string& key) const {
  const auto it = metadata.find(key);
  if (it == metadata.end()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || end != it->second.c_str() + it->second.size() || !std::isfinite(v)) {
    const auto at = metadata_at.find(key);
    const MetadataPosition where = at != metadata_at.end() ? at->second : MetadataPosition{};
    throw TelemetryError(source, where.line, where.column,
                         "metadata " + text_input::quoted(key) + ": expected a finite number, got " +
                             text_input::quoted(it->second));
  }
  return v;
}

const std::vector<std::string>& telemetry_columns() { return kNames; }

namespace {

// The metadata the tools read as numbers, checked where they are read so that
// a bad value is reported at its line and column.
void check_metadata(const TelemetryLog& log) {
  const std::pair<const char*, const Range*> numeric[] = {
      {"gravity_mps2", &kGravityRange}, {"mass_kg", &kMassRange}, {"embedding_x_m", &kPositionRange},
      {"embedding_time_s", &kTimeSRange}};
  for (const auto& [key, range] : numeric) {
    const auto it = log.metadata.find(key);
    if (it == log.metadata.end() || (std::string(key) == "embedding_x_m" && it->second == "none")) continue;
    const double v = *log.number(key);  // throws, at the value, when not a number
    if (!range->contains(v)) {
      const MetadataPosition& at = log.metadata_at.at(key);
      throw TelemetryError(log.source, at.line, at.column,
                           "metadata '" + std::string(key) + "': " + text_input::out_of_range_message(v, *range));
    }
  }
}

}  // namespace

TelemetryLog read_telemetry_csv(std::istream& in, const std::string& source) {
  TelemetryLog log;
  log.source = source;
  std::optional<RowParser> parser;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1) text_input::strip_bom(line);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (const std::optional<std::size_t> at = text_input::first_binary_byte(line)) {
      throw TelemetryError(source, number, *at + 1, text_input::binary_message(static_cast<unsigned char>(line[*at])));
    }
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      if (parser) continue;  // comments between rows are allowed and ignored
      const std::string body = trim(t.substr(1));
      const auto colon = body.find(':');
      if (colon != std::string::npos && colon > 0 && body.find(' ') > colon) {
        const std::string key = body.substr(0, colon);
        log.metadata[key] = trim(body.substr(colon + 1));
        // The key holds no ':', so the line's first ':' is this one.
        const std::size_t colon_in_line = line.find(':');
        const std::size_t value_at = line.find_first_not_of(" \t", colon_in_line + 1);
        log.metadata_at[key] = MetadataPosition{number, (value_at == std::string::npos ? colon_in_line + 1 : value_at) + 1};
      } else {
        log.comments.push_back(body);
      }
      continue;
    }
    if (!parser) {
      parser.emplace(source, split(line), number);
      check_metadata(log);
      continue;
    }
    const std::vector<Cell> cells = split(line);
    TelemetryRow row = parser->parse(cells, number);
    // A log whose clock runs backwards is corrupt: refuse it where it turns,
    // rather than let the flight code see samples "from the future". Equal
    // stamps are kept: the flight code reports them itself (repeated).
    if (!log.rows.empty() && row.time_s < log.rows.back().time_s) {
      throw TelemetryError(source, number, parser->time_column(cells),
                           "time goes backwards: " + fmt("%.3f", row.time_s) + " s after " +
                               fmt("%.3f", log.rows.back().time_s) + " s at line " +
                               std::to_string(log.rows.back().line));
    }
    log.rows.push_back(std::move(row));
  }
  if (in.bad()) throw TelemetryError(source, number, 0, "read error");
  if (!parser) throw TelemetryError(source, number, 1, "no header line (the file has only comments or is empty)");
  if (log.rows.empty()) throw TelemetryError(source, number, 1, "no data rows after the header");
  return log;
}

TelemetryLog read_telemetry_file(const std::string& path) {
  if (path == text_input::kStdinPath) return read_telemetry_csv(std::cin, text_input::kStdinName);
  const std::string problem = text_input::unreadable_reason(path);
  if (!problem.empty()) throw TelemetryError(path, 0, 0, problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TelemetryError(path, 0, 0, "cannot open the file for reading");
  return read_telemetry_csv(in, path);
}

TelemetryLog parse_telemetry_text(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  return read_telemetry_csv(in, source);
}

std::string format_telemetry_row(const TelemetryRow& r) {
  std::string s = fmt("%.3f", r.time_s);
  s += r.valid ? ",1" : ",0";
  // A missing sensor is an empty cell (its group's every cell for the attitude
  // and the joints).
  for (std::size_t w = 0; w < kTelemetryWheels; ++w) {
    s += "," + (r.current_missing[w] ? std::string() : fmt("%.5f", r.current_a[w]));
  }
  s += r.reverse ? ",R" : ",F";
  for (double a : {r.pitch_deg, r.roll_deg}) s += "," + (r.attitude_missing ? std::string() : fmt("%.4f", a));
  for (double a : {r.rocker_deg[0], r.rocker_deg[1], r.bogie_deg[0], r.bogie_deg[1]}) {
    s += "," + (r.joints_missing ? std::string() : fmt("%.4f", a));
  }
  s += "," + opt("%.5f", r.accel_mps2);
  s += "," + opt("%.5f", r.speed_mps);
  s += "," + opt("%.5f", r.rim_speed_mps);
  s += "," + opt("%.4f", r.x_m);
  s += "," + opt("%.4f", r.true_slip);
  s += "," + opt("%.2f", r.true_sinkage_mm);
  s += "," + r.phase;
  return s;
}

TelemetryRow parse_telemetry_row(const std::string& line) {
  std::vector<Cell> header;
  std::size_t col = 1;
  for (const std::string& h : writer_header()) {
    header.push_back(Cell{h, col});
    col += h.size() + 1;
  }
  const RowParser parser("<row>", header, 1);
  return parser.parse(split(line), 2);
}

void write_telemetry_csv(std::ostream& out, const TelemetryLog& log) {
  for (const std::string& c : log.comments) out << "# " << c << '\n';
  for (const auto& [key, value] : log.metadata) out << "# " << key << ": " << value << '\n';
  const std::vector<std::string> header = writer_header();
  for (std::size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << '\n';
  for (const TelemetryRow& r : log.rows) out << format_telemetry_row(r) << '\n';
}

}  // namespace sinkwatch::ground
