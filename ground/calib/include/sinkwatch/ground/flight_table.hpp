// flight_table.hpp: turns a calibration into the binary flight parameter table
// (flight/param_table.hpp: header, sections, CRC-32 trailer) that the flight
// loader accepts. Only the correction section (C1, C2, C3 and DP_max/W per
// load: the paper's Table 2 as a function C(W) for Eq. 11) and, when the data
// carry it, the wheel radius are replaced; every other section comes from a
// base table (the flight default, or a table file the operators already use).
//
// The bytes are written by the flight module's own encode(), validated with
// its validate() and decoded back with its decode() before they are returned:
// a table this code hands out is one the flight loader has already accepted.
#ifndef SINKWATCH_GROUND_FLIGHT_TABLE_HPP
#define SINKWATCH_GROUND_FLIGHT_TABLE_HPP

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

/// One row of the C(W) table in double precision, before quantisation.
struct CorrectionEntry {
  double load_n = 0.0;
  Coefficients c{};
  double dp_max_ratio = 0.0;  // largest measured DP/W at this load (section 7)
};

struct FlightTableRequest {
  std::vector<CorrectionEntry> rows;     // strictly increasing loads
  std::optional<double> wheel_radius_m;  // none: keep the base table's
  std::optional<std::uint16_t> table_version;  // none: keep the base table's
};

struct FlightTable {
  flight::ParameterTable table{};  // as decoded back from the bytes
  std::vector<std::uint8_t> bytes;
  std::uint32_t crc = 0;           // the CRC-32 trailer
};

/// The name of a flight RejectReason, for messages ("c2_out_of_range").
[[nodiscard]] std::string reject_reason_name(flight::RejectReason reason);

/// The C(W) rows for a calibration: one per load with per-load fits, else a
/// single row at the data's one load. DP_max/W is the largest DP/W measured
/// at that load. Throws CalibrationError when the loads are unknown or, without
/// per-load fits, not all equal.
[[nodiscard]] std::vector<CorrectionEntry> correction_entries(const SoilBinDataset& dataset,
                                                              const CalibrationFit& pooled,
                                                              const std::vector<LoadFit>* per_load);

/// The wheel radius all rows agree on, none if the data carry no radius.
/// Throws CalibrationError if rows disagree.
[[nodiscard]] std::optional<double> common_wheel_radius(const SoilBinDataset& dataset);

/// Fills the base table with the request, quantises, validates, encodes and
/// decodes back. Throws CalibrationError naming the refused value.
[[nodiscard]] FlightTable build_flight_table(const flight::ParameterTable& base,
                                             const FlightTableRequest& request);

/// Reads and decodes a binary table file (for --base-table). Throws
/// CalibrationError with the loader's reason.
[[nodiscard]] flight::ParameterTable read_flight_table(const std::string& path);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_FLIGHT_TABLE_HPP
