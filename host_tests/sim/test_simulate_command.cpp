// `sinkwatch simulate`: output, reproducibility and clear errors for bad flags.
#include "sinkwatch/ground/simulate_command.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace sg = sinkwatch::ground;

namespace {
struct CliRun {
  int code;
  std::string out;
  std::string err;
};
CliRun run(const std::vector<std::string>& args) {
  std::ostringstream out;
  std::ostringstream err;
  const int code = sg::run_simulate(args, out, err);
  return {code, out.str(), err.str()};
}
const std::vector<std::string> kSmall = {"--soil", "lunar-soil", "--body", "moon", "--masses", "20,60",
                                         "--slips", "0.1:0.2:0.5", "--effect", "bulldozing:scale=0.5",
                                         "--noise", "torque=2%,sinkage=0.0005", "--seed", "9"};
}  // namespace

TEST(SimulateCommand, WritesCommentedCsvWithTheCalibrationColumns) {
  const CliRun r = run(kSmall);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  int comments = 0;
  int data = 0;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      EXPECT_FALSE(header) << "comment after the header";
      ++comments;
    } else if (!header) {
      EXPECT_EQ(line, "slip,load_N,sinkage_m,torque_Nm,drawbar_pull_N,wheel_radius_m,wheel_width_m");
      header = true;
    } else {
      ++data;
    }
  }
  EXPECT_EQ(data, 2 * 3);
  EXPECT_GE(comments, 6);
  EXPECT_NE(r.out.find("# command: sinkwatch simulate --soil lunar-soil"), std::string::npos);
  EXPECT_NE(r.out.find("effects: bulldozing(scale=0.5)"), std::string::npos);
  EXPECT_NE(r.out.find("seed: 9"), std::string::npos);
  EXPECT_NE(r.out.find("(moon)"), std::string::npos);
  // 20 kg on the Moon: W = 20 * 1.62 = 32.4 N.
  EXPECT_NE(r.out.find("\n0.1,32.4,"), std::string::npos);
}

TEST(SimulateCommand, SameSeedGivesByteIdenticalOutputAlsoToAFile) {
  const CliRun a = run(kSmall);
  const CliRun b = run(kSmall);
  EXPECT_EQ(a.out, b.out);
  std::vector<std::string> other = kSmall;
  other.back() = "10";
  EXPECT_NE(run(other).out.substr(a.out.find("slip,")), a.out.substr(a.out.find("slip,")));

  const std::string path = ::testing::TempDir() + "sinkwatch_simulate_test.csv";
  std::vector<std::string> to_file = kSmall;
  to_file.insert(to_file.end(), {"--out", path});
  ASSERT_EQ(run(to_file).code, 0);
  std::ifstream f(path, std::ios::binary);
  std::stringstream content;
  content << f.rdbuf();
  // Same data rows; only the recorded command differs (it names --out).
  EXPECT_EQ(content.str().substr(content.str().find("# soil")), a.out.substr(a.out.find("# soil")));
  std::remove(path.c_str());
}

TEST(SimulateCommand, ListPrintsTheCatalogue) {
  const CliRun r = run({"--list"});
  EXPECT_EQ(r.code, 0);
  for (const char* word : {"hit-lss1", "lunar-soil", "dry-sand", "slip_sinkage", "stress_peak_shift", "rear_contact",
                           "grouser", "bulldozing", "load_dependence", "drive_friction", "soil.kphi"}) {
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
  }
}

TEST(SimulateCommand, BadFlagsGiveClearErrors) {
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"--effect", "mud"}, "unknown effect 'mud'"},
      {{"--effect", "grouser:depth=1"}, "no parameter 'depth'"},
      {{"--soil", "clay"}, "unknown soil 'clay'"},
      {{"--body", "pluto"}, "unknown body 'pluto'"},
      {{"--slips", "0:0:1"}, "step must be > 0"},
      {{"--slips", "0.5,1.5"}, "outside [0, 1]"},
      {{"--loads", "10,abc"}, "'abc' is not a finite number"},
      {{"--loads", "10", "--masses", "3"}, "excludes"},
      {{"--body", "moon", "--gravity", "2"}, "excludes"},
      {{"--radius", "-0.1"}, "--radius"},
      {{"--noise", "torque=x%"}, "'x' is not a finite number"},
      {{"--noise", "voltage=1"}, "unknown noise channel"},
      {{"--set", "soil.bogus=1"}, "unknown model parameter"},
      {{"--loads", "1e7"}, "sinks past its axle"},
      {{"--bogus"}, "bogus"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_NE(r.code, 0) << c.args.front();
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args.front() << " -> " << r.err;
    EXPECT_TRUE(r.out.empty() || r.out.find("slip,") == std::string::npos) << c.args.front();
  }
}

TEST(SimulateCommand, JoinCommandLineQuotesAndStripsThePath) {
  const char* argv[] = {"/usr/local/bin/sinkwatch", "simulate", "--effect", "a b", "it's"};
  EXPECT_EQ(sg::join_command_line(5, argv), "sinkwatch simulate --effect 'a b' 'it'\\''s'");
}

// Outputs (docs/output-files.md): a write error on standard output or --out
// is an error (exit 1), and --out is checked before the simulation.
TEST(SimulateCommand, AFullStandardOutputIsAnError) {
  std::ofstream full("/dev/full");  // what `sinkwatch simulate > /dev/full` writes to
  ASSERT_TRUE(full.is_open());
  std::ostringstream err;
  const int code = sg::run_simulate(kSmall, full, err);
  EXPECT_EQ(code, 1);
  EXPECT_NE(err.str().find("sinkwatch simulate: standard output: write failed"), std::string::npos) << err.str();
}

TEST(SimulateCommand, OutToAFullDeviceOrAMissingDirectoryIsAnError) {
  CliRun r = run({"--out", "/dev/full"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/dev/full: refusing to replace a character device"), std::string::npos) << r.err;
  r = run({"--out", "/nonexistent/x.csv"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/nonexistent/x.csv: cannot write here"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(SimulateCommand, OutDashIsStandardOutput) {
  std::vector<std::string> args = kSmall;
  args.insert(args.end(), {"--out", "-"});
  const CliRun r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("slip,load_N,sinkage_m"), std::string::npos);
}
