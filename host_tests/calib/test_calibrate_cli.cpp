// End-to-end tests of `sinkwatch calibrate`: the command function on the
// paper's Table 1, and the built executable itself (exit codes, messages on
// stderr, and no file written when the input is bad).
#include <gtest/gtest.h>
#include <unistd.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/calibrate_command.hpp"
#include "sinkwatch/ground/calibration.hpp"
#include "sinkwatch/ground/soil_bin_csv.hpp"
#include "scratch_dir.hpp"

namespace sinkwatch {
namespace ground {
namespace {

using sinkwatch::test::scratch_dir;

namespace fs = std::filesystem;

const std::string kTable1 = std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv";


std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The number after "key": at the top level of our JSON (keys at two-space
// indent), enough to check values without a JSON library.
double json_top_level_number(const std::string& json, const std::string& key) {
  const std::string marker = "\n  \"" + key + "\": ";
  const auto at = json.find(marker);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no top-level key " << key;
    return 0.0;
  }
  return std::strtod(json.c_str() + at + marker.size(), nullptr);
}

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

CliRun run_cli(const std::string& arguments, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  const std::string command = std::string("'") + SINKWATCH_CLI + "' " + arguments + " >'" +
                              out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

TEST(CalibrateCommand, Table1ReportAndJsonCarryTheFit) {
  const fs::path dir = scratch_dir();
  CalibrateOptions options;
  options.data_path = kTable1;
  options.json_path = (dir / "fit.json").string();
  std::ostringstream out;
  run_calibrate(options, out);

  const CalibrationFit fit = fit_sinkage_function(observations_of(read_soil_bin_csv(kTable1)));
  const std::string json = slurp(dir / "fit.json");
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "c1"), fit.c[0]);
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "c2"), fit.c[1]);
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "c3"), fit.c[2]);
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "condition_number"), fit.condition_number);
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "rms"), fit.rms);
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "loo_rms"), fit.loo_rms);
  EXPECT_NE(json.find("\n  \"std_err\": {\"c1\": "), std::string::npos);
  EXPECT_NE(json.find("\"correlation\""), std::string::npos);
  EXPECT_NE(json.find("\"residuals\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "fit.json.tmp"));

  const std::string report = out.str();
  EXPECT_NE(report.find("16 rows, dimensionless input"), std::string::npos) << report;
  EXPECT_NE(report.find("condition number of A"), std::string::npos);
  EXPECT_NE(report.find("leave-one-out RMS"), std::string::npos);
  EXPECT_NE(report.find("residuals by slip"), std::string::npos);
}

TEST(CalibrateCommand, FixedTable2FormPerLoadInJson) {
  const fs::path dir = scratch_dir();
  CalibrateOptions options;
  options.data_path = kTable1;
  options.load_n = 3.0 * 9.81;
  options.per_load = true;
  options.fix = "c1=1,c2=1";
  options.json_path = (dir / "fit.json").string();
  std::ostringstream out;
  run_calibrate(options, out);
  const std::string json = slurp(dir / "fit.json");
  EXPECT_NE(json.find("\"per_load\": ["), std::string::npos);
  EXPECT_NE(json.find("\"load_N\": 29.43"), std::string::npos);
  EXPECT_NE(json.find("\"std_err\": {\"c1\": null, \"c2\": null, \"c3\": "), std::string::npos);
  EXPECT_NE(out.str().find("C(W) table"), std::string::npos);
}

TEST(CalibrateCommand, NothingIsWrittenWhenTheFitFails) {
  const fs::path dir = scratch_dir();
  CalibrateOptions options;
  options.data_path = kTable1;
  options.per_load = true;  // Table 1 has no load_N and no --load: refused
  options.json_path = (dir / "fit.json").string();
  std::ostringstream out;
  EXPECT_THROW(run_calibrate(options, out), CalibrationError);
  EXPECT_FALSE(fs::exists(dir / "fit.json"));
  EXPECT_TRUE(out.str().empty());
}

TEST(CalibrateCli, RunsOnTable1) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("calibrate '" + kTable1 + "' --json '" + (dir / "t1.json").string() + "'",
                          dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  EXPECT_NE(run.out.find("coef    estimate     std err    95 % interval"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("correlation"), std::string::npos);
  const std::string json = slurp(dir / "t1.json");
  const CalibrationFit fit = fit_sinkage_function(observations_of(read_soil_bin_csv(kTable1)));
  EXPECT_DOUBLE_EQ(json_top_level_number(json, "c2"), fit.c[1]);
}

TEST(CalibrateCli, RejectsAMalformedRowNamingFileLineAndColumnAndWritesNothing) {
  const fs::path dir = scratch_dir();
  const fs::path bad = dir / "bad.csv";
  std::ofstream(bad) << "# soil bin\nslip,sinkage_ratio,drive_coeff,traction_coeff\n"
                        "0.1,0.08,0.35,0.1\n0.2,0.09,oops,0.2\n";
  const fs::path json = dir / "out.json";
  const CliRun run = run_cli("calibrate '" + bad.string() + "' --json '" + json.string() + "'", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find(bad.string() + ":4:3: column 'drive_coeff': 'oops' is not a number"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(json));
  EXPECT_FALSE(fs::exists(dir / "out.json.tmp"));
}

TEST(CalibrateCli, RejectsBadOptions) {
  const fs::path dir = scratch_dir();
  // Bad option values are usage errors (2), unreadable data an I/O error (1):
  // docs/conventions.md.
  CliRun run = run_cli("calibrate '" + kTable1 + "' --fix c7=1", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("sinkwatch calibrate: --fix: unknown coefficient 'c7'"), std::string::npos) << run.err;

  run = run_cli("calibrate '" + kTable1 + "' --load 0", dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--load: '0' is not a finite number > 0"), std::string::npos) << run.err;

  run = run_cli("calibrate '" + (dir / "missing.csv").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("cannot open"), std::string::npos) << run.err;

  run = run_cli("calibrate", dir);  // no data file: CLI11's own error, a usage error
  EXPECT_EQ(run.exit_code, 2);
}

// Outputs of `sinkwatch diagnose` (docs/output-files.md): a path that cannot
// be written is refused before the run (no summary printed), and a failing
// gnuplot leaves no half-written report.
TEST(DiagnoseCli, JsonIntoAMissingDirectoryFailsBeforeTheRun) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("diagnose --real '" + kTable1 + "' --load 29.43 --radius 0.15 --width 0.15 " +
                                 "--model estimator --json /nonexistent/x.json",
                             dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("/nonexistent/x.json: cannot write here"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "") << "the diagnosis must not have run";
}

TEST(DiagnoseCli, ReportIntoAMissingParentOrOverAFifoFailsBeforeTheRun) {
  const fs::path dir = scratch_dir();
  const std::string data = "diagnose --real '" + kTable1 + "' --load 29.43 --radius 0.15 --width 0.15 --model estimator";
  CliRun run = run_cli(data + " --report /nonexistent/report", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("/nonexistent/report: cannot write here"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "");
  fs::create_directories(dir / "report");
  ASSERT_EQ(::mkfifo((dir / "report" / "summary.md").c_str(), 0600), 0);
  run = run_cli(data + " --report '" + (dir / "report").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("summary.md: refusing to replace a FIFO"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "");
  EXPECT_TRUE(fs::is_fifo(dir / "report" / "summary.md"));
}

TEST(DiagnoseCli, FailingGnuplotLeavesNoHalfWrittenReport) {
  const fs::path dir = scratch_dir();
  // Answers find_gnuplot()'s probe (-e exit), fails on a script.
  const fs::path fake = dir / "fake-gnuplot";
  {
    std::ofstream script(fake);
    script << "#!/bin/sh\n[ \"$1\" = -e ] && exit 0\necho 'fake gnuplot: no terminal' >&2\nexit 1\n";
  }
  fs::permissions(fake, fs::perms::owner_all);
  fs::create_directories(dir / "report");
  {
    std::ofstream old(dir / "report" / "summary.md");
    old << "old summary\n";
  }
  ::setenv("SINKWATCH_GNUPLOT", fake.c_str(), 1);
  const CliRun run = run_cli("diagnose --real '" + kTable1 + "' --load 29.43 --radius 0.15 --width 0.15 " +
                                 "--model estimator --report '" + (dir / "report").string() + "'",
                             dir);
  ::unsetenv("SINKWATCH_GNUPLOT");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("gnuplot"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("fake gnuplot: no terminal"), std::string::npos) << run.err;
  EXPECT_EQ(slurp(dir / "report" / "summary.md"), "old summary\n");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir / "report")) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(names, std::vector<std::string>{"summary.md"}) << "no temporary or partial file left";
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
