// The rover's mass in the replay (issue 14): the log's "# mass_kg:" line, the
// --mass-kg option, the table's section 6 and the Yutu-like default, in that
// order after the option; a bad mass refused at its line; the scenario
// generator writing the mass its flight code ran with.
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/replay_command.hpp"
#include "sinkwatch/ground/rover_table.hpp"
#include "sinkwatch/ground/scenario.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <gtest/gtest.h>

#include "replay_command_run.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fl = sinkwatch::flight;
namespace fs = std::filesystem;

namespace {

using sinkwatch::ground::test::CommandRun;
using sinkwatch::ground::test::run;

constexpr double kYutuMassKg = 140.0;

// The shipped embedding scenario with its "# mass_kg:" line (the generator
// writes the 140 kg it ran with) saying `value` instead; `line` gets that
// line's number.
std::string with_mass_line(const std::string& value, std::size_t* line = nullptr) {
  const std::string text = sg::embedded_scenario_text("embedding");
  EXPECT_FALSE(text.empty());
  const std::size_t at = text.find("# mass_kg:");
  EXPECT_NE(at, std::string::npos) << "the shipped log has no mass_kg line";
  const std::size_t end = text.find('\n', at) + 1;
  if (line) *line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  return text.substr(0, at) + "# mass_kg: " + value + "\n" + text.substr(end);
}

// The shipped embedding scenario without its "# mass_kg:" line: a log that
// does not say the rover's mass.
std::string without_mass_line() {
  const std::string text = sg::embedded_scenario_text("embedding");
  const std::size_t at = text.find("# mass_kg:");
  EXPECT_NE(at, std::string::npos) << "the shipped log has no mass_kg line";
  return text.substr(0, at) + text.substr(text.find('\n', at) + 1);
}

// One directory per test: ctest runs the tests of this file in parallel, and
// two of them writing the same m120.csv made one read the other's half file.
fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "sinkwatch_replay_rover_mass" /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

fs::path write_table(const std::string& name, const sg::RoverTable& t) {
  return write_temp(name, std::string(t.bytes.begin(), t.bytes.end()));
}

// The sum of the six wheel loads in the first cycle where they are valid.
double first_load_sum_n(const sg::ReplayResult& r) {
  for (const sg::CycleRecord& c : r.cycles) {
    if (!c.wheels[0].load_valid) continue;
    double sum = 0.0;
    for (const sg::WheelCycle& w : c.wheels) sum += w.load_n;
    return sum;
  }
  ADD_FAILURE() << "no cycle with valid loads";
  return 0.0;
}

double load_sum_with(const sg::TelemetryLog& log, sg::ReplayConfig config) {
  return first_load_sum_n(sg::run_replay(log, config));
}

}  // namespace

TEST(ReplayRoverMass, HeaderIsReadAndScalesTheWheelLoads) {
  std::size_t line = 0;
  const sg::TelemetryLog log = sg::parse_telemetry_text(with_mass_line("120", &line), "m120.csv");
  sg::ReplayConfig config;
  sg::resolve_rover_mass(log, std::nullopt, config);
  EXPECT_EQ(config.mass_source, sg::MassSource::log_header);
  ASSERT_TRUE(config.mass_kg.has_value());
  EXPECT_EQ(*config.mass_kg, 120.0);
  EXPECT_EQ(config.mass_line, line);
  EXPECT_EQ(sg::replay_mass_kg(config), 120.0);
  // The statics are linear in the mass: the loads scale by 120/140.
  const double with_header = load_sum_with(log, config);
  const double yutu = load_sum_with(log, sg::ReplayConfig{});
  EXPECT_NEAR(with_header / yutu, 120.0 / kYutuMassKg, 1e-4);
}

TEST(ReplayRoverMass, ReportNamesTheMassAndWhereItCameFrom) {
  std::size_t line = 0;
  const fs::path log = write_temp("m120.csv", with_mass_line("120", &line));
  const CommandRun header = run({log.string()});
  ASSERT_EQ(header.code, 0) << header.err;
  EXPECT_NE(header.out.find("120.0 kg (from the log's mass_kg (line " + std::to_string(line) + "))"),
            std::string::npos)
      << header.out;
  // The shipped log says the 140 kg it was made with; a log that says
  // nothing gets the Yutu-like default.
  const CommandRun builtin = run({});
  ASSERT_EQ(builtin.code, 0) << builtin.err;
  EXPECT_NE(builtin.out.find("140.0 kg (from the log's mass_kg (line "), std::string::npos) << builtin.out;
  const CommandRun silent = run({write_temp("no_mass.csv", without_mass_line()).string()});
  ASSERT_EQ(silent.code, 0) << silent.err;
  EXPECT_NE(silent.out.find("140.0 kg (from the Yutu-like default"), std::string::npos) << silent.out;
}

TEST(ReplayRoverMass, OptionOverridesTheHeader) {
  const fs::path log = write_temp("m120.csv", with_mass_line("120"));
  const CommandRun r = run({log.string(), "--mass-kg", "150"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("150.0 kg (from --mass-kg)"), std::string::npos) << r.out;
  sg::ReplayConfig config;
  sg::resolve_rover_mass(sg::parse_telemetry_text(with_mass_line("120"), "m"), 150.0, config);
  EXPECT_EQ(config.mass_source, sg::MassSource::option);
  EXPECT_EQ(sg::replay_mass_kg(config), 150.0);
}

TEST(ReplayRoverMass, BadHeaderMassIsRefusedAtItsLine) {
  for (const std::string bad : {"0", "-5", "1000.5", "nan", "inf", "heavy", ""}) {
    std::size_t line = 0;
    const std::string text = with_mass_line(bad, &line);
    try {
      (void)sg::parse_telemetry_text(text, "bad.csv");
      ADD_FAILURE() << "mass_kg '" << bad << "' accepted";
    } catch (const sg::TelemetryError& e) {
      EXPECT_EQ(e.line(), line) << bad;
      EXPECT_EQ(std::string(e.what()).rfind("bad.csv:" + std::to_string(line) + ":", 0), 0U) << e.what();
      EXPECT_NE(std::string(e.what()).find("mass_kg"), std::string::npos) << e.what();
    }
  }
  const fs::path log = write_temp("bad.csv", with_mass_line("2000"));
  const CommandRun r = run({log.string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(log.string() + ":"), std::string::npos) << r.err;
}

TEST(ReplayRoverMass, BadOptionMassIsAUsageError) {
  for (const std::string bad : {"0", "-1", "1000.5", "nan"}) {
    const CommandRun r = run({"--mass-kg", bad});
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
  }
  sg::ReplayConfig config;
  EXPECT_THROW(sg::resolve_rover_mass(sg::parse_telemetry_text(with_mass_line("120"), "m"), 1001.0, config),
               std::invalid_argument);
  config.mass_kg = 1001.0;  // past the resolver: the loop refuses it too
  EXPECT_THROW(sg::OnboardLoop loop(config), std::invalid_argument);
}

TEST(ReplayRoverMass, TableWithARoverSectionIsUsed) {
  const sg::RoverTable t160 = sg::build_rover_table(sg::default_table(), {{"mass-kg", 160.0}});
  const fs::path table = write_table("m160.tbl", t160);
  // A log without a mass of its own (the shipped one says 140 kg, which
  // would come first: HeaderOverridesTheTablesMassWithANote).
  const CommandRun r = run({write_temp("no_mass.csv", without_mass_line()).string(), "--table", table.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("the table's section 6 geometry, 160.0 kg (from the table's section 6)"), std::string::npos)
      << r.out;
  sg::ReplayConfig config;
  sg::load_parameter_table(table.string(), config);
  ASSERT_TRUE(config.rover.has_value());
  EXPECT_EQ(config.mass_source, sg::MassSource::table);
  const sg::TelemetryLog log = sg::parse_telemetry_text(sg::embedded_scenario_text("embedding"), "e");
  EXPECT_NEAR(load_sum_with(log, config) / load_sum_with(log, sg::ReplayConfig{}), 160.0 / kYutuMassKg, 1e-4);
}

TEST(ReplayRoverMass, HeaderOverridesTheTablesMassWithANote) {
  const fs::path table = write_table("m160.tbl", sg::build_rover_table(sg::default_table(), {{"mass-kg", 160.0}}));
  const fs::path log = write_temp("m120.csv", with_mass_line("120"));
  const CommandRun r = run({log.string(), "--table", table.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("the table's section 6 geometry, 120.0 kg (from the log's mass_kg"), std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("note: the log's mass_kg (120 kg) replaces the table's section-6 mass (160 kg)"),
            std::string::npos)
      << r.err;
  const CommandRun quiet = run({log.string(), "--table", table.string(), "-q"});
  EXPECT_EQ(quiet.err, "");
}

TEST(ReplayRoverMass, ScenarioWritesTheMassItsFlightCodeRanWith) {
  sg::ScenarioSpec spec = sg::embedding_scenario();
  spec.name = "short-heavy";
  spec.terrain = {{0.0, 1.0, 0.0}, {0.3, 1.0, 0.0}, {0.9, 0.05, 0.0}};
  spec.end_x_m = 1.2;
  spec.max_time_s = 80.0;
  spec.stuck_tail_s = 2.0;
  spec.settle_s = 1.0;
  spec.mass_kg = 155.0;
  // Low sinkage levels, so that the flight code in the loop stops on this short drive.
  sinkwatch::fx::Status st;
  const auto mm = [&st](double v) { return fl::SinkageM{sinkwatch::fx::from_double<fl::LengthQ>(v / 1000.0, st)}; };
  fl::ParameterTable& table = spec.flight.table;
  table.monitor.stop_sinkage_m = mm(20.0);
  table.monitor.caution_sinkage_m = mm(14.0);
  table.monitor.allowed_sinkage_m = mm(20.0);
  table.monitor.sinkage_hysteresis_m = mm(4.0);
  table.escape.freed_sinkage_m = mm(10.0);
  ASSERT_TRUE(st.ok());
  ASSERT_EQ(fl::validate(table), fl::RejectReason::ok);
  const sg::Scenario s = sg::generate_scenario(spec, "test");
  ASSERT_EQ(s.log.metadata.count("mass_kg"), 1U);
  EXPECT_EQ(s.log.metadata.at("mass_kg"), "155.000");
  // Written and read back, the log replays to the stop made in the loop.
  std::ostringstream csv;
  sg::write_telemetry_csv(csv, s.log);
  const sg::TelemetryLog log = sg::parse_telemetry_text(csv.str(), "short-heavy.csv");
  sg::ReplayConfig config;
  config.table = table;
  config.gravity_mps2 = sg::log_gravity(log);
  sg::resolve_rover_mass(log, std::nullopt, config);
  EXPECT_EQ(sg::replay_mass_kg(config), 155.0);
  const sg::ReplayResult r = sg::run_replay(log, config);
  ASSERT_TRUE(s.truth.stop_time_s.has_value()) << "the scenario should stop the rover";
  ASSERT_TRUE(r.first_stop.has_value());
  // Same cycle (the log keeps the time to the millisecond; cycles are 0.2 s apart).
  EXPECT_NEAR(r.cycles[*r.first_stop].time_s, *s.truth.stop_time_s, 5e-4);
  // Without the line the replay would run at 140 kg and stop elsewhere:
  // the check above can tell the two apart.
  config.mass_kg.reset();
  const sg::ReplayResult yutu = sg::run_replay(log, config);
  ASSERT_TRUE(yutu.first_stop.has_value());
  EXPECT_GT(std::abs(yutu.cycles[*yutu.first_stop].time_s - *s.truth.stop_time_s), 0.1);
}
