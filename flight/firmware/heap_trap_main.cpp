// heap_trap_main.cpp: a firmware image that calls every public flight and
// fixed-point function, for two proofs (docs/firmware.md):
//  1. No allocation: the image links with malloc/free/new/delete wrapped and
//     no wrapper defined (CMakeLists.txt), so any allocation fails the link.
//  2. Stack and size: -fcallgraph-info=su gives the worst-case stack of each
//     entry point (stack_entries.txt); arm-none-eabi-size gives text/data/bss.
// Inputs come from volatile memory so that nothing is folded at compile time.
// MISRA C++:2023 deviation D-02 (docs/misra.md): volatile globals, here only.
#include <cstddef>
#include <cstdint>

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/sqrt.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/drawbar_pull.hpp"
#include "sinkwatch/flight/escape.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/monitor.hpp"
#include "sinkwatch/flight/prepared_params.hpp"
#include "sinkwatch/flight/rover_step.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"
#include "sinkwatch/flight/wheel_load.hpp"
#include "sinkwatch/sinkwatch.h"

namespace fx = sinkwatch::fx;
namespace fl = sinkwatch::flight;

namespace {

volatile std::int32_t g_raw_in[8] = {0x00018000, -0x00024000, 0x7FFFFFFF, 1, 0x00100000, 0x02000000, 0, 100};
volatile std::int64_t g_sink;
volatile std::uint32_t g_sink_u;

void keep(std::int64_t value) { g_sink = g_sink + value; }
void keep_u(std::uint32_t value) { g_sink_u = g_sink_u + value; }

void exercise_fixedpoint() {
  fx::Status st;
  const fx::Q15_16 a = fx::Q15_16::from_raw(g_raw_in[0]);
  const fx::Q15_16 b = fx::Q15_16::from_raw(g_raw_in[1]);
  keep(fx::add(a, b, st).raw());
  keep(fx::sub(a, b, st).raw());
  keep(fx::mul(a, b, st).raw());
  keep(fx::div(a, b, st).raw());
  keep(fx::sqrt(a, st).raw());
  keep(fx::reciprocal<fx::Q15_16>(a, st).raw());
  keep(fx::rescale<fx::Q31_32>(a, st).raw());
  keep(fx::div<fx::Q31_32>(fx::Q31_32::from_raw(g_raw_in[2]), fx::Q31_32::from_raw(g_raw_in[3]), st).raw());
  keep(fx::neg(fx::abs(b, st), st).raw());
  keep(fx::clamp(a, b, a, st).raw());
  keep(fx::sin(a, st).raw());
  keep(fx::cos(a, st).raw());
  keep(fx::asin(fx::Q1_30::from_raw(g_raw_in[4]), st).raw());
  keep(fx::acos(fx::Q1_30::from_raw(g_raw_in[4]), st).raw());
  keep(fx::entry_angle(fl::RatioQ::from_raw(g_raw_in[5]), st).raw());
  keep_u(st.bits());
}

void exercise_estimator(const fl::ParameterTable& table) {
  const fl::WheelLoadN load = fl::WheelLoadN::from_raw(g_raw_in[5]);
  // The divisors are prepared once per table load (prepared_params.hpp).
  const fl::CorrectionDivisors cd = fl::make_correction_divisors(table.correction);
  const fl::MotorDivisors md = fl::make_motor_divisors(table.motor);
  const fl::CorrectionResult c = fl::corrections_at(table.correction, cd, load);
  keep(c.coefficients.c3.raw());
  const fl::TorqueResult t = fl::torque_from_current(table.motor, fl::CurrentA::from_raw(g_raw_in[4]),
                                                     fl::DriveDirection::forward);
  keep(t.torque_nm.raw());
  keep(fl::current_from_torque(table.motor, md, t.torque_nm, fl::DriveDirection::reverse).current_a.raw());
  keep(static_cast<std::int64_t>(fl::check_motor(table.motor)));
  const fl::SinkageResult z = fl::sinkage_from_pull(c.coefficients, table.wheel_radius_m, load, t.torque_nm,
                                                    fl::DrawbarPullN::from_raw(g_raw_in[0]));
  keep(z.sinkage_m.raw());
  keep(fl::pull_from_sinkage(c.coefficients, table.wheel_radius_m, load, t.torque_nm, z.sinkage_m).drawbar_pull_n.raw());
  keep(static_cast<std::int64_t>(fl::check_estimator_inputs(c.coefficients, table.wheel_radius_m, load)));
  keep(fl::torque_limit(c.coefficients, c.dp_max_ratio, table.wheel_radius_m, load,
                        table.monitor.allowed_sinkage_m).torque_nm.raw());
  keep(fl::current_limit(c, table.motor, md, table.wheel_radius_m, load, table.monitor.allowed_sinkage_m)
           .current_limit_a.raw());
}

// The C++ step and monitor entry points the C interface does not reach (it
// steps on prepared parameters only). Namespace-scope objects: a function's
// static would need a guard variable.
fl::RoverStep g_step;
fl::RoverStepOutput g_step_out;
fl::RoverMonitor g_monitor;
fl::WheelMonitor g_wheel(1U);

void exercise_step(const fl::PreparedParameters& prepared) {
  fl::RoverTelemetry t{};
  t.time = fl::TimeMs{static_cast<std::uint32_t>(g_raw_in[7])};
  t.valid = true;
  g_step.step(t, t.time, prepared, g_step_out);
  keep(g_step_out.monitor.wheels[0].sinkage_m.raw());
  fl::WheelInput inputs[fl::kMaxWheels]{};
  inputs[0].current_a = fl::CurrentA::from_raw(g_raw_in[4]);
  inputs[0].load_n = fl::WheelLoadN::from_raw(g_raw_in[5]);
  inputs[0].valid = true;
  inputs[0].drive_torque = fl::torque_from_current(prepared.table().motor, inputs[0].current_a, inputs[0].direction);
  fl::RoverOutput monitored{};
  g_monitor.step(inputs, t.time, prepared, monitored);
  keep(static_cast<std::int64_t>(monitored.decision));
  fl::WheelOutput wheel_out{};
  g_wheel.step(inputs[0], t.time, prepared, wheel_out);
  keep(wheel_out.current_limit_a.raw());
}

void exercise_rover(const fl::ParameterTable& table) {
  const fl::RoverParams rover = fl::yutu_like_rover_params(fl::kGravityMoon);
  keep(static_cast<std::int64_t>(fl::validate_rover_params(rover)));
  const fl::RoverAttitude attitude{fl::AngleRad::from_raw(g_raw_in[6]), fl::AngleRad::from_raw(g_raw_in[6])};
  const fl::JointAnglesRad joints{};
  fl::DrawbarInput in{};
  in.slip_known = true;
  for (std::uint32_t i = 0U; i < fl::kWheelCount; ++i) {
    in.dp_max_ratio[i] = fl::Ratio::from_raw(g_raw_in[5] / 4);
  }
  static fl::PreparedParameters prepared;
  keep(static_cast<std::int64_t>(fl::prepare(table, rover, prepared)));
  const fl::WheelLoadResult prepared_loads = fl::wheel_loads(prepared, attitude, joints, fl::kNoDriveTorques);
  keep(prepared_loads.load_n[1].raw());
  keep(fl::drawbar_pulls(prepared, prepared_loads, in).total_n.raw());
  exercise_step(prepared);
  // Section 6 through the table's codec: encode with the rover, decode
  // (which validates it once).
  // Static, like the other tables of this image: off the measured stack.
  static std::uint8_t rover_bytes[fl::kMaxTableBytes];
  static fl::ParameterTable with_rover;
  static fl::ParameterTable decoded;
  with_rover = table;
  with_rover.rover_geometry.present = true;
  with_rover.rover_geometry.params = rover;
  const fl::EncodeResult rover_enc = fl::encode(with_rover, &rover_bytes[0], sizeof(rover_bytes));
  keep(static_cast<std::int64_t>(fl::decode(&rover_bytes[0], rover_enc.size, decoded)));
  keep(decoded.rover_geometry.params.mass_kg.raw());
}

void exercise_table_and_escape(fl::ParameterTable& table) {
  static std::uint8_t bytes[fl::kMaxTableBytes];
  table = fl::default_parameter_table();
  const fl::ParameterTable eq15 = fl::eq15_parameter_table();
  keep(static_cast<std::int64_t>(fl::validate(eq15)));
  const fl::EncodeResult enc = fl::encode(table, &bytes[0], sizeof(bytes));
  keep(static_cast<std::int64_t>(enc.size));
  keep_u(fl::crc32(&bytes[0], enc.size));
  fl::ParameterTable decoded{};
  keep(static_cast<std::int64_t>(fl::decode(&bytes[0], enc.size, decoded)));
  fl::EscapeSequencer escape;
  keep(escape.start(fl::TimeMs{0U}, fl::SinkageM::from_raw(g_raw_in[4])) ? 1 : 0);
  const fl::EscapeInput ein{fl::TimeMs{static_cast<std::uint32_t>(g_raw_in[7])}, true,
                            fl::SinkageM::from_raw(g_raw_in[4])};
  keep(static_cast<std::int64_t>(escape.step(ein, table.escape).command));
  escape.abort();
  escape.reset();
}

// The per-cycle step and the loader, through the C interface.
sw_context g_context;

void exercise_c_api(const fl::ParameterTable& table) {
  static std::uint8_t bytes[fl::kMaxTableBytes];
  static_cast<void>(sw_init(&g_context));
  const fl::EncodeResult enc = fl::encode(table, &bytes[0], sizeof(bytes));
  keep(sw_load_table(&g_context, &bytes[0], enc.size));
  keep_u(sw_active_table_crc(&g_context));
  sw_telemetry t{};
  t.time_ms = static_cast<std::uint32_t>(g_raw_in[7]);
  t.valid = 1U;
  t.current_a_q20[0] = g_raw_in[4];
  sw_cycle_result out{};
  keep(static_cast<std::int64_t>(sw_step(&g_context, &t, t.time_ms, &out)));
  keep(out.wheel[0].sinkage_m_q24);
  sw_event event{};
  keep(sw_last_event(&g_context, 0U, &event));
  sw_stop_record stop{};
  keep(sw_last_stop(&g_context, &stop));
  keep(stop.recent_sinkage_m_q24);
  sw_clear_stop(&g_context);
}

}  // namespace

int main() {
  static fl::ParameterTable table;
  exercise_fixedpoint();
  exercise_table_and_escape(table);
  exercise_estimator(table);
  exercise_rover(table);
  exercise_c_api(table);
  return 0;
}
