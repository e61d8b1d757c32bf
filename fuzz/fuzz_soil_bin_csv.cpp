// libFuzzer harness: the ground tools' soil-bin CSV reader
// (ground/common soil_bin_csv.hpp, parse_soil_bin_csv).
//
// Input: one control byte (bit 0: pass a wheel radius, bit 1: pass a wheel
// load, bit 2: pass a non-finite or non-positive one instead), then the CSV
// text. Besides "no crash, no sanitizer finding":
//   * the only exception is DataError (the header's contract: "every
//     malformed input throws DataError"); anything else escapes and libFuzzer
//     reports it as a crash;
//   * a DataError's line and column are 0 or point into the text;
//   * an accepted dataset has rows, each from a line of the text in
//     increasing order, and every dimensionless quantity finite; has_load
//     means every row has a load.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sg = sinkwatch::ground;

namespace {
void check(bool condition) {
  if (!condition) {
    std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1U) {
    return 0;
  }
  const std::uint8_t control = data[0];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1U);
  const bool bad_option = (control & 4U) != 0U;
  sg::SoilBinReadOptions options;
  if ((control & 1U) != 0U) {
    options.wheel_radius_m = bad_option ? std::numeric_limits<double>::quiet_NaN() : 0.15;
  }
  if ((control & 2U) != 0U) {
    options.load_n = bad_option ? -1.0 : 29.43;
  }
  std::size_t lines = 1U;
  for (char ch : text) {
    lines += (ch == '\n') ? 1U : 0U;
  }
  std::istringstream in(text);
  try {
    const sg::SoilBinDataset d = sg::parse_soil_bin_csv(in, "fuzz.csv", options);
    check(!bad_option || (control & 3U) == 0U);  // a bad option must be refused
    check(!d.rows.empty());
    std::size_t previous_line = 0U;
    for (const sg::SoilBinRow& row : d.rows) {
      check(row.line > previous_line && row.line <= lines);
      previous_line = row.line;
      check(std::isfinite(row.slip) && std::isfinite(row.sinkage_ratio) && std::isfinite(row.drive_coeff) &&
            std::isfinite(row.traction_coeff));
      check(!d.has_load || row.load_n.has_value());
    }
  } catch (const sg::DataError& e) {
    check(e.line() <= lines);
    check(std::string(e.what()).size() > 0U);
  }
  return 0;
}
