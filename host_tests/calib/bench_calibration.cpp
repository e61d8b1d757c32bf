// Benchmark (prints numbers; not a test): cost of `sinkwatch calibrate` on a
// large soil-bin data set (issue 17), docs/calibration.md.
//
//   bench_calibration [ROWS] [--no-csv]
//
// ROWS (default 1,000,000) synthetic soil-bin runs at five loads are made in
// memory and fitted three ways: all coefficients free, --fix c1=1,c2=1, and
// --per-load. Then the same rows are written to a CSV file in the temporary
// directory, read back (the CSV reader alone), and run through the whole
// command in process (read, pooled and per-load fits, report to a discarded
// stream); --no-csv skips this part. Each line prints seconds and rows/s.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <random>
#include <streambuf>
#include <string>
#include <vector>

#include "sinkwatch/ground/calibrate_command.hpp"
#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sg = sinkwatch::ground;

namespace {

constexpr double kLoads[] = {29.43, 49.05, 68.67, 98.1, 147.15};

// Soil-bin-like runs: slip 0.02..0.7, drive coefficient and sinkage ratio
// rising with slip and load but not in proportion, DP/W from Eq. 11 with
// C = (0.95, 1.1, 0.15) plus noise of 0.01.
sg::SoilBinDataset synthetic(std::size_t rows) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> slip(0.02, 0.7);
  std::normal_distribution<double> noise(0.0, 0.01);
  sg::SoilBinDataset data;
  data.source = "synthetic";
  data.has_load = true;
  data.rows.reserve(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    sg::SoilBinRow r;
    r.line = i + 2;
    const double load = kLoads[i % 5];
    r.load_n = load;
    r.slip = slip(rng);
    r.drive_coeff = 0.2 + 1.4 * r.slip - r.slip * r.slip + 0.0005 * load;
    r.sinkage_ratio = 0.07 + 0.2 * r.slip + 0.03 * std::cos(9.0 * r.slip) + 0.0008 * load;
    r.traction_coeff = 0.95 * r.drive_coeff - 1.1 * r.sinkage_ratio - 0.15 + noise(rng);
    data.rows.push_back(r);
  }
  return data;
}

struct NullBuffer : std::streambuf {
  int overflow(int c) override { return c; }
};

template <typename F>
double seconds_of(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void print(const char* what, std::size_t rows, double seconds, double check) {
  std::printf("%-46s %9zu rows %8.3f s %12.0f rows/s  (check %.6g)\n", what, rows, seconds,
              static_cast<double>(rows) / seconds, check);
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t rows = 1000000;
  bool csv = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--no-csv") {
      csv = false;
    } else {
      rows = static_cast<std::size_t>(std::strtoull(argv[i], nullptr, 10));
    }
  }
  if (rows < 20) {
    std::fprintf(stderr, "usage: bench_calibration [ROWS >= 20] [--no-csv]\n");
    return 2;
  }

  const sg::SoilBinDataset data = synthetic(rows);
  double check = 0.0;
  double t = seconds_of([&] { check = sg::fit_sinkage_function(sg::observations_of(data)).loo_rms; });
  print("fit, 3 free (in memory)", rows, t, check);

  sg::FixedCoefficients fixed;
  fixed.value = {1.0, 1.0, std::nullopt};
  t = seconds_of([&] { check = sg::fit_sinkage_function(sg::observations_of(data), fixed).loo_rms; });
  print("fit, --fix c1=1,c2=1 (in memory)", rows, t, check);

  t = seconds_of([&] { check = sg::fit_per_load(data).back().fit.loo_rms; });
  print("fit --per-load, 5 loads (in memory)", rows, t, check);

  if (!csv) {
    return 0;
  }
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("sinkwatch_bench_calibration_" + std::to_string(std::random_device{}()) + ".csv");
  t = seconds_of([&] {
    std::ofstream out(path);
    out << "slip,load_N,sinkage_ratio,drive_coeff,traction_coeff\n";
    out.precision(17);
    for (const sg::SoilBinRow& r : data.rows) {
      out << r.slip << ',' << *r.load_n << ',' << r.sinkage_ratio << ',' << r.drive_coeff << ','
          << r.traction_coeff << '\n';
    }
  });
  std::printf("CSV written: %s, %.1f MB, %.3f s\n", path.string().c_str(),
              static_cast<double>(std::filesystem::file_size(path)) / 1e6, t);

  t = seconds_of([&] { check = static_cast<double>(sg::read_soil_bin_csv(path.string()).rows.size()); });
  print("CSV read only", rows, t, check);

  sg::CalibrateOptions options;
  options.data_path = path.string();
  options.per_load = true;
  NullBuffer null_buffer;
  std::ostream null_out(&null_buffer);
  int status = 0;
  t = seconds_of([&] {
    try {
      sg::run_calibrate(options, null_out);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "run_calibrate: %s\n", e.what());
      status = 1;
    }
  });
  print("sinkwatch calibrate --per-load (CSV to report)", rows, t, 0.0);
  std::filesystem::remove(path);
  return status;
}
