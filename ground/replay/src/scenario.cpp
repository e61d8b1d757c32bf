// Scenario generator (scenario.hpp, docs/scenarios.md).
#include "sinkwatch/ground/scenario.hpp"

#include "sinkwatch/ground/reference.hpp"
#include "sinkwatch/ground/rover_loads.hpp"
#include "sinkwatch/ground/soil_presets.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

// The soil with its moduli and cohesion scaled (softer below 1).
SimParameters scaled_soil(SimParameters p, double scale) {
  p.soil.kc *= scale;
  p.soil.kphi *= scale;
  p.soil.cohesion_pa *= scale;
  return p;
}

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr std::size_t kN = kTelemetryWheels;

// Portable Gaussian draws: the standard library's distributions differ
// between implementations, the engine does not.
class Noise {
 public:
  explicit Noise(std::uint64_t seed) : engine_(seed) {}
  double gauss(double sigma) {
    if (sigma <= 0.0) return 0.0;
    if (has_spare_) {
      has_spare_ = false;
      return sigma * spare_;
    }
    double u1 = 0.0;
    do {
      u1 = uniform();
    } while (u1 <= 0.0);
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return sigma * r * std::cos(2.0 * kPi * u2);
  }

 private:
  double uniform() { return static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0); }
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

std::string number(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

// The scenario's mass_kg metadata (the flight code in the loop reads it back).
std::string mass_text(const ScenarioSpec& spec) { return number(spec.mass_kg, 3); }

struct WheelTruth {
  double sinkage_m = 0.0;
  double torque_nm = 0.0;  // in the direction of driving
  double drawbar_pull_n = 0.0;
  double soil_torque_nm = 0.0;  // without drive friction: what the link's balance sees
};

WheelTruth wheel_truth(const WheelSoilState& s) {
  return WheelTruth{s.sinkage_m, s.torque_nm, s.drawbar_pull_n, s.soil_torque_nm};
}

// The soil under the rover: the left wheels' scale and the right wheels'
// factor on it (one-side softening).
struct SideSoil {
  double scale = 1.0;
  double right_factor = 1.0;
};

struct SideParams {
  SimParameters left;
  SimParameters right;
  bool same = true;  // both sides on the same soil: a wheel may reuse its mirror's state
};

struct SlipSolution {
  bool ok = false;
  std::string failure;  // why no slip carries the rover
  double slip = 0.0;
  std::array<WheelTruth, kN> wheels{};
};

class World {
 public:
  explicit World(const ScenarioSpec& spec)
      : spec_(spec), base_(scenario_soil(spec, 1.0)), geometry_(yutu_like_geometry(spec.gravity_mps2)) {
    geometry_.mass_kg = spec.mass_kg;
    if (spec.terrain.empty()) throw std::invalid_argument("scenario '" + spec.name + "' has no terrain");
  }

  double slope_deg(double x) const { return interpolate(x, &TerrainKnot::slope_deg); }
  double roll_deg(double x) const { return interpolate(x, &TerrainKnot::roll_deg); }
  double soil_scale(double x) const { return interpolate(x, &TerrainKnot::soil_scale); }
  SideSoil soil(double x, double gain) const {
    return SideSoil{soil_scale(x) * gain, interpolate(x, &TerrainKnot::right_soil_factor)};
  }
  // The flight code's statics at this attitude with `torques` (each wheel's
  // torque from its logged current, as the step takes it: docs/rover-loads.md
  // 12.8): what CycleLoads::flight_statics_n compares with.
  std::array<double, kN> statics_loads(double pitch_deg, double roll_deg, const DriveTorques& torques) const {
    const WheelLoads w = wheel_loads(geometry_, Attitude{pitch_deg * kDeg, roll_deg * kDeg}, JointAngles{}, torques);
    if (w.status != LoadStatus::ok) throw std::runtime_error("scenario: wheel loads failed at the path's slope");
    std::array<double, kN> out{};
    for (std::size_t i = 0; i < kN; ++i) out[i] = w.load_n[i];
    return out;
  }

  // The simulated rover's loads: the fuller balance with the wheels' pulls
  // and soil torques (`traction`, body frame) and the acceleration
  // (docs/rover-loads.md section 11).
  std::array<double, kN> loads(double pitch_deg, double roll_deg, double accel_mps2,
                               const WheelTraction& traction) const {
    ForceBalanceInput in;
    in.attitude = Attitude{pitch_deg * kDeg, roll_deg * kDeg};
    in.accel_mps2 = accel_mps2;
    in.traction = traction;
    const ForceBalanceLoads w = force_balance_loads(geometry_, in);
    if (w.status != LoadStatus::ok) throw std::runtime_error("scenario: force-balance wheel loads failed");
    std::array<double, kN> out = w.load_n;
    // A left-right symmetric case gets exactly symmetric loads (the
    // elimination's rounding differs by side), so mirror wheels share states.
    bool symmetric = roll_deg == 0.0;
    for (std::size_t i = 0; i < kN / 2; ++i) {
      symmetric = symmetric && traction.tangential_n[i] == traction.tangential_n[i + kN / 2] &&
                  traction.soil_torque_nm[i] == traction.soil_torque_nm[i + kN / 2];
    }
    for (std::size_t i = 0; symmetric && i < kN / 2; ++i) out[i] = out[i + kN / 2] = 0.5 * (out[i] + out[i + kN / 2]);
    return out;
  }

  double mass_kg() const { return geometry_.mass_kg; }

  // The slip at which the six wheels' drawbar pulls give `required_n`, on the
  // branch where DP rises with slip, searched near `hint`: bracketed in steps
  // of 0.04 down and 0.02 up, then bisected.
  SlipSolution solve(SideSoil soil, const std::array<double, kN>& w, double required_n, double hint) const {
    const SideParams p = scaled(soil);
    SlipSolution sol;
    const auto total = [&](double s, std::array<WheelTruth, kN>& wheels) {
      return total_pull(p, w, s, wheels, sol.failure);
    };
    std::array<WheelTruth, kN> lo_w{};
    std::array<WheelTruth, kN> hi_w{};
    double lo = std::max(0.0, hint - spec_.slip_step_down);
    std::optional<double> f_lo = total(lo, lo_w);
    while (f_lo && *f_lo >= required_n && lo > 0.0) {
      lo = std::max(0.0, lo - spec_.slip_step_down);
      f_lo = total(lo, lo_w);
    }
    if (!f_lo) return sol;
    if (*f_lo >= required_n) {  // free rolling carries it
      sol.ok = true;
      sol.slip = lo;
      sol.wheels = lo_w;
      return sol;
    }
    double hi = lo;
    std::optional<double> f_hi;
    while (true) {
      if (hi >= kEmbedMaxSlip) {
        sol.failure = "net traction <= 0: no slip up to 95 % gives the pull the slope needs";
        return sol;
      }
      hi = std::min(hi + spec_.slip_step_up, kEmbedMaxSlip);
      f_hi = total(hi, hi_w);
      if (!f_hi) return sol;
      if (*f_hi >= required_n) break;
      lo = hi;
      f_lo = f_hi;
      lo_w = hi_w;
    }
    const Bracket b{lo, *f_lo - required_n, hi, *f_hi - required_n, hi_w};
    return spec_.slip_refine == SlipRefine::bisection ? bisect(total, b, required_n, sol)
                                                      : illinois(total, b, required_n, sol);
  }

  // The largest total pull at any slip up to kEmbedMaxSlip, on a grid of
  // kReserveSlipStep (the pull's maximum is flat, so the grid's error is a
  // small fraction of a newton), up to the first slip at which a wheel sinks
  // to its axle; nothing when one does so already at zero slip.
  std::optional<double> max_pull(SideSoil soil, const std::array<double, kN>& w) const {
    constexpr double kReserveSlipStep = 0.025;
    const SideParams p = scaled(soil);
    std::optional<double> best;
    std::string failure;
    std::array<WheelTruth, kN> wheels{};
    for (int k = 0; k * kReserveSlipStep <= kEmbedMaxSlip + 1e-9; ++k) {
      const std::optional<double> pull = total_pull(p, w, k * kReserveSlipStep, wheels, failure);
      if (!pull) break;
      best = best ? std::max(*best, *pull) : *pull;
    }
    return best;
  }

  // The wheels spinning in place at the highest slip, for a stuck rover.
  std::array<WheelTruth, kN> spinning(SideSoil soil, const std::array<double, kN>& w) const {
    const SideParams p = scaled(soil);
    std::array<WheelTruth, kN> out{};
    for (std::size_t i = 0; i < kN; ++i) {
      const Evaluation e = evaluate(i < kN / 2 ? p.left : p.right, w[i], kEmbedMaxSlip);
      out[i] = e.ok() ? wheel_truth(e.state) : WheelTruth{geometry_.wheel_radius_m, e.state.torque_nm, 0.0, 0.0};
    }
    return out;
  }

 private:
  // lo carries less than the rover needs (g_lo < 0), hi enough (g_hi >= 0).
  struct Bracket {
    double lo, g_lo, hi, g_hi;
    std::array<WheelTruth, kN> hi_w;
  };

  template <typename Total>
  SlipSolution bisect(const Total& total, Bracket b, double required_n, SlipSolution& sol) const {
    for (int k = 0; k < spec_.slip_bisections; ++k) {
      const double mid = 0.5 * (b.lo + b.hi);
      std::array<WheelTruth, kN> mid_w{};
      const std::optional<double> f_mid = total(mid, mid_w);
      if (!f_mid) return sol;
      if (*f_mid >= required_n) {
        b.hi = mid;
        b.hi_w = mid_w;
      } else {
        b.lo = mid;
      }
    }
    return SlipSolution{true, "", b.hi, b.hi_w};
  }

  // False position with the Illinois modification (the retained end's
  // value halved): superlinear, so a few steps reach what 14 bisections do.
  // Stops when the bracket is narrower than kIllinoisSlip or the pull is
  // within kIllinoisPullN of the need; returns the end that carries the rover.
  template <typename Total>
  SlipSolution illinois(const Total& total, Bracket b, double required_n, SlipSolution& sol) const {
    constexpr double kIllinoisSlip = 1e-4;
    constexpr double kIllinoisPullN = 0.005;
    int side = 0;
    for (int k = 0; k < spec_.slip_bisections && b.hi - b.lo > kIllinoisSlip && b.g_hi > kIllinoisPullN; ++k) {
      const double s = std::clamp(b.hi - b.g_hi * (b.hi - b.lo) / (b.g_hi - b.g_lo), b.lo, b.hi);
      std::array<WheelTruth, kN> s_w{};
      const std::optional<double> f_s = total(s, s_w);
      if (!f_s) return sol;
      const double g = *f_s - required_n;
      if (g >= 0.0) {
        b.hi = s;
        b.g_hi = g;
        b.hi_w = s_w;
        if (side == 1) b.g_lo *= 0.5;
        side = 1;
      } else {
        b.lo = s;
        b.g_lo = g;
        if (side == -1) b.g_hi *= 0.5;
        side = -1;
      }
    }
    return SlipSolution{true, "", b.hi, b.hi_w};
  }

  SideParams scaled(SideSoil soil) const {
    SideParams p{scaled_soil(base_, soil.scale), {}, soil.right_factor == 1.0};
    p.right = p.same ? p.left : scaled_soil(base_, soil.scale * soil.right_factor);
    return p;
  }

  // The six wheels' total drawbar pull at slip s (each wheel's state in
  // `wheels`); nothing, and why in `failure`, when a wheel sinks to its axle.
  // A right wheel on the same soil and load as its left mirror reuses its
  // state (the simulator is deterministic: the same numbers, once).
  static std::optional<double> total_pull(const SideParams& p, const std::array<double, kN>& w, double s,
                                          std::array<WheelTruth, kN>& wheels, std::string& failure) {
    double sum = 0.0;
    for (std::size_t i = 0; i < kN; ++i) {
      if (i >= kN / 2 && p.same && w[i] == w[i - kN / 2]) {
        wheels[i] = wheels[i - kN / 2];
        sum += wheels[i].drawbar_pull_n;
        continue;
      }
      const Evaluation e = evaluate(i < kN / 2 ? p.left : p.right, w[i], s);
      if (!e.ok()) {
        failure = "wheel " + std::string(kWheelNames[i]) + " sinks to its axle at slip " + number(s, 2) +
                  ", before the wheels give the pull the rover needs";
        return std::nullopt;
      }
      wheels[i] = wheel_truth(e.state);
      sum += e.state.drawbar_pull_n;
    }
    return sum;
  }

  double interpolate(double x, double TerrainKnot::*field) const {
    const std::vector<TerrainKnot>& k = spec_.terrain;
    if (x <= k.front().x_m) return k.front().*field;
    for (std::size_t i = 1; i < k.size(); ++i) {
      if (x <= k[i].x_m) {
        const double f = (x - k[i - 1].x_m) / (k[i].x_m - k[i - 1].x_m);
        return k[i - 1].*field + f * (k[i].*field - k[i - 1].*field);
      }
    }
    return k.back().*field;
  }

  const ScenarioSpec& spec_;
  SimParameters base_;
  RoverGeometry geometry_;
};

// The rover's motion state between cycles.
struct Motion {
  double t = 0.0;
  double x = 0.0;
  double v = 0.0;     // signed, along the path
  double a = 0.0;     // signed
  double hint = 0.0;  // last slip
  double gain = 1.0;  // soil improvement from escape reversals
  WheelTraction traction{};  // last cycle's pulls and soil torques, body frame
};

struct CycleTruth {
  bool ok = true;
  std::string failure;
  double slip = 0.0;
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
  std::array<double, kN> load_n{};
  std::array<WheelTruth, kN> wheels{};
};

// The slip that carries the rover at the cycle's loads c.load_n in direction
// d at rim speed u. The wheels carry the slope and the acceleration. When the
// soil cannot give the extra pull a speed ramp needs, the rover accelerates
// only as fast as traction allows: quasi-static (docs/scenarios.md). The
// acceleration `a` is this cycle's own (v_new - v) / dt, found by a few
// fixed-point passes, so that the IMU's reading and the pull agree.
SlipSolution carry(const World& world, const ScenarioSpec& spec, const Motion& m, const CycleTruth& c, int d,
                   double u, double& a) {
  const double slope_along = d * c.pitch_deg * kDeg;  // the slope as the driving direction sees it
  const double slope_pull = world.mass_kg() * spec.gravity_mps2 * std::sin(slope_along);
  const SideSoil soil = world.soil(m.x, m.gain);
  SlipSolution s;
  for (int pass = 0; pass < 4; ++pass) {
    s = world.solve(soil, c.load_n, slope_pull + world.mass_kg() * d * a, m.hint);
    if (!s.ok && d * a > 0.0) s = world.solve(soil, c.load_n, slope_pull, m.hint);
    if (!s.ok) break;
    const double a_new = (d * u * (1.0 - s.slip) - m.v) / spec.cycle_s;
    if (std::fabs(a_new - a) < 1e-4) break;
    a = a_new;
  }
  return s;
}

// The wheels' pulls and soil torques in the body frame (driving direction d).
WheelTraction traction_of(const std::array<WheelTruth, kN>& wheels, int d) {
  WheelTraction t;
  for (std::size_t i = 0; i < kN; ++i) {
    t.tangential_n[i] = d * wheels[i].drawbar_pull_n;
    t.soil_torque_nm[i] = d * wheels[i].soil_torque_nm;
  }
  return t;
}

double max_abs_difference(const std::array<double, kN>& a, const std::array<double, kN>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < kN; ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

// Loads <-> simulator to a fixed point: the loads from
// the last cycle's forces, the slip at them, the loads from the new forces,
// until they change by less than this, at most spec.load_iterations times.
constexpr double kLoadFixedPointN = 0.05;

// One cycle of driving in direction d (+1 / -1) at rim speed u >= 0.
CycleTruth advance(const World& world, const ScenarioSpec& spec, Motion& m, int d, double u) {
  CycleTruth c;
  c.pitch_deg = world.slope_deg(m.x);
  c.roll_deg = world.roll_deg(m.x);
  c.load_n = world.loads(c.pitch_deg, c.roll_deg, m.a, m.traction);
  double v_new = 0.0;
  if (u > 1e-6) {
    double a = m.a;
    SlipSolution s = carry(world, spec, m, c, d, u, a);
    for (int it = 0; s.ok && it < spec.load_iterations; ++it) {
      const std::array<double, kN> w = world.loads(c.pitch_deg, c.roll_deg, a, traction_of(s.wheels, d));
      if (max_abs_difference(w, c.load_n) < kLoadFixedPointN) break;
      c.load_n = w;
      s = carry(world, spec, m, c, d, u, a);
    }
    if (!s.ok) {
      c.ok = false;
      c.failure = s.failure;
      return c;
    }
    c.slip = s.slip;
    c.wheels = s.wheels;
    m.hint = s.slip;
    m.traction = traction_of(s.wheels, d);
    v_new = d * u * (1.0 - s.slip);
  } else {
    // Standing: the wheels keep their last sinkage, carry no torque.
    m.hint = 0.0;
    m.traction = WheelTraction{};
  }
  m.a = (v_new - m.v) / spec.cycle_s;
  m.v = v_new;
  m.x += v_new * spec.cycle_s;
  return c;
}

}  // namespace

ScenarioSpec embedding_scenario() {
  ScenarioSpec s;
  s.name = "embedding";
  s.description =
      "firm ground, then softer soil, then a soft ripple whose loose core would embed the wheels "
      "(after Opportunity at Purgatory), then the escape";
  s.seed = 446;  // Opportunity's sol at Purgatory
  s.terrain = {
      {0.0, 1.0, 0.0},   {4.0, 1.0, 0.0},    {6.0, 0.3, 0.5},    {9.0, 0.3, 1.0},
      {11.0, 0.1, 1.0},  {13.0, 0.03, 0.5},  {16.0, 0.02, 0.0},  {20.0, 0.012, 0.0},
  };
  s.end_x_m = 20.0;
  return s;
}

ScenarioSpec nominal_scenario() {
  ScenarioSpec s;
  s.name = "nominal";
  s.description = "firm and moderately soft ground (down to 15 % of the firm soil's moduli) with gentle undulations (up to 5 deg): an ordinary drive";
  s.seed = 2013;  // Yutu's landing year
  s.terrain = {
      {0.0, 1.0, 0.0},  {3.0, 1.0, 2.0},   {6.0, 0.6, 5.0},  {9.0, 0.3, 0.0},
      {11.0, 0.15, 2.0}, {13.0, 0.15, -3.0}, {15.0, 0.5, 3.0}, {18.0, 1.0, 0.0}, {20.0, 1.0, 0.0},
  };
  s.end_x_m = 20.0;
  return s;
}

ScenarioSpec steep_ripple_scenario() {
  ScenarioSpec s = embedding_scenario();
  s.name = "steep-ripple";
  s.description =
      "as 'embedding', but the soft ripple's flank steepens to 6-8 deg: the default table does not stop the rover "
      "in time (docs/scenarios.md, finding 2)";
  s.terrain = {
      {0.0, 1.0, 0.0},  {4.0, 1.0, 0.0},   {6.0, 0.3, 0.5}, {9.0, 0.3, 1.0},
      {11.0, 0.1, 2.0}, {14.0, 0.03, 6.0}, {20.0, 0.03, 8.0},
  };
  return s;
}

ScenarioSpec scenario_by_name(const std::string& name) {
  if (name == "embedding") return embedding_scenario();
  if (name == "nominal") return nominal_scenario();
  if (name == "steep-ripple") return steep_ripple_scenario();
  throw std::invalid_argument("unknown scenario '" + name + "'; known: embedding nominal steep-ripple");
}

namespace {

// One cycle's command: direction d (+1 / -1), rim speed u >= 0, and the
// phase the log names.
struct Command {
  int d = 1;
  double u = 0.0;
  std::string phase;
};

// The closed loop of generate_scenario: the simulated rover driven by the
// phase it is in, the flight code (OnboardLoop) reading its telemetry, and
// the phase changed by the flight code's decisions.
class ScenarioRun {
 public:
  enum class Mode { drive, escape, settle, stuck, done };

  ScenarioRun(const ScenarioSpec& spec, Scenario& out, bool open_loop = false)
      : open_loop_(open_loop), spec_(spec), world_(spec), noise_(spec.seed), onboard_(flight_config(spec)),
        motor_(reference::from_flight(onboard_.config().table.motor)),
        forward_ms_(onboard_.config().table.escape.forward_phase_ms / 1000.0),
        reverse_ms_(onboard_.config().table.escape.reverse_phase_ms / 1000.0), out_(out) {}

  // Drives until the last phase ends or the time runs out.
  void run(const std::function<void(double)>& progress) {
    for (std::size_t k = 0; mode_ != Mode::done; ++k) {
      m_.t = static_cast<double>(k) * spec_.cycle_s;
      if (m_.t > spec_.max_time_s) break;
      if (progress && k % 50 == 0) progress(m_.t);
      Command cmd = command();
      CycleTruth c;
      if (!truth_of(cmd, c)) {
        --k;  // log this cycle as stuck
        continue;
      }
      last_wheels_ = c.wheels;
      last_direction_ = cmd.d;
      const TelemetryRow row = telemetry_row(c, cmd);
      if (open_loop_) {
        out_.log.rows.push_back(row);
        out_.cycle_loads.push_back(
            CycleLoads{c.load_n, world_.statics_loads(c.pitch_deg, c.roll_deg, logged_torques(row)), reserve(c, k)});
        next_open_loop_mode();
        continue;
      }
      const CycleRecord rec = onboard_.step(row, spec_.name, *row.x_m);
      out_.log.rows.push_back(row);
      next_mode(rec);
    }
  }

  // The traction reserve of a driving row (CycleLoads::reserve_n), on the
  // rows the spec asks for; an axle-deep wheel at zero slip is no reserve.
  std::optional<double> reserve(const CycleTruth& c, std::size_t k) const {
    const auto every = static_cast<std::size_t>(std::max(spec_.reserve_every_rows, 0));
    if (every == 0 || k % every != 0 || mode_ != Mode::drive) return std::nullopt;
    const double slope_pull = world_.mass_kg() * spec_.gravity_mps2 * std::sin(c.pitch_deg * kDeg);
    const std::optional<double> pull = world_.max_pull(world_.soil(m_.x, m_.gain), c.load_n);
    return pull ? *pull - slope_pull : -slope_pull;
  }

  // Where would the rover have embedded had it not stopped? The drive up to
  // the stop is the open-loop drive; continue it without telemetry.
  void find_open_loop_embedding() {
    if (!at_stop_) return;
    Motion m2 = *at_stop_;
    for (std::size_t k = 1; m2.x < spec_.end_x_m; ++k) {
      m2.t = *out_.truth.stop_time_s + static_cast<double>(k) * spec_.cycle_s;
      if (m2.t > spec_.max_time_s) break;
      const CycleTruth c = advance(world_, spec_, m2, 1, spec_.speed_mps);
      if (!c.ok) {
        record_embedding(m2, c.failure);
        break;
      }
    }
  }

 private:
  // The flight code in the loop runs with the mass the log's mass_kg line
  // will say (the number as written), so that the log replays to the
  // decisions it was made with (a replay takes that line over the table's).
  static ReplayConfig flight_config(const ScenarioSpec& spec) {
    ReplayConfig flight = spec.flight;
    flight.gravity_mps2 = spec.gravity_mps2;
    flight.mass_kg = std::stod(mass_text(spec));
    flight.mass_source = MassSource::log_header;
    return flight;
  }

  // The command for this cycle, by mode.
  Command command() {
    switch (mode_) {
      case Mode::drive:
        return Command{1, spec_.speed_mps * std::min(1.0, m_.t / spec_.ramp_s), "drive"};
      case Mode::escape:
        return escape_command();
      case Mode::settle:
      case Mode::stuck:
      case Mode::done:
        break;
    }
    return Command{last_direction_, 0.0, mode_ == Mode::stuck ? "stuck" : "stopped"};
  }

  // In the escape: the sequencer's direction, the speed ramped up and down
  // within each phase; a reversal carries soil under the wheels.
  Command escape_command() {
    const flight::EscapeState es = onboard_.escape_state();
    if (es != last_escape_) {
      if (last_escape_ == flight::EscapeState::forward || last_escape_ == flight::EscapeState::reverse) {
        m_.gain *= spec_.escape_soil_gain;
      }
      last_escape_ = es;
      phase_start_ = m_.t;
    }
    const bool fwd = es == flight::EscapeState::forward;
    const double len = fwd ? forward_ms_ : reverse_ms_;
    const double tin = m_.t - phase_start_;
    return Command{fwd ? 1 : -1,
                   spec_.speed_mps *
                       std::clamp(std::min(tin / spec_.ramp_s, (len - tin - spec_.cycle_s) / spec_.ramp_s), 0.0, 1.0),
                   fwd ? "escape-fwd" : "escape-rev"};
  }

  // The wheels spinning in place at the highest slip: the rover stands.
  void spin_in_place(CycleTruth& c) {
    c.wheels = world_.spinning(world_.soil(m_.x, m_.gain), c.load_n);
    c.slip = kEmbedMaxSlip;
    m_.a = (0.0 - m_.v) / spec_.cycle_s;
    m_.v = 0.0;
  }

  void record_embedding(const Motion& m, const std::string& reason) {
    out_.truth.embedded = true;
    out_.truth.embed_x_m = m.x;
    out_.truth.embed_time_s = m.t;
    out_.truth.embed_reason = reason;
  }

  // The simulator's truth for this cycle; false when the rover embeds while
  // driving (then stuck from here on, and the cycle is run again as stuck).
  bool truth_of(Command& cmd, CycleTruth& c) {
    if (mode_ == Mode::stuck) {
      c.pitch_deg = world_.slope_deg(m_.x);
      c.roll_deg = world_.roll_deg(m_.x);
      c.load_n = world_.loads(c.pitch_deg, c.roll_deg, 0.0, WheelTraction{});
      spin_in_place(c);
      cmd.u = spec_.speed_mps;
      return true;
    }
    c = advance(world_, spec_, m_, cmd.d, cmd.u);
    if (!c.ok && mode_ != Mode::drive) {
      // No slip carries the rover: its wheels spin in place, digging.
      c.ok = true;
      spin_in_place(c);
      cmd.phase += "-spinning";
    }
    if (!c.ok) {
      record_embedding(m_, c.failure);
      mode_ = Mode::stuck;
      mode_end_ = m_.t + spec_.stuck_tail_s;
      return false;
    }
    if (cmd.u <= 1e-6) {
      // Standing: the wheels keep their last sinkage, carry no torque.
      c.wheels = last_wheels_;
      for (WheelTruth& w : c.wheels) {
        w.torque_nm = 0.0;
        w.drawbar_pull_n = 0.0;
        w.soil_torque_nm = 0.0;
      }
    }
    return true;
  }

  // Each wheel's drive torque from the row's current through the flight
  // motor model (T = N eta Kt (I - d I0)), as the step computes it; a
  // current beyond the sensor's range leaves the wheel without a torque.
  DriveTorques logged_torques(const TelemetryRow& row) const {
    DriveTorques t;
    const flight::DriveDirection d = row.reverse ? flight::DriveDirection::reverse : flight::DriveDirection::forward;
    for (std::size_t i = 0; i < kN; ++i) {
      t.usable[i] = std::fabs(row.current_a[i]) <= motor_.current_abs_max_a;
      t.torque_nm[i] = t.usable[i] ? reference::torque_nm(motor_, row.current_a[i], d) : 0.0;
    }
    return t;
  }

  // The telemetry row: the truth plus sensor noise, rounded through the
  // file format so that the loop sees what the file holds.
  TelemetryRow telemetry_row(const CycleTruth& c, const Command& cmd) {
    const int d = cmd.d;
    const double u = cmd.u;
    const ScenarioNoise& noise = spec_.noise;
    TelemetryRow row;
    row.time_s = m_.t;
    row.valid = true;
    double deepest = 0.0;
    for (std::size_t i = 0; i < kN; ++i) {
      const double torque = d * c.wheels[i].torque_nm;
      const double clean =
          u > 1e-6 ? reference::current_a(motor_, torque, d > 0 ? flight::DriveDirection::forward
                                                                 : flight::DriveDirection::reverse)
                   : 0.0;
      row.current_a[i] = clean + noise_.gauss(std::hypot(noise.current_abs_a, noise.current_rel * std::fabs(clean)));
      deepest = std::max(deepest, c.wheels[i].sinkage_m);
    }
    row.reverse = d < 0;
    row.pitch_deg = c.pitch_deg + noise_.gauss(noise.attitude_deg);
    row.roll_deg = c.roll_deg + noise_.gauss(noise.attitude_deg);
    row.rocker_deg = {noise_.gauss(noise.joint_deg), noise_.gauss(noise.joint_deg)};
    row.bogie_deg = {noise_.gauss(noise.joint_deg), noise_.gauss(noise.joint_deg)};
    row.accel_mps2 = m_.a + noise_.gauss(noise.accel_mps2);
    row.speed_mps = m_.v + noise_.gauss(noise.speed_mps);
    row.rim_speed_mps = d * u;
    row.x_m = m_.x;
    row.true_slip = c.slip;
    row.true_sinkage_mm = deepest * 1000.0;
    row.phase = cmd.phase;
    return parse_telemetry_row(format_telemetry_row(row));
  }

  // The open-loop drive: to the goal, or to the embedding and its stuck tail.
  void next_open_loop_mode() {
    if ((mode_ == Mode::drive && m_.x >= spec_.end_x_m) || (mode_ == Mode::stuck && m_.t >= mode_end_)) {
      mode_ = Mode::done;
    }
  }

  // The next cycle's mode from the flight code's decision and the path.
  void next_mode(const CycleRecord& rec) {
    switch (mode_) {
      case Mode::drive:
        if (rec.decision == flight::RoverDecision::stop_and_replan) {
          out_.truth.stop_time_s = m_.t;
          out_.truth.stop_x_m = m_.x;
          at_stop_ = m_;
          mode_ = rec.escape_active ? Mode::escape : Mode::settle;
          mode_end_ = m_.t + spec_.settle_s;
          last_escape_ = flight::EscapeState::idle;
        } else if (m_.x >= spec_.end_x_m) {
          mode_ = Mode::settle;
          mode_end_ = m_.t + spec_.settle_s;
        }
        break;
      case Mode::escape:
        if (rec.escape_state != flight::EscapeState::forward && rec.escape_state != flight::EscapeState::reverse) {
          mode_ = Mode::settle;
          mode_end_ = m_.t + spec_.settle_s;
        }
        break;
      case Mode::settle:
      case Mode::stuck:
        if (m_.t >= mode_end_) mode_ = Mode::done;
        break;
      case Mode::done:
        break;
    }
  }

  const bool open_loop_;
  const ScenarioSpec& spec_;
  const World world_;
  Noise noise_;
  OnboardLoop onboard_;
  const reference::Motor motor_;
  const double forward_ms_;
  const double reverse_ms_;
  Scenario& out_;

  Mode mode_ = Mode::drive;
  Motion m_;
  std::optional<Motion> at_stop_;
  flight::EscapeState last_escape_ = flight::EscapeState::idle;
  double phase_start_ = 0.0;
  double mode_end_ = 0.0;
  std::array<WheelTruth, kN> last_wheels_{};
  int last_direction_ = 1;
};

// The log's comments and metadata: what made it, and the simulator's truth
// about the embedding.
void describe_scenario(const ScenarioSpec& spec, const std::string& command_line, Scenario& out) {
  TelemetryLog& log = out.log;
  log.comments = {
      "sinkwatch telemetry scenario '" + spec.name + "': " + spec.description,
      "made by the reference wheel-soil simulator (Wong-Reece, soil " + spec.soil +
          ", slip-sinkage on; wheel loads from the fuller force balance) with the flight code in the loop; "
          "docs/scenarios.md",
      "x_m, true_slip, true_sinkage_mm and phase are simulator truth: the flight code never sees them",
  };
  log.metadata["scenario"] = spec.name;
  log.metadata["command"] = command_line;
  log.metadata["seed"] = std::to_string(spec.seed);
  log.metadata["gravity_mps2"] = number(spec.gravity_mps2, 2);
  log.metadata["cycle_s"] = number(spec.cycle_s, 3);
  log.metadata["commanded_speed_mps"] = number(spec.speed_mps, 3);
  log.metadata["rover"] = "yutu-like " + number(spec.mass_kg, 0) + " kg, r = 0.15 m (docs/rover-loads.md)";
  log.metadata["mass_kg"] = mass_text(spec);
  std::string knots;
  for (const TerrainKnot& t : spec.terrain) {
    knots += (knots.empty() ? "" : " ") + number(t.x_m, 1) + "/" + number(t.soil_scale, 3) + "/" + number(t.slope_deg, 1);
  }
  log.metadata["terrain_x_scale_slope"] = knots;
  log.metadata["escape_soil_gain"] = number(spec.escape_soil_gain, 2);
  if (out.truth.embedded) {
    log.metadata["embedding_x_m"] = number(out.truth.embed_x_m, 3);
    log.metadata["embedding_time_s"] = number(out.truth.embed_time_s, 1);
    log.metadata["embedding_reason"] = out.truth.embed_reason;
  } else {
    log.metadata["embedding_x_m"] = "none";
  }
}

}  // namespace

Scenario generate_scenario(const ScenarioSpec& spec, const std::string& command_line,
                           const std::function<void(double)>& progress) {
  Scenario out;
  out.log.source = spec.name;
  ScenarioRun run(spec, out);
  run.run(progress);
  run.find_open_loop_embedding();
  describe_scenario(spec, command_line, out);
  return out;
}

Scenario generate_open_loop_drive(const ScenarioSpec& spec) {
  Scenario out;
  out.log.source = spec.name;
  ScenarioRun run(spec, out, true);
  run.run({});
  const double weight_n = spec.mass_kg * spec.gravity_mps2;
  for (std::size_t i = 0; i < out.cycle_loads.size() && i < out.log.rows.size(); ++i) {
    const std::optional<double>& r = out.cycle_loads[i].reserve_n;
    if (out.truth.embedded && out.log.rows[i].time_s >= out.truth.embed_time_s) break;
    if (r) out.truth.min_reserve_frac = std::min(out.truth.min_reserve_frac.value_or(*r / weight_n), *r / weight_n);
  }
  return out;
}

SimParameters scenario_soil(const ScenarioSpec& spec, double soil_scale) {
  SimParameters p = default_parameters(spec.soil_parameters ? std::string("hit-lss1") : spec.soil);
  if (spec.soil_parameters) p.soil = *spec.soil_parameters;
  p.gravity_m_s2 = spec.gravity_mps2;
  p.quadrature_rel_tol = spec.quadrature_rel_tol;
  if (spec.effects) {
    p.effects = *spec.effects;
  } else {
    // Sinkage grows with slip (Ding et al.): the slip-sinkage the paper's
    // soil-bin tests show and Purgatory's dig-in needs.
    p.effects.slip_sinkage.enabled = true;
  }
  return scaled_soil(p, soil_scale);
}

}  // namespace sinkwatch::ground
