// libFuzzer harness (issue 18): the flight six-wheel step (RoverStep::step,
// fixed point) against its double-precision twin (ground/reference:
// wheel_loads, drawbar_pulls, corrections_at, torque_nm, sinkage_m,
// torque_limit_nm, current_a) within the documented error bounds.
//
// From the input: a random parameter table (motor, correction rows, monitor
// thresholds and persistence; each section either the default or drawn over
// the validator's envelope; the wheel radius is the rover's 0.15 m, since the
// statics and Eq. 15 must describe the same wheel), a Yutu-like rover on the
// Moon, Mars or Earth with its centre of mass within +-5 cm (the envelope of
// the wheel-load bound, docs/rover-loads.md 7.2), and one telemetry sample
// within the documented input ranges (attitude and joints to 1.05 times their
// limits, currents to 1.05 times the sensor range, acceleration and speeds to
// 1.05 times their accepted magnitudes, each scaled down by a drawn shift).
// A table prepare() refuses is not a finding: the input is skipped.
//
// The sample is stepped trip_n times (fresh time stamps, measured
// acceleration), so that each wheel's state is the one its evidence implies
// (STOP, else CAUTION, else NOMINAL) and the twin can predict it. Each stage
// is compared on the flight step's own inputs to it, as the documented bounds
// are defined (docs/assurance.md, "Differential harness"):
//   loads        twin on the same quantised attitude, joints and drive torques (each wheel's
//                torque from its current where the health stage passed the current),
//                2^-17 N + 2^-25 m g + 2^-24 sum|T| / 1 m                          (rover-loads.md 7.2, 12.5)
//   torques      the fallback mask is the unusable currents' while the twin's torque loads are
//                > +bound; all six fall back when they are < -bound (rover-loads.md 12.3, 12.4)
//   stability    flight tip_over only when the twin's smallest load is < +bound, ok only when > -bound
//   refusals     the twin's reason; where its lateral span is beyond Q6.25 (its largest term >= 16, no
//                lever collapsed) any of tip_over, degenerate, overflow, whatever the twin says (7.4)
//   slip         1 - v/v_rim clamped to [-1, 1]: 0.5 LSB of Q7.24 + 2 u              (one division, one rescale)
//   drawbar      twin on the flight's loads, slip and DP_max/W, 2^-17 N + 2^-28 (m g + |sum DP|)  (7.3)
//   corrections  0.5 LSB + (max |delta c| + 1) u                                        (flight.md)
//   torque       0.5 LSB_T + N (eta + 1) u                                              (flight.md)
//   sinkage      twin on the flight's W, T, DP and C(W): 0.5 LSB_z + (C1 + 2 + r) u / C2 (flight.md)
//   I_max        0.5 LSB_I + u (1/(eta Kt) + 1/Kt + 1) + e(T_max)/(N eta Kt),
//                e(T_max) = 0.5 LSB_T + (2 W u + u)/C1                                  (flight.md)
// (u = 2^-33, plus 16 ulp of the double twin's own terms). Decision flags
// (current and sinkage STOP/CAUTION evidence, saturation at high slip, a load
// outside the monitor's range, an estimate that overflowed) may differ only
// where the twin's value is within the bound of the threshold. A disagreement
// beyond the bound prints both values and aborts.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>

#include "estimator_bounds.hpp"
#include "rover_test_support.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "sinkwatch/ground/rover_loads.hpp"

namespace sf = sinkwatch::flight;
namespace sg = sinkwatch::ground;
namespace ref = sinkwatch::ground::reference;
namespace rt = sinkwatch::rover_test;
using rt::d;

namespace {

constexpr double kU = 0x1p-33;            // half an LSB of Q31.32
constexpr double kHalfLsbQ15 = 0x1p-17;   // loads, torques, pulls
constexpr double kHalfLsbQ24 = 0x1p-25;   // ratios, sinkage
constexpr double kHalfLsbQ20 = 0x1p-21;   // currents
constexpr double kUlps = 16.0 * 0x1p-52;  // the double twin's own rounding

[[noreturn]] void disagree(const char* what, int wheel, double flight, double twin, double bound) {
  std::fprintf(stderr, "fuzz_step_differential: %s, wheel %d: flight %.17g twin %.17g |difference| %.6g > bound %.6g\n",
               what, wheel, flight, twin, std::fabs(flight - twin), bound);
  std::abort();
}

/// With SINKWATCH_FUZZ_STATS set, the harness prints at exit how many inputs
/// reached each comparison and the largest |flight - twin| / bound of each
/// quantity (the figures of docs/assurance.md).
struct Stats {
  static constexpr int kQuantities = 16;
  const char* name[kQuantities]{};
  double worst[kQuantities]{};
  unsigned long long inputs{0U}, prepared{0U}, completed{0U}, wheels{0U}, by_state[3]{}, ambiguous{0U};
  unsigned long long unusable{0U};
  unsigned long long beyond_fine{0U};  ///< refusals named by a wider format (check_loads)
  unsigned long long beyond_fine_renamed{0U};  ///< of those, named otherwise than the twin

  void record(const char* what, double ratio) {
    for (int i = 0; i < kQuantities; ++i) {
      if (name[i] == nullptr || name[i] == what) {
        name[i] = what;
        worst[i] = std::max(worst[i], ratio);
        return;
      }
    }
  }
  void print() const {
    std::fprintf(stderr,
                 "step_differential stats: inputs %llu prepared %llu completed %llu wheels compared %llu "
                 "(nominal %llu caution %llu stop %llu; state ambiguous %llu) wheels unusable %llu; refusals beyond "
                 "Q6.25 %llu (named otherwise than the twin %llu)\n",
                 inputs, prepared, completed, wheels, by_state[0], by_state[1], by_state[2], ambiguous, unusable,
                 beyond_fine, beyond_fine_renamed);
    for (int i = 0; i < kQuantities && name[i] != nullptr; ++i) {
      std::fprintf(stderr, "step_differential worst |flight - twin| / bound: %-24s %.6f\n", name[i], worst[i]);
    }
  }
};
Stats& stats() {
  static Stats s;
  return s;
}
const bool kStatsWanted = std::getenv("SINKWATCH_FUZZ_STATS") != nullptr;

void expect_close(const char* what, int wheel, double flight, double twin, double bound) {
  const double difference = std::fabs(flight - twin);
  if (!(difference <= bound)) {
    disagree(what, wheel, flight, twin, bound);
  }
  if (kStatsWanted && bound > 0.0) {
    stats().record(what, difference / bound);
  }
}

[[noreturn]] void inconsistent(const char* what, int wheel, double twin, double threshold, double bound) {
  std::fprintf(stderr,
               "fuzz_step_differential: %s, wheel %d: twin %.17g threshold %.17g bound %.6g (flight decided the "
               "other way)\n",
               what, wheel, twin, threshold, bound);
  std::abort();
}

/// The input bytes, read as little-endian numbers; zeros past the end.
class Reader {
 public:
  Reader(const std::uint8_t* p, std::size_t n) : p_(p), n_(n) {}
  std::uint8_t u8() { return (pos_ < n_) ? p_[pos_++] : 0U; }
  std::uint32_t u32() {
    std::uint32_t v = 0U;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(u8()) << (8 * i);
    }
    return v;
  }
  /// A raw value in [lo, hi].
  std::int32_t in(std::int32_t lo, std::int32_t hi) {
    const auto span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi) - lo) + 1U;
    return static_cast<std::int32_t>(lo + static_cast<std::int64_t>(u32() % span));
  }
  /// A quantity in [lo, hi] (physical units), any LSB.
  template <typename Quantity>
  Quantity within(double lo, double hi) {
    return Quantity::from_raw(in(rt::q<Quantity>(lo).raw(), rt::q<Quantity>(hi).raw()));
  }
  /// A quantity in [-1.05 limit, 1.05 limit] scaled down by 0..15 bits, so
  /// that both small and extreme magnitudes occur.
  template <typename Quantity>
  Quantity around(Quantity limit) {
    const auto reach = static_cast<std::int32_t>(std::min<std::int64_t>(limit.raw() + (limit.raw() / 20), INT32_MAX));
    const std::int32_t v = in(-reach, reach);
    return Quantity::from_raw(v / (std::int32_t{1} << (u8() & 15U)));
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
  std::size_t pos_{0U};
};

void draw_motor(Reader& r, sf::MotorParams& m) {
  m.gear_ratio = r.within<sf::GearRatio>(1.0, 10000.0);
  m.efficiency = r.within<sf::Efficiency>(0.01, 1.0);
  m.kt_nm_per_a = r.within<sf::TorqueConstantNmPerA>(1e-4, 4.0);
  m.no_load_current_a = r.within<sf::CurrentA>(0.0, 100.0);
  m.current_abs_max_a = sf::CurrentA::from_raw(r.in(m.no_load_current_a.raw() + 1, rt::q<sf::CurrentA>(1000.0).raw()));
}

void draw_corrections(Reader& r, sf::CorrectionTable& c) {
  c.count = static_cast<std::uint8_t>(1U + (r.u8() % sf::kMaxCorrectionRows));
  // Breakpoints up to 30 kN / 2^k, so that rover-sized loads fall between them.
  const double top_n = 30000.0 / static_cast<double>(1U << (r.u8() % 10U));
  std::int32_t loads[sf::kMaxCorrectionRows];
  for (std::uint8_t i = 0U; i < c.count; ++i) {
    loads[i] = r.in(1, rt::q<sf::WheelLoadN>(top_n).raw());
  }
  std::sort(loads, loads + c.count);  // equal breakpoints: refused by validate()
  for (std::uint8_t i = 0U; i < c.count; ++i) {
    sf::CorrectionRow& row = c.rows[i];
    row.load_n = sf::WheelLoadN::from_raw(loads[i]);
    row.c1 = r.within<sf::Ratio>(0.25, 4.0);
    row.c2 = r.within<sf::Ratio>(0.25, 4.0);
    row.c3 = r.within<sf::Ratio>(-1.0, 1.0);
    row.dp_max_ratio = sf::Ratio::from_raw(r.in(1, sf::kMaxDpMaxRatio.raw()));
  }
}

void draw_monitor(Reader& r, std::int32_t radius_raw, sf::MonitorParams& m) {
  m.allowed_sinkage_m = sf::SinkageM::from_raw(r.in(1, radius_raw));
  m.stop_sinkage_m = sf::SinkageM::from_raw(r.in(2, radius_raw));
  m.caution_sinkage_m = sf::SinkageM::from_raw(r.in(1, m.stop_sinkage_m.raw() - 1));
  m.sinkage_hysteresis_m = sf::SinkageM::from_raw(r.in(0, m.caution_sinkage_m.raw() - 1));
  m.current_caution_fraction = sf::Ratio::from_raw(r.in(1, rt::q<sf::Ratio>(1.0).raw()));
  m.current_hysteresis_fraction = sf::Ratio::from_raw(r.in(0, m.current_caution_fraction.raw() - 1));
  m.load_min_n = r.within<sf::WheelLoadN>(1e-4, 200.0);
  m.load_max_n = sf::WheelLoadN::from_raw(r.in(m.load_min_n.raw() + 1, rt::q<sf::WheelLoadN>(30000.0).raw()));
  m.window_m = static_cast<std::uint8_t>(1U + (r.u8() % 16U));
  m.trip_n = static_cast<std::uint8_t>(1U + (r.u8() % m.window_m));
  m.clear_n = static_cast<std::uint8_t>(1U + (r.u8() % m.window_m));
  m.invalid_to_stop = static_cast<std::uint8_t>(1U + (r.u8() % 255U));
  m.wheel_count = static_cast<std::uint8_t>(1U + (r.u8() % sf::kWheelCount));
  m.rover_stop_k = static_cast<std::uint8_t>(1U + (r.u8() % m.wheel_count));
}

/// The table: each section the default or drawn (selector byte bits 0..2).
sf::ParameterTable draw_table(Reader& r, sf::LengthM radius) {
  sf::ParameterTable t = sf::default_parameter_table();
  // The twin has no sensor health stage, and the step repeats one sample
  // trip_n times (a stuck sensor by the health checks' rules): checks off
  // here. fuzz_rover_step and the props drive the health stage.
  t.health = sf::HealthParams{};
  t.wheel_radius_m = radius;
  const std::uint8_t drawn = r.u8();
  if ((drawn & 1U) != 0U) {
    draw_motor(r, t.motor);
  }
  if ((drawn & 2U) != 0U) {
    draw_corrections(r, t.correction);
  }
  if ((drawn & 4U) != 0U) {
    draw_monitor(r, radius.raw(), t.monitor);
  }
  return t;
}

sf::RoverParams draw_rover(Reader& r) {
  const sf::AccelMps2 gravities[4] = {sf::kGravityMoon, sf::kGravityMars, sf::kGravityEarth, sf::kGravityMoon};
  sf::RoverParams p = sf::yutu_like_rover_params(gravities[r.u8() & 3U]);
  const std::int32_t five_cm = rt::q<sf::LengthM>(0.05).raw();
  p.com_x_m = sf::LengthM::from_raw(p.com_x_m.raw() + r.in(-five_cm, five_cm));
  p.com_y_m = sf::LengthM::from_raw(p.com_y_m.raw() + r.in(-five_cm, five_cm));
  p.com_z_m = sf::LengthM::from_raw(p.com_z_m.raw() + r.in(-five_cm, five_cm));
  return p;
}

sf::RoverTelemetry draw_telemetry(Reader& r, const sf::RoverParams& p, const sf::MotorParams& m) {
  sf::RoverTelemetry t{};
  const std::uint8_t flags = r.u8();
  t.valid = true;
  t.accel_valid = true;  // measured: every repetition of the sample is the same cycle
  t.speed_valid = (flags & 1U) != 0U;
  t.rim_speed_valid = (flags & 2U) != 0U;
  for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
    t.current_a[i] = r.around(m.current_abs_max_a);
    t.direction[i] =
        ((flags >> (2U + (i % 6U))) & 1U) != 0U ? sf::DriveDirection::reverse : sf::DriveDirection::forward;
  }
  t.attitude.pitch_rad = r.around(p.attitude_limit_rad);
  t.attitude.roll_rad = r.around(p.attitude_limit_rad);
  for (std::uint32_t s = 0U; s < sf::kSideCount; ++s) {
    t.joints.rocker_rad[s] = r.around(p.rocker_limit_rad);
    t.joints.bogie_rad[s] = r.around(p.bogie_limit_rad);
  }
  t.accel_mps2 = r.around(sf::kMaxAbsAccel);
  t.speed_mps = r.around(sf::kMaxAbsSpeed);
  t.rim_speed_mps = r.around(sf::kMaxAbsSpeed);
  return t;
}

/// Whether the flight may have decided "x >= threshold" either way: a
/// predicate is {can be true, can be false}.
struct Tri {
  bool can_true;
  bool can_false;
};
Tri at_least(double x, double threshold, double bound) { return Tri{x >= threshold - bound, x < threshold + bound}; }
Tri any_of(Tri a, Tri b) { return Tri{a.can_true || b.can_true, a.can_false && b.can_false}; }

struct Context {
  const sf::ParameterTable& table;
  const sf::RoverParams& rover;
  const sf::RoverTelemetry& t;
  const sf::RoverStepOutput& out;
  const sg::WheelLoads& twin_loads;  ///< the twin on the same attitude, joints and torques
  double weight_n;
  std::uint8_t torque_mask;  ///< the wheels whose current gives the loads no torque
  double torque_abs_sum_nm;  ///< sum |T_i| of the usable torques: the bound's torque term
};

/// The load bound of docs/rover-loads.md 12.5 for this cycle's torques.
double load_bound(const Context& c) { return rt::load_bound_with_torques_n(c.weight_n, c.torque_abs_sum_nm); }

// -------------------------------------------------------------- rover level

/// Whether the flight and the twin took the same loads, both with or both
/// without the torques (they may differ only inside the band of the bound).
bool same_torque_choice(const Context& c) {
  const bool any_torque = c.torque_mask != sf::kEveryTorqueFallsBack;
  const bool flight_fell_back = any_torque && (c.out.torque_fallback_mask == sf::kEveryTorqueFallsBack);
  const bool twin_fell_back = any_torque && (c.twin_loads.torque_min_load_n < 0.0);
  return flight_fell_back == twin_fell_back;
}

/// The torques' decision (docs/rover-loads.md 12.3, 12.4): outside the band
/// of the bound, the flight falls back for exactly the unusable currents, or
/// for all six wheels when the torque loads would lift one.
void check_torque_decision(const Context& c, double bound) {
  const double torque_min = c.twin_loads.torque_min_load_n;
  if ((torque_min > bound) && (c.out.torque_fallback_mask != c.torque_mask)) {
    disagree("torque fallback mask with the twin's torque loads positive", -1,
             static_cast<double>(c.out.torque_fallback_mask), static_cast<double>(c.torque_mask), 0.0);
  }
  const bool any_torque = c.torque_mask != sf::kEveryTorqueFallsBack;
  if (any_torque && (torque_min < -bound) && (c.out.torque_fallback_mask != sf::kEveryTorqueFallsBack)) {
    inconsistent("torques kept with the twin's torque loads lifting a wheel", -1, torque_min, 0.0, bound);
  }
}

/// A term of the twin's lateral span (WheelLoads::largest_term) at least this
/// large may, in a sum of up to four such terms, leave Q6.25 (range 64): the
/// flight then reads the span in a wider format (docs/rover-loads.md 7.4).
/// Below it every term and every partial sum up to the span stays in range
/// in the flight's Q6.25 pass, which rounds the span to about 2^-20 m; and
/// after the span a twin that says ok has every term within a few units
/// (shares and side totals in [0, 1]), so a flight overflow against it needs a term
/// beyond this bound before the span.
constexpr double kBeyondFineTerm = 16.0;

/// Whether the flight refused the balance (a lifting wheel, a collapsed
/// lever, a term beyond its formats).
bool refused_balance(sf::WheelLoadStatus s) {
  return s == sf::WheelLoadStatus::tip_over || s == sf::WheelLoadStatus::degenerate ||
         s == sf::WheelLoadStatus::overflow;
}

/// Whether the flight's refusal is the twin's (an overflow the twin's
/// degenerate, as section 7.4 of docs/rover-loads.md accepts within Q6.25).
bool same_refusal(sf::WheelLoadStatus s, sg::LoadStatus twin) {
  return (s == sf::WheelLoadStatus::tip_over) ? (twin == sg::LoadStatus::tip_over)
                                              : (twin == sg::LoadStatus::degenerate);
}

/// Where the twin's lateral span is beyond Q6.25 (its largest term, over
/// every evaluation, at least kBeyondFineTerm), and no lever a + b or bogie
/// span collapsed (which the flight decides in Q6.25 whatever overflows), the
/// flight may refuse the balance under any of its three names, whatever the
/// twin says: its span is rounded there by about (1 + |beta|) times a wider
/// format's LSB over a bogie span of a few millimetres, centimetres in the
/// folded poses that reach it, against a 1 mm guard; and an `ok` of a wider
/// pass stays `overflow` (docs/rover-loads.md 7.4, docs/assurance.md).
bool refusal_name_unresolved(const Context& c) {
  const sg::WheelLoads& twin = c.twin_loads;
  const bool lever_collapsed = twin.shortest_lever_m < 1e-3;
  return !lever_collapsed && (twin.largest_term >= kBeyondFineTerm) && refused_balance(c.out.load_status);
}

/// Loads and stability (docs/rover-loads.md 7.2, 12).
void check_loads(const Context& c) {
  const sg::WheelLoads& twin = c.twin_loads;
  const double bound = load_bound(c);
  const sf::WheelLoadStatus s = c.out.load_status;
  if (refusal_name_unresolved(c)) {
    ++stats().beyond_fine;
    stats().beyond_fine_renamed += same_refusal(s, twin.status) ? 0U : 1U;
    return;
  }
  // An overflow of every format of the statics (docs/rover-loads.md 7.4) is
  // refused like a degenerate lever, and comes only with a collapsed span.
  if (s == sf::WheelLoadStatus::attitude_out_of_range || s == sf::WheelLoadStatus::joint_out_of_range ||
      s == sf::WheelLoadStatus::degenerate || s == sf::WheelLoadStatus::overflow) {
    const sg::LoadStatus expected =
        (s == sf::WheelLoadStatus::attitude_out_of_range) ? sg::LoadStatus::attitude_out_of_range
        : (s == sf::WheelLoadStatus::joint_out_of_range)  ? sg::LoadStatus::joint_out_of_range
                                                          : sg::LoadStatus::degenerate;  // or overflow
    if (twin.status != expected) {
      disagree("load status (flight refused, twin did not)", -1, static_cast<double>(s),
               static_cast<double>(twin.status), 0.0);
    }
    return;
  }
  if (s == sf::WheelLoadStatus::invalid_params) {
    disagree("load status invalid_params inside the envelope", -1, static_cast<double>(s), 0.0, 0.0);
  }
  if (twin.status != sg::LoadStatus::ok && twin.status != sg::LoadStatus::tip_over) {
    disagree("load status (twin refused, flight did not)", -1, static_cast<double>(s), static_cast<double>(twin.status),
             0.0);
  }
  check_torque_decision(c, bound);
  if (!same_torque_choice(c)) {
    return;  // one side kept the torques inside the band: different loads, both allowed
  }
  if (s == sf::WheelLoadStatus::tip_over && twin.min_load_n >= bound) {
    inconsistent("tip_over with the twin stable", -1, twin.min_load_n, 0.0, bound);
  }
  if (s == sf::WheelLoadStatus::ok) {
    if (twin.min_load_n <= -bound) {
      inconsistent("loads ok with the twin beyond the stability limit", -1, twin.min_load_n, 0.0, bound);
    }
    for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
      expect_close("wheel load [N]", static_cast<int>(i), d(c.out.load_n[i]), twin.load_n[i], bound);
    }
  }
}

/// Slip (one division and one rescale) and the high-slip saturation.
void check_slip(const Context& c) {
  if (!c.out.slip_known) {
    return;
  }
  const double twin = std::clamp(1.0 - (d(c.t.speed_mps) / d(c.t.rim_speed_mps)), -1.0, 1.0);
  const double bound = kHalfLsbQ24 + (2.0 * kU) + kUlps;
  expect_close("slip", -1, d(c.out.slip), twin, bound);
  if (!c.out.drawbar_valid) {
    return;
  }
  const Tri saturated = at_least(twin, d(c.rover.high_slip), bound);
  const bool flight_saturated = c.out.drawbar_status == sf::DrawbarStatus::saturated;
  if ((flight_saturated && !saturated.can_true) || (!flight_saturated && !saturated.can_false)) {
    inconsistent("high-slip saturation", -1, twin, d(c.rover.high_slip), bound);
  }
}

/// Drawbar pulls, on the flight's loads, slip and DP_max/W (7.3).
void check_drawbar(const Context& c, const sf::CorrectionResult (&corr)[sf::kWheelCount]) {
  sg::WheelLoads loads;
  loads.status = sg::LoadStatus::ok;
  sg::DrawbarParams params;
  params.high_slip = d(c.rover.high_slip);
  for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
    loads.load_n[i] = d(c.out.load_n[i]);
    params.dp_max_over_w[i] = d(corr[i].dp_max_ratio);
  }
  const sg::DrawbarInput in{d(c.out.accel_mps2), d(c.t.attitude.pitch_rad), c.out.slip_known, d(c.out.slip)};
  const sg::DrawbarPulls twin = sg::drawbar_pulls(rt::to_ground(c.rover), loads, in, params);
  if (twin.status == sg::DrawbarStatus::invalid_input) {
    disagree("drawbar status (twin refused, flight did not)", -1, static_cast<double>(c.out.drawbar_status), 0.0, 0.0);
  }
  if ((twin.status == sg::DrawbarStatus::saturated) != (c.out.drawbar_status == sf::DrawbarStatus::saturated)) {
    disagree("saturation on the same slip", -1, static_cast<double>(c.out.drawbar_status),
             static_cast<double>(twin.status), 0.0);
  }
  const double bound = rt::drawbar_bound_n(c.weight_n, twin.total_n);
  for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
    expect_close("drawbar pull [N]", static_cast<int>(i), d(c.out.drawbar_pull_n[i]), twin.dp_n[i], bound);
  }
}

// -------------------------------------------------------------- per wheel

/// The largest |c_{i+1} - c_i| of any coefficient column, for the
/// interpolation bound.
double max_step(const sf::CorrectionTable& t) {
  double step = 0.0;
  for (std::uint8_t i = 1U; i < t.count; ++i) {
    const sf::CorrectionRow& a = t.rows[i - 1U];
    const sf::CorrectionRow& b = t.rows[i];
    step = std::max({step, std::fabs(d(b.c1) - d(a.c1)), std::fabs(d(b.c2) - d(a.c2)), std::fabs(d(b.c3) - d(a.c3)),
                     std::fabs(d(b.dp_max_ratio) - d(a.dp_max_ratio))});
  }
  return step;
}

void check_corrections(const sf::CorrectionTable& table, const sf::CorrectionResult& f, double load_n, int wheel) {
  const ref::Corrections twin = ref::corrections_at(ref::from_flight(table), load_n);
  const double bound = kHalfLsbQ24 + ((max_step(table) + 1.0) * kU) + kUlps * 4.0;
  expect_close("C1", wheel, d(f.coefficients.c1), twin.coefficients.c1, bound);
  expect_close("C2", wheel, d(f.coefficients.c2), twin.coefficients.c2, bound);
  expect_close("C3", wheel, d(f.coefficients.c3), twin.coefficients.c3, bound);
  expect_close("DP_max/W", wheel, d(f.dp_max_ratio), twin.dp_max_ratio, bound);
}

/// One wheel's twin numbers on the flight's inputs to each stage, and the
/// bounds of the flight's numbers against them.
struct WheelTwin {
  double torque_nm, torque_bound;
  double sinkage_m, sinkage_bound;
  double limit_a, limit_bound;
  double torque_limit_nm;
  double a_ratio;  ///< C1 T / W, the largest intermediate of Eq. 11
};

WheelTwin wheel_twin(const Context& c, const sf::CorrectionResult& corr, std::uint32_t i) {
  const ref::Motor motor = ref::from_flight(c.table.motor);
  const ref::Coefficients k = ref::from_flight(corr.coefficients);
  const double r = d(c.table.wheel_radius_m);
  const double w = d(c.out.load_n[i]);
  const double dp = d(c.out.drawbar_pull_n[i]);
  const double current = d(c.t.current_a[i]);
  WheelTwin tw{};
  tw.torque_nm = ref::torque_nm(motor, current, c.t.direction[i]);
  tw.torque_bound =
      kHalfLsbQ15 + (motor.gear_ratio * (motor.efficiency + 1.0) * kU) + (kUlps * std::fabs(tw.torque_nm));
  // Eq. 11 on the flight's torque when it has one, else on the twin's.
  const double torque = c.out.monitor.wheels[i].estimate_valid ? d(c.out.monitor.wheels[i].torque_nm) : tw.torque_nm;
  tw.sinkage_m = ref::sinkage_m(k, r, w, torque, dp);
  tw.a_ratio = k.c1 * torque / w;
  // docs/flight.md, "Sinkage" (host_tests/flight/estimator_bounds.hpp):
  // one normalised division of Q23.40 operands.
  tw.sinkage_bound = sinkwatch::test::sinkage_error_bound_m(k.c2, w, tw.sinkage_m) +
                     (kUlps * (std::fabs(tw.a_ratio) + (r * (std::fabs(k.c3) + std::fabs(dp / w)))) / k.c2);
  const double z_max = d(c.table.monitor.allowed_sinkage_m);
  tw.torque_limit_nm = ref::torque_limit_nm(k, d(corr.dp_max_ratio), r, w, z_max);
  tw.limit_a = ref::current_a(motor, tw.torque_limit_nm, sf::DriveDirection::forward);
  const double gain = motor.gear_ratio * motor.efficiency * motor.kt_nm_per_a;
  // docs/flight.md, "Current limit": the lever's leading word and the
  // normalised division.
  const double torque_limit_bound = sinkwatch::test::torque_limit_error_bound_nm(tw.torque_limit_nm);
  tw.limit_bound = kHalfLsbQ20 +
                   (kU * ((1.0 / (motor.efficiency * motor.kt_nm_per_a)) + (1.0 / motor.kt_nm_per_a) + 1.0)) +
                   (torque_limit_bound / gain) + (kUlps * std::fabs(tw.limit_a));
  return tw;
}

/// Every twin number comfortably inside its format and intermediates: the
/// flight must then have an estimate.
bool comfortably_inside(const WheelTwin& tw) {
  return std::fabs(tw.torque_nm) < 0x1p14 && std::fabs(tw.sinkage_m) < 0x1p6 &&
         std::fabs(tw.torque_limit_nm) < 0x1p14 && std::fabs(tw.limit_a) < 0x1p10 && std::fabs(tw.a_ratio) < 0x1p29;
}

/// The states the flight may be in after trip_n repetitions of a usable sample.
struct AllowedStates {
  bool nominal, caution, stop;
};

AllowedStates evidence(const Context& c, const WheelTwin& tw, std::uint32_t i) {
  const sf::MonitorParams& m = c.table.monitor;
  const double directed =
      (c.t.direction[i] == sf::DriveDirection::reverse) ? -d(c.t.current_a[i]) : d(c.t.current_a[i]);
  const double f = d(m.current_caution_fraction);
  const Tri current_stop = at_least(directed, tw.limit_a, tw.limit_bound);
  const Tri current_caution = at_least(directed, f * tw.limit_a, (f * tw.limit_bound) + kHalfLsbQ20);
  const Tri sinkage_stop = at_least(tw.sinkage_m, d(m.stop_sinkage_m), tw.sinkage_bound);
  const Tri sinkage_caution = at_least(tw.sinkage_m, d(m.caution_sinkage_m), tw.sinkage_bound);
  Tri stop = any_of(current_stop, sinkage_stop);
  if (c.out.drawbar_status == sf::DrawbarStatus::saturated) {
    stop = Tri{true, false};  // DP assumed at DP_max: STOP evidence (flight.md, monitor step 3)
  }
  const Tri caution = any_of(stop, any_of(current_caution, sinkage_caution));
  return AllowedStates{stop.can_false && caution.can_false, stop.can_false && caution.can_true, stop.can_true};
}

/// The monitor's load range [load_min, load_max] against the twin's load:
/// inside by more than the bound, the flight must have accepted the load;
/// outside by more than the bound, it must have refused it.
void check_load_range(const Context& c, std::uint32_t i, bool flight_accepted) {
  const double bound = load_bound(c);
  if (!same_torque_choice(c)) {
    return;  // the twin's loads are the other choice's (inside the band)
  }
  const double lo = d(c.table.monitor.load_min_n);
  const double hi = d(c.table.monitor.load_max_n);
  const double twin = c.twin_loads.load_n[i];
  const bool surely_inside = twin > lo + bound && twin < hi - bound;
  const bool surely_outside = twin < lo - bound || twin > hi + bound;
  if ((flight_accepted && surely_outside) || (!flight_accepted && surely_inside)) {
    inconsistent(flight_accepted ? "load accepted outside [load_min, load_max]" : "load_out_of_range inside the range",
                 static_cast<int>(i), twin, twin < lo + bound ? lo : hi, bound);
  }
}

/// One wheel of a cycle the step completed; counts the wheels that must and
/// that may be in STOP (for the rover decision).
void check_wheel(const Context& c, const sf::CorrectionResult& corr, std::uint32_t i, int& min_stop, int& max_stop) {
  const sf::WheelOutput& w = c.out.monitor.wheels[i];
  const int wheel = static_cast<int>(i);
  const double load = d(c.out.load_n[i]);
  check_corrections(c.table.correction, corr, load, wheel);
  const bool flight_stop = w.state == sf::WheelState::stop;
  if (w.sample_status != sf::SampleStatus::ok) {
    ++stats().unusable;
    min_stop += flight_stop ? 1 : 0;
    max_stop += flight_stop ? 1 : 0;
    if (w.sample_status == sf::SampleStatus::load_out_of_range) {
      check_load_range(c, i, false);
    }
    if (w.sample_status == sf::SampleStatus::estimate_failed && comfortably_inside(wheel_twin(c, corr, i))) {
      inconsistent("estimate_failed with every twin number inside its format", wheel, 0.0, 0.0, 0.0);
    }
    return;
  }
  check_load_range(c, i, true);
  const WheelTwin tw = wheel_twin(c, corr, i);
  expect_close("torque [N m]", wheel, d(w.torque_nm), tw.torque_nm, tw.torque_bound);
  expect_close("sinkage [m]", wheel, d(w.sinkage_m), tw.sinkage_m, tw.sinkage_bound);
  expect_close("current limit [A]", wheel, d(w.current_limit_a), tw.limit_a, tw.limit_bound);
  const AllowedStates allowed = evidence(c, tw, i);
  const bool ok = (w.state == sf::WheelState::nominal && allowed.nominal) ||
                  (w.state == sf::WheelState::caution && allowed.caution) || (flight_stop && allowed.stop);
  if (!ok) {
    std::fprintf(stderr, "fuzz_step_differential: wheel %d state %u; twin allows nominal %d caution %d stop %d\n",
                 wheel, static_cast<unsigned>(w.state), allowed.nominal, allowed.caution, allowed.stop);
    disagree("wheel state (I_max twin vs sinkage twin)", wheel, tw.limit_a, tw.sinkage_m, 0.0);
  }
  Stats& st = stats();
  ++st.wheels;
  ++st.by_state[static_cast<unsigned>(w.state) % 3U];
  st.ambiguous += ((allowed.nominal ? 1 : 0) + (allowed.caution ? 1 : 0) + (allowed.stop ? 1 : 0) > 1) ? 1U : 0U;
  min_stop += (allowed.stop && !allowed.caution && !allowed.nominal) ? 1 : 0;
  max_stop += allowed.stop ? 1 : 0;
}

void check_completed(const Context& c) {
  sf::CorrectionResult corr[sf::kWheelCount];
  const sf::CorrectionDivisors divisors = sf::make_correction_divisors(c.table.correction);
  for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
    // The same C(W) the step used, on the divisors prepare() made.
    corr[i] = sf::corrections_at(c.table.correction, divisors, c.out.load_n[i]);
  }
  check_slip(c);
  check_drawbar(c, corr);
  int min_stop = 0;
  int max_stop = 0;
  for (std::uint32_t i = 0U; i < c.table.monitor.wheel_count; ++i) {
    check_wheel(c, corr[i], i, min_stop, max_stop);
  }
  const int k = c.table.monitor.rover_stop_k;
  const bool stop = c.out.decision == sf::RoverDecision::stop_and_replan;
  // The motion-resistance check stops the rover on its own (traction.hpp).
  const bool traction_stop = c.out.traction.state == sf::TractionState::stop;
  if ((stop && max_stop < k && !traction_stop) || (!stop && (min_stop >= k || traction_stop))) {
    disagree("rover decision (wheels that may / must be in STOP)", -1, stop ? 1.0 : 0.0,
             static_cast<double>(stop ? max_stop : min_stop), static_cast<double>(k));
  }
}

void check_motion_status(const Context& c) {
  const bool beyond = std::fabs(d(c.t.accel_mps2)) > d(sf::kMaxAbsAccel) ||
                      (c.t.speed_valid && std::fabs(d(c.t.speed_mps)) > d(sf::kMaxAbsSpeed)) ||
                      (c.t.rim_speed_valid && std::fabs(d(c.t.rim_speed_mps)) > d(sf::kMaxAbsSpeed));
  // The load stage's own refusal is reported first.
  const bool loads_refused =
      c.out.status == sf::RoverStepStatus::loads_failed || c.out.status == sf::RoverStepStatus::tip_over;
  const bool reported = c.out.status == sf::RoverStepStatus::motion_out_of_range;
  if ((reported && !beyond) || (beyond && !reported && !loads_refused)) {
    disagree("motion_out_of_range", -1, static_cast<double>(c.out.status), beyond ? 1.0 : 0.0, 0.0);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (kStatsWanted && stats().inputs == 0U) {
    std::atexit([] { stats().print(); });
  }
  ++stats().inputs;
  Reader r(data, size);
  const sf::RoverParams rover = draw_rover(r);
  const sf::ParameterTable table = draw_table(r, rover.wheel_radius_m);
  sf::PreparedParameters prepared;
  if (sf::prepare(table, rover, prepared) != sf::PrepareStatus::ok) {
    return 0;  // the loader refuses the table: not a finding
  }
  ++stats().prepared;
  const sf::RoverTelemetry sample = draw_telemetry(r, rover, table.motor);

  sf::RoverStep step;
  sf::RoverStepOutput out{};
  sf::RoverTelemetry t = sample;
  for (std::uint8_t k = 0U; k < table.monitor.trip_n; ++k) {
    t.time = sf::TimeMs{100U * (k + 1U)};
    step.step(t, t.time, prepared, out);
  }
  // The twin takes each wheel's torque where the step's health stage passed
  // the current and the motor model gives one (docs/rover-loads.md 12.3).
  sg::DriveTorques torques{};
  std::uint8_t torque_mask = 0U;
  double torque_abs_sum_nm = 0.0;
  for (std::uint32_t i = 0U; i < sf::kWheelCount; ++i) {
    const sf::TorqueResult torque = sf::torque_from_current(table.motor, t.current_a[i], t.direction[i]);
    torques.usable[i] = out.health.current_usable[i] && (torque.status == sf::EstimateStatus::ok);
    torques.torque_nm[i] = torques.usable[i] ? d(torque.torque_nm) : 0.0;
    torque_mask = static_cast<std::uint8_t>(torque_mask | (torques.usable[i] ? 0U : (1U << i)));
    torque_abs_sum_nm += std::fabs(torques.torque_nm[i]);
  }
  const sg::WheelLoads twin_loads =
      sg::wheel_loads(rt::to_ground(rover), rt::to_ground(t.attitude), rt::to_ground(t.joints), torques);
  const Context c{table, rover, t, out, twin_loads, d(rover.mass_kg) * d(rover.gravity_mps2), torque_mask,
                  torque_abs_sum_nm};
  check_motion_status(c);
  check_loads(c);  // the load stage runs before the motion check
  switch (out.status) {
    case sf::RoverStepStatus::ok:
      ++stats().completed;
      check_completed(c);
      break;
    case sf::RoverStepStatus::tip_over:
    case sf::RoverStepStatus::loads_failed:
    case sf::RoverStepStatus::motion_out_of_range:
      break;  // checked above
    case sf::RoverStepStatus::drawbar_failed:
      // C(W) refuses only a load <= 0 (the twin throws for it as well).
      if (*std::min_element(std::begin(out.load_n), std::end(out.load_n)) > sf::WheelLoadN::zero()) {
        disagree("drawbar_failed with every load positive", -1, static_cast<double>(out.status), 0.0, 0.0);
      }
      break;
    default:
      // Valid, fresh, measured-acceleration telemetry on a prepared table.
      disagree("unexpected step status", -1, static_cast<double>(out.status), 0.0, 0.0);
  }
  return 0;
}
