// Benchmark (prints numbers; not a test): host cost of one wheel_loads call,
// one drawbar_pulls call and one full RoverStep::step cycle, and the sizes of
// the step's state and output (the firmware stack figure comes from
// scripts/stack_report.py on the ARM builds).
#include <chrono>
#include <cstdint>
#include <cstdio>

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/wheel_load.hpp"

namespace sf = sinkwatch::flight;
namespace fx = sinkwatch::fx;

constexpr sf::Ratio kDpMaxRatio{fx::constant<sf::RatioQ>(0.5)};
constexpr sf::CurrentA kCurrent{fx::constant<sf::CurrentQ>(0.35)};

int main() {
  const sf::RoverParams rover = sf::yutu_like_rover_params(sf::kGravityMoon);
  const sf::ParameterTable table = sf::default_parameter_table();
  sf::PreparedParameters prepared{};  // once per load
  static_cast<void>(sf::prepare(table, rover, prepared));
  constexpr int kCalls = 20000;
  std::int64_t checksum = 0;

  auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) {
    const sf::RoverAttitude att{sf::AngleRad::from_raw((i % 1000) * 100000), sf::AngleRad::from_raw((i % 700) * -90000)};
    sf::JointAnglesRad j{};
    j.rocker_rad[0] = sf::AngleRad::from_raw((i % 300) * 100000);
    checksum += sf::wheel_loads(prepared, att, j, sf::kNoDriveTorques).load_n[0].raw();
  }
  auto t1 = std::chrono::steady_clock::now();
  std::printf("wheel_loads:    %.2f us per call\n",
              std::chrono::duration<double, std::micro>(t1 - t0).count() / kCalls);

  const sf::WheelLoadResult loads = sf::wheel_loads(prepared, sf::RoverAttitude{}, sf::JointAnglesRad{}, sf::kNoDriveTorques);
  sf::DrawbarInput in{};
  for (sf::Ratio& r : in.dp_max_ratio) r = kDpMaxRatio;
  t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) {
    in.accel_mps2 = sf::AccelMps2::from_raw(i * 10);
    checksum += sf::drawbar_pulls(prepared, loads, in).dp_n[2].raw();
  }
  t1 = std::chrono::steady_clock::now();
  std::printf("drawbar_pulls:  %.2f us per call\n",
              std::chrono::duration<double, std::micro>(t1 - t0).count() / kCalls);

  sf::RoverStep step;
  sf::RoverTelemetry t{};
  t.valid = true;
  t.accel_valid = true;
  for (std::uint32_t w = 0U; w < sf::kWheelCount; ++w) {
    t.current_a[w] = kCurrent;
    t.direction[w] = sf::DriveDirection::forward;
  }
  sf::RoverStepOutput out{};  // one record every cycle overwrites
  t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) {
    t.time = sf::TimeMs{static_cast<std::uint32_t>(100 * (i + 1))};
    step.step(t, t.time, prepared, out);
    checksum += out.monitor.wheels[0].sinkage_m.raw();
  }
  t1 = std::chrono::steady_clock::now();
  std::printf("RoverStep::step: %.2f us per cycle (6 wheels, on parameters prepared once)\n",
              std::chrono::duration<double, std::micro>(t1 - t0).count() / kCalls);
  std::printf("sizeof(RoverStep) = %zu bytes, sizeof(RoverStepOutput) = %zu bytes\n", sizeof(sf::RoverStep),
              sizeof(sf::RoverStepOutput));
  std::printf("checksum %lld\n", static_cast<long long>(checksum));
  return 0;
}
