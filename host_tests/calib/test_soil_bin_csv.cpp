// Tests of the soil-bin CSV reader: both input forms, comments and unknown
// columns, and every malformed input rejected with a message that names the
// file, the line and the column.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {
namespace {

SoilBinDataset parse(const std::string& text, const SoilBinReadOptions& options = {}) {
  std::istringstream in(text);
  return parse_soil_bin_csv(in, "test.csv", options);
}

// Parses text that must be rejected and returns the error.
DataError rejection(const std::string& text, const SoilBinReadOptions& options = {}) {
  try {
    (void)parse(text, options);
  } catch (const DataError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted malformed input:\n" << text;
  return DataError("", 0, 0, "", "");
}

const std::string kDimensionless =
    "slip,sinkage_ratio,drive_coeff,traction_coeff\n"
    "0.1,0.08,0.35,0.10\n"
    "0.2,0.09,0.55,0.29\n";

TEST(SoilBinCsv, ReadsTheDimensionlessForm) {
  const SoilBinDataset d = parse(kDimensionless);
  EXPECT_EQ(d.form, SoilBinForm::dimensionless);
  EXPECT_FALSE(d.has_load);
  ASSERT_EQ(d.rows.size(), 2U);
  EXPECT_EQ(d.rows[1].line, 3U);
  EXPECT_DOUBLE_EQ(d.rows[1].slip, 0.2);
  EXPECT_DOUBLE_EQ(d.rows[1].sinkage_ratio, 0.09);
  EXPECT_DOUBLE_EQ(d.rows[1].drive_coeff, 0.55);
  EXPECT_DOUBLE_EQ(d.rows[1].traction_coeff, 0.29);
  EXPECT_FALSE(d.rows[1].load_n.has_value());
}

TEST(SoilBinCsv, ReadsTheDimensionalFormAndNormalises) {
  const SoilBinDataset d = parse(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
      "0.3,29.43,3.0,0.012,10.0,0.15,0.165\n");
  EXPECT_EQ(d.form, SoilBinForm::dimensional);
  EXPECT_TRUE(d.has_load);
  ASSERT_EQ(d.rows.size(), 1U);
  const SoilBinRow& r = d.rows[0];
  EXPECT_DOUBLE_EQ(r.sinkage_ratio, 0.012 / 0.15);
  EXPECT_DOUBLE_EQ(r.drive_coeff, 3.0 / (0.15 * 29.43));
  EXPECT_DOUBLE_EQ(r.traction_coeff, 10.0 / 29.43);
  EXPECT_DOUBLE_EQ(*r.load_n, 29.43);
  EXPECT_DOUBLE_EQ(*r.wheel_radius_m, 0.15);
}

TEST(SoilBinCsv, TakesTheRadiusFromTheCallerWhenThereIsNoColumn) {
  SoilBinReadOptions options;
  options.wheel_radius_m = 0.2;
  const SoilBinDataset d =
      parse("slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N\n0.3,50,4,0.02,12\n", options);
  EXPECT_DOUBLE_EQ(d.rows[0].sinkage_ratio, 0.1);
  EXPECT_DOUBLE_EQ(d.rows[0].drive_coeff, 4.0 / (0.2 * 50.0));
}

TEST(SoilBinCsv, TakesTheLoadFromTheCallerForDimensionlessData) {
  SoilBinReadOptions options;
  options.load_n = 29.43;
  const SoilBinDataset d = parse(kDimensionless, options);
  EXPECT_TRUE(d.has_load);
  EXPECT_DOUBLE_EQ(*d.rows[0].load_n, 29.43);
}

TEST(SoilBinCsv, SkipsCommentsBlankLinesAndCarriageReturnsAndIgnoresUnknownColumns) {
  const SoilBinDataset d = parse(
      "# a comment before the header\r\n"
      "\r\n"
      "run, slip ,notes,sinkage_ratio,drive_coeff,traction_coeff\r\n"
      "  # an indented comment\r\n"
      "7,+0.1,soft patch,0.08,0.35,-0.05\r\n"
      "\r\n"
      "8,0.2,,9e-2,0.55,0.29\r\n");
  ASSERT_EQ(d.rows.size(), 2U);
  EXPECT_EQ(d.rows[0].line, 5U);
  EXPECT_EQ(d.rows[1].line, 7U);
  EXPECT_DOUBLE_EQ(d.rows[0].slip, 0.1);
  EXPECT_DOUBLE_EQ(d.rows[0].traction_coeff, -0.05);
  EXPECT_DOUBLE_EQ(d.rows[1].sinkage_ratio, 0.09);
}

TEST(SoilBinCsv, ReadsThePapersTable1) {
  const SoilBinDataset d = read_soil_bin_csv(std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv");
  EXPECT_EQ(d.form, SoilBinForm::dimensionless);
  ASSERT_EQ(d.rows.size(), 16U);
  EXPECT_DOUBLE_EQ(d.rows.front().slip, 0.06);
  EXPECT_DOUBLE_EQ(d.rows.front().traction_coeff, -0.051);
  EXPECT_DOUBLE_EQ(d.rows.back().slip, 0.66);
  EXPECT_DOUBLE_EQ(d.rows.back().drive_coeff, 0.833);
}

// --- malformed input: each one rejected, with file, line and column named ---

TEST(SoilBinCsvRejects, AnEmptyFile) {
  const DataError e = rejection("");
  EXPECT_NE(std::string(e.what()).find("test.csv"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("empty file"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AFileOfOnlyComments) {
  const DataError e = rejection("# nothing here\n\n# still nothing\n");
  EXPECT_NE(std::string(e.what()).find("empty file"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AHeaderWithoutRows) {
  const DataError e = rejection("# c\nslip,sinkage_ratio,drive_coeff,traction_coeff\n# no rows\n");
  EXPECT_EQ(e.line(), 2U);
  EXPECT_NE(std::string(e.what()).find("no data rows"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AMissingDimensionlessColumn) {
  const DataError e = rejection("slip,sinkage_ratio,traction_coeff\n0.1,0.08,0.1\n");
  EXPECT_EQ(e.line(), 1U);
  EXPECT_NE(std::string(e.what()).find("missing column(s) drive_coeff"), std::string::npos)
      << e.what();
}

TEST(SoilBinCsvRejects, AMissingDimensionalColumn) {
  const DataError e =
      rejection("slip,load_N,torque_Nm,drawbar_pull_N,wheel_radius_m\n0.1,30,3,10,0.15\n");
  EXPECT_NE(std::string(e.what()).find("missing column(s) sinkage_m"), std::string::npos)
      << e.what();
}

TEST(SoilBinCsvRejects, AHeaderOfNeitherForm) {
  const DataError e = rejection("a,b,c\n1,2,3\n");
  EXPECT_NE(std::string(e.what()).find("neither"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ADuplicateColumn) {
  const DataError e =
      rejection("slip,sinkage_ratio,drive_coeff,traction_coeff,slip\n0.1,0.08,0.35,0.1,0.2\n");
  EXPECT_EQ(e.line(), 1U);
  EXPECT_EQ(e.column(), 5U);
  EXPECT_NE(std::string(e.what()).find("twice"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ANonNumber) {
  const DataError e = rejection(kDimensionless + "0.3,0.1,abc,0.3\n");
  EXPECT_EQ(e.line(), 4U);
  EXPECT_EQ(e.column(), 3U);
  EXPECT_EQ(e.column_name(), "drive_coeff");
  EXPECT_EQ(std::string(e.what()), "test.csv:4:3: column 'drive_coeff': 'abc' is not a number");
}

TEST(SoilBinCsvRejects, ANumberWithTrailingGarbage) {
  const DataError e = rejection(kDimensionless + "0.3,0.1x,0.6,0.3\n");
  EXPECT_EQ(e.column(), 2U);
  EXPECT_NE(std::string(e.what()).find("'0.1x' is not a number"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AnEmptyField) {
  const DataError e = rejection(kDimensionless + "0.3,0.1,,0.3\n");
  EXPECT_EQ(e.column(), 3U);
  EXPECT_NE(std::string(e.what()).find("empty field"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, NaN) {
  const DataError e = rejection(kDimensionless + "0.3,0.1,0.6,nan\n");
  EXPECT_EQ(e.line(), 4U);
  EXPECT_EQ(e.column(), 4U);
  EXPECT_NE(std::string(e.what()).find("not a finite number"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, Infinity) {
  const DataError e = rejection(kDimensionless + "inf,0.1,0.6,0.3\n");
  EXPECT_EQ(e.column(), 1U);
  EXPECT_NE(std::string(e.what()).find("not a finite number"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ANumberOutOfRange) {
  const DataError e = rejection(kDimensionless + "0.3,1e999,0.6,0.3\n");
  EXPECT_EQ(e.column(), 2U);
  EXPECT_NE(std::string(e.what()).find("out of the range"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, TooFewFields) {
  const DataError e = rejection(kDimensionless + "0.3,0.1,0.6\n");
  EXPECT_EQ(e.line(), 4U);
  EXPECT_EQ(e.column(), 4U);
  EXPECT_EQ(e.column_name(), "traction_coeff");
  EXPECT_NE(std::string(e.what()).find("wrong number of fields: the header has 4, this row has 3"),
            std::string::npos)
      << e.what();
}

TEST(SoilBinCsvRejects, TooManyFields) {
  const DataError e = rejection(kDimensionless + "0.3,0.1,0.6,0.3,9\n");
  EXPECT_EQ(e.column(), 5U);
  EXPECT_NE(std::string(e.what()).find("this row has 5"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AMissingRadius) {
  const DataError e = rejection("slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N\n0.3,50,4,0.02,12\n");
  EXPECT_EQ(e.line(), 1U);
  EXPECT_NE(std::string(e.what()).find("missing wheel radius"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ARadiusGivenTwice) {
  SoilBinReadOptions options;
  options.wheel_radius_m = 0.15;
  const DataError e = rejection(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m\n0.3,50,4,0.02,12,0.15\n",
      options);
  EXPECT_EQ(e.column_name(), "wheel_radius_m");
  EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ALoadGivenTwice) {
  SoilBinReadOptions options;
  options.load_n = 29.43;
  const DataError e =
      rejection("slip,load_N,sinkage_ratio,drive_coeff,traction_coeff\n0.1,29.43,0.08,0.35,0.1\n",
                options);
  EXPECT_EQ(e.column_name(), "load_N");
  EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AZeroLoad) {
  const DataError e = rejection(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m\n"
      "0.3,50,4,0.02,12,0.15\n"
      "0.4,0,4,0.02,12,0.15\n");
  EXPECT_EQ(e.line(), 3U);
  EXPECT_EQ(e.column(), 2U);
  EXPECT_EQ(std::string(e.what()), "test.csv:3:2: column 'load_N': '0' must be greater than zero");
}

TEST(SoilBinCsvRejects, ANegativeLoadInDimensionlessData) {
  const DataError e =
      rejection("slip,load_N,sinkage_ratio,drive_coeff,traction_coeff\n0.1,-3,0.08,0.35,0.1\n");
  EXPECT_EQ(e.column_name(), "load_N");
  EXPECT_NE(std::string(e.what()).find("greater than zero"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AZeroRadiusColumn) {
  const DataError e = rejection(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m\n0.3,50,4,0.02,12,0\n");
  EXPECT_EQ(e.column_name(), "wheel_radius_m");
  EXPECT_NE(std::string(e.what()).find("greater than zero"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ABadRadiusOrLoadFromTheCaller) {
  SoilBinReadOptions radius;
  radius.wheel_radius_m = -0.1;
  EXPECT_NE(std::string(rejection(kDimensionless, radius).what()).find("wheel radius"),
            std::string::npos);
  SoilBinReadOptions load;
  load.load_n = 0.0;
  EXPECT_NE(std::string(rejection(kDimensionless, load).what()).find("wheel load"),
            std::string::npos);
}

TEST(SoilBinCsvRejects, AnEmptyColumnName) {
  const DataError e = rejection("slip,,sinkage_ratio,drive_coeff,traction_coeff\n1,2,3,4,5\n");
  EXPECT_EQ(e.column(), 2U);
  EXPECT_NE(std::string(e.what()).find("empty column name"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, AFileThatDoesNotExist) {
  try {
    (void)read_soil_bin_csv("/nonexistent/soil.csv");
    FAIL() << "opened a file that does not exist";
  } catch (const DataError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/soil.csv: cannot open the file for reading");
  }
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
