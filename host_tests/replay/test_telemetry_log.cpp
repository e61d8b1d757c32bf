// The telemetry CSV format: round trip, and every kind of bad row reported
// with its file, line and column.
#include "sinkwatch/ground/telemetry_log.hpp"
#include "../calib/input_test_support.hpp"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace sg = sinkwatch::ground;

namespace {

const std::string kHeader =
    "time_s,i_lf_a,i_lm_a,i_lr_a,i_rf_a,i_rm_a,i_rr_a,pitch_deg,roll_deg,rocker_l_deg,rocker_r_deg,bogie_l_deg,"
    "bogie_r_deg,accel_mps2\n";
const std::string kRow = "0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n";

// The message of the TelemetryError `text` raises (fails the test if none).
std::string error_of(const std::string& text, std::size_t* line = nullptr, std::size_t* column = nullptr) {
  try {
    sg::parse_telemetry_text(text, "log.csv");
  } catch (const sg::TelemetryError& e) {
    if (line) *line = e.line();
    if (column) *column = e.column();
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

}  // namespace

TEST(TelemetryLog, MinimalLogParses) {
  const sg::TelemetryLog log = sg::parse_telemetry_text("# gravity_mps2: 3.71\n# a comment\n" + kHeader + kRow, "x");
  ASSERT_EQ(log.rows.size(), 1U);
  EXPECT_EQ(log.rows[0].line, 4U);
  EXPECT_DOUBLE_EQ(log.rows[0].time_s, 0.2);
  EXPECT_DOUBLE_EQ(log.rows[0].pitch_deg, 1.0);
  EXPECT_TRUE(log.rows[0].valid);
  EXPECT_FALSE(log.rows[0].reverse);
  EXPECT_FALSE(log.rows[0].speed_mps.has_value());
  ASSERT_TRUE(log.rows[0].accel_mps2.has_value());
  EXPECT_DOUBLE_EQ(*log.rows[0].accel_mps2, 0.01);
  EXPECT_EQ(log.number("gravity_mps2").value(), 3.71);
  ASSERT_EQ(log.comments.size(), 1U);
  EXPECT_EQ(log.comments[0], "a comment");
}

TEST(TelemetryLog, TimeInMillisecondsIsAccepted) {
  std::string header = kHeader;
  header.replace(0, 6, "time_ms");
  const sg::TelemetryLog log = sg::parse_telemetry_text(header + "1500" + kRow.substr(3), "x");
  EXPECT_DOUBLE_EQ(log.rows[0].time_s, 1.5);
}

TEST(TelemetryLog, RowRoundTripsThroughTheWriter) {
  sg::TelemetryRow r;
  r.time_s = 12.4;
  r.valid = false;
  r.current_a = {0.1, -0.2, 0.30001, 0.4, 0.5, 0.6};
  r.reverse = true;
  r.pitch_deg = 2.5;
  r.roll_deg = -1.25;
  r.rocker_deg = {0.5, -0.5};
  r.bogie_deg = {1.0, -2.0};
  r.speed_mps = 0.04;
  r.rim_speed_mps = -0.05;
  r.true_sinkage_mm = 12.5;
  r.phase = "escape-rev";
  const sg::TelemetryRow back = sg::parse_telemetry_row(sg::format_telemetry_row(r));
  EXPECT_EQ(back.time_s, r.time_s);
  EXPECT_EQ(back.valid, r.valid);
  EXPECT_EQ(back.current_a, r.current_a);
  EXPECT_EQ(back.reverse, r.reverse);
  EXPECT_EQ(back.pitch_deg, r.pitch_deg);
  EXPECT_EQ(back.rocker_deg, r.rocker_deg);
  EXPECT_EQ(back.bogie_deg, r.bogie_deg);
  EXPECT_FALSE(back.accel_mps2.has_value());
  EXPECT_EQ(back.speed_mps, r.speed_mps);
  EXPECT_EQ(back.rim_speed_mps, r.rim_speed_mps);
  EXPECT_FALSE(back.x_m.has_value());
  EXPECT_EQ(back.true_sinkage_mm, r.true_sinkage_mm);
  EXPECT_EQ(back.phase, r.phase);
}

TEST(TelemetryLog, WholeLogRoundTrips) {
  const sg::TelemetryLog log = sg::parse_telemetry_text("# seed: 7\n" + kHeader + kRow + kRow, "x");
  std::ostringstream out;
  sg::write_telemetry_csv(out, log);
  const sg::TelemetryLog back = sg::parse_telemetry_text(out.str(), "y");
  ASSERT_EQ(back.rows.size(), 2U);
  EXPECT_EQ(back.metadata.at("seed"), "7");
  EXPECT_EQ(back.rows[1].current_a, log.rows[1].current_a);
}

TEST(TelemetryLog, NotANumberNamesLineColumnAndCell) {
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string msg = error_of(kHeader + kRow + "0.4,0.5,abc,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n", &line, &column);
  EXPECT_EQ(line, 3U);
  EXPECT_EQ(column, 9U);  // where "abc" starts
  EXPECT_NE(msg.find("log.csv:3:9:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("i_lm_a"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'abc'"), std::string::npos) << msg;
}

TEST(TelemetryLog, TrailingGarbageAndNonFiniteAreRejected) {
  EXPECT_NE(error_of(kHeader + "0.2,0.5x,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("log.csv:2:5:"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0.2,nan,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("finite"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0.2,inf,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("finite"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0.2,1e999,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("finite"), std::string::npos);
}

TEST(TelemetryLog, WrongCellCount) {
  std::size_t line = 0;
  const std::string msg = error_of(kHeader + kRow + kRow + "0.6,0.5,0.5\n", &line);
  EXPECT_EQ(line, 4U);
  EXPECT_NE(msg.find("expected 14 cells, found 3"), std::string::npos) << msg;
}

TEST(TelemetryLog, EmptyRequiredCell) {
  // The time has no "missing": every row is a cycle at a time.
  const std::string msg = error_of(kHeader + ",0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n");
  EXPECT_NE(msg.find("log.csv:2:1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("time_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("empty cell where a number is required"), std::string::npos) << msg;
}

TEST(TelemetryLog, EmptyCurrentCellIsADropoutOfThatSensorOnly) {
  const sg::TelemetryLog log = sg::parse_telemetry_text(kHeader + "0.2,0.5,,0.5,0.5,0.5,0.7,1,0,0,0,0,0,0.01\n", "x");
  const sg::TelemetryRow& r = log.rows[0];
  EXPECT_EQ(r.current_missing, (std::array<bool, 6>{false, true, false, false, false, false}));
  EXPECT_EQ(r.current_a[1], 0.0);
  EXPECT_EQ(r.current_a[5], 0.7);
  EXPECT_FALSE(r.attitude_missing);
  EXPECT_FALSE(r.joints_missing);
}

TEST(TelemetryLog, AnEmptyAttitudeOrJointCellMarksItsWholeGroupMissing) {
  const sg::TelemetryLog log = sg::parse_telemetry_text(
      kHeader + "0.2,0.5,0.5,0.5,0.5,0.5,0.5,,2,1,1,1,1,0.01\n0.4,0.5,0.5,0.5,0.5,0.5,0.5,1,2,1,,1,1,0.01\n", "x");
  const sg::TelemetryRow& a = log.rows[0];
  EXPECT_TRUE(a.attitude_missing);
  EXPECT_EQ(a.pitch_deg, 0.0);
  EXPECT_EQ(a.roll_deg, 0.0);  // roll was 2, but pitch and roll are one sensor
  EXPECT_FALSE(a.joints_missing);
  EXPECT_EQ(a.bogie_deg[1], 1.0);
  const sg::TelemetryRow& j = log.rows[1];
  EXPECT_FALSE(j.attitude_missing);
  EXPECT_EQ(j.roll_deg, 2.0);
  EXPECT_TRUE(j.joints_missing);
  EXPECT_EQ(j.rocker_deg, (std::array<double, 2>{0.0, 0.0}));
  EXPECT_EQ(j.bogie_deg, (std::array<double, 2>{0.0, 0.0}));
}

TEST(TelemetryLog, MissingSensorsRoundTripAsEmptyCells) {
  sg::TelemetryRow r;
  r.time_s = 3.0;
  r.current_a = {0.1, 0.0, 0.3, 0.4, 0.0, 0.6};
  r.current_missing = {false, true, false, false, true, false};
  r.attitude_missing = true;
  r.joints_missing = true;
  r.accel_mps2 = 0.0;
  const std::string text = sg::format_telemetry_row(r);
  EXPECT_EQ(text.substr(0, 40), "3.000,1,0.10000,,0.30000,0.40000,,0.6000") << text;
  EXPECT_NE(text.find(",F,,,,,,,"), std::string::npos) << text;
  const sg::TelemetryRow back = sg::parse_telemetry_row(text);
  EXPECT_EQ(back.current_missing, r.current_missing);
  EXPECT_EQ(back.current_a, r.current_a);
  EXPECT_TRUE(back.attitude_missing);
  EXPECT_TRUE(back.joints_missing);
}

TEST(TelemetryLog, AMissingSensorsCellStillHasToBeANumberWhenGiven) {
  EXPECT_NE(error_of(kHeader + "0.2,0.5,x,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("log.csv:2:9:"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n0.4,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,"
                               "99,0.01\n")
                .find("log.csv:3:"),
            std::string::npos);
}

TEST(TelemetryLog, BadFlagsAndDirections) {
  const std::string header = "time_s,valid,direction" + kHeader.substr(6);
  EXPECT_NE(error_of(header + "0.2,2,F,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("expected 0 or 1"),
            std::string::npos);
  EXPECT_NE(error_of(header + "0.2,1,X,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n").find("expected F or R"),
            std::string::npos);
}

TEST(TelemetryLog, NegativeTimeIsOutOfTheFlightClock) {
  EXPECT_NE(error_of(kHeader + "-0.2" + kRow.substr(3)).find("time out of range"), std::string::npos);
}

TEST(TelemetryLog, TimeGoingBackwardsIsRejectedWhereItTurns) {
  // Found by fuzz_telemetry_csv (fuzz/findings/telemetry_time_backwards.csv).
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string msg =
      error_of(kHeader + "5.0" + kRow.substr(3) + "0.1" + kRow.substr(3), &line, &column);
  EXPECT_EQ(line, 3U);
  EXPECT_EQ(column, 1U);  // the time cell
  EXPECT_NE(msg.find("time goes backwards: 0.100 s after 5.000 s at line 2"), std::string::npos) << msg;
}

TEST(TelemetryLog, RepeatedTimeIsKeptForTheFlightCodeToReport) {
  const sg::TelemetryLog log = sg::parse_telemetry_text(kHeader + kRow + kRow, "x");
  EXPECT_EQ(log.rows.size(), 2U);
}

TEST(TelemetryLog, HeaderProblems) {
  EXPECT_NE(error_of("time_s,foo\n1,2\n").find("unknown column 'foo'"), std::string::npos);
  EXPECT_NE(error_of("time_s,foo\n1,2\n").find("the known columns are time_s, time_ms, valid"), std::string::npos);
  EXPECT_NE(error_of("time_s,time_s\n1,2\n").find("appears twice"), std::string::npos);
  std::string no_pitch = kHeader;
  no_pitch.replace(no_pitch.find("pitch_deg,"), 10, "");
  EXPECT_NE(error_of(no_pitch + "1\n").find("missing column 'pitch_deg'"), std::string::npos);
  std::string no_time = kHeader.substr(7);
  EXPECT_NE(error_of(no_time + "1\n").find("time_s or time_ms"), std::string::npos);
  std::string no_motion = kHeader.substr(0, kHeader.find(",accel_mps2")) + "\n";
  EXPECT_NE(error_of(no_motion + "1\n").find("accel_mps2 or speed_mps"), std::string::npos);
  EXPECT_NE(error_of("# only a comment\n").find("no header"), std::string::npos);
  EXPECT_NE(error_of(kHeader).find("no data rows"), std::string::npos);
}

TEST(TelemetryLog, MissingFileIsAnError) {
  EXPECT_THROW(sg::read_telemetry_file("/nonexistent/telemetry.csv"), std::runtime_error);
}

// --- the input rules of docs/input-files.md ---

namespace {

using sinkwatch::test::printable_ascii;
using sinkwatch::test::StdinFrom;

}  // namespace

TEST(TelemetryLogInput, SkipsAUtf8ByteOrderMark) {
  const sg::TelemetryLog log = sg::parse_telemetry_text("\xEF\xBB\xBF" + kHeader + kRow, "x");
  ASSERT_EQ(log.rows.size(), 1U);
  EXPECT_DOUBLE_EQ(log.rows[0].time_s, 0.2);
  const sg::TelemetryLog with_metadata =
      sg::parse_telemetry_text("\xEF\xBB\xBF# gravity_mps2: 3.71\n" + kHeader + kRow, "x");
  EXPECT_EQ(with_metadata.number("gravity_mps2").value(), 3.71);
}

TEST(TelemetryLogInput, DashReadsStandardInput) {
  const StdinFrom redirect(kHeader + kRow + kRow);
  const sg::TelemetryLog log = sg::read_telemetry_file("-");
  EXPECT_EQ(log.source, "<stdin>");
  EXPECT_EQ(log.rows.size(), 2U);
}

TEST(TelemetryLogInput, NoteColumnsAreIgnored) {
  std::string header = kHeader;
  header.insert(header.size() - 1, ",notes");
  std::string row = kRow;
  row.insert(row.size() - 1, ",wheel LF \xC2\xB0 looked stuck");
  const sg::TelemetryLog log = sg::parse_telemetry_text(header + row, "x");
  ASSERT_EQ(log.rows.size(), 1U);
  EXPECT_DOUBLE_EQ(*log.rows[0].accel_mps2, 0.01);
}

TEST(TelemetryLogInput, ADirectoryIsRefusedAsSuch) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  try {
    (void)sg::read_telemetry_file(dir);
    FAIL() << "read a directory";
  } catch (const sg::TelemetryError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": is a directory, not a file");
  }
}

TEST(TelemetryLogInput, ABinaryFileIsRefusedAtItsFirstNonTextByte) {
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string msg = error_of(kHeader + kRow + std::string("\x7f" "ELF\0\0\1", 7) + "\n", &line, &column);
  EXPECT_EQ(line, 3U);
  EXPECT_EQ(column, 1U);
  EXPECT_EQ(msg, "log.csv:3:1: binary file, not CSV text (byte 0x7f)");
}

TEST(TelemetryLogInput, QuotedInputIsEscapedAndCut) {
  const std::string msg = error_of("time_s,\xE2\x80\x8B" + std::string(300, 'y') + "\n1,2\n");
  EXPECT_TRUE(printable_ascii(msg)) << msg;
  EXPECT_NE(msg.find("unknown column '\\xe2\\x80\\x8byyy"), std::string::npos) << msg;
  EXPECT_NE(msg.find("y...'"), std::string::npos) << msg;
  const std::string cell = error_of(kHeader + "0.2,0.5,\xFF" + "abc,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01\n");
  EXPECT_TRUE(printable_ascii(cell)) << cell;
  EXPECT_NE(cell.find("got '\\xffabc'"), std::string::npos) << cell;
}

TEST(TelemetryLogInput, BothTimeColumnsConflict) {
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string header = "time_s,time_ms," + kHeader.substr(7);
  const std::string msg = error_of(header + "0.2,200," + kRow.substr(4), &line, &column);
  EXPECT_EQ(line, 1U);
  EXPECT_EQ(column, 8U);  // where time_ms starts
  EXPECT_NE(msg.find("conflicting columns time_s and time_ms"), std::string::npos) << msg;
}

TEST(TelemetryLogInput, ABadGravityLineIsReportedAtItsLineAndColumn) {
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string msg = error_of("# made by hand\n# gravity_mps2: lunar\n" + kHeader + kRow, &line, &column);
  EXPECT_EQ(line, 2U);
  EXPECT_EQ(column, 17U);  // where "lunar" starts
  EXPECT_EQ(msg, "log.csv:2:17: metadata 'gravity_mps2': expected a finite number, got 'lunar'");
}

TEST(TelemetryLogInput, GravityOutsideItsPhysicalRangeIsRefused) {
  for (const char* const g : {"1e300", "0", "-9.81", "31", "nan", "inf"}) {
    std::size_t line = 0;
    const std::string msg = error_of(std::string("# gravity_mps2: ") + g + "\n" + kHeader + kRow, &line);
    EXPECT_EQ(line, 1U) << g;
    EXPECT_NE(msg.find("log.csv:1:17: metadata 'gravity_mps2': "), std::string::npos) << msg;
  }
  EXPECT_NE(error_of("# gravity_mps2: 1e300\n" + kHeader + kRow).find("1e+300 is outside the physical range (0, 30] m/s^2"),
            std::string::npos);
  EXPECT_EQ(sg::parse_telemetry_text("# gravity_mps2: 30\n" + kHeader + kRow, "x").number("gravity_mps2").value(), 30.0);
}

TEST(TelemetryLogInput, NumbersOutsideTheirPhysicalRangeAreRefusedWithLineAndColumn) {
  struct Case {
    std::string row;
    std::size_t column;
    std::string detail;
  };
  for (const Case& c : std::vector<Case>{
           {"0.2,1e300,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01", 5,
            "column 'i_lf_a': 1e+300 is outside the physical range [-1000, 1000] A"},
           {"0.2,0.5,0.5,0.5,0.5,0.5,0.5,95,0,0,0,0,0,0.01", 29,
            "column 'pitch_deg': 95 is outside the physical range [-90, 90] deg"},
           {"0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,-91,0,0,0,0,0.01", 31, "column 'roll_deg': -91 is outside"},
           {"0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,90.5,0.01", 39, "column 'bogie_r_deg': 90.5 is outside"},
           {"0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,-2e3", 41,
            "column 'accel_mps2': -2000 is outside the physical range [-100, 100] m/s^2"},
           {"5e9,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01", 1,
            "column 'time_s': time out of range: 5000000000 is outside the physical range [0, 4294967.295] s"},
       }) {
    std::size_t line = 0;
    std::size_t column = 0;
    const std::string msg = error_of(kHeader + c.row + "\n", &line, &column);
    EXPECT_EQ(line, 2U) << c.row;
    EXPECT_EQ(column, c.column) << msg;
    EXPECT_NE(msg.find(c.detail), std::string::npos) << msg;
  }
  const std::string truth_header = kHeader.substr(0, kHeader.size() - 1) + ",true_slip,true_sinkage_mm,x_m\n";
  EXPECT_NE(error_of(truth_header + "0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01,1.5,10,0\n")
                .find("column 'true_slip': 1.5 is outside the physical range [-1, 1]"),
            std::string::npos);
  EXPECT_NE(error_of(truth_header + "0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01,0.1,1e5,0\n")
                .find("column 'true_sinkage_mm': 100000 is outside"),
            std::string::npos);
  EXPECT_NE(error_of(truth_header + "0.2,0.5,0.5,0.5,0.5,0.5,0.5,1,0,0,0,0,0,0.01,0.1,10,1e300\n")
                .find("column 'x_m': 1e+300 is outside"),
            std::string::npos);
  std::string ms = kHeader;
  ms.replace(0, 6, "time_ms");
  EXPECT_NE(error_of(ms + "1e300" + kRow.substr(3)).find("time out of range"), std::string::npos);
}

TEST(TelemetryLogInput, EmbeddingMetadataIsCheckedToo) {
  std::size_t line = 0;
  std::size_t column = 0;
  const std::string msg = error_of("# embedding_time_s: 10\n# embedding_x_m: 1e300\n" + kHeader + kRow, &line, &column);
  EXPECT_EQ(line, 2U);
  EXPECT_EQ(column, 18U);
  EXPECT_NE(msg.find("metadata 'embedding_x_m': 1e+300 is outside"), std::string::npos) << msg;
  EXPECT_EQ(sg::parse_telemetry_text("# embedding_x_m: none\n" + kHeader + kRow, "x").rows.size(), 1U);
}
