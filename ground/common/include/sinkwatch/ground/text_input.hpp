// text_input.hpp: the input rules shared by the ground tools' CSV readers
// (soil_bin_csv.hpp, telemetry_log.hpp; docs/input-files.md):
//
//   - "-" as a path means standard input;
//   - a directory is refused as such, not read as an empty file;
//   - a leading UTF-8 byte-order mark (Excel's "CSV UTF-8") is skipped;
//   - a control byte other than tab, CR and LF (NUL, ESC, DEL, ...) makes the
//     input a binary file, refused at the line and column of that byte;
//   - input text quoted in a message is escaped (every byte outside printable
//     ASCII as \xNN) and cut to a few dozen characters, so that a message
//     never sends the input's raw bytes to the terminal;
//   - a number is checked against a physical range per column, and printed
//     in messages with %g.
//
// Host only. Each reader throws its own error type; these helpers only return
// what is wrong.
#ifndef SINKWATCH_GROUND_TEXT_INPUT_HPP
#define SINKWATCH_GROUND_TEXT_INPUT_HPP

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace sinkwatch {
namespace ground {
namespace text_input {

/// The path that means standard input, and the name messages give it.
inline constexpr const char* kStdinPath = "-";
inline constexpr const char* kStdinName = "<stdin>";

/// Why `path` cannot be read as a text file ("is a directory, not a file",
/// "cannot open the file for reading"), or empty when it can. Not for "-".
[[nodiscard]] std::string unreadable_reason(const std::string& path);

/// Removes a UTF-8 byte-order mark (EF BB BF) from the start of `line`.
/// Returns whether there was one.
bool strip_bom(std::string& line);

/// The 0-based index of the first byte of `line` that text does not contain
/// (a control byte other than tab and CR; LF ends lines), or nullopt.
[[nodiscard]] std::optional<std::size_t> first_binary_byte(std::string_view line);

/// The message for a binary byte: "binary file, not CSV text (byte 0x00)".
[[nodiscard]] std::string binary_message(unsigned char byte);

/// `text` between single quotes, every byte outside printable ASCII written
/// as \xNN and anything beyond `max_chars` input bytes replaced by "...".
[[nodiscard]] std::string quoted(std::string_view text, std::size_t max_chars = 40);

/// `text` escaped like quoted(), without the quotes.
[[nodiscard]] std::string escaped(std::string_view text, std::size_t max_chars = 40);

/// A number as %.10g prints it ("1e+300", "0.25", "-90", "4294967.295").
[[nodiscard]] std::string format_number(double value);

/// The physical range of a column: [min, max], each end open or closed.
struct Range {
  double min;
  double max;
  bool min_open = false;  // true: min itself is outside
  bool max_open = false;
  const char* unit = "";  // for the message, e.g. "m", "deg"; "" for none

  [[nodiscard]] bool contains(double value) const noexcept;
  /// "[-1, 1]", "(0, 30] m/s^2".
  [[nodiscard]] std::string describe() const;
};

/// "1e+300 is outside the physical range [-1, 1]" (numbers with %g).
[[nodiscard]] std::string out_of_range_message(double value, const Range& range);

/// Whether a column with this name is an annotation column that every reader
/// ignores: the name starts with "note" (note, notes, note_run, ...).
[[nodiscard]] bool is_note_column(std::string_view name) noexcept;

}  // namespace text_input
}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_TEXT_INPUT_HPP
