// Study (not part of the repo): dump the campaign's open-loop drives with the
// flight code's per-cycle view, for offline evaluation of decision rules.
#include "sinkwatch/ground/campaign.hpp"
#include "sinkwatch/ground/replay.hpp"
#include "sinkwatch/ground/scenario.hpp"
#include "sinkwatch/ground/soil_presets.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
using namespace sinkwatch;
using namespace sinkwatch::ground;


static double interp(const std::vector<TerrainKnot>& k, double x, double TerrainKnot::*field) {
  if (x <= k.front().x_m) return k.front().*field;
  for (std::size_t i = 1; i < k.size(); ++i)
    if (x <= k[i].x_m) { const double f = (x - k[i-1].x_m) / (k[i].x_m - k[i-1].x_m); return k[i-1].*field + f * (k[i].*field - k[i-1].*field); }
  return k.back().*field;
}
static SimParameters base_of(const ScenarioSpec& spec) {
  SimParameters p = default_parameters(spec.soil_parameters ? std::string("hit-lss1") : spec.soil);
  if (spec.soil_parameters) p.soil = *spec.soil_parameters;
  p.gravity_m_s2 = spec.gravity_mps2;
  p.quadrature_rel_tol = spec.quadrature_rel_tol;
  if (spec.effects) p.effects = *spec.effects; else p.effects.slip_sinkage.enabled = true;
  return p;
}
static SimParameters scaled(SimParameters p, double s) { p.soil.kc *= s; p.soil.kphi *= s; p.soil.cohesion_pa *= s; return p; }
// max over slip of the six pulls (NaN if a wheel sinks to its axle at every slip), and its slip
static std::pair<double,double> max_pull(const ScenarioSpec& spec, const SimParameters& base, double x, const std::array<double,6>& w) {
  const double sc = interp(spec.terrain, x, &TerrainKnot::soil_scale);
  const double rf = interp(spec.terrain, x, &TerrainKnot::right_soil_factor);
  const SimParameters L = scaled(base, sc), Rr = scaled(base, sc * rf);
  double best = -1e9, sbest = -1;
  for (double s = 0.0; s <= 0.951; s += 0.025) {
    double sum = 0; bool ok = true;
    for (int i = 0; i < 6 && ok; ++i) { const Evaluation e = evaluate(i < 3 ? L : Rr, w[static_cast<std::size_t>(i)], s); ok = e.ok(); sum += e.state.drawbar_pull_n; }
    if (!ok) break;
    if (sum > best) { best = sum; sbest = s; }
  }
  return {best, sbest};
}

static void dump_one(const TraverseDraw& d, const CampaignOptions& o, const std::string& dir) {
  const Scenario drive = generate_open_loop_drive(d.spec);
  ReplayConfig cfg = traverse_flight_config(d, o, o.table);
  cfg.run_escape = false;
  OnboardLoop loop(cfg);
  std::string path = dir + "/" + d.spec.name + ".csv";
  FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "# family=%s index=%zu embedded=%d embed_x=%.4f embed_t=%.3f mass=%.3f slope=%.3f roll=%.3f min_scale=%.5f soil=%s effects=%s\n",
               family_name(d.family), d.index, drive.truth.embedded ? 1 : 0, drive.truth.embed_x_m, drive.truth.embed_time_s,
               d.mass_kg, d.slope_deg, d.roll_deg, d.min_soil_scale, d.soil.c_str(), d.effects.c_str());
  const SimParameters base = base_of(d.spec);
  std::fprintf(f, "dpmax,speak,t,x,phase,true_slip,true_z_mm,pitch_deg,roll_deg,accel,speed,slip,sat");
  for (int w = 0; w < 6; ++w) std::fprintf(f, ",W%d,Wt%d,DP%d,T%d,z%d,I%d,Imax%d,st%d", w, w, w, w, w, w, w, w);
  std::fprintf(f, "\n");
  for (std::size_t i = 0; i < drive.log.rows.size(); ++i) {
    const TelemetryRow& row = drive.log.rows[i];
    const CycleRecord rec = loop.step(row, drive.log.source, row.x_m.value_or(0.0));
    double dpmax = NAN, speak = NAN;
    if (row.phase == "drive" && i % 5 == 0 && i < drive.cycle_loads.size()) { auto m = max_pull(d.spec, base, row.x_m.value_or(0.0), drive.cycle_loads[i].true_n); dpmax = m.first; speak = m.second; }
    std::fprintf(f, "%.3f,%.3f,", dpmax, speak);
    std::fprintf(f, "%.2f,%.4f,%s,%.5f,%.3f,%.4f,%.4f,%.5f,%.5f,%.5f,%d", row.time_s, rec.x_m, row.phase.c_str(),
                 row.true_slip.value_or(-1.0), row.true_sinkage_mm.value_or(-1.0), row.pitch_deg, row.roll_deg,
                 rec.accel_mps2.value_or(0.0), row.speed_mps.value_or(0.0), rec.slip.value_or(-9.0), rec.drawbar_saturated ? 1 : 0);
    for (int w = 0; w < 6; ++w) {
      const WheelCycle& wc = rec.wheels[static_cast<std::size_t>(w)];
      const double wt = i < drive.cycle_loads.size() ? drive.cycle_loads[i].true_n[static_cast<std::size_t>(w)] : 0.0;
      std::fprintf(f, ",%.3f,%.3f,%.3f,%.4f,%.5f,%.4f,%.4f,%d", wc.load_n, wt, wc.drawbar_pull_n, wc.torque_nm,
                   wc.estimate_valid ? wc.sinkage_m : -1.0, wc.current_a, wc.limit_valid ? wc.current_limit_a : -1.0,
                   static_cast<int>(wc.state));
    }
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

int main(int argc, char** argv) {
  const std::string dir = argv[1];
  const std::size_t n = std::stoul(argv[2]);
  const std::uint64_t seed = std::stoull(argv[3]);
  const unsigned threads = static_cast<unsigned>(std::stoul(argv[4]));
  CampaignOptions o;
  std::vector<TraverseDraw> draws;
  for (CampaignFamily fam : kAllCampaignFamilies)
    for (std::size_t k = 0; k < n; ++k) draws.push_back(draw_traverse(fam, seed, k, 16.0));
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> ts;
  for (unsigned t = 0; t < threads; ++t)
    ts.emplace_back([&] { for (std::size_t i = next++; i < draws.size(); i = next++) { dump_one(draws[i], o, dir); std::fprintf(stderr, "."); } });
  for (auto& t : ts) t.join();
  std::fprintf(stderr, "\n");
}
