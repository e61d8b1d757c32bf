// The mass the campaign gives the flight code in the loop (--flight-mass,
// issue 14): each traverse's drawn mass ("true"), or the rover's own whatever
// the draw ("default": the table's section 6, else the Yutu-like 140 kg).
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/campaign_command.hpp"
#include "sinkwatch/ground/cli_conventions.hpp"
#include "sinkwatch/ground/replay.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using namespace sinkwatch::ground;
namespace fl = sinkwatch::flight;
namespace fx = sinkwatch::fx;

double loop_mass_kg(const ReplayConfig& config) { return fx::to_double(OnboardLoop(config).rover().mass_kg.q()); }

TEST(CampaignFlightMass, TrueGivesTheFlightCodeTheDrawnMassAndDefaultTheRoversOwn) {
  const TraverseDraw draw = draw_traverse(CampaignFamily::gradual, 14, 3);
  ASSERT_GT(std::fabs(draw.mass_kg - 140.0), 0.5) << "pick a draw whose mass is not the default's";
  CampaignOptions options;
  EXPECT_EQ(options.flight_mass, FlightMass::true_mass);  // the default
  EXPECT_NEAR(loop_mass_kg(traverse_flight_config(draw, options, options.table)), draw.mass_kg, 1e-4);
  options.flight_mass = FlightMass::default_mass;
  EXPECT_EQ(loop_mass_kg(traverse_flight_config(draw, options, options.table)), 140.0);
  // A table with a rover section: its geometry in both modes, its mass only in "default".
  fl::RoverParams rover = fl::yutu_like_rover_params(fl::kGravityMoon);
  fx::Status st;
  rover.mass_kg = fl::MassKg{fx::from_double<fl::MassQ>(150.0, st)};
  rover.com_z_m = fl::LengthM{fx::from_double<fl::LengthQ>(0.2, st)};
  ASSERT_TRUE(st.ok());
  options.rover = rover;
  const ReplayConfig own = traverse_flight_config(draw, options, options.table);
  EXPECT_EQ(loop_mass_kg(own), 150.0);
  options.flight_mass = FlightMass::true_mass;
  const ReplayConfig drawn = traverse_flight_config(draw, options, options.table);
  EXPECT_NEAR(loop_mass_kg(drawn), draw.mass_kg, 1e-4);
  EXPECT_EQ(OnboardLoop(drawn).rover().com_z_m.q().raw(), rover.com_z_m.q().raw());
}

TEST(CampaignFlightMass, TheMassReachesTheVerdict) {
  // A heavy rover into a soft ripple: the flight code's wheel loads, and so
  // its sinkage estimates and its stop, depend on the mass it is given.
  TraverseDraw draw = draw_traverse(CampaignFamily::gradual, 1, 0, 9.0);
  ScenarioSpec& s = draw.spec;
  s.seed = 7;
  s.noise = ScenarioNoise{};
  s.terrain = {{0, 1, 0}, {1, 1, 0}, {3, 0.1, 0}, {6, 0.02, 0}, {9, 0.008, 0}};
  draw.mass_kg = 160.0;
  s.mass_kg = draw.mass_kg;
  const Scenario drive = generate_open_loop_drive(s);
  CampaignOptions options;
  const FlightVerdict drawn = flight_verdict(drive, traverse_flight_config(draw, options, options.table));
  options.flight_mass = FlightMass::default_mass;
  const FlightVerdict yutu = flight_verdict(drive, traverse_flight_config(draw, options, options.table));
  ASSERT_TRUE(drawn.stop_x_m.has_value());
  ASSERT_TRUE(yutu.stop_x_m.has_value());
  EXPECT_NE(*drawn.stop_x_m, *yutu.stop_x_m);
}

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CampaignFlightMass, CommandNamesItInTheSummaryAndTheJson) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sinkwatch_campaign_flight_mass";
  std::filesystem::remove_all(dir);
  std::ostringstream out, err;
  EXPECT_EQ(run_campaign_command({"--flight-mass", "nope", "--out", dir.string()}, out, err),
            exit_status(ExitCode::usage_error));
  const int rc = run_campaign_command({"--flight-mass", "default", "--families", "abrupt", "--traverses", "1",
                                       "--path-length", "7", "--levels", "45", "-q", "--out", dir.string()},
                                      out, err);
  ASSERT_EQ(rc, 0) << err.str();
  EXPECT_NE(out.str().find("Flight mass: default"), std::string::npos) << out.str();
  EXPECT_NE(read(dir / "traverses.json").find("\"flight_mass\": \"default\""), std::string::npos);
}

}  // namespace
