// One command-line convention for every subcommand (issue 17,
// docs/conventions.md), checked on the built `sinkwatch` executable: exit
// codes (0 done, 1 data or I/O error, 2 usage error, CLI11's own errors
// included), the "sinkwatch <tool>: " prefix, -q/--quiet and -v/--verbose,
// conflicting or meaningless options refused, defaults in --help, and the
// reject reason of a bad parameter table by name.
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace fl = sinkwatch::flight;

namespace {

const std::string kTable1 = std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv";

struct CliRun {
  int code;
  std::string out;
  std::string err;
};

fs::path scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_cli_conventions_" + std::to_string(::getpid())) /
                       info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string quote(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs `sinkwatch ARGS...` with stdin from /dev/null.
CliRun cli(const std::vector<std::string>& args) {
  static int serial = 0;
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_cli_conventions_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path out = dir / ("out" + std::to_string(serial) + ".txt");
  const fs::path err = dir / ("err" + std::to_string(serial) + ".txt");
  ++serial;
  std::string command = quote(SINKWATCH_CLI);
  for (const std::string& a : args) command += " " + quote(a);
  command += " </dev/null >" + quote(out.string()) + " 2>" + quote(err.string());
  const int status = std::system(command.c_str());
  CliRun run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  fs::remove(out);
  fs::remove(err);
  return run;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes, std::size_t size) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(size));
}

// The flight default table, with the rover section when asked, encoded.
std::vector<std::uint8_t> table_bytes(bool with_rover, std::size_t& size) {
  fl::ParameterTable t = fl::default_parameter_table();
  if (with_rover) t.rover_geometry = fl::RoverSection{true, fl::detail::kYutuLikeRoverParams};
  std::vector<std::uint8_t> bytes(fl::kMaxTableBytes);
  const fl::EncodeResult enc = fl::encode(t, bytes.data(), bytes.size());
  EXPECT_EQ(enc.status, fl::RejectReason::ok);
  size = enc.size;
  return bytes;
}

const std::vector<std::string> kTools = {"calibrate", "diagnose", "replay", "rover-table", "simulate", "table-info"};

}  // namespace

TEST(CliConventions, UsageErrorsExitTwoWithThePrefix) {
  const std::vector<std::vector<std::string>> unknown = {
      {"calibrate", kTable1, "--no-such-option"},
      {"diagnose", "--real", kTable1, "--no-such-option"},
      {"replay", "--no-such-option"},
      {"rover-table", "--out", (scratch() / "u.tbl").string(), "--no-such-option"},
      {"simulate", "--no-such-option"},
      {"table-info", kTable1, "--no-such-option"},
  };
  for (const std::vector<std::string>& args : unknown) {
    const CliRun r = cli(args);
    const std::string& tool = args.front();
    EXPECT_EQ(r.code, 2) << tool << ": " << r.err;
    EXPECT_EQ(r.err.rfind("sinkwatch " + tool + ": ", 0), 0U) << tool << ": " << r.err;
    EXPECT_TRUE(has(r.err, "--no-such-option")) << r.err;
  }
  const CliRun none = cli({});
  EXPECT_EQ(none.code, 2);
  EXPECT_EQ(none.err.rfind("sinkwatch: ", 0), 0U) << none.err;
  // Missing argument, missing value, bad value: all CLI11 errors are usage errors.
  EXPECT_EQ(cli({"calibrate"}).code, 2);
  EXPECT_EQ(cli({"diagnose"}).code, 2);
  EXPECT_EQ(cli({"replay", "--every"}).code, 2);
  EXPECT_EQ(cli({"simulate", "--radius", "abc"}).code, 2);
  EXPECT_EQ(cli({"diagnose", "--real", kTable1, "--model", "nope"}).code, 2);
}

TEST(CliConventions, DataErrorsExitOneWithThePrefix) {
  const fs::path missing = scratch() / "missing.csv";
  const std::vector<std::vector<std::string>> cases = {
      {"calibrate", missing.string()},
      {"diagnose", "--real", missing.string()},
      {"replay", missing.string()},
      {"rover-table", "--out", (scratch() / "d.tbl").string(), "--base-table", missing.string()},
      {"simulate", "--loads", "1e7"},  // the wheel sinks past its axle
      {"table-info", missing.string()},
  };
  for (const std::vector<std::string>& args : cases) {
    const CliRun r = cli(args);
    EXPECT_EQ(r.code, 1) << args.front() << ": " << r.err;
    EXPECT_EQ(r.err.rfind("sinkwatch " + args.front() + ": ", 0), 0U) << r.err;
  }
}

TEST(CliConventions, HelpAndVersionExitZero) {
  EXPECT_EQ(cli({"--version"}).code, 0);
  EXPECT_EQ(cli({"--help"}).code, 0);
  for (const std::string& tool : kTools) {
    const CliRun r = cli({tool, "--help"});
    EXPECT_EQ(r.code, 0) << tool;
    EXPECT_TRUE(has(r.out, "-q,--quiet")) << tool << ": " << r.out;
    EXPECT_TRUE(has(r.out, "-v,--verbose")) << tool << ": " << r.out;
  }
}

TEST(CliConventions, HelpShowsDefaults) {
  const CliRun replay = cli({"replay", "--help"});
  EXPECT_TRUE(has(replay.out, "=embedding")) << replay.out;
  EXPECT_TRUE(has(replay.out, "=30")) << replay.out;
  const CliRun diagnose = cli({"diagnose", "--help"});
  EXPECT_TRUE(has(diagnose.out, "=wong-reece")) << diagnose.out;
  EXPECT_TRUE(has(diagnose.out, "=hit-lss1")) << diagnose.out;
  EXPECT_TRUE(has(diagnose.out, "=9.81")) << diagnose.out;
  const CliRun simulate = cli({"simulate", "--help"});
  EXPECT_TRUE(has(simulate.out, "=0:0.05:0.7")) << simulate.out;
}

TEST(CliConventions, QuietSilencesNotesAndVerboseAddsDetail) {
  // replay: --gravity beside a table with a rover section is a note on stderr.
  const fs::path dir = scratch();
  std::size_t size = 0;
  const std::vector<std::uint8_t> bytes = table_bytes(true, size);
  write_bytes(dir / "rover.bin", bytes, size);
  const CliRun noted = cli({"replay", "--table", (dir / "rover.bin").string(), "--gravity", "1.62"});
  ASSERT_EQ(noted.code, 0) << noted.err;
  EXPECT_TRUE(has(noted.err, "sinkwatch replay: note: --gravity is ignored")) << noted.err;
  const CliRun quiet = cli({"replay", "--table", (dir / "rover.bin").string(), "--gravity", "1.62", "--quiet"});
  EXPECT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  EXPECT_EQ(quiet.out, noted.out) << "quiet leaves the report alone";

  const std::vector<std::vector<std::string>> runs = {
      {"calibrate", kTable1},
      {"diagnose", "--real", kTable1, "--model", "estimator", "--radius", "0.15", "--width", "0.15"},
      {"simulate", "--masses", "3", "--slips", "0.1"},
  };
  for (std::vector<std::string> args : runs) {
    args.push_back("-q");
    const CliRun q = cli(args);
    EXPECT_EQ(q.code, 0) << args.front() << ": " << q.err;
    EXPECT_TRUE(q.err.empty()) << args.front() << ": " << q.err;
    args.back() = "-v";
    const CliRun v = cli(args);
    EXPECT_EQ(v.code, 0) << args.front() << ": " << v.err;
    EXPECT_TRUE(has(v.err, "sinkwatch " + args.front() + ": ")) << args.front() << " -v: " << v.err;
    args.push_back("-q");
    EXPECT_EQ(cli(args).code, 2) << args.front() << ": -q and -v exclude each other";
  }
  const CliRun every = cli({"replay", "--scenario", "nominal", "-v"});
  EXPECT_EQ(every.code, 0) << every.err;
  EXPECT_GT(std::count(every.out.begin(), every.out.end(), '\n'), 2000) << "-v prints every cycle";
}

TEST(CliConventions, ConflictingOrMeaninglessOptionsAreUsageErrors) {
  const fs::path dir = scratch();
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> named;  // every one must appear in the message
  };
  const std::vector<Case> cases = {
      {{"replay", (dir / "log.csv").string(), "--scenario", "nominal"}, {"telemetry", "--scenario"}},
      {{"replay", "--gravity", "nan"}, {"--gravity"}},
      {{"replay", "--every", "nan"}, {"--every"}},
      {{"replay", "--every", "inf"}, {"--every"}},
      {{"replay", "--csv", ""}, {"--csv"}},
      {{"diagnose", "--real", kTable1, "--model", "estimator", "--soil", "dry-sand"}, {"--soil", "--model"}},
      {{"diagnose", "--real", kTable1, "--model", "estimator", "--gravity", "1.62"}, {"--gravity", "--model"}},
      {{"diagnose", "--real", kTable1, "--model", "estimator", "--fit", "soil.n"}, {"--fit", "--model"}},
      {{"diagnose", "--real", kTable1, "--gravity", "nan"}, {"--gravity"}},
      {{"diagnose", "--real", kTable1, "--fit", "soil.bogus"}, {"--fit"}},
      {{"diagnose", "--real", kTable1, "--soil", "clay"}, {"--soil"}},
      {{"calibrate", kTable1, "--base-table", "base.bin"}, {"--base-table", "--table"}},
      {{"calibrate", kTable1, "--table-version", "3"}, {"--table-version", "--table"}},
      {{"calibrate", kTable1, "--radius", "nan"}, {"--radius"}},
      {{"calibrate", kTable1, "--fix", ""}, {"--fix"}},
      {{"simulate", "--seed", "-1"}, {"--seed"}},
      {{"simulate", "--seed", "1.5"}, {"--seed"}},
      {{"simulate", "--loads", ""}, {"--loads"}},
      {{"simulate", "--masses", ","}, {"--masses"}},
      {{"simulate", "--gravity", "nan"}, {"--gravity"}},
      {{"simulate", "--out", ""}, {"--out"}},
      {{"simulate", "--list", "--seed", "3"}, {"--list", "--seed"}},
  };
  for (const Case& c : cases) {
    const CliRun r = cli(c.args);
    std::string shown;
    for (const std::string& a : c.args) shown += a + " ";
    EXPECT_EQ(r.code, 2) << shown << "-> " << r.err;
    EXPECT_EQ(r.err.rfind("sinkwatch " + c.args.front() + ": ", 0), 0U) << shown << "-> " << r.err;
    for (const std::string& name : c.named) EXPECT_TRUE(has(r.err, name)) << shown << "-> " << r.err;
    EXPECT_TRUE(r.out.empty()) << shown << "-> nothing runs: " << r.out;
  }
}

TEST(CliConventions, SeedIsReadAsDecimal) {
  const CliRun octal = cli({"simulate", "--masses", "3", "--slips", "0.1", "--noise", "torque=5%", "--seed", "010"});
  const CliRun ten = cli({"simulate", "--masses", "3", "--slips", "0.1", "--noise", "torque=5%", "--seed", "10"});
  ASSERT_EQ(octal.code, 0) << octal.err;
  ASSERT_EQ(ten.code, 0) << ten.err;
  EXPECT_TRUE(has(octal.out, "# seed: 10")) << octal.out;
  EXPECT_EQ(octal.out.substr(octal.out.find("slip,")), ten.out.substr(ten.out.find("slip,")));
}

TEST(CliConventions, CorruptTableNamesItsRejectReason) {
  const fs::path dir = scratch();
  std::size_t size = 0;
  std::vector<std::uint8_t> bytes = table_bytes(false, size);
  bytes[20] = static_cast<std::uint8_t>(bytes[20] ^ 0x01U);  // the CRC no longer matches
  write_bytes(dir / "bad.bin", bytes, size);
  const CliRun r = cli({"replay", "--table", (dir / "bad.bin").string()});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("sinkwatch replay: ", 0), 0U) << r.err;
  EXPECT_TRUE(has(r.err, "crc_mismatch")) << r.err;
  // The same name as calibrate --base-table gives.
  const CliRun base = cli({"calibrate", kTable1, "--load", "29.43", "--table", (dir / "out.bin").string(),
                           "--base-table", (dir / "bad.bin").string()});
  EXPECT_EQ(base.code, 1) << base.err;
  EXPECT_TRUE(has(base.err, "crc_mismatch")) << base.err;
}
