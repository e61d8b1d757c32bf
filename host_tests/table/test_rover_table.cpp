// `sinkwatch rover-table` and `table-info` (issue 14): every field written
// and loaded back through flight::load() bit for bit, a wheel radius other
// than the table's refused, the flight code's own check on the rover, the
// base table's sections kept.
#include "sinkwatch/ground/rover_table.hpp"
#include "sinkwatch/ground/rover_table_command.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/load.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fl = sinkwatch::flight;
namespace fs = std::filesystem;

namespace {

struct CommandRun {
  int code;
  std::string out;
  std::string err;
};

CommandRun rover_table(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = sg::run_rover_table_command(args, out, err);
  return CommandRun{code, out.str(), err.str()};
}

CommandRun table_info(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = sg::run_table_info_command(args, out, err);
  return CommandRun{code, out.str(), err.str()};
}

fs::path temp(const std::string& name) {
  // One directory per test: ctest runs this file's tests in parallel.
  const fs::path dir = fs::temp_directory_path() / "sinkwatch_rover_table_test" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir / name;
}

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every field's raw Q value, in section 6's order.
std::vector<std::int64_t> raw_fields(const fl::RoverParams& p) {
  return {p.mass_kg.q().raw(),          p.gravity_mps2.q().raw(),          p.com_x_m.q().raw(),
          p.com_y_m.q().raw(),          p.com_z_m.q().raw(),               p.track_width_m.q().raw(),
          p.wheel_radius_m.q().raw(),   p.rocker_front_axle.x_m.q().raw(), p.rocker_front_axle.z_m.q().raw(),
          p.rocker_bogie_pivot.x_m.q().raw(), p.rocker_bogie_pivot.z_m.q().raw(),
          p.bogie_middle_axle.x_m.q().raw(),  p.bogie_middle_axle.z_m.q().raw(),
          p.bogie_rear_axle.x_m.q().raw(),    p.bogie_rear_axle.z_m.q().raw(), p.rocker_limit_rad.q().raw(),
          p.bogie_limit_rad.q().raw(),  p.attitude_limit_rad.q().raw(),    p.high_slip.q().raw()};
}

// A value for every field but the radius, each different from the Yutu-like
// rover's and valid together.
const std::vector<std::pair<std::string, std::string>> kEveryField = {
    {"mass-kg", "151.25"},
    {"gravity-mps2", "3.71"},
    {"com-x-m", "0.03"},
    {"com-y-m", "-0.02"},
    {"com-z-m", "0.22"},
    {"track-width-m", "1.1"},
    {"rocker-front-axle-x-m", "0.55"},
    {"rocker-front-axle-z-m", "-0.32"},
    {"rocker-bogie-pivot-x-m", "-0.2"},
    {"rocker-bogie-pivot-z-m", "-0.12"},
    {"bogie-middle-axle-x-m", "0.3"},
    {"bogie-middle-axle-z-m", "-0.17"},
    {"bogie-rear-axle-x-m", "-0.28"},
    {"bogie-rear-axle-z-m", "-0.18"},
    {"rocker-limit-rad", "0.4"},
    {"bogie-limit-rad", "0.45"},
    {"attitude-limit-rad", "0.9"},
    {"high-slip", "0.7"},
};

}  // namespace

TEST(RoverTable, EveryFieldRoundTripsThroughTheFlightLoaderBitForBit) {
  const fs::path out = temp("every.tbl");
  std::vector<std::string> args{"--out", out.string(), "--wheel-radius-m", "0.15"};
  fl::RoverParams expected = fl::yutu_like_rover_params(fl::kGravityMoon);
  for (const auto& [name, value] : kEveryField) {
    args.push_back("--" + name);
    args.push_back(value);
    bool found = false;
    for (const sg::RoverField& f : sg::rover_fields()) {
      if (name == f.name) found = f.set(expected, std::stod(value));
    }
    ASSERT_TRUE(found) << name;
  }
  ASSERT_EQ(sg::rover_fields().size(), kEveryField.size() + 1U);  // + the radius
  const CommandRun r = rover_table(args);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<std::uint8_t> bytes = read_bytes(out);
  fl::PreparedParameters loaded;
  ASSERT_EQ(fl::load(bytes.data(), bytes.size(), loaded), fl::RejectReason::ok);
  ASSERT_TRUE(loaded.table().rover_geometry.present);
  EXPECT_EQ(raw_fields(loaded.rover()), raw_fields(expected));
  // Every field differs from the default, so none was left at it.
  const std::vector<std::int64_t> yutu = raw_fields(fl::yutu_like_rover_params(fl::kGravityMoon));
  const std::vector<std::int64_t> got = raw_fields(loaded.rover());
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (i != 6U) {
      EXPECT_NE(got[i], yutu[i]) << sg::rover_fields()[i].name;
    }
  }
  EXPECT_NE(r.out.find("accepted by the flight loader"), std::string::npos) << r.out;
}

TEST(RoverTable, OtherSectionsComeFromTheBaseTableAndItsRoverIsTheStart) {
  const fs::path base = temp("base.tbl");
  ASSERT_EQ(rover_table({"--out", base.string(), "--mass-kg", "130", "--com-z-m", "0.2"}).code, 0);
  const fs::path next = temp("next.tbl");
  ASSERT_EQ(rover_table({"--out", next.string(), "--base-table", base.string(), "--mass-kg", "125"}).code, 0);
  const sg::LoadedTable t = sg::read_table_file(next.string());
  ASSERT_TRUE(t.rover.has_value());
  EXPECT_EQ(sinkwatch::fx::to_double(t.rover->mass_kg.q()), 125.0);
  EXPECT_NEAR(sinkwatch::fx::to_double(t.rover->com_z_m.q()), 0.2, 1e-7);  // kept from the base's section 6
  const std::vector<std::uint8_t> a = read_bytes(base);
  const std::vector<std::uint8_t> b = read_bytes(next);
  ASSERT_EQ(a.size(), b.size());
  const fl::ParameterTable d = fl::default_parameter_table();
  EXPECT_EQ(t.table.correction.rows[0].c3.q().raw(), d.correction.rows[0].c3.q().raw());
  EXPECT_EQ(t.table.monitor.stop_sinkage_m.q().raw(), d.monitor.stop_sinkage_m.q().raw());
}

TEST(RoverTable, RadiusOtherThanTheTablesIsRefused) {
  const fs::path out = temp("radius.tbl");
  fs::remove(out);
  const CommandRun r = rover_table({"--out", out.string(), "--wheel-radius-m", "0.2"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("rover_radius_mismatch"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("0.15 m"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // A table whose section 1 has another radius: the rover takes it.
  fl::ParameterTable t = fl::default_parameter_table();
  sinkwatch::fx::Status st;
  t.wheel_radius_m = fl::LengthM{sinkwatch::fx::from_double<fl::LengthQ>(0.125, st)};
  sg::LoadedTable base = sg::default_table();
  base.table = t;
  const sg::RoverTable built = sg::build_rover_table(base, {{"mass-kg", 90.0}});
  EXPECT_EQ(built.rover.wheel_radius_m.q().raw(), t.wheel_radius_m.q().raw());
}

TEST(RoverTable, RoverTheFlightCodeRefusesIsAUsageError) {
  const fs::path out = temp("bad.tbl");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--mass-kg", "0"}, {"--mass-kg", "1001"}, {"--gravity-mps2", "11"},
        {"--com-y-m", "0.5"}, {"--rocker-front-axle-x-m", "-0.1"}, {"--high-slip", "1.5"}, {"--mass-kg", "nan"},
        {"--mass-kg", "1e12"}}) {
    std::vector<std::string> args{"--out", out.string()};
    args.insert(args.end(), bad.begin(), bad.end());
    const CommandRun r = rover_table(args);
    EXPECT_EQ(r.code, 2) << bad[0] << " " << bad[1] << ": " << r.err;
  }
}

TEST(RoverTable, BaseTableTheLoaderRefusesIsADataError) {
  const fs::path junk = temp("junk.tbl");
  std::ofstream(junk, std::ios::binary) << "not a table";
  const CommandRun r = rover_table({"--out", temp("x.tbl").string(), "--base-table", junk.string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(junk.string() + ": the flight code rejects this parameter table"), std::string::npos) << r.err;
}

TEST(TableInfo, ShowsEverySectionAndTheRover) {
  const fs::path out = temp("info.tbl");
  ASSERT_EQ(rover_table({"--out", out.string(), "--mass-kg", "133.5"}).code, 0);
  const CommandRun r = table_info({out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* part : {"section 1", "section 2", "section 3", "section 4", "section 5", "section 6", "section 7",
                           "section 8 traction    motion-resistance coefficient carried 2 m ahead", "STOP at 0.38",
                           "CRC-32 0x", "133.5 kg"}) {
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
  }
  EXPECT_EQ(table_info({temp("missing.tbl").string()}).code, 1);
}
