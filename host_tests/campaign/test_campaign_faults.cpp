// The campaign with sensor faults (campaign.hpp FaultClass, docs/fault-
// injection.md): the fault draws are a pure function of the traverse, the
// faulty verdicts keep the clean timeline, the files do not depend on the
// thread count, and a small run through the command writes faults.csv and
// the table (seconds: short paths, few traverses).
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/campaign_report.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using namespace sinkwatch::ground;
namespace fs = std::filesystem;

CampaignOptions small_fault_campaign(unsigned threads) {
  CampaignOptions o;
  o.families = {CampaignFamily::abrupt};
  o.traverses_per_family = 2;
  o.seed = 5;
  o.path_length_m = 7.0;
  o.threads = threads;
  o.sweep_stop_mm = {45};
  o.faults = {FaultClass::stuck_current, FaultClass::dropout_imu, FaultClass::jump_clock};
  return o;
}

int campaign(const std::vector<std::string>& args, std::string* out_text = nullptr, std::string* err_text = nullptr) {
  std::ostringstream out, err;
  const int rc = run_campaign_command(args, out, err);
  if (out_text) *out_text = out.str();
  if (err_text) *err_text = err.str();
  return rc;
}

}  // namespace

TEST(CampaignFaults, ClassNamesRoundTripAndUnknownOnesAreNamed) {
  for (const FaultClass c : all_fault_classes()) EXPECT_EQ(fault_class_from_name(fault_class_name(c)), c);
  EXPECT_EQ(all_fault_classes().size(), kFaultClasses);
  try {
    (void)fault_class_from_name("melt");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown fault class 'melt'; known: stuck-current"), std::string::npos);
  }
}

TEST(CampaignFaults, DrawsAreAPureFunctionOfTheTraverseAndStayInTheWindow) {
  for (const FaultClass c : all_fault_classes()) {
    for (std::uint64_t seed = 1; seed < 40; ++seed) {
      const FaultSpec f = draw_fault(c, seed, 300.0);
      EXPECT_EQ(f.text(), draw_fault(c, seed, 300.0).text());
      EXPECT_GE(f.start_s, 30.0 - 0.05) << f.text();
      EXPECT_LE(f.start_s, 270.0 + 0.05) << f.text();
      EXPECT_NO_THROW((void)parse_fault(f.text())) << f.text();  // every drawn fault is a valid spec
    }
  }
  EXPECT_EQ(draw_fault(FaultClass::noise_imu, 3, 300.0).text().rfind("noise:imu@", 0), 0U);
  EXPECT_NE(draw_fault(FaultClass::stuck_current, 3, 300.0).text(), draw_fault(FaultClass::stuck_current, 4, 300.0).text());
}

TEST(CampaignFaults, SameSeedGivesTheSameFaultsWhateverTheThreadCount) {
  const CampaignResult one = run_campaign(small_fault_campaign(1));
  const CampaignResult two = run_campaign(small_fault_campaign(2));
  EXPECT_EQ(faults_csv(one), faults_csv(two));
  ASSERT_EQ(one.traverses.size(), 2U);
  ASSERT_EQ(one.traverses[0].faults.size(), 3U);
  for (const TraverseResult& t : one.traverses) {
    for (const FaultVerdict& f : t.faults) {
      // A stop caused after the fault began; the times are the clean rows' (a
      // clock jump does not move them past the log).
      if (f.flight.stop_time_s && !t.flight.stop_time_s) {
        EXPECT_GE(*f.flight.stop_time_s, f.spec.start_s);
      }
      if (f.flight.stop_time_s) {
        EXPECT_LE(*f.flight.stop_time_s, t.draw.spec.max_time_s + 1.0);
      }
      if (f.detected_time_s) {
        EXPECT_GE(*f.detected_time_s, f.spec.start_s - 1e-6) << f.spec.text();
      }
    }
  }
  std::istringstream csv(faults_csv(one));
  std::string line;
  std::getline(csv, line);
  std::string header;
  for (const std::string& c : fault_csv_columns()) header += (header.empty() ? "" : ",") + c;
  EXPECT_EQ(line, header);
  std::size_t rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 6U);
  const std::string table = fault_table(one);
  EXPECT_NE(table.find("| stuck-current | 2 | "), std::string::npos) << table;
  EXPECT_NE(table.find("| jump-clock | 2 | "), std::string::npos) << table;
}

TEST(CampaignFaults, TheCommandWritesFaultsCsvAndTheTable) {
  const fs::path dir = fs::temp_directory_path() / "sinkwatch_campaign_faults_test";
  fs::remove_all(dir);
  std::string out, err;
  ASSERT_EQ(campaign({"--out", dir.string(), "--traverses", "1", "--families", "abrupt", "--path-length", "7",
                      "--levels", "45", "-j", "1", "-q", "--faults", "all"},
                     &out, &err),
            0)
      << err;
  EXPECT_TRUE(fs::exists(dir / "faults.csv"));
  EXPECT_NE(out.find("Sensor faults"), std::string::npos) << out;
  for (const FaultClass c : all_fault_classes()) {
    EXPECT_NE(out.find(std::string("| ") + fault_class_name(c) + " | 1 | "), std::string::npos) << fault_class_name(c);
  }
  fs::remove_all(dir);
  // Without --faults: no faults.csv, no table.
  ASSERT_EQ(campaign({"--out", dir.string(), "--traverses", "1", "--families", "abrupt", "--path-length", "7",
                      "--levels", "45", "-j", "1", "-q"},
                     &out),
            0);
  EXPECT_FALSE(fs::exists(dir / "faults.csv"));
  EXPECT_EQ(out.find("Sensor faults"), std::string::npos);
  fs::remove_all(dir);
}

TEST(CampaignFaults, BadFaultClassesAreUsageErrors) {
  const std::string dir = (fs::temp_directory_path() / "sinkwatch_campaign_faults_bad").string();
  std::string err;
  EXPECT_EQ(campaign({"--out", dir, "--faults", "stuck-current,melt"}, nullptr, &err), exit_status(ExitCode::usage_error));
  EXPECT_NE(err.find("--faults: unknown fault class 'melt'"), std::string::npos) << err;
  EXPECT_EQ(campaign({"--out", dir, "--faults", ""}), exit_status(ExitCode::usage_error));
  EXPECT_FALSE(fs::exists(dir));
}
