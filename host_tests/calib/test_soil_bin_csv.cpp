// Tests of the soil-bin CSV reader: both input forms, comments, note columns,
// the input rules of docs/input-files.md (BOM, standard input, directories,
// binary files, physical ranges, unknown columns), and every malformed input
// rejected with a message that names the file, the line and the column.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "sinkwatch/ground/soil_bin_csv.hpp"
#include "input_test_support.hpp"

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

TEST(SoilBinCsv, SkipsCommentsBlankLinesAndCarriageReturnsAndIgnoresNoteColumns) {
  const SoilBinDataset d = parse(
      "# a comment before the header\r\n"
      "\r\n"
      "note_run, slip ,notes,sinkage_ratio,drive_coeff,traction_coeff\r\n"
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
  const DataError e = rejection("slip,load_N,wheel_radius_m\n0.1,2,0.3\n");
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

// --- the input rules of docs/input-files.md ---

using test::printable_ascii;
using test::StdinFrom;

TEST(SoilBinCsvInput, SkipsAUtf8ByteOrderMark) {
  const SoilBinDataset d = parse("\xEF\xBB\xBF" + kDimensionless);
  ASSERT_EQ(d.rows.size(), 2U);
  EXPECT_DOUBLE_EQ(d.rows[0].slip, 0.1);
}

TEST(SoilBinCsvInput, SkipsAByteOrderMarkBeforeAComment) {
  const SoilBinDataset d = parse("\xEF\xBB\xBF# exported by Excel\r\n" + kDimensionless);
  EXPECT_EQ(d.rows.size(), 2U);
}

TEST(SoilBinCsvInput, DashReadsStandardInput) {
  const StdinFrom redirect(kDimensionless);
  const SoilBinDataset d = read_soil_bin_csv("-");
  EXPECT_EQ(d.source, "<stdin>");
  ASSERT_EQ(d.rows.size(), 2U);
  EXPECT_DOUBLE_EQ(d.rows[1].drive_coeff, 0.55);
}

TEST(SoilBinCsvInput, ErrorsFromStandardInputNameIt) {
  const StdinFrom redirect(kDimensionless + "0.3,0.1,abc,0.3\n");
  try {
    (void)read_soil_bin_csv("-");
    FAIL() << "accepted a bad row";
  } catch (const DataError& e) {
    EXPECT_EQ(std::string(e.what()), "<stdin>:4:3: column 'drive_coeff': 'abc' is not a number");
  }
}

TEST(SoilBinCsvInput, ReadsTheWidthColumnAndTheCallersWidth) {
  const SoilBinDataset d = parse(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
      "0.3,29.43,3.0,0.012,10.0,0.15,0.165\n");
  EXPECT_DOUBLE_EQ(*d.rows[0].wheel_width_m, 0.165);
  SoilBinReadOptions options;
  options.wheel_width_m = 0.2;
  EXPECT_DOUBLE_EQ(*parse(kDimensionless, options).rows[0].wheel_width_m, 0.2);
}

TEST(SoilBinCsvRejects, ADirectoryAsSuch) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  try {
    (void)read_soil_bin_csv(dir);
    FAIL() << "read a directory";
  } catch (const DataError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": is a directory, not a file");
  }
}

TEST(SoilBinCsvRejects, ABinaryFileAtItsFirstNonTextByte) {
  const DataError e = rejection(kDimensionless + std::string("0.3,0.1\0\x01\x02,0.6,0.3\n", 19));
  EXPECT_EQ(e.line(), 4U);
  EXPECT_EQ(e.column(), 8U);  // the byte's column in the line
  EXPECT_EQ(std::string(e.what()), "test.csv:4:8: binary file, not CSV text (byte 0x00)");
}

TEST(SoilBinCsvRejects, ABinaryFileEvenInAComment) {
  const DataError e = rejection("# \x1b[2J clear the screen\n" + kDimensionless);
  EXPECT_EQ(e.line(), 1U);
  EXPECT_NE(std::string(e.what()).find("binary file, not CSV text (byte 0x1b)"), std::string::npos)
      << e.what();
}

TEST(SoilBinCsvRejects, WithQuotedInputEscapedAndCut) {
  const std::string cell = "\xC3\xA9t\xE9" + std::string(200, 'x');
  const DataError e = rejection(kDimensionless + "0.3,0.1," + cell + ",0.3\n");
  const std::string what = e.what();
  EXPECT_TRUE(printable_ascii(what)) << what;
  EXPECT_NE(what.find("'\\xc3\\xa9t\\xe9xxxx"), std::string::npos) << what;
  EXPECT_NE(what.find("x...' is not a number"), std::string::npos) << what;
  EXPECT_LT(what.size(), 120U) << what;
}

TEST(SoilBinCsvRejects, AnUnknownColumnNamingItAndTheKnownOnes) {
  const DataError e = rejection(
      "slip,sinkage_ratio,drive_coeff,traction_coeff,wheel_radus_m\n0.1,0.08,0.35,0.1,0.15\n");
  EXPECT_EQ(e.line(), 1U);
  EXPECT_EQ(e.column(), 5U);
  EXPECT_EQ(e.column_name(), "wheel_radus_m");
  const std::string what = e.what();
  EXPECT_NE(what.find("test.csv:1:5: column 'wheel_radus_m': unknown column"), std::string::npos)
      << what;
  EXPECT_NE(what.find("wheel_radius_m"), std::string::npos) << what;
  EXPECT_NE(what.find("'note'"), std::string::npos) << what;
}

TEST(SoilBinCsvRejects, AnUnknownColumnNameWithoutEchoingItsBytes) {
  const DataError e = rejection("slip,sinkage_ratio,drive_coeff,traction_coeff,\xFF\xFE\n1,2,3,4,5\n");
  EXPECT_TRUE(printable_ascii(e.what())) << e.what();
  EXPECT_NE(std::string(e.what()).find("column '\\xff\\xfe'"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ANumberOutsideItsColumnsPhysicalRange) {
  const DataError e = rejection(kDimensionless + "1e300,0.1,0.6,0.3\n");
  EXPECT_EQ(e.line(), 4U);
  EXPECT_EQ(e.column(), 1U);
  EXPECT_EQ(std::string(e.what()),
            "test.csv:4:1: column 'slip': 1e+300 is outside the physical range [-1, 1]");
}

TEST(SoilBinCsvRejects, NonsenseInEveryKindOfColumn) {
  const std::string header =
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n";
  struct Case {
    std::string row;
    std::size_t column;
    std::string detail;
  };
  for (const Case& c : std::vector<Case>{
           {"0.3,1e9,3,0.01,10,0.15,0.16", 2, "1000000000 is outside the physical range (0, 100000] N"},
           {"0.3,30,-1e300,0.01,10,0.15,0.16", 3, "-1e+300 is outside the physical range"},
           {"0.3,30,3,12,10,0.15,0.16", 4, "12 is outside the physical range [-1, 10] m"},
           {"0.3,30,3,0.01,2e5,0.15,0.16", 5, "200000 is outside the physical range"},
           {"0.3,30,3,0.01,10,150,0.16", 6, "150 is outside the physical range (0, 5] m"},
           {"0.3,30,3,0.01,10,0.15,-0.16", 7, "'-0.16' must be greater than zero"},
           {"1.5,30,3,0.01,10,0.15,0.16", 1, "1.5 is outside the physical range [-1, 1]"},
       }) {
    const DataError e = rejection(header + c.row + "\n");
    EXPECT_EQ(e.line(), 2U) << c.row;
    EXPECT_EQ(e.column(), c.column) << c.row;
    EXPECT_NE(std::string(e.what()).find(c.detail), std::string::npos) << e.what();
  }
  const DataError ratio = rejection("slip,sinkage_ratio,drive_coeff,traction_coeff\n0.1,30,0.3,0.1\n");
  EXPECT_EQ(ratio.column_name(), "sinkage_ratio");
  EXPECT_NE(std::string(ratio.what()).find("30 is outside the physical range [-1, 2]"),
            std::string::npos)
      << ratio.what();
}

TEST(SoilBinCsvRejects, DimensionalRowsWhoseRatiosAreNonsense) {
  // Sinkage in millimetres in the metre column: each number is in range, z/r is not.
  const DataError e = rejection(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m\n0.3,30,3,9,10,0.15\n");
  EXPECT_EQ(e.line(), 2U);
  EXPECT_NE(std::string(e.what()).find("z/r = 60 is outside the physical range [-1, 2]"),
            std::string::npos)
      << e.what();
}

TEST(SoilBinCsvRejects, AWidthGivenTwice) {
  SoilBinReadOptions options;
  options.wheel_width_m = 0.16;
  const DataError e = rejection(
      "slip,load_N,torque_Nm,sinkage_m,drawbar_pull_N,wheel_radius_m,wheel_width_m\n"
      "0.3,30,3,0.01,10,0.15,0.16\n",
      options);
  EXPECT_EQ(e.line(), 1U);
  EXPECT_EQ(e.column(), 7U);
  EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
}

TEST(SoilBinCsvRejects, ARadiusLoadOrWidthFromTheCallerOutOfRange) {
  SoilBinReadOptions radius;
  radius.wheel_radius_m = 1e300;
  EXPECT_NE(std::string(rejection(kDimensionless, radius).what()).find("1e+300"), std::string::npos);
  SoilBinReadOptions width;
  width.wheel_width_m = 0.0;
  EXPECT_NE(std::string(rejection(kDimensionless, width).what()).find("wheel width"),
            std::string::npos);
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch
