// Writes the committed seed corpora of fuzz/corpus/ (run by hand after a
// format change: build/fuzz/fuzz/fuzz_make_seeds fuzz/corpus). Each seed is
// a valid, typical input of its harness, so the fuzzer starts from the deep
// paths instead of rediscovering the formats.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/rover_step.hpp"

namespace sf = sinkwatch::flight;
namespace fx = sinkwatch::fx;
using Bytes = std::vector<std::uint8_t>;

namespace {

void write(const std::string& path, const Bytes& b) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    std::perror(path.c_str());
    return;
  }
  std::fwrite(b.data(), 1, b.size(), f);
  std::fclose(f);
}

Bytes table_seed(std::uint8_t control, const sf::ParameterTable& t) {
  std::uint8_t buf[sf::kMaxTableBytes];
  const sf::EncodeResult e = sf::encode(t, buf, sizeof buf);
  Bytes b{control};
  b.insert(b.end(), buf, buf + e.size);
  return b;
}

void u32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void i32(Bytes& b, std::int32_t v) { u32(b, static_cast<std::uint32_t>(v)); }

template <typename Q>
std::int32_t raw(double v) {
  fx::Status st;
  return static_cast<std::int32_t>(fx::from_double<Q>(v, st).raw());
}

struct Cycle {
  std::uint8_t flags = 0x0FU;  // valid, accel, speed, rim speed; raw mode
  std::uint32_t dt_ms = 100U;
  std::uint32_t lag_ms = 0U;
  double current_a = 0.35;
  std::uint8_t direction = 0U;
  double pitch = 0.0, roll = 0.0, rocker = 0.0, bogie = 0.0;
  double accel = 0.0, speed = 0.05, rim = 0.055;
};

void append(Bytes& b, const Cycle& c) {
  b.push_back(c.flags);
  u32(b, c.dt_ms);
  u32(b, c.lag_ms);
  for (int w = 0; w < 6; ++w) i32(b, raw<sf::CurrentQ>(c.current_a));
  for (int w = 0; w < 6; ++w) b.push_back(c.direction);
  i32(b, raw<sf::AngleQ>(c.pitch));
  i32(b, raw<sf::AngleQ>(c.roll));
  for (int s = 0; s < 2; ++s) i32(b, raw<sf::AngleQ>(c.rocker));
  for (int s = 0; s < 2; ++s) i32(b, raw<sf::AngleQ>(c.bogie));
  i32(b, raw<sf::AccelQ>(c.accel));
  i32(b, raw<sf::SpeedQ>(c.speed));
  i32(b, raw<sf::SpeedQ>(c.rim));
}

/// One sample of fuzz_step_differential: the bytes its Reader turns into
/// these values (Reader::in(lo, hi) = lo + u32 % span; Reader::around(limit)
/// spans +-1.05 limit, then a shift byte, 0 here).
struct DifferentialSample {
  std::uint8_t gravity = 0U;    // Moon
  std::uint8_t sections = 0U;   // the default table's motor, corrections, monitor
  std::uint8_t flags = 0x03U;   // speed and rim speed valid, every wheel forward
  double current_a = 0.35;
  double pitch = 0.05, roll = 0.0, rocker = 0.02, bogie = 0.0;
  double accel = 0.0, speed = 0.05, rim = 0.055;
};

template <typename Q>
void around(Bytes& b, double value, std::int32_t limit_raw) {
  const std::int64_t reach = limit_raw + (limit_raw / 20);
  u32(b, static_cast<std::uint32_t>(raw<Q>(value) + reach));
  b.push_back(0U);
}

Bytes differential_seed(const DifferentialSample& s) {
  const sf::RoverParams p = sf::yutu_like_rover_params(sf::kGravityMoon);
  Bytes b{s.gravity};
  const std::int32_t five_cm = raw<sf::LengthQ>(0.05);
  for (int i = 0; i < 3; ++i) i32(b, five_cm);  // centre of mass offsets 0
  b.push_back(s.sections);
  b.push_back(s.flags);
  const std::int32_t range = sf::default_parameter_table().motor.current_abs_max_a.raw();
  for (int w = 0; w < 6; ++w) around<sf::CurrentQ>(b, s.current_a, range);
  around<sf::AngleQ>(b, s.pitch, p.attitude_limit_rad.raw());
  around<sf::AngleQ>(b, s.roll, p.attitude_limit_rad.raw());
  for (int side = 0; side < 2; ++side) {
    around<sf::AngleQ>(b, s.rocker, p.rocker_limit_rad.raw());
    around<sf::AngleQ>(b, s.bogie, p.bogie_limit_rad.raw());
  }
  around<sf::AccelQ>(b, s.accel, sf::kMaxAbsAccel.raw());
  around<sf::SpeedQ>(b, s.speed, sf::kMaxAbsSpeed.raw());
  around<sf::SpeedQ>(b, s.rim, sf::kMaxAbsSpeed.raw());
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "fuzz/corpus";
  // Parameter tables: the default and Eq. 15 tables, with and without the
  // rover section, checked with the validator; one with a stale CRC that the
  // control byte repairs.
  sf::ParameterTable with_rover = sf::default_parameter_table();
  with_rover.rover_geometry.present = true;
  with_rover.rover_geometry.params = sf::yutu_like_rover_params(sf::kGravityMoon);
  write(dir + "/param_table/default", table_seed(0U, sf::default_parameter_table()));
  write(dir + "/param_table/eq15", table_seed(0U, sf::eq15_parameter_table()));
  write(dir + "/param_table/rover_section", table_seed(4U, with_rover));
  Bytes stale = table_seed(7U, with_rover);
  stale[40] ^= 0x01U;  // a changed value; control bits 0..1 refresh length and CRC
  write(dir + "/param_table/patched_crc", stale);

  // Rover step: a nominal drive, a rising current into STOP, a reverse drive
  // on a slope, and a sequence of bad samples (invalid, stale, repeated,
  // future) ending in a clear_stop().
  Bytes nominal{0U};
  for (int i = 0; i < 20; ++i) {
    Cycle c;
    c.pitch = 0.05;
    c.rocker = 0.02 * (i % 3);
    append(nominal, c);
  }
  write(dir + "/rover_step/nominal", nominal);
  Bytes rising{0U};
  for (int i = 0; i < 30; ++i) {
    Cycle c;
    c.current_a = 0.3 + 0.25 * i;
    c.speed = 0.05 - 0.0015 * i;
    append(rising, c);
  }
  write(dir + "/rover_step/rising_current", rising);
  Bytes reverse{2U};
  for (int i = 0; i < 20; ++i) {
    Cycle c;
    c.direction = 1U;
    c.current_a = -0.4;
    c.pitch = -0.15;
    c.roll = 0.05;
    c.bogie = -0.1;
    c.speed = -0.04;
    c.rim = -0.05;
    c.flags = (i % 2 == 0) ? 0x0DU : 0x0FU;  // every other cycle: acceleration from speeds
    append(reverse, c);
  }
  write(dir + "/rover_step/reverse_slope", reverse);
  Bytes bad{1U};
  const std::uint8_t flags[] = {0x0FU, 0x0EU, 0x0FU, 0x0FU, 0x0FU, 0x0FU, 0x1FU, 0x2FU};
  const std::uint32_t dts[] = {100U, 100U, 0U, 100U, 100U, 100U, 100U, 100U};
  const std::uint32_t lags[] = {0U, 0U, 0U, 900U, 0xFFFFFF00U, 0U, 0U, 0U};
  for (int i = 0; i < 8; ++i) {
    Cycle c;
    c.flags = flags[i];
    c.dt_ms = dts[i];
    c.lag_ms = lags[i];
    if (i == 5) c.pitch = 0.9;  // beyond the stability limit
    append(bad, c);
  }
  write(dir + "/rover_step/bad_samples", bad);
  // Step against its twin: a nominal drive, currents into STOP on Earth, a
  // slipping rover (high slip: DP assumed at DP_max), and drawn sections.
  write(dir + "/step_differential/nominal", differential_seed(DifferentialSample{}));
  DifferentialSample stop;
  stop.gravity = 2U;
  stop.current_a = 4.5;
  write(dir + "/step_differential/current_stop", differential_seed(stop));
  DifferentialSample slipping;
  slipping.speed = 0.01;
  slipping.accel = 0.05;
  write(dir + "/step_differential/high_slip", differential_seed(slipping));
  DifferentialSample drawn;
  drawn.sections = 7U;  // the bytes after the selector draw the table, the rest the sample
  write(dir + "/step_differential/drawn_sections", differential_seed(drawn));
  std::printf("seeds written under %s\n", dir.c_str());
  return 0;
}
