// Driver of the performance report (docs/performance.md): runs N control
// cycles of the six-wheel step, either the flight fixed-point code
// (RoverStep::step on parameters prepared once) or the double-precision
// reference twin of the same chain
// (ground/reference: wheel_loads -> corrections_at -> drawbar_pulls ->
// torque_nm -> sinkage_m -> current_limit_a, and the monitor's threshold
// comparisons), on 16 precomputed telemetry records. The report counts the
// instructions of N cycles and of 0 cycles and divides the difference by N.
//
// PERF_IMPL_DOUBLE selects the double twin. PERF_STEPS fixes N at compile
// time (the bare-metal ARM build has no command line); otherwise N is argv[1].
// The telemetry is built at compile time in both variants, so the measured
// difference is the cycles themselves plus a copy of the record per cycle.
#include <cstdint>
#include <cstdlib>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"

#ifdef PERF_IMPL_DOUBLE
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/ground/reference.hpp"
#include "sinkwatch/ground/rover_loads.hpp"
#endif

#ifdef PERF_BARE_METAL
extern "C" void sw_sys_write(const char* s, unsigned n);
#else
#include <cstdio>
#endif

namespace sf = sinkwatch::flight;
namespace fx = sinkwatch::fx;

namespace {

constexpr int kRecords = 16;

/// One cycle's measurements in SI units (radians, m/s, A).
struct Record {
  double pitch, roll, rocker_l, rocker_r, bogie_l, bogie_r, accel, speed, rim;
  double current[6];
};

constexpr Record record(int k) {
  Record r{};
  r.pitch = 0.03 + (0.004 * k);
  r.roll = -0.02 + (0.003 * k);
  r.rocker_l = 0.01 * (k % 4);
  r.rocker_r = -r.rocker_l;
  r.bogie_l = 0.02 - (0.005 * (k % 3));
  r.bogie_r = -r.bogie_l;
  r.accel = (0.002 * (k % 5)) - 0.004;
  r.speed = 0.05 + (0.0005 * k);
  r.rim = 0.055 + (0.0005 * k);
  for (int w = 0; w < 6; ++w) {
    r.current[w] = 0.3 + (0.02 * w) + (0.01 * (k % 7));
  }
  return r;
}

struct Records {
  Record r[kRecords];
};
constexpr Records make_records() {
  Records out{};
  for (int k = 0; k < kRecords; ++k) {
    out.r[k] = record(k);
  }
  return out;
}
constexpr Records kRecordsSi = make_records();

#ifndef PERF_IMPL_DOUBLE
struct Telemetry {
  sf::RoverTelemetry t[kRecords];
};
constexpr sf::RoverTelemetry fixed_telemetry(const Record& r) {
  sf::RoverTelemetry t{};
  t.valid = true;
  t.accel_valid = true;
  t.speed_valid = true;
  t.rim_speed_valid = true;
  t.attitude.pitch_rad = sf::AngleRad{fx::constant<sf::AngleQ>(r.pitch)};
  t.attitude.roll_rad = sf::AngleRad{fx::constant<sf::AngleQ>(r.roll)};
  t.joints.rocker_rad[0] = sf::AngleRad{fx::constant<sf::AngleQ>(r.rocker_l)};
  t.joints.rocker_rad[1] = sf::AngleRad{fx::constant<sf::AngleQ>(r.rocker_r)};
  t.joints.bogie_rad[0] = sf::AngleRad{fx::constant<sf::AngleQ>(r.bogie_l)};
  t.joints.bogie_rad[1] = sf::AngleRad{fx::constant<sf::AngleQ>(r.bogie_r)};
  t.accel_mps2 = sf::AccelMps2{fx::constant<sf::AccelQ>(r.accel)};
  t.speed_mps = sf::SpeedMps{fx::constant<sf::SpeedQ>(r.speed)};
  t.rim_speed_mps = sf::SpeedMps{fx::constant<sf::SpeedQ>(r.rim)};
  for (int w = 0; w < 6; ++w) {
    t.current_a[w] = sf::CurrentA{fx::constant<sf::CurrentQ>(r.current[w])};
    t.direction[w] = sf::DriveDirection::forward;
  }
  return t;
}
constexpr Telemetry make_telemetry() {
  Telemetry out{};
  for (int k = 0; k < kRecords; ++k) {
    out.t[k] = fixed_telemetry(kRecordsSi.r[k]);
  }
  return out;
}
constexpr Telemetry kTelemetry = make_telemetry();

/// Returns the number of cycles that ran the whole chain (status ok): the
/// report checks that it is every cycle, so that no early rejection is timed.
long run(long steps, std::int64_t& checksum) {
  // Set-up, once per parameter load: not per cycle.
  sf::PreparedParameters prepared;
  static_cast<void>(
      sf::prepare(sf::default_parameter_table(), sf::yutu_like_rover_params(sf::kGravityMoon), prepared));
  sf::RoverStep step;
  // One record that every cycle overwrites, as the C interface keeps it.
  sf::RoverStepOutput out{};
  long full = 0;
  for (long i = 0; i < steps; ++i) {
    sf::RoverTelemetry t = kTelemetry.t[i % kRecords];
    t.time = sf::TimeMs{static_cast<std::uint32_t>(100 * (i + 1))};
    step.step(t, t.time, prepared, out);
    checksum += out.monitor.wheels[i % 6].sinkage_m.raw();
    full += (out.status == sf::RoverStepStatus::ok) ? 1 : 0;
  }
  return full;
}
#else
namespace sg = sinkwatch::ground;
namespace ref = sinkwatch::ground::reference;

long run(long steps, std::int64_t& checksum) {
  const ref::Parameters p = ref::from_flight(sf::default_parameter_table());  // setup: not per cycle
  const sg::RoverGeometry g = sg::yutu_like_geometry(sg::k_gravity_moon_mps2);
  const sf::ParameterTable table = sf::default_parameter_table();
  const double high_slip = fx::to_double(sf::yutu_like_rover_params(sf::kGravityMoon).high_slip.q());
  const double caution_fraction = fx::to_double(table.monitor.current_caution_fraction.q());
  long full = 0;
  for (long i = 0; i < steps; ++i) {
    const Record& r = kRecordsSi.r[i % kRecords];
    // Each wheel's torque from its current, then the wheel loads with the
    // torques (as the flight step: docs/rover-loads.md 12), DP_max/W at each
    // load, drawbar pulls.
    sg::DriveTorques torques;
    for (std::size_t w = 0; w < sg::k_wheel_count; ++w) {
      torques.torque_nm[w] = ref::torque_nm(p.motor, r.current[w], sf::DriveDirection::forward);
      torques.usable[w] = true;
    }
    const sg::Attitude att{r.pitch, r.roll};
    sg::JointAngles joints;
    joints.rocker_rad = {r.rocker_l, r.rocker_r};
    joints.bogie_rad = {r.bogie_l, r.bogie_r};
    const sg::WheelLoads loads = sg::wheel_loads(g, att, joints, torques);
    sg::DrawbarParams dpp;
    dpp.high_slip = high_slip;
    for (std::size_t w = 0; w < sg::k_wheel_count; ++w) {
      dpp.dp_max_over_w[w] = ref::corrections_at(p.correction, loads.load_n[w]).dp_max_ratio;
    }
    sg::DrawbarInput in;
    in.accel_mps2 = r.accel;
    in.pitch_rad = r.pitch;
    in.slip_known = true;
    in.slip = 1.0 - (r.speed / r.rim);
    const sg::DrawbarPulls dp = sg::drawbar_pulls(g, loads, in, dpp);
    full += (loads.status == sg::LoadStatus::ok && dp.status != sg::DrawbarStatus::invalid_input) ? 1 : 0;
    // Per wheel: torque, Eq. 11, the current limit and the monitor's tests.
    for (std::size_t w = 0; w < sg::k_wheel_count; ++w) {
      const double torque = torques.torque_nm[w];
      const ref::Corrections c = ref::corrections_at(p.correction, loads.load_n[w]);
      const double z = ref::sinkage_m(c.coefficients, p.wheel_radius_m, loads.load_n[w], torque, dp.dp_n[w]);
      const double limit =
          ref::current_limit_a(p.correction, p.motor, p.wheel_radius_m, loads.load_n[w], p.allowed_sinkage_m);
      const bool stop = (r.current[w] >= limit) || (z >= p.stop_sinkage_m);
      const bool caution = stop || (r.current[w] >= caution_fraction * limit) || (z >= p.caution_sinkage_m);
      checksum += static_cast<std::int64_t>(z * 1e6) + (stop ? 2 : 0) + (caution ? 1 : 0);
    }
  }
  return full;
}
#endif

#ifdef PERF_BARE_METAL
/// Appends "<name>=" to buf.
unsigned append_name(char* buf, unsigned n, const char* name) {
  while (*name != '\0') {
    buf[n++] = *name++;
  }
  buf[n++] = '=';
  return n;
}

/// Appends "<name>=<v> " in decimal (v >= 0: the count of full cycles, one
/// digit for every N the report uses, so its cost is the same in every run).
unsigned append(char* buf, unsigned n, const char* name, long v) {
  n = append_name(buf, n, name);
  char digits[24];
  unsigned d = 0U;
  auto m = static_cast<unsigned long>(v);
  do {
    digits[d++] = static_cast<char>('0' + static_cast<int>(m % 10U));
    m /= 10U;
  } while (m != 0U);
  while (d > 0U) {
    buf[n++] = digits[--d];
  }
  buf[n++] = ' ';
  return n;
}

/// Appends "<name>=0x<16 hex digits> ": the same instructions whatever the
/// value. In decimal, the N-cycle run's seven-digit checksum cost six more
/// 64-bit divisions by ten than the 0-cycle run's "0", which the report
/// counted as part of the cycles (docs/performance.md, session 17).
unsigned append_hex(char* buf, unsigned n, const char* name, std::int64_t v) {
  n = append_name(buf, n, name);
  buf[n++] = '0';
  buf[n++] = 'x';
  auto m = static_cast<std::uint64_t>(v);
  for (int i = 0; i < 16; ++i) {
    const auto nibble = static_cast<int>(m >> 60U);
    buf[n++] = static_cast<char>((nibble < 10) ? ('0' + nibble) : ('a' + nibble - 10));
    m <<= 4U;
  }
  buf[n++] = ' ';
  return n;
}
#endif

void print(long full, std::int64_t v) {
#ifdef PERF_BARE_METAL
  char buf[96];
  unsigned n = append(buf, 0U, "full_chain_steps", full);
  n = append_hex(buf, n, "checksum", v);
  buf[n - 1U] = '\n';
  sw_sys_write(buf, n);
#else
  std::printf("full_chain_steps=%ld checksum=0x%016llx\n", full, static_cast<unsigned long long>(v));
#endif
}

}  // namespace

#ifdef PERF_STEPS
int main() {
  std::int64_t checksum = 0;
  const long full = run(PERF_STEPS, checksum);
  print(full, checksum);
  return 0;
}
#else
int main(int argc, char** argv) {
  const long steps = (argc > 1) ? std::strtol(argv[1], nullptr, 10) : 1000;
  std::int64_t checksum = 0;
  const long full = run(steps, checksum);
  print(full, checksum);
  return 0;
}
#endif
