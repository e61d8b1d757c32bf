// The dividing oracle (dividing_oracle.hpp).
#include "dividing_oracle.hpp"

#include <cmath>

namespace sinkwatch {
namespace oracle {

namespace {

using flight::CorrectionResult;
using flight::EstimateStatus;
using flight::LoadClamp;
using flight::Ratio;
using flight::WideQ;

/// a + f (b - a) in Q31.32, rounded once into Q7.24.
Ratio lerp(Ratio a, Ratio b, WideQ fraction, fx::Status& st) noexcept {
  const WideQ span = fx::sub(fx::rescale<WideQ>(b.q(), st), fx::rescale<WideQ>(a.q(), st), st);
  const WideQ step = fx::mul<WideQ>(fraction, span, st);
  const WideQ value = fx::add(fx::rescale<WideQ>(a.q(), st), step, st);
  return Ratio(fx::rescale<flight::RatioQ>(value, st));
}

CorrectionResult from_row(const flight::CorrectionRow& row, LoadClamp clamp) noexcept {
  return CorrectionResult{flight::Coefficients{row.c1, row.c2, row.c3}, row.dp_max_ratio, clamp, EstimateStatus::ok};
}

/// The segment k with W_k <= W < W_k+1 (the flight code's rule).
std::uint8_t segment_of(const flight::CorrectionTable& table, flight::WheelLoadN load_n) noexcept {
  const auto last = static_cast<std::uint8_t>(table.count - 1U);
  for (std::uint8_t i = 0U; (i + 1U) < last; ++i) {
    if (load_n < table.rows[i + 1U].load_n) {
      return i;
    }
  }
  return static_cast<std::uint8_t>(last - 1U);
}

}  // namespace

CorrectionResult corrections_at(const flight::CorrectionTable& table, flight::WheelLoadN load_n) noexcept {
  CorrectionResult failed{flight::Coefficients{Ratio::zero(), Ratio::zero(), Ratio::zero()}, Ratio::zero(),
                          LoadClamp::none, EstimateStatus::invalid_coefficient};
  if ((table.count == 0U) || (table.count > flight::kMaxCorrectionRows)) {
    return failed;
  }
  if (load_n <= flight::WheelLoadN::zero()) {
    failed.status = EstimateStatus::invalid_load;
    return failed;
  }
  const auto last = static_cast<std::uint8_t>(table.count - 1U);
  if (load_n < table.rows[0].load_n) {
    return from_row(table.rows[0], LoadClamp::below_first);
  }
  if (load_n > table.rows[last].load_n) {
    return from_row(table.rows[last], LoadClamp::above_last);
  }
  if (load_n == table.rows[last].load_n) {
    return from_row(table.rows[last], LoadClamp::none);
  }
  const std::uint8_t seg = segment_of(table, load_n);
  const flight::CorrectionRow& lo = table.rows[seg];
  const flight::CorrectionRow& hi = table.rows[seg + 1U];
  fx::Status st;
  const flight::LoadQ offset = fx::sub(load_n.q(), lo.load_n.q(), st);
  const WideQ fraction = fx::div<WideQ>(offset, fx::sub(hi.load_n.q(), lo.load_n.q(), st), st);
  const flight::Coefficients c{lerp(lo.c1, hi.c1, fraction, st), lerp(lo.c2, hi.c2, fraction, st),
                               lerp(lo.c3, hi.c3, fraction, st)};
  const Ratio dp = lerp(lo.dp_max_ratio, hi.dp_max_ratio, fraction, st);
  if (!st.ok()) {
    return failed;
  }
  return CorrectionResult{c, dp, LoadClamp::none, EstimateStatus::ok};
}

flight::CurrentResult current_from_torque(const flight::MotorParams& motor, flight::TorqueNm torque_nm,
                                          flight::DriveDirection direction) noexcept {
  const EstimateStatus motor_status = flight::check_motor(motor);
  if (motor_status != EstimateStatus::ok) {
    return flight::CurrentResult{flight::CurrentA::zero(), motor_status};
  }
  if ((direction != flight::DriveDirection::forward) && (direction != flight::DriveDirection::reverse)) {
    return flight::CurrentResult{flight::CurrentA::zero(), EstimateStatus::invalid_direction};
  }
  fx::Status st;
  const WideQ per_gear = fx::div<WideQ>(torque_nm.q(), motor.gear_ratio.q(), st);
  const WideQ before_loss = fx::div<WideQ>(per_gear, motor.efficiency.q(), st);
  const WideQ driving = fx::div<WideQ>(before_loss, motor.kt_nm_per_a.q(), st);
  const WideQ i0 = fx::rescale<WideQ>(motor.no_load_current_a.q(), st);
  const WideQ total =
      (direction == flight::DriveDirection::forward) ? fx::add(driving, i0, st) : fx::sub(driving, i0, st);
  const flight::CurrentQ current = fx::rescale<flight::CurrentQ>(total, st);
  if (!st.ok()) {
    return flight::CurrentResult{flight::CurrentA::zero(), EstimateStatus::overflow};
  }
  return flight::CurrentResult{flight::CurrentA(current), EstimateStatus::ok};
}

double current_tolerance_a(const flight::MotorParams& motor, flight::CurrentA oracle_a) noexcept {
  const double lsb = std::ldexp(1.0, -20);
  const double eta = std::ldexp(static_cast<double>(motor.efficiency.raw()), -30);
  const double kt = std::ldexp(static_cast<double>(motor.kt_nm_per_a.raw()), -28);
  const double i0 = std::ldexp(static_cast<double>(motor.no_load_current_a.raw()), -20);
  const double driving = std::fabs(static_cast<double>(oracle_a.raw()) * lsb) + i0;
  const double oracle_error = (0.5 * lsb) + (std::ldexp(1.0, -33) * ((1.0 / (eta * kt)) + (1.0 / kt) + 1.0));
  return oracle_error + (0.5 * lsb) + std::ldexp(driving, -29);
}

flight::CurrentLimitResult current_limit(const CorrectionResult& corr, const flight::MotorParams& motor,
                                         flight::LengthM radius_m, flight::WheelLoadN load_n,
                                         flight::SinkageM allowed_sinkage_m) noexcept {
  // The flight code's own T_max (torque_limit), then the three divisions by
  // N, eta and Kt: the only difference from the flight path is the motor's
  // reciprocal under test. The status plumbing is flight::current_limit's.
  flight::CurrentLimitResult result{flight::CurrentA::zero(), flight::TorqueNm::zero(), corr.clamp,
                                    EstimateStatus::ok};
  if (corr.status != EstimateStatus::ok) {
    result.status = corr.status;
    return result;
  }
  const flight::TorqueLimitResult t =
      flight::torque_limit(corr.coefficients, corr.dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
  if (t.status != EstimateStatus::ok) {
    result.status = t.status;
    return result;
  }
  const flight::CurrentResult i = current_from_torque(motor, t.torque_nm, flight::DriveDirection::forward);
  if (i.status != EstimateStatus::ok) {
    result.status = i.status;
    return result;
  }
  result.current_limit_a = i.current_a;
  result.torque_limit_nm = t.torque_nm;
  return result;
}

flight::CurrentLimitResult current_limit(const flight::ParameterTable& table, flight::WheelLoadN load_n) noexcept {
  return current_limit(corrections_at(table.correction, load_n), table.motor, table.wheel_radius_m, load_n,
                       table.monitor.allowed_sinkage_m);
}

}  // namespace oracle
}  // namespace sinkwatch
