// `sinkwatch replay` end to end: the default run, CSV and plot outputs, the
// plot's fallback without gnuplot, and errors with line numbers.
#include "sinkwatch/ground/replay_command.hpp"

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/param_table.hpp"

#include <gtest/gtest.h>

#include "replay_command_run.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fs = std::filesystem;

namespace {

using sinkwatch::ground::test::CommandRun;
using sinkwatch::ground::test::run;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_replay_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::size_t line_count(const fs::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

}  // namespace

TEST(ReplayCommand, DefaultRunStopsBeforeTheEmbeddingAndSaysSo) {
  const CommandRun r = run({});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("STOP AND RE-PLAN"), std::string::npos);
  EXPECT_NE(r.out.find("BEFORE the embedding"), std::string::npos) << r.out;
  // The default table's first stop is the motion-resistance check's
  // (docs/traction.md), and the report says so.
  EXPECT_NE(r.out.find("the motion-resistance check stopped the rover"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("escape     FREED"), std::string::npos) << r.out;
  // Section 8's stop leaves no wheel event; the rover's stop record gives
  // the sinkage at the stop, beside the simulator's, at the stop and in the summary.
  EXPECT_NE(r.out.find("stop record: motion resistance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("record     the rover's stop record: motion resistance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(simulator: 32.0 mm)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Summary"), std::string::npos);
  // Compact: not one line per cycle (the log has > 1200 cycles).
  EXPECT_LT(std::count(r.out.begin(), r.out.end(), '\n'), 80);
  EXPECT_TRUE(r.err.empty()) << "no progress bar when stderr is not a terminal: " << r.err;
}

TEST(ReplayCommand, NominalScenarioNeverStops) {
  const CommandRun r = run({"--scenario", "nominal"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("stops      none"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("STOP AND RE-PLAN"), std::string::npos);
}

TEST(ReplayCommand, VerbosePrintsEveryCycle) {
  const CommandRun r = run({"--scenario", "nominal", "--verbose"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(std::count(r.out.begin(), r.out.end(), '\n'), 2000);
}

TEST(ReplayCommand, CsvHasOneLinePerCycle) {
  const fs::path dir = temp_dir("csv");
  const fs::path csv = dir / "series.csv";
  const CommandRun r = run({"--csv", csv.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(csv));
  const std::string& text = sg::embedded_scenario_text("embedding");
  std::size_t data_rows = 0;
  std::istringstream in(text);
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    ++data_rows;
  }
  EXPECT_EQ(line_count(csv), data_rows + 1);
  std::ifstream f(csv);
  std::string first;
  std::getline(f, first);
  EXPECT_EQ(first.rfind("time_s,x_m,status,decision,slip", 0), 0U) << first;
  EXPECT_NE(first.find("z_RR_mm"), std::string::npos);
}

TEST(ReplayCommand, PlotIsDrawnWhenGnuplotIsInstalled) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const fs::path dir = temp_dir("plot");
  for (const std::string ext : {"svg", "png"}) {
    const fs::path image = dir / ("replay." + ext);
    const CommandRun r = run({"--plot", image.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(image)) << r.out;
    EXPECT_GT(fs::file_size(image), 1000U);
    EXPECT_FALSE(fs::exists(image.string() + ".gp")) << "the script is removed after a good plot";
  }
  std::ifstream svg(dir / "replay.svg");
  std::string head((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_NE(head.find("<svg"), std::string::npos);
}

TEST(ReplayCommand, PlotWithoutGnuplotLeavesTheScriptAndANote) {
  const fs::path dir = temp_dir("noplot");
  const fs::path image = dir / "replay.png";
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path ? old_path : "";
  setenv("PATH", dir.string().c_str(), 1);  // no gnuplot there (the shell is found by absolute path)
  const CommandRun r = run({"--plot", image.string()});
  setenv("PATH", saved.c_str(), 1);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gnuplot was not found"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(image));
  EXPECT_TRUE(fs::exists(image.string() + ".gp"));
  EXPECT_NE(r.out.find("Summary"), std::string::npos) << "the replay itself still ran";
}

TEST(ReplayCommand, BadRowIsReportedWithItsLine) {
  const fs::path dir = temp_dir("bad");
  const fs::path log = dir / "bad.csv";
  {
    std::ofstream f(log);
    f << "# a log with a bad row\n"
      << "time_s,i_lf_a,i_lm_a,i_lr_a,i_rf_a,i_rm_a,i_rr_a,pitch_deg,roll_deg,rocker_l_deg,rocker_r_deg,"
         "bogie_l_deg,bogie_r_deg,speed_mps\n"
      << "0.0,0.5,0.5,0.5,0.5,0.5,0.5,0,0,0,0,0,0,0.05\n"
      << "0.2,0.5,0.5,0.5,0.5,0.5,0.5,0,0,0,0,0,0,0.05\n"
      << "0.4,0.5,0.5,0.5,0.5,0.5,0.5,zero,0,0,0,0,0,0.05\n";
  }
  const CommandRun r = run({log.string()});
  EXPECT_EQ(r.code, 1) << "a data error (docs/conventions.md)";
  EXPECT_NE(r.err.find(log.string() + ":5:29: column 'pitch_deg'"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << "nothing is replayed from a bad file";
}

TEST(ReplayCommand, UserLogWithoutTruthColumnsReplays) {
  const fs::path dir = temp_dir("user");
  const fs::path log = dir / "user.csv";
  {
    std::ofstream f(log);
    f << "time_ms,i_lf_a,i_lm_a,i_lr_a,i_rf_a,i_rm_a,i_rr_a,pitch_deg,roll_deg,rocker_l_deg,rocker_r_deg,"
         "bogie_l_deg,bogie_r_deg,speed_mps,rim_speed_mps\n";
    for (int i = 0; i < 50; ++i) f << i * 200 << ",0.4,0.4,0.4,0.4,0.4,0.4,0,0,0,0,0,0,0.05,0.055\n";
  }
  const CommandRun r = run({log.string(), "--gravity", "1.62"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("50 cycles"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("embedding  "), std::string::npos) << "a user log has no simulated embedding";
  EXPECT_NE(r.out.find("0.49 m driven"), std::string::npos) << "distance integrated from speed_mps: " << r.out;
}

TEST(ReplayCommand, MissingFileAndBadOptions) {
  const CommandRun missing = run({"/nonexistent/log.csv"});
  EXPECT_EQ(missing.code, 1) << "an I/O error (docs/conventions.md)";
  EXPECT_NE(missing.err.find("cannot open"), std::string::npos);
  EXPECT_EQ(run({"--scenario", "nope"}).code, 2) << "a usage error";
  EXPECT_EQ(run({"--every", "-1"}).code, 2);
}

TEST(ReplayCommand, UploadedTableIsUsedAndABadOneRejected) {
  namespace fl = sinkwatch::flight;
  const fs::path dir = temp_dir("table");
  // Lower stop levels must stop the rover earlier: a longer lead. (The
  // default stops on section 8's coefficient first: lower both.)
  fl::ParameterTable t = fl::default_parameter_table();
  t.table_version = 7;
  constexpr fl::SinkageM kLowerStop{sinkwatch::fx::constant<fl::LengthQ>(0.040)};
  t.monitor.stop_sinkage_m = kLowerStop;
  t.monitor.allowed_sinkage_m = t.monitor.stop_sinkage_m;
  constexpr fl::Ratio kLowerTractionStop{sinkwatch::fx::constant<fl::RatioQ>(0.34)};
  t.traction.stop_coefficient = kLowerTractionStop;
  ASSERT_EQ(fl::validate(t), fl::RejectReason::ok);
  std::vector<std::uint8_t> bytes(fl::kMaxTableBytes);
  const fl::EncodeResult enc = fl::encode(t, bytes.data(), bytes.size());
  ASSERT_EQ(enc.status, fl::RejectReason::ok);
  const fs::path table = dir / "table.bin";
  {
    std::ofstream f(table, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(enc.size));
  }
  const CommandRun base = run({});
  const CommandRun low = run({"--table", table.string()});
  ASSERT_EQ(low.code, 0) << low.err;
  EXPECT_NE(low.out.find("version 7"), std::string::npos);
  EXPECT_NE(low.out.find("sinkage >= 40.0 mm"), std::string::npos) << low.out;
  EXPECT_NE(low.out.find("reaches 0.34 (section 8)"), std::string::npos) << low.out;
  const auto stop_time = [](const std::string& out) {
    const std::size_t at = out.find("the first at ");
    return at == std::string::npos ? -1.0 : std::stod(out.substr(at + 13));
  };
  ASSERT_GT(stop_time(base.out), 0.0);
  ASSERT_GT(stop_time(low.out), 0.0);
  EXPECT_LT(stop_time(low.out), stop_time(base.out));

  // One flipped byte: the CRC no longer matches.
  bytes[20] = static_cast<std::uint8_t>(bytes[20] ^ 0x01U);
  {
    std::ofstream f(table, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(enc.size));
  }
  const CommandRun bad = run({"--table", table.string()});
  EXPECT_EQ(bad.code, 1) << "a data error (docs/conventions.md)";
  EXPECT_NE(bad.err.find("rejects this parameter table"), std::string::npos) << bad.err;
}

// Outputs (docs/output-files.md): a write error is an error, and a path that
// cannot be written is refused before the replay runs.
TEST(ReplayCommand, CsvToAFullDeviceIsAnError) {
  const CommandRun r = run({"--csv", "/dev/full"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/dev/full: refusing to replace a character device"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << "refused before the replay: " << r.out;
}

TEST(ReplayCommand, PlotIntoAMissingDirectoryIsRefusedBeforeTheReplay) {
  const CommandRun r = run({"--plot", "/nonexistent/x.png"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/nonexistent/x.png: cannot write here"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << "refused before the replay: " << r.out;
}

TEST(ReplayCommand, FailingGnuplotIsAnErrorAndLeavesNothing) {
  const fs::path dir = temp_dir("badgnuplot");
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  {
    std::ofstream fake(bin / "gnuplot");
    fake << "#!/bin/sh\necho 'gnuplot: cannot draw' >&2\nexit 1\n";
  }
  fs::permissions(bin / "gnuplot", fs::perms::owner_all);
  fs::create_directories(dir / "out");
  const fs::path image = dir / "out" / "replay.png";
  {
    std::ofstream old(image);
    old << "old";
  }
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path ? old_path : "";
  setenv("PATH", (bin.string() + ":" + saved).c_str(), 1);
  const CommandRun r = run({"--plot", image.string(), "--csv", (dir / "out" / "series.csv").string()});
  setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(image.string() + ": gnuplot failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("gnuplot: cannot draw"), std::string::npos) << r.err;
  std::ifstream in(image);
  std::string content;
  std::getline(in, content);
  EXPECT_EQ(content, "old") << "the old image is untouched";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir / "out")) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"replay.png"}) << "no temporary, script, log or CSV left behind";
}

TEST(ReplayCommand, CsvThroughASymlinkKeepsTheLink) {
  const fs::path dir = temp_dir("csvlink");
  {
    std::ofstream real(dir / "real.csv");
    real << "old\n";
  }
  fs::create_symlink("real.csv", dir / "link.csv");
  const CommandRun r = run({"--scenario", "nominal", "--csv", (dir / "link.csv").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_GT(line_count(dir / "real.csv"), 10U);
}
