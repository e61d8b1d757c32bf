// Eq. 11 in both directions (estimator.hpp); docs/flight.md has the error
// bound per step.
#include "sinkwatch/flight/estimator.hpp"

#include "sinkwatch/fixedpoint/normalised_quotient.hpp"

#include "of_valid.hpp"

namespace sinkwatch {
namespace flight {

EstimateStatus check_estimator_inputs(const Coefficients& c, LengthM radius_m, WheelLoadN load_n) noexcept {
  if ((radius_m < kMinRadiusM) || (radius_m > kMaxRadiusM)) {
    return EstimateStatus::invalid_radius;
  }
  if (load_n <= WheelLoadN::zero()) {
    return EstimateStatus::invalid_load;
  }
  if ((c.c1 < kMinC12) || (c.c1 > kMaxC12) || (c.c2 < kMinC12) || (c.c2 > kMaxC12) || (c.c3 < kMinC3) ||
      (c.c3 > kMaxC3)) {
    return EstimateStatus::invalid_coefficient;
  }
  return EstimateStatus::ok;
}

SinkageResult sinkage_from_pull(const Coefficients& c, LengthM radius_m, WheelLoadN load_n, TorqueNm torque_nm,
                                DrawbarPullN drawbar_pull_n) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return SinkageResult{SinkageM::zero(), input_status};
  }
  return detail::sinkage_of_valid(c, radius_m, load_n, torque_nm, drawbar_pull_n);
}

SinkageResult detail::sinkage_of_valid(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                       TorqueNm torque_nm, DrawbarPullN drawbar_pull_n) noexcept {
  fx::Status st;
  // z = (C1 T - r C3 W - r DP) / (C2 W): one division, its operands in
  // Q23.40 on 64 bits (docs/flight.md, "Sinkage"). C1 T, r DP and C2 W are
  // exact products; r C3 (|r C3| <= 2) is rounded to Q2.29 before it meets
  // W, so r C3 W is one product rounded to Q23.40. Every term is below 2^57.5
  // raw, their sum below 2^59: no intermediate can overflow.
  using Moment = fx::Q<std::int64_t, 40>;
  const Moment drive = fx::mul<Moment>(c.c1.q(), torque_nm.q(), st);
  const Moment pull_moment = fx::mul<Moment>(radius_m.q(), drawbar_pull_n.q(), st);
  const auto r_c3 = fx::mul<fx::Q<std::int32_t, 29>>(radius_m.q(), c.c3.q(), st);
  const Moment offset_moment = fx::mul<Moment>(r_c3, load_n.q(), st);
  const Moment numerator = fx::sub(fx::sub(drive, pull_moment, st), offset_moment, st);
  const Moment denominator = fx::mul<Moment>(c.c2.q(), load_n.q(), st);
  const LengthQ z = fx::divide_normalised<LengthQ>(numerator, denominator, st);
  if (!st.ok()) {
    return SinkageResult{SinkageM::zero(), EstimateStatus::overflow};
  }
  return SinkageResult{SinkageM(z), EstimateStatus::ok};
}

DrawbarPullResult pull_from_sinkage(const Coefficients& c, LengthM radius_m, WheelLoadN load_n,
                                    TorqueNm torque_nm, SinkageM sinkage_m) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return DrawbarPullResult{DrawbarPullN::zero(), input_status};
  }
  fx::Status st;
  // DP = C1 * T/r - W * (C2 * z/r + C3)
  const WideQ t_over_r = fx::div<WideQ>(torque_nm.q(), radius_m.q(), st);
  const WideQ drive = fx::mul<WideQ>(c.c1.q(), t_over_r, st);
  const WideQ z_over_r = fx::div<WideQ>(sinkage_m.q(), radius_m.q(), st);
  const WideQ sink = fx::mul<WideQ>(c.c2.q(), z_over_r, st);
  const WideQ coeff = fx::add(sink, fx::rescale<WideQ>(c.c3.q(), st), st);
  const WideQ resistance = fx::mul<WideQ>(load_n.q(), coeff, st);
  const WideQ dp = fx::sub(drive, resistance, st);
  const LoadQ out = fx::rescale<LoadQ>(dp, st);
  if (!st.ok()) {
    return DrawbarPullResult{DrawbarPullN::zero(), EstimateStatus::overflow};
  }
  return DrawbarPullResult{DrawbarPullN(out), EstimateStatus::ok};
}

}  // namespace flight
}  // namespace sinkwatch
