// soil_bin_csv.cpp: the soil-bin CSV reader (see the header for the forms).
#include "sinkwatch/ground/soil_bin_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

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
    out << ": column '" << column_name << "'";
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

struct Header {
  std::size_t line = 0;
  std::vector<std::string> names;

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

// Reads one line into `line`, without the trailing CR of a CRLF file.
bool next_line(std::istream& in, std::string& line) {
  if (!std::getline(in, line)) {
    return false;
  }
  if (!line.empty() && line.back() == '\r') {
    line.pop_back();
  }
  return true;
}

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
      fail(index, "'" + std::string(text) + "' is out of the range of a double");
    }
    if (error != std::errc() || end != digits.data() + digits.size()) {
      fail(index, "'" + std::string(text) + "' is not a number");
    }
    if (!std::isfinite(value)) {
      fail(index, "'" + std::string(text) + "' is not a finite number");
    }
    return value;
  }

  [[nodiscard]] double positive(std::size_t index) const {
    const double value = number(index);
    if (!(value > 0.0)) {
      fail(index, "'" + std::string(fields_[index]) + "' must be greater than zero");
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

SoilBinDataset parse_soil_bin_csv(std::istream& in, const std::string& source,
                                  const SoilBinReadOptions& options) {
  if (options.wheel_radius_m && !(std::isfinite(*options.wheel_radius_m) &&
                                  *options.wheel_radius_m > 0.0)) {
    throw DataError(source, 0, 0, "", "the wheel radius must be a finite number greater than zero");
  }
  if (options.load_n && !(std::isfinite(*options.load_n) && *options.load_n > 0.0)) {
    throw DataError(source, 0, 0, "", "the wheel load must be a finite number greater than zero");
  }

  std::string text;
  std::size_t line_number = 0;

  // Header: the first line that is neither blank nor a comment.
  Header header;
  while (next_line(in, text)) {
    ++line_number;
    if (is_skipped(text)) {
      continue;
    }
    header.line = line_number;
    for (std::string_view name : split_fields(text)) {
      const std::size_t column = header.names.size() + 1;
      if (name.empty()) {
        throw DataError(source, line_number, column, "", "empty column name in the header");
      }
      if (header.find(name) != kAbsent) {
        throw DataError(source, line_number, column, std::string(name),
                        "column appears twice in the header");
      }
      header.names.emplace_back(name);
    }
    break;
  }
  if (header.line == 0) {
    throw DataError(source, 0, 0, "", "empty file: no header row (only blank or comment lines)");
  }

  SoilBinDataset dataset;
  dataset.source = source;
  const std::string dimensional_missing = missing_columns(header, kDimensionalColumns);
  const std::string dimensionless_missing = missing_columns(header, kDimensionlessColumns);
  if (dimensional_missing.empty()) {
    dataset.form = SoilBinForm::dimensional;
  } else if (dimensionless_missing.empty()) {
    dataset.form = SoilBinForm::dimensionless;
  } else {
    // Name what is missing for the form the header was apparently meant to be.
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

  const std::size_t slip_col = header.find("slip");
  const std::size_t load_col = header.find("load_N");
  const std::size_t radius_col = header.find("wheel_radius_m");
  if (load_col != kAbsent && options.load_n) {
    throw DataError(source, header.line, load_col + 1, "load_N",
                    "the load is given twice (this column and --load); keep one");
  }
  dataset.has_load = load_col != kAbsent || options.load_n.has_value();
  if (radius_col != kAbsent && options.wheel_radius_m) {
    throw DataError(source, header.line, radius_col + 1, "wheel_radius_m",
                    "the radius is given twice (this column and --radius); keep one");
  }
  if (dataset.form == SoilBinForm::dimensional) {
    if (radius_col == kAbsent && !options.wheel_radius_m) {
      throw DataError(source, header.line, 0, "",
                      "missing wheel radius: the dimensional form needs a wheel_radius_m column "
                      "or --radius");
    }
  }

  while (next_line(in, text)) {
    ++line_number;
    if (is_skipped(text)) {
      continue;
    }
    const std::vector<std::string_view> fields = split_fields(text);
    if (fields.size() != header.names.size()) {
      const std::size_t column = std::min(fields.size(), header.names.size()) + 1;
      const std::string name = fields.size() < header.names.size() ? header.names[column - 1] : "";
      throw DataError(source, line_number, column, name,
                      "wrong number of fields: the header has " +
                          std::to_string(header.names.size()) + ", this row has " +
                          std::to_string(fields.size()));
    }
    const RowParser parse(source, header, line_number, fields);
    SoilBinRow row;
    row.line = line_number;
    row.slip = parse.number(slip_col);
    if (load_col != kAbsent) {
      row.load_n = parse.positive(load_col);
    } else {
      row.load_n = options.load_n;
    }
    if (dataset.form == SoilBinForm::dimensional) {
      const double radius_m =
          radius_col != kAbsent ? parse.positive(radius_col) : *options.wheel_radius_m;
      const double load_n = *row.load_n;
      row.wheel_radius_m = radius_m;
      row.torque_nm = parse.number(header.find("torque_Nm"));
      row.sinkage_m = parse.number(header.find("sinkage_m"));
      row.drawbar_pull_n = parse.number(header.find("drawbar_pull_N"));
      row.sinkage_ratio = *row.sinkage_m / radius_m;
      row.drive_coeff = *row.torque_nm / (radius_m * load_n);
      row.traction_coeff = *row.drawbar_pull_n / load_n;
      if (!std::isfinite(row.sinkage_ratio) || !std::isfinite(row.drive_coeff) ||
          !std::isfinite(row.traction_coeff)) {
        throw DataError(source, line_number, 0, "",
                        "z/r, T/(rW) or DP/W is not a finite number (extreme values in this row)");
      }
    } else {
      row.sinkage_ratio = parse.number(header.find("sinkage_ratio"));
      row.drive_coeff = parse.number(header.find("drive_coeff"));
      row.traction_coeff = parse.number(header.find("traction_coeff"));
      // Not needed for the fit, but carried for tools that need the size.
      row.wheel_radius_m =
          radius_col != kAbsent ? parse.positive(radius_col) : options.wheel_radius_m;
    }
    dataset.rows.push_back(row);
  }
  if (in.bad()) {
    throw DataError(source, line_number, 0, "", "read error");
  }
  if (dataset.rows.empty()) {
    throw DataError(source, header.line, 0, "", "no data rows after the header");
  }
  return dataset;
}

SoilBinDataset read_soil_bin_csv(const std::string& path, const SoilBinReadOptions& options) {
  std::ifstream in(path);
  if (!in) {
    throw DataError(path, 0, 0, "", "cannot open the file for reading");
  }
  return parse_soil_bin_csv(in, path, options);
}

}  // namespace ground
}  // namespace sinkwatch
