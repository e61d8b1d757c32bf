// text_input.cpp: the input rules shared by the CSV readers (text_input.hpp).
#include "sinkwatch/ground/text_input.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <sys/stat.h>

namespace sinkwatch {
namespace ground {
namespace text_input {

std::string unreadable_reason(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    return "is a directory, not a file";
  }
  const std::ifstream in(path);
  if (!in) {
    return "cannot open the file for reading";
  }
  return {};
}

bool strip_bom(std::string& line) {
  if (line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEFU &&
      static_cast<unsigned char>(line[1]) == 0xBBU && static_cast<unsigned char>(line[2]) == 0xBFU) {
    line.erase(0, 3);
    return true;
  }
  return false;
}

std::optional<std::size_t> first_binary_byte(std::string_view line) {
  for (std::size_t i = 0; i < line.size(); ++i) {
    const auto byte = static_cast<unsigned char>(line[i]);
    if ((byte < 0x20U && byte != '\t' && byte != '\r' && byte != '\n') || byte == 0x7FU) {
      return i;
    }
  }
  return std::nullopt;
}

std::string binary_message(unsigned char byte) {
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(byte));
  return std::string("binary file, not CSV text (byte ") + hex + ")";
}

std::string escaped(std::string_view text, std::size_t max_chars) {
  std::string out;
  const std::size_t shown = text.size() > max_chars ? max_chars : text.size();
  for (std::size_t i = 0; i < shown; ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20U && byte < 0x7FU && byte != '\\') {
      out += static_cast<char>(byte);
    } else if (byte == '\\') {
      out += "\\\\";
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(byte));
      out += hex;
    }
  }
  if (shown < text.size()) {
    out += "...";
  }
  return out;
}

std::string quoted(std::string_view text, std::size_t max_chars) {
  return "'" + escaped(text, max_chars) + "'";
}

std::string format_number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", value);
  return buf;
}

bool Range::contains(double value) const noexcept {
  if (!std::isfinite(value)) {
    return false;
  }
  const bool above_min = min_open ? value > min : value >= min;
  const bool below_max = max_open ? value < max : value <= max;
  return above_min && below_max;
}

std::string Range::describe() const {
  std::string text = std::string(min_open ? "(" : "[") + format_number(min) + ", " +
                     format_number(max) + (max_open ? ")" : "]");
  if (unit[0] != '\0') {
    text += ' ';
    text += unit;
  }
  return text;
}

std::string out_of_range_message(double value, const Range& range) {
  return format_number(value) + " is outside the physical range " + range.describe();
}

bool is_note_column(std::string_view name) noexcept { return name.substr(0, 4) == "note"; }

}  // namespace text_input
}  // namespace ground
}  // namespace sinkwatch
