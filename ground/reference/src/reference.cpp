#include "sinkwatch/ground/reference.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/rover_limits.hpp"

namespace sinkwatch {
namespace ground {
namespace reference {

namespace {

void require(bool condition, const char* what) {
  if (!condition) {
    throw std::invalid_argument(std::string("reference: ") + what);
  }
}

double sign_of(flight::DriveDirection d) { return d == flight::DriveDirection::reverse ? -1.0 : 1.0; }

}  // namespace

double sinkage_m(const Coefficients& c, double r, double w, double t, double dp) {
  require(r >= flight::limits::kMinWheelRadiusM, "wheel radius must be at least 0.01 m");
  require(w > 0.0, "wheel load must be positive");
  require(c.c2 != 0.0, "C2 must not be zero");
  return (c.c1 * t / w - r * (c.c3 + dp / w)) / c.c2;
}

double drawbar_pull_n(const Coefficients& c, double r, double w, double t, double z) {
  require(r >= flight::limits::kMinWheelRadiusM, "wheel radius must be at least 0.01 m");
  require(w > 0.0, "wheel load must be positive");
  return c.c1 * t / r - w * (c.c2 * z / r + c.c3);
}

double torque_nm(const Motor& m, double i, flight::DriveDirection d) {
  require(std::fabs(i) <= m.current_abs_max_a, "current beyond the sensor range");
  return m.gear_ratio * m.efficiency * m.kt_nm_per_a * (i - sign_of(d) * m.no_load_current_a);
}

double current_a(const Motor& m, double t, flight::DriveDirection d) {
  const double gain = m.gear_ratio * m.efficiency * m.kt_nm_per_a;
  require(gain > 0.0, "motor gain N eta Kt must be positive");
  return t / gain + sign_of(d) * m.no_load_current_a;
}

Corrections corrections_at(const std::vector<CorrectionRow>& table, double w) {
  require(!table.empty(), "correction table is empty");
  require(w > 0.0, "wheel load must be positive");
  auto from_row = [](const CorrectionRow& row, Clamp clamp) {
    return Corrections{Coefficients{row.c1, row.c2, row.c3}, row.dp_max_ratio, clamp};
  };
  if (w < table.front().load_n) {
    return from_row(table.front(), Clamp::below_first);
  }
  if (w >= table.back().load_n) {
    return from_row(table.back(), w > table.back().load_n ? Clamp::above_last : Clamp::none);
  }
  for (std::size_t i = 0; i + 1 < table.size(); ++i) {
    const CorrectionRow& lo = table[i];
    const CorrectionRow& hi = table[i + 1];
    if (w >= lo.load_n && w < hi.load_n) {
      const double f = (w - lo.load_n) / (hi.load_n - lo.load_n);
      auto lerp = [f](double a, double b) { return a + f * (b - a); };
      return Corrections{Coefficients{lerp(lo.c1, hi.c1), lerp(lo.c2, hi.c2), lerp(lo.c3, hi.c3)},
                         lerp(lo.dp_max_ratio, hi.dp_max_ratio), Clamp::none};
    }
  }
  throw std::invalid_argument("reference: load breakpoints are not increasing");
}

double torque_limit_nm(const Coefficients& c, double dp_max_ratio, double r, double w, double z_max) {
  require(r >= flight::limits::kMinWheelRadiusM, "wheel radius must be at least 0.01 m");
  require(w > 0.0, "wheel load must be positive");
  require(c.c1 != 0.0, "C1 must not be zero");
  return (w / c.c1) * (r * (dp_max_ratio + c.c3) + c.c2 * z_max);
}

double current_limit_a(const std::vector<CorrectionRow>& table, const Motor& m, double r, double w, double z_max) {
  const Corrections corr = corrections_at(table, w);
  const double t_max = torque_limit_nm(corr.coefficients, corr.dp_max_ratio, r, w, z_max);
  return current_a(m, t_max, flight::DriveDirection::forward);
}

Coefficients from_flight(const flight::Coefficients& c) {
  return Coefficients{fx::to_double(c.c1.q()), fx::to_double(c.c2.q()), fx::to_double(c.c3.q())};
}

Motor from_flight(const flight::MotorParams& m) {
  return Motor{fx::to_double(m.gear_ratio.q()), fx::to_double(m.efficiency.q()), fx::to_double(m.kt_nm_per_a.q()),
               fx::to_double(m.no_load_current_a.q()), fx::to_double(m.current_abs_max_a.q())};
}

std::vector<CorrectionRow> from_flight(const flight::CorrectionTable& t) {
  std::vector<CorrectionRow> rows;
  const std::size_t n = t.count > flight::kMaxCorrectionRows ? flight::kMaxCorrectionRows : t.count;
  for (std::size_t i = 0; i < n; ++i) {
    const flight::CorrectionRow& r = t.rows[i];
    rows.push_back(CorrectionRow{fx::to_double(r.load_n.q()), fx::to_double(r.c1.q()), fx::to_double(r.c2.q()),
                                 fx::to_double(r.c3.q()), fx::to_double(r.dp_max_ratio.q())});
  }
  return rows;
}

Parameters from_flight(const flight::ParameterTable& t) {
  Parameters p;
  p.wheel_radius_m = fx::to_double(t.wheel_radius_m.q());
  p.motor = from_flight(t.motor);
  p.correction = from_flight(t.correction);
  p.allowed_sinkage_m = fx::to_double(t.monitor.allowed_sinkage_m.q());
  p.caution_sinkage_m = fx::to_double(t.monitor.caution_sinkage_m.q());
  p.stop_sinkage_m = fx::to_double(t.monitor.stop_sinkage_m.q());
  return p;
}

}  // namespace reference
}  // namespace ground
}  // namespace sinkwatch
