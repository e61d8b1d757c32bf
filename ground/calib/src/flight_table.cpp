// flight_table.cpp: the calibration's C(W) table as flight parameter-table bytes.
#include "sinkwatch/ground/flight_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <utility>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/estimator.hpp"

namespace sinkwatch {
namespace ground {

namespace {

// Rows whose loads agree to this relative tolerance are one load (as in
// fit_per_load).
constexpr double kSameLoad = 1e-9;

template <typename QuantityType>
QuantityType quantise(double value, const char* what, double load_n) {
  fx::Status status;
  const auto q = fx::from_double<typename QuantityType::q_type>(value, status);
  if (!status.ok()) {
    std::ostringstream message;
    message << "flight table: " << what << " = " << value << " at load " << load_n
            << " N does not fit its fixed-point format";
    throw CalibrationError(message.str());
  }
  return QuantityType(q);
}

template <typename QuantityType>
double as_double(QuantityType value) {
  return fx::to_double(value.q());
}

std::string describe_rows(const flight::CorrectionTable& c) {
  std::ostringstream out;
  out.precision(6);
  for (std::uint8_t i = 0U; i < c.count && i < flight::kMaxCorrectionRows; ++i) {
    const flight::CorrectionRow& row = c.rows[i];
    out << "\n  load " << as_double(row.load_n) << " N: C1 " << as_double(row.c1) << ", C2 "
        << as_double(row.c2) << ", C3 " << as_double(row.c3) << ", DP_max/W "
        << as_double(row.dp_max_ratio);
  }
  return out.str();
}

}  // namespace

std::string reject_reason_name(flight::RejectReason reason) {
  // One name table, the flight module's (flight/src/reject_reason.cpp).
  if (static_cast<std::size_t>(reason) < flight::kRejectReasonCount) {
    return flight::reason_name(reason);
  }
  return "reason " + std::to_string(static_cast<unsigned>(reason));
}

std::vector<CorrectionEntry> correction_entries(const SoilBinDataset& dataset,
                                                const CalibrationFit& pooled,
                                                const std::vector<LoadFit>* per_load) {
  if (!dataset.has_load) {
    throw CalibrationError(dataset.source +
                           ": the flight table needs the wheel load: a load_N column or --load");
  }
  auto dp_max_at = [&dataset](double load_n) {
    double best = -HUGE_VAL;
    for (const SoilBinRow& row : dataset.rows) {
      if (std::abs(*row.load_n - load_n) <= kSameLoad * load_n) {
        best = std::max(best, row.traction_coeff);
      }
    }
    return best;
  };
  std::vector<CorrectionEntry> rows;
  if (per_load != nullptr) {
    for (const LoadFit& entry : *per_load) {
      rows.push_back({entry.load_n, entry.fit.c, dp_max_at(entry.load_n)});
    }
    return rows;
  }
  const double load = *dataset.rows.front().load_n;
  for (const SoilBinRow& row : dataset.rows) {
    if (std::abs(*row.load_n - load) > kSameLoad * load) {
      throw CalibrationError(dataset.source +
                             ": the data hold several loads; use --per-load to build the C(W) "
                             "table for the flight table");
    }
  }
  rows.push_back({load, pooled.c, dp_max_at(load)});
  return rows;
}

std::optional<double> common_wheel_radius(const SoilBinDataset& dataset) {
  std::optional<double> radius;
  for (const SoilBinRow& row : dataset.rows) {
    if (!row.wheel_radius_m) {
      continue;
    }
    if (radius && *radius != *row.wheel_radius_m) {
      throw CalibrationError(dataset.source + ":" + std::to_string(row.line) +
                             ": the wheel radius differs between rows; the flight table holds one");
    }
    radius = row.wheel_radius_m;
  }
  return radius;
}

namespace {

// The C(W) rows in the flight's fixed-point formats; a value that does not
// fit is an error naming it and its load.
flight::CorrectionTable correction_table(const std::vector<CorrectionEntry>& rows) {
  flight::CorrectionTable correction{};
  correction.count = static_cast<std::uint8_t>(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CorrectionEntry& e = rows[i];
    flight::CorrectionRow& row = correction.rows[i];
    row.load_n = quantise<flight::WheelLoadN>(e.load_n, "load", e.load_n);
    row.c1 = quantise<flight::Ratio>(e.c[0], "C1", e.load_n);
    row.c2 = quantise<flight::Ratio>(e.c[1], "C2", e.load_n);
    row.c3 = quantise<flight::Ratio>(e.c[2], "C3", e.load_n);
    row.dp_max_ratio = quantise<flight::Ratio>(e.dp_max_ratio, "DP_max/W", e.load_n);
  }
  return correction;
}

// The flight code's own validation; a refusal names the reason, the ranges
// the estimator accepts and the rows the table would hold.
void check_flight_validation(const flight::ParameterTable& table) {
  const flight::RejectReason verdict = flight::validate(table);
  if (verdict == flight::RejectReason::ok) {
    return;
  }
  std::ostringstream message;
  message.precision(4);
  message << "the flight validation refuses the table (" << reject_reason_name(verdict)
          << "); the flight estimator accepts C1 and C2 in [" << as_double(flight::kMinC12)
          << ", " << as_double(flight::kMaxC12) << "], C3 in [" << as_double(flight::kMinC3)
          << ", " << as_double(flight::kMaxC3) << "] and a wheel radius in ["
          << as_double(flight::kMinRadiusM) << ", " << as_double(flight::kMaxRadiusM)
          << "] m; the table would hold" << describe_rows(table.correction);
  throw CalibrationError(message.str());
}

// Encodes the table, reads the bytes back with the loader's own decoder
// (what we hand out must load) and takes the CRC-32 the flight module reads
// from the trailer (flight::table_crc).
FlightTable encode_and_reload(const flight::ParameterTable& table) {
  std::array<std::uint8_t, flight::kMaxTableBytes> buffer{};
  const flight::EncodeResult encoded = flight::encode(table, buffer.data(), buffer.size());
  if (encoded.status != flight::RejectReason::ok) {
    throw CalibrationError("flight table: encode failed (" + reject_reason_name(encoded.status) +
                           ")");
  }
  FlightTable result;
  result.bytes.assign(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(encoded.size));
  const flight::RejectReason loaded =
      flight::decode(result.bytes.data(), result.bytes.size(), result.table);
  if (loaded != flight::RejectReason::ok) {
    throw CalibrationError("flight table: the encoded bytes do not decode (" +
                           reject_reason_name(loaded) + ")");
  }
  result.crc = flight::table_crc(result.bytes.data(), result.bytes.size());
  return result;
}

}  // namespace

FlightTable build_flight_table(const flight::ParameterTable& base,
                               const FlightTableRequest& request) {
  if (request.rows.empty() || request.rows.size() > flight::kMaxCorrectionRows) {
    throw CalibrationError("flight table: " + std::to_string(request.rows.size()) +
                           " loads, the table holds 1 to " +
                           std::to_string(flight::kMaxCorrectionRows));
  }
  flight::ParameterTable table = base;
  if (request.table_version) {
    table.table_version = *request.table_version;
  }
  if (request.wheel_radius_m) {
    table.wheel_radius_m =
        quantise<flight::LengthM>(*request.wheel_radius_m, "wheel radius", request.rows[0].load_n);
  }
  table.correction = correction_table(request.rows);
  check_flight_validation(table);
  return encode_and_reload(table);
}

flight::ParameterTable read_flight_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw CalibrationError(path + ": cannot open the base table for reading");
  }
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  flight::ParameterTable table{};
  const flight::RejectReason reason = flight::decode(bytes.data(), bytes.size(), table);
  if (reason != flight::RejectReason::ok) {
    throw CalibrationError(path + ": the flight loader refuses this table (" +
                           reject_reason_name(reason) + ")");
  }
  return table;
}

}  // namespace ground
}  // namespace sinkwatch
