// soil_bin_csv.cpp: the soil-bin CSV reader (see the header for the forms).
#include "sinkwatch/ground/soil_bin_csv.hpp"

#include <iostream>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <sstream>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>

#include "sinkwatch/ground/text_input.hpp"

namespace sinkwatch {
namespace ground {

namespace {

std::string format_location(const std::string& source, std::size_t line, std::size_t column,
                            const std::string& column_name) {
  std::ostringstream out;
  out << source;
  if (line > 0) {
    out << ':' << line;
    if (column > 0) {
      out << ':' << column;
    }
  }
  if (!column_name.empty()) {
    out << ": column " << text_input::quoted(column_name, 60);
  }
  return out.str();
}

std::string_view trim(std::string_view text) {
  const char* const blanks = " \t\r\n";
  const std::size_t first = text.find_first_not_of(blanks);
  if (first == std::string_view::npos) {
    return {};
  }
  const std::size_t last = text.find_last_not_of(blanks);
  return text.substr(first, last - first + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(line.substr(start)));
      return fields;
    }
    fields.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

// The columns each form needs; "slip" is shared.
constexpr std::array<const char*, 5> kDimensionalColumns = {"slip", "load_N", "torque_Nm",
                                                            "sinkage_m", "drawbar_pull_N"};
constexpr std::array<const char*, 4> kDimensionlessColumns = {"slip", "sinkage_ratio",
                                                              "drive_coeff", "traction_coeff"};

constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);

// Every column the reader knows, with its physical range: generous enough for
// any real wheel and soil bin, narrow enough to catch nonsense (1e300, a
// length in millimetres in a metre column). docs/input-files.md has the table.
struct KnownColumn {
  const char* name;
  text_input::Range range;
};
constexpr double kMaxLoadN = 1e5;  // 10 t on one wheel
const std::array<KnownColumn, 11> kKnownColumns = {{
    {"slip", {-1.0, 1.0, false, false, ""}},
    {"load_N", {0.0, kMaxLoadN, true, false, "N"}},
    {"torque_Nm", {-1e4, 1e4, false, false, "N m"}},
    {"sinkage_m", {-1.0, 10.0, false, false, "m"}},
    {"drawbar_pull_N", {-kMaxLoadN, kMaxLoadN, false, false, "N"}},
    {"wheel_radius_m", {0.0, 5.0, true, false, "m"}},
    {"wheel_width_m", {0.0, 5.0, true, false, "m"}},
    {"sinkage_ratio", {-1.0, 2.0, false, false, ""}},
    {"drive_coeff", {-10.0, 10.0, false, false, ""}},
    {"traction_coeff", {-10.0, 10.0, false, false, ""}},
    {"paper_eq10_fit", {-20.0, 20.0, false, false, ""}},
}};

const KnownColumn* known_column(std::string_view name) {
  for (const KnownColumn& column : kKnownColumns) {
    if (name == column.name) {
      return &column;
    }
  }
  return nullptr;
}

const text_input::Range& range_of(std::string_view name) { return known_column(name)->range; }

std::string known_column_list() {
  std::string list;
  for (const KnownColumn& column : kKnownColumns) {
    list += list.empty() ? "" : ", ";
    list += column.name;
  }
  return list;
}

struct Header {
  std::size_t line = 0;
  std::vector<std::string> names;
  std::vector<const text_input::Range*> ranges;  // per column; nullptr: a note column

  [[nodiscard]] std::size_t find(std::string_view name) const {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) {
        return i;
      }
    }
    return kAbsent;
  }
};

template <std::size_t N>
std::string missing_columns(const Header& header, const std::array<const char*, N>& wanted) {
  std::string missing;
  for (const char* name : wanted) {
    if (header.find(name) == kAbsent) {
      missing += missing.empty() ? "" : ", ";
      missing += name;
    }
  }
  return missing;
}

// Reads the input line by line, counting lines: drops the trailing CR of a
// CRLF file and a UTF-8 byte-order mark at the start, and refuses a line
// holding a byte that text does not contain (binary input).
class LineReader {
 public:
  LineReader(std::istream& in, const std::string& source) : in_(in), source_(source) {}

  bool next(std::string& line) {
    if (!std::getline(in_, line)) {
      return false;
    }
    ++number_;
    if (number_ == 1) {
      (void)text_input::strip_bom(line);
    }
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
    }
    if (const std::optional<std::size_t> at = text_input::first_binary_byte(line)) {
      throw DataError(source_, number_, *at + 1, "",
                      text_input::binary_message(static_cast<unsigned char>(line[*at])));
    }
    return true;
  }

  [[nodiscard]] std::size_t number() const noexcept { return number_; }

 private:
  std::istream& in_;
  const std::string& source_;
  std::size_t number_ = 0;
};

bool is_skipped(std::string_view line) {
  const std::string_view body = trim(line);
  return body.empty() || body.front() == '#';
}

class RowParser {
 public:
  RowParser(const std::string& source, const Header& header, std::size_t line,
            const std::vector<std::string_view>& fields)
      : source_(source), header_(header), line_(line), fields_(fields) {}

  // The finite number in column `index` (0-based).
  [[nodiscard]] double number(std::size_t index) const {
    std::string_view text = fields_[index];
    if (text.empty()) {
      fail(index, "empty field, expected a number");
    }
    std::string_view digits = text;
    if (digits.front() == '+') {
      digits.remove_prefix(1);  // from_chars rejects a leading '+', CSV writers emit it
    }
    double value = 0.0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error == std::errc::result_out_of_range) {
      fail(index, text_input::quoted(text) + " is out of the range of a double");
    }
    if (error != std::errc() || end != digits.data() + digits.size()) {
      fail(index, text_input::quoted(text) + " is not a number");
    }
    if (!std::isfinite(value)) {
      fail(index, text_input::quoted(text) + " is not a finite number");
    }
    return value;
  }

  // The number in column `index`, inside the column's physical range.
  [[nodiscard]] double checked(std::size_t index) const {
    const double value = number(index);
    const text_input::Range& range = *header_.ranges[index];
    if (!range.contains(value)) {
      if (range.min == 0.0 && range.min_open && value <= 0.0) {
        fail(index, text_input::quoted(fields_[index]) + " must be greater than zero");
      }
      fail(index, text_input::out_of_range_message(value, range));
    }
    return value;
  }

  [[noreturn]] void fail(std::size_t index, const std::string& detail) const {
    throw DataError(source_, line_, index + 1, header_.names[index], detail);
  }

 private:
  const std::string& source_;
  const Header& header_;
  std::size_t line_;
  const std::vector<std::string_view>& fields_;
};

}  // namespace

DataError::DataError(std::string source, std::size_t line, std::size_t column,
                     std::string column_name, const std::string& detail)
    : std::runtime_error(format_location(source, line, column, column_name) + ": " + detail),
      source_(std::move(source)),
      line_(line),
      column_(column),
      column_name_(std::move(column_name)),
      detail_(detail) {}

const char* to_string(SoilBinForm form) noexcept {
  switch (form) {
    case SoilBinForm::dimensional:
      return "dimensional";
    case SoilBinForm::dimensionless:
      return "dimensionless";
  }
  return "unknown";
}

namespace {

// --radius, --load and --width, when given, are in their columns' ranges.
void check_options(const SoilBinReadOptions& options, const std::string& source) {
  const std::array<std::tuple<const std::optional<double>&, const char*, const char*>, 3> given = {{
      {options.wheel_radius_m, "wheel_radius_m", "the wheel radius"},
      {options.load_n, "load_N", "the wheel load"},
      {options.wheel_width_m, "wheel_width_m", "the wheel width"},
  }};
  for (const auto& [value, column, what] : given) {
    if (value && !range_of(column).contains(*value)) {
      throw DataError(source, 0, 0, "",
                      std::string(what) + " must be a finite number in " +
                          range_of(column).describe() + ", got " +
                          text_input::format_number(*value));
    }
  }
}

// The header's column names, each known or a note column, none twice.
void read_header_names(std::string_view text, const std::string& source, Header& header) {
  for (std::string_view name : split_fields(text)) {
    const std::size_t column = header.names.size() + 1;
    if (name.empty()) {
      throw DataError(source, header.line, column, "", "empty column name in the header");
    }
    if (header.find(name) != kAbsent) {
      throw DataError(source, header.line, column, std::string(name),
                      "column appears twice in the header");
    }
    if (known_column(name) == nullptr && !text_input::is_note_column(name)) {
      throw DataError(source, header.line, column, std::string(name),
                      "unknown column; the known columns are " + known_column_list() +
                          " (a column whose name starts with 'note' is ignored)");
    }
    const KnownColumn* const known = known_column(name);
    header.ranges.push_back(known != nullptr ? &known->range : nullptr);
    header.names.emplace_back(name);
  }
}

// The header: the first line that is neither blank nor a comment.
Header read_header(std::istream& in, LineReader& lines, const std::string& source) {
  Header header;
  std::string text;
  while (lines.next(text)) {
    if (!is_skipped(text)) {
      header.line = lines.number();
      read_header_names(text, source, header);
      break;
    }
  }
  if (in.bad()) {
    throw DataError(source, lines.number(), 0, "", "read error");
  }
  if (header.line == 0) {
    throw DataError(source, 0, 0, "", "empty file: no header row (only blank or comment lines)");
  }
  return header;
}

// The form whose columns the header holds; otherwise an error naming what is
// missing for the form the header was apparently meant to be.
SoilBinForm form_of(const Header& header, const std::string& source) {
  const std::string dimensional_missing = missing_columns(header, kDimensionalColumns);
  const std::string dimensionless_missing = missing_columns(header, kDimensionlessColumns);
  if (dimensional_missing.empty()) {
    return SoilBinForm::dimensional;
  }
  if (dimensionless_missing.empty()) {
    return SoilBinForm::dimensionless;
  }
  const bool looks_dimensional = header.find("torque_Nm") != kAbsent ||
                                 header.find("sinkage_m") != kAbsent ||
                                 header.find("drawbar_pull_N") != kAbsent;
  const bool looks_dimensionless = header.find("sinkage_ratio") != kAbsent ||
                                   header.find("drive_coeff") != kAbsent ||
                                   header.find("traction_coeff") != kAbsent;
  std::string detail;
  if (looks_dimensional && !looks_dimensionless) {
    detail = "missing column(s) " + dimensional_missing +
             " for the dimensional form (slip, load_N, torque_Nm, sinkage_m, drawbar_pull_N)";
  } else if (looks_dimensionless && !looks_dimensional) {
    detail = "missing column(s) " + dimensionless_missing +
             " for the dimensionless form (slip, sinkage_ratio, drive_coeff, traction_coeff)";
  } else {
    detail = "the header has neither the dimensional columns (missing " + dimensional_missing +
             ") nor the dimensionless columns (missing " + dimensionless_missing + ")";
  }
  throw DataError(source, header.line, 0, "", detail);
}

// Where the shared columns are, each column or its option (never both).
struct Columns {
  std::size_t slip = kAbsent;
  std::size_t load = kAbsent;
  std::size_t radius = kAbsent;
  std::size_t width = kAbsent;
};

Columns locate_columns(const Header& header, SoilBinForm form, const SoilBinReadOptions& options,
                       const std::string& source) {
  const Columns columns{header.find("slip"), header.find("load_N"), header.find("wheel_radius_m"),
                        header.find("wheel_width_m")};
  if (columns.load != kAbsent && options.load_n) {
    throw DataError(source, header.line, columns.load + 1, "load_N",
                    "the load is given twice (this column and --load); keep one");
  }
  if (columns.radius != kAbsent && options.wheel_radius_m) {
    throw DataError(source, header.line, columns.radius + 1, "wheel_radius_m",
                    "the radius is given twice (this column and --radius); keep one");
  }
  if (columns.width != kAbsent && options.wheel_width_m) {
    throw DataError(source, header.line, columns.width + 1, "wheel_width_m",
                    "the width is given twice (this column and --width); keep one");
  }
  if (form == SoilBinForm::dimensional && columns.radius == kAbsent && !options.wheel_radius_m) {
    throw DataError(source, header.line, 0, "",
                    "missing wheel radius: the dimensional form needs a wheel_radius_m column "
                    "or --radius");
  }
  return columns;
}

// The row's fields, split; a row with a field too many or too few is an
// error at the first field that does not match the header.
std::vector<std::string_view> row_fields(std::string_view text, const Header& header,
                                         const std::string& source, std::size_t line_number) {
  std::vector<std::string_view> fields = split_fields(text);
  if (fields.size() != header.names.size()) {
    const std::size_t column = std::min(fields.size(), header.names.size()) + 1;
    const std::string name = fields.size() < header.names.size() ? header.names[column - 1] : "";
    throw DataError(source, line_number, column, name,
                    "wrong number of fields: the header has " +
                        std::to_string(header.names.size()) + ", this row has " +
                        std::to_string(fields.size()));
  }
  return fields;
}

// The ratios of a dimensional row. Each measurement is in range, but a unit
// mistake (millimetres in a metre column) shows in the ratios: they get the
// ranges of the dimensionless columns.
void set_dimensional_ratios(SoilBinRow& row, const std::string& source) {
  const double radius_m = *row.wheel_radius_m;
  const double load_n = *row.load_n;
  row.sinkage_ratio = *row.sinkage_m / radius_m;
  row.drive_coeff = *row.torque_nm / (radius_m * load_n);
  row.traction_coeff = *row.drawbar_pull_n / load_n;
  for (const auto& [name, ratio] :
       {std::pair<const char*, double>{"sinkage_ratio", row.sinkage_ratio},
        {"drive_coeff", row.drive_coeff},
        {"traction_coeff", row.traction_coeff}}) {
    if (!range_of(name).contains(ratio)) {
      throw DataError(source, row.line, 0, "",
                      std::string(name == std::string_view("sinkage_ratio") ? "z/r"
                                  : name == std::string_view("drive_coeff")  ? "T/(rW)"
                                                                              : "DP/W") +
                          " = " + text_input::out_of_range_message(ratio, range_of(name)) +
                          " (check the units of this row)");
    }
  }
}

// What the reader needs to turn a data line into a row.
struct RowContext {
  const std::string& source;
  const Header& header;
  const Columns& columns;
  SoilBinForm form;
  const SoilBinReadOptions& options;
};

SoilBinRow parse_row(std::string_view text, std::size_t line_number, const RowContext& context) {
  const Header& header = context.header;
  const std::vector<std::string_view> fields =
      row_fields(text, header, context.source, line_number);
  const RowParser parse(context.source, header, line_number, fields);
  // Every known column is a number in its range, used or not (a column
  // that is there is checked); the note columns are free text.
  std::vector<double> values(fields.size(), 0.0);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (header.ranges[i] != nullptr) {
      values[i] = parse.checked(i);
    }
  }
  const auto value = [&](const char* name) { return values[header.find(name)]; };
  const auto column_or_option = [&values](std::size_t column, const std::optional<double>& option) {
    return column != kAbsent ? std::optional<double>(values[column]) : option;
  };
  SoilBinRow row;
  row.line = line_number;
  row.slip = values[context.columns.slip];
  row.load_n = column_or_option(context.columns.load, context.options.load_n);
  row.wheel_radius_m = column_or_option(context.columns.radius, context.options.wheel_radius_m);
  row.wheel_width_m = column_or_option(context.columns.width, context.options.wheel_width_m);
  if (context.form == SoilBinForm::dimensional) {
    row.torque_nm = value("torque_Nm");
    row.sinkage_m = value("sinkage_m");
    row.drawbar_pull_n = value("drawbar_pull_N");
    set_dimensional_ratios(row, context.source);
  } else {
    row.sinkage_ratio = value("sinkage_ratio");
    row.drive_coeff = value("drive_coeff");
    row.traction_coeff = value("traction_coeff");
  }
  return row;
}

}  // namespace

SoilBinDataset parse_soil_bin_csv(std::istream& in, const std::string& source,
                                  const SoilBinReadOptions& options) {
  check_options(options, source);
  LineReader lines(in, source);
  const Header header = read_header(in, lines, source);

  SoilBinDataset dataset;
  dataset.source = source;
  dataset.form = form_of(header, source);
  const Columns columns = locate_columns(header, dataset.form, options, source);
  dataset.has_load = columns.load != kAbsent || options.load_n.has_value();

  const RowContext context{source, header, columns, dataset.form, options};
  std::string text;
  while (lines.next(text)) {
    if (!is_skipped(text)) {
      dataset.rows.push_back(parse_row(text, lines.number(), context));
    }
  }
  if (in.bad()) {
    throw DataError(source, lines.number(), 0, "", "read error");
  }
  if (dataset.rows.empty()) {
    throw DataError(source, header.line, 0, "", "no data rows after the header");
  }
  return dataset;
}

SoilBinDataset read_soil_bin_csv(const std::string& path, const SoilBinReadOptions& options) {
  if (path == text_input::kStdinPath) {
    return parse_soil_bin_csv(std::cin, text_input::kStdinName, options);
  }
  const std::string problem = text_input::unreadable_reason(path);
  if (!problem.empty()) {
    throw DataError(path, 0, 0, "", problem);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw DataError(path, 0, 0, "", "cannot open the file for reading");
  }
  return parse_soil_bin_csv(in, path, options);
}

}  // namespace ground
}  // namespace sinkwatch
