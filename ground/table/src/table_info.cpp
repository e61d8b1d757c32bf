// A parameter table in human units (rover_table.hpp: describe_table; the
// `sinkwatch table-info` command, docs/rover-table.md).
#include "sinkwatch/ground/strf.hpp"
#include "sinkwatch/ground/rover_table.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"

#include <cstdarg>
#include <cstdio>

namespace sinkwatch::ground {
namespace {

template <typename Quantity>
double d(const Quantity& q) {
  return fx::to_double(q.q());
}

std::string motor_and_corrections(const flight::ParameterTable& t) {
  const flight::MotorParams& m = t.motor;
  std::string s = strf("  section 1 estimator   wheel radius %.6g m\n", d(t.wheel_radius_m));
  s += strf("  section 2 motor       gear ratio %.6g, efficiency %.4g, Kt %.6g N m/A, no-load current %.4g A, "
            "current sensor range +-%.4g A\n",
            d(m.gear_ratio), d(m.efficiency), d(m.kt_nm_per_a), d(m.no_load_current_a), d(m.current_abs_max_a));
  s += strf("  section 3 correction  C(W) for Eq. 11, %u row(s):\n", static_cast<unsigned>(t.correction.count));
  s += "      load N        C1        C2        C3   DP_max/W\n";
  for (std::size_t i = 0; i < t.correction.count && i < flight::kMaxCorrectionRows; ++i) {
    const flight::CorrectionRow& r = t.correction.rows[i];
    s += strf("    %8.2f  %8.4f  %8.4f  %8.4f  %8.4f\n", d(r.load_n), d(r.c1), d(r.c2), d(r.c3), d(r.dp_max_ratio));
  }
  return s;
}

std::string monitor_and_escape(const flight::ParameterTable& t) {
  const flight::MonitorParams& m = t.monitor;
  std::string s = strf(
      "  section 4 monitor     caution %.1f mm, stop %.1f mm, hysteresis %.1f mm, allowed z_max %.1f mm;\n"
      "                        current caution at %.3g I_max (hysteresis %.3g); loads valid in [%.1f, %.1f] N;\n"
      "                        %u of %u samples trip, %u clear; %u unusable samples stop; stale after %u ms;\n"
      "                        %u wheel(s) monitored, %u in STOP stop the rover\n",
      d(m.caution_sinkage_m) * 1000.0, d(m.stop_sinkage_m) * 1000.0, d(m.sinkage_hysteresis_m) * 1000.0,
      d(m.allowed_sinkage_m) * 1000.0, d(m.current_caution_fraction), d(m.current_hysteresis_fraction),
      d(m.load_min_n), d(m.load_max_n), static_cast<unsigned>(m.trip_n), static_cast<unsigned>(m.window_m),
      static_cast<unsigned>(m.clear_n), static_cast<unsigned>(m.invalid_to_stop),
      static_cast<unsigned>(m.stale_timeout_ms), static_cast<unsigned>(m.wheel_count),
      static_cast<unsigned>(m.rover_stop_k));
  const flight::EscapeParams& e = t.escape;
  s += strf("  section 5 escape      forward %.1f s, reverse %.1f s, at most %u cycles, patience %u, progress >= "
            "%.1f mm per cycle, freed at <= %.1f mm\n",
            e.forward_phase_ms / 1000.0, e.reverse_phase_ms / 1000.0, static_cast<unsigned>(e.max_cycles),
            static_cast<unsigned>(e.patience_cycles), d(e.min_decrease_m) * 1000.0, d(e.freed_sinkage_m) * 1000.0);
  return s;
}

std::string health(const flight::HealthParams& h) {
  return strf("  section 7 health      loss policy %s; stuck after %u, implausible after %u, recovered after %u "
              "cycles (0: off); %u blind wheel(s) tolerated; bridge %u ms; spikes: current %.4g A, attitude "
              "%.4g rad, joint %.4g rad (0: off)\n",
              h.policy == flight::LossPolicy::continue_degraded ? "continue-degraded" : "stop",
              static_cast<unsigned>(h.stuck_cycles), static_cast<unsigned>(h.implausible_cycles),
              static_cast<unsigned>(h.recover_cycles), static_cast<unsigned>(h.max_blind_wheels),
              static_cast<unsigned>(h.bridge_ms), d(h.current_step_a), d(h.attitude_step_rad), d(h.joint_step_rad));
}

std::string traction(const flight::TractionParams& p) {
  if (!flight::traction_check_on(p)) return "  section 8 traction    absent: the motion-resistance check is off\n";
  return strf("  section 8 traction    motion-resistance coefficient carried %.4g m ahead along its rise over %.4g m: "
              "CAUTION at %.4g, STOP at %.4g, clear below %.4g (docs/traction.md)\n",
              d(p.lookahead_m), d(p.trend_span_m), d(p.caution_coefficient), d(p.stop_coefficient),
              d(p.caution_coefficient) - d(p.hysteresis));
}

}  // namespace

std::string describe_table(const LoadedTable& t) {
  std::string s = strf("table %s: version %u", t.source.c_str(), static_cast<unsigned>(t.table.table_version));
  s += t.bytes > 0 ? strf(", %zu bytes, CRC-32 0x%08x\n", t.bytes, static_cast<unsigned>(t.crc))
                   : std::string(" (built in, no bytes)\n");
  s += motor_and_corrections(t.table);
  s += monitor_and_escape(t.table);
  if (t.rover) {
    s += "  section 6 rover       the rover the wheel loads are computed for:\n" + describe_rover(*t.rover);
  } else {
    s += "  section 6 rover       absent: the flight code uses the Yutu-like rover on the Moon:\n" +
         describe_rover(flight::yutu_like_rover_params(flight::kGravityMoon));
  }
  s += health(t.table.health);
  s += traction(t.table.traction);
  return s;
}

}  // namespace sinkwatch::ground
