// The golden vectors: the flight code still produces the recorded bits.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "golden_vectors.hpp"

namespace {

const std::string kPath = std::string(SINKWATCH_DATA_DIR) + "/golden/flight_vectors.csv";

TEST(FlightGolden, EveryRowMatchesBitForBit) {
  const sinkwatch::golden::Report r = sinkwatch::golden::check_flight_golden(kPath.c_str());
  ASSERT_TRUE(r.readable) << r.message;
  EXPECT_GT(r.rows, 500);
  EXPECT_EQ(r.failures, 0) << r.message;
}

TEST(FlightGolden, ACorruptedRowIsDetected) {
  // The checker must be able to fail: flip one output and check a copy.
  std::FILE* in = std::fopen(kPath.c_str(), "r");
  ASSERT_NE(in, nullptr);
  const std::string copy = testing::TempDir() + "flight_vectors_corrupt.csv";
  std::FILE* out = std::fopen(copy.c_str(), "w");
  ASSERT_NE(out, nullptr);
  char line[1024];
  bool changed = false;
  while (std::fgets(line, sizeof line, in) != nullptr) {
    std::string s(line);
    if (!changed && s.rfind("sinkage,", 0) == 0) {
      // Replace the status column (last) by 9.
      const std::size_t last = s.find_last_of(',');
      s = s.substr(0, last + 1) + "9\n";
      changed = true;
    }
    std::fputs(s.c_str(), out);
  }
  std::fclose(in);
  std::fclose(out);
  ASSERT_TRUE(changed);
  const sinkwatch::golden::Report r = sinkwatch::golden::check_flight_golden(copy.c_str());
  EXPECT_TRUE(r.readable);
  EXPECT_EQ(r.failures, 1);
}

TEST(FlightGolden, AMissingFileIsReportedNotPassed) {
  const sinkwatch::golden::Report r = sinkwatch::golden::check_flight_golden("/nonexistent/flight_vectors.csv");
  EXPECT_FALSE(r.readable);
}

}  // namespace
