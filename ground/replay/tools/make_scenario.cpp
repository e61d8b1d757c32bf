// sinkwatch_make_scenario: writes a shipped telemetry scenario
// (data/telemetry/README.md records the exact commands).
#include "sinkwatch/ground/scenario.hpp"
#include "sinkwatch/ground/telemetry_log.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"Generate a telemetry scenario with the reference simulator and the flight code in the loop"};
  std::string name = "embedding";
  std::string out_path;
  std::uint64_t seed = 0;
  app.add_option("--scenario", name, "embedding, nominal or steep-ripple")
      ->check(CLI::IsMember({"embedding", "nominal", "steep-ripple"}));
  app.add_option("--seed", seed, "noise seed (default: the scenario's own)");
  app.add_option("--out", out_path, "output CSV")->required();
  CLI11_PARSE(app, argc, argv);

  std::string command = "sinkwatch_make_scenario";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  try {
    sinkwatch::ground::ScenarioSpec spec = sinkwatch::ground::scenario_by_name(name);
    if (seed != 0) spec.seed = seed;
    const sinkwatch::ground::Scenario s = sinkwatch::ground::generate_scenario(
        spec, command, [](double t) { std::fprintf(stderr, "\r  simulated %.0f s", t); });
    std::fprintf(stderr, "\n");
    std::ofstream f(out_path);
    if (!f) throw std::runtime_error("cannot write " + out_path);
    sinkwatch::ground::write_telemetry_csv(f, s.log);
    std::fprintf(stderr, "%s: %zu rows\n", out_path.c_str(), s.log.rows.size());
    if (s.truth.stop_time_s) std::fprintf(stderr, "  flight stop at %.1f s, x = %.3f m\n", *s.truth.stop_time_s, *s.truth.stop_x_m);
    if (s.truth.embedded) {
      std::fprintf(stderr, "  embedding at %.1f s, x = %.3f m: %s\n", s.truth.embed_time_s, s.truth.embed_x_m,
                   s.truth.embed_reason.c_str());
    } else {
      std::fprintf(stderr, "  no embedding on this path\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinkwatch_make_scenario: %s\n", e.what());
    return 2;
  }
  return 0;
}
