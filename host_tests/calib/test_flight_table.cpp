// Tests of `calibrate --table`: the emitted bytes load in the flight loader
// (ParameterStore), and the flight estimator (Eq. 11 solved for z, in fixed
// point) fed from the loaded table gives the ground fit's sinkage estimates
// within the fixed-point bound derived below. Also: a fit outside the flight
// envelope is refused with its reason and nothing is written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "estimator_bounds.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/calibrate_command.hpp"
#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"
#include "scratch_dir.hpp"

namespace sinkwatch {
namespace ground {
namespace {

using sinkwatch::test::scratch_dir;

namespace fs = std::filesystem;

const std::string kTable1 = std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv";
constexpr double kTable1LoadN = 3.0 * 9.81;
constexpr double kRatioLsb = 1.0 / 16777216.0;  // Q7.24: 2^-24


std::vector<std::uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename QType>
QType to_q(double value) {
  fx::Status status;
  const QType q = fx::from_double<QType>(value, status);
  EXPECT_TRUE(status.ok()) << value;
  return q;
}

// Feeds every run of `data` at `load_n` through the flight estimator with the
// loaded table's coefficients and compares with Eq. 11 solved for z in double
// precision with the ground fit's (unquantised) coefficients, on the same
// (quantised) inputs, so that only the table's quantisation and the
// estimator's rounding remain. Returns the largest error seen.
double check_estimates(const flight::ParameterTable& table, const std::vector<Observation>& data,
                       double load_n, double radius_m, const Coefficients& ground_c) {
  const flight::WheelLoadN load(to_q<flight::LoadQ>(load_n));
  const flight::CorrectionResult corrections = test::corrections_of(table.correction, load);
  EXPECT_EQ(corrections.status, flight::EstimateStatus::ok);
  EXPECT_EQ(corrections.clamp, flight::LoadClamp::none);

  const double w = fx::to_double(load.q());
  const double r = fx::to_double(table.wheel_radius_m.q());
  EXPECT_NEAR(r, radius_m, kRatioLsb);
  double worst = 0.0;
  for (const Observation& o : data) {
    const flight::TorqueNm torque(to_q<flight::LoadQ>(o.drive_coeff * radius_m * load_n));
    const flight::DrawbarPullN pull(to_q<flight::LoadQ>(o.traction_coeff * load_n));
    const flight::SinkageResult flight_z =
        flight::sinkage_from_pull(corrections.coefficients, table.wheel_radius_m, load, torque, pull);
    EXPECT_EQ(flight_z.status, flight::EstimateStatus::ok);

    const double t = fx::to_double(torque.q());
    const double dp = fx::to_double(pull.q());
    const double ground_z =
        (ground_c[0] * t / w - r * (ground_c[2] + dp / w)) / ground_c[1];

    // Bound. Each coefficient is rounded to nearest in Q7.24 (|dC| <= 2^-25).
    // z = N / C2 with N = C1 T/W - r (C3 + DP/W): |dN| <= 2^-25 (|T/W| + r),
    // and N'/C2' - N/C2 = (dN - z dC2) / C2', |C2'| >= |C2| - 2^-25. The
    // estimator's own error is docs/flight.md's (estimator_bounds.hpp).
    const double half_lsb = kRatioLsb / 2.0;
    const double c2 = fx::to_double(corrections.coefficients.c2.q());
    const double bound = half_lsb * (std::abs(t / w) + r + std::abs(ground_z)) /
                             (std::abs(ground_c[1]) - half_lsb) +
                         test::sinkage_error_bound_m(c2, w, ground_z);
    const double error = std::abs(fx::to_double(flight_z.sinkage_m.q()) - ground_z);
    EXPECT_LE(error, bound) << "slip " << o.slip << " load " << load_n;
    worst = std::max(worst, error / bound);
  }
  return worst;
}

TEST(FlightTable, Table2FormOfTable1LoadsAndReproducesTheGroundEstimates) {
  const fs::path dir = scratch_dir();
  CalibrateOptions options;
  options.data_path = kTable1;
  options.load_n = kTable1LoadN;
  options.wheel_radius_m = 0.15;
  options.fix = "c1=1,c2=1";
  options.table_path = (dir / "t1.bin").string();
  options.table_version = 42;
  std::ostringstream out;
  run_calibrate(options, out);
  EXPECT_NE(out.str().find("flight parameter table"), std::string::npos) << out.str();

  const std::vector<std::uint8_t> bytes = read_bytes(dir / "t1.bin");
  ASSERT_GT(bytes.size(), 4U);
  flight::ParameterStore store;
  ASSERT_EQ(store.load(bytes.data(), bytes.size()), flight::RejectReason::ok);
  const std::uint32_t trailer = static_cast<std::uint32_t>(bytes[bytes.size() - 4]) |
                                (static_cast<std::uint32_t>(bytes[bytes.size() - 3]) << 8U) |
                                (static_cast<std::uint32_t>(bytes[bytes.size() - 2]) << 16U) |
                                (static_cast<std::uint32_t>(bytes[bytes.size() - 1]) << 24U);
  EXPECT_EQ(flight::crc32(bytes.data(), bytes.size() - 4), trailer);
  EXPECT_EQ(store.active_crc(), trailer);

  const flight::ParameterTable& table = store.active();
  EXPECT_EQ(table.table_version, 42U);
  ASSERT_EQ(table.correction.count, 1U);
  const std::vector<Observation> data = observations_of(read_soil_bin_csv(kTable1));
  FixedCoefficients fixed;
  fixed.value = {1.0, 1.0, std::nullopt};
  const CalibrationFit fit = fit_sinkage_function(data, fixed);
  EXPECT_NEAR(fx::to_double(table.correction.rows[0].c3.q()), fit.c[2], kRatioLsb / 2.0);
  EXPECT_NEAR(fx::to_double(table.correction.rows[0].dp_max_ratio.q()), 0.526, kRatioLsb / 2.0);
  // Everything but the corrections, radius and version is the default's.
  const flight::ParameterTable def = flight::default_parameter_table();
  EXPECT_EQ(table.motor.gear_ratio, def.motor.gear_ratio);
  EXPECT_EQ(table.monitor.allowed_sinkage_m, def.monitor.allowed_sinkage_m);

  const double worst = check_estimates(table, data, kTable1LoadN, 0.15, fit.c);
  EXPECT_LE(worst, 1.0);
  RecordProperty("worst_error_over_bound", std::to_string(worst));
}

// Dimensional data at two loads, generated with known coefficients other
// than 1 and a wheel radius in the file: per-load fit, all three free.
TEST(FlightTable, PerLoadFitOfDimensionalDataLoadsAndReproducesTheGroundEstimates) {
  const fs::path dir = scratch_dir();
  const double radius = 0.135;
  const std::vector<std::pair<double, Coefficients>> loads = {{29.43, {0.9, 1.2, 0.18}},
                                                              {147.15, {1.05, 0.8, 0.12}}};
  {
    std::ofstream csv(dir / "bin.csv");
    csv.precision(17);
    csv << "# synthetic soil-bin runs\nslip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,"
           "wheel_radius_m,wheel_width_m\n";
    for (const auto& [load, c] : loads) {
      for (int i = 0; i < 12; ++i) {
        const double s = 0.05 + 0.05 * i;
        const double drive = 0.2 + 1.4 * s - 1.0 * s * s;
        const double sink = 0.07 + 0.2 * s + 0.03 * std::cos(9.0 * s);
        const double noise = 0.004 * std::sin(3.7 * i + load);  // deterministic, small
        const double traction = c[0] * drive - c[1] * sink - c[2] + noise;
        csv << s << ',' << load << ',' << drive * radius * load << ',' << sink * radius << ','
            << traction * load << ',' << radius << ",0.165\n";
      }
    }
  }
  CalibrateOptions options;
  options.data_path = (dir / "bin.csv").string();
  options.per_load = true;
  options.table_path = (dir / "bin.bin").string();
  options.json_path = (dir / "bin.json").string();
  std::ostringstream out;
  run_calibrate(options, out);

  const std::vector<std::uint8_t> bytes = read_bytes(dir / "bin.bin");
  flight::ParameterStore store;
  ASSERT_EQ(store.load(bytes.data(), bytes.size()), flight::RejectReason::ok);
  const flight::ParameterTable& table = store.active();
  ASSERT_EQ(table.correction.count, 2U);
  EXPECT_NE(read_bytes(dir / "bin.json").size(), 0U);

  const SoilBinDataset dataset = read_soil_bin_csv(options.data_path);
  const std::vector<LoadFit> fits = fit_per_load(dataset);
  ASSERT_EQ(fits.size(), 2U);
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const flight::CorrectionRow& row = table.correction.rows[i];
    EXPECT_NEAR(fx::to_double(row.load_n.q()), fits[i].load_n, 1.0 / 131072.0);
    EXPECT_NEAR(fx::to_double(row.c1.q()), fits[i].fit.c[0], kRatioLsb / 2.0);
    EXPECT_NEAR(fx::to_double(row.c2.q()), fits[i].fit.c[1], kRatioLsb / 2.0);
    EXPECT_NEAR(fx::to_double(row.c3.q()), fits[i].fit.c[2], kRatioLsb / 2.0);
    // The fit is near the generating coefficients (small deterministic noise).
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(fits[i].fit.c[k], loads[i].second[k], 5.0 * fits[i].fit.std_err[k]);
    }
    std::vector<Observation> group;
    for (const SoilBinRow& r : dataset.rows) {
      if (*r.load_n == fits[i].load_n) {
        group.push_back({r.line, r.slip, r.drive_coeff, r.sinkage_ratio, r.traction_coeff});
      }
    }
    ASSERT_EQ(group.size(), 12U);
    const double worst = check_estimates(table, group, fits[i].load_n, radius, fits[i].fit.c);
    EXPECT_LE(worst, 1.0);
    RecordProperty("worst_error_over_bound_" + std::to_string(i), std::to_string(worst));
  }
}

TEST(FlightTable, TheFullFitOfTable1IsRefusedByTheFlightEnvelopeAndNothingIsWritten) {
  const fs::path dir = scratch_dir();
  CalibrateOptions options;
  options.data_path = kTable1;
  options.load_n = kTable1LoadN;
  options.table_path = (dir / "full.bin").string();
  options.json_path = (dir / "full.json").string();
  std::ostringstream out;
  try {
    run_calibrate(options, out);
    FAIL() << "wrote a table with C2 < 0.25";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("c2_out_of_range"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "full.bin"));
  EXPECT_FALSE(fs::exists(dir / "full.json"));
}

TEST(FlightTable, NeedsTheLoad) {
  CalibrateOptions options;
  options.data_path = kTable1;
  options.fix = "c1=1,c2=1";
  options.table_path = (scratch_dir() / "x.bin").string();
  std::ostringstream out;
  try {
    run_calibrate(options, out);
    FAIL();
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("needs the wheel load"), std::string::npos) << e.what();
  }
}

TEST(FlightTable, KeepsTheOtherSectionsOfABaseTableAndRefusesACorruptOne) {
  const fs::path dir = scratch_dir();
  flight::ParameterTable base = flight::default_parameter_table();
  fx::Status status;
  base.motor.gear_ratio = flight::GearRatio(fx::from_double<flight::GearQ>(250.0, status));
  base.wheel_radius_m = flight::LengthM(fx::from_double<flight::LengthQ>(0.2, status));
  ASSERT_TRUE(status.ok());
  std::vector<std::uint8_t> buffer(flight::kMaxTableBytes);
  const flight::EncodeResult encoded = flight::encode(base, buffer.data(), buffer.size());
  ASSERT_EQ(encoded.status, flight::RejectReason::ok);
  buffer.resize(encoded.size);
  std::ofstream(dir / "base.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));

  CalibrateOptions options;
  options.data_path = kTable1;
  options.load_n = kTable1LoadN;
  options.fix = "c1=1,c2=1";
  options.base_table_path = (dir / "base.bin").string();
  options.table_path = (dir / "out.bin").string();
  std::ostringstream out;
  run_calibrate(options, out);
  const std::vector<std::uint8_t> bytes = read_bytes(dir / "out.bin");
  flight::ParameterTable loaded{};
  ASSERT_EQ(flight::decode(bytes.data(), bytes.size(), loaded), flight::RejectReason::ok);
  EXPECT_EQ(loaded.motor.gear_ratio, base.motor.gear_ratio);
  EXPECT_EQ(loaded.wheel_radius_m, base.wheel_radius_m);  // Table 1 carries no radius
  EXPECT_NE(out.str().find("kept from the base table"), std::string::npos);

  buffer[20] ^= 0x01U;  // one flipped bit
  std::ofstream(dir / "bad.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));
  options.base_table_path = (dir / "bad.bin").string();
  options.table_path = (dir / "out2.bin").string();
  try {
    run_calibrate(options, out);
    FAIL();
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("crc_mismatch"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "out2.bin"));
}

TEST(FlightTable, RejectReasonNamesAreDistinct) {
  EXPECT_EQ(reject_reason_name(flight::RejectReason::c2_out_of_range), "c2_out_of_range");
  std::vector<std::string> seen;
  for (std::uint8_t i = 0U; i < flight::kRejectReasonCount; ++i) {
    const std::string name = reject_reason_name(static_cast<flight::RejectReason>(i));
    EXPECT_EQ(name.find("reason "), std::string::npos) << "no name for reason " << int(i);
    EXPECT_EQ(std::count(seen.begin(), seen.end(), name), 0) << name;
    seen.push_back(name);
  }
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
