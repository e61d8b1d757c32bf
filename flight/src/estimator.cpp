// Eq. 11 in both directions (estimator.hpp). Every chain runs in Q31.32 and
// rounds once into its output; docs/flight.md has the error bound per step.
#include "sinkwatch/flight/estimator.hpp"

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
  fx::Status st;
  // z = (C1 * T/W - r * (C3 + DP/W)) / C2
  const WideQ t_over_w = fx::div<WideQ>(torque_nm.q(), load_n.q(), st);
  const WideQ drive = fx::mul<WideQ>(c.c1.q(), t_over_w, st);
  const WideQ dp_over_w = fx::div<WideQ>(drawbar_pull_n.q(), load_n.q(), st);
  const WideQ offset = fx::add(fx::rescale<WideQ>(c.c3.q(), st), dp_over_w, st);
  const WideQ r_offset = fx::mul<WideQ>(radius_m.q(), offset, st);
  const WideQ numerator = fx::sub(drive, r_offset, st);
  const LengthQ z = fx::div<LengthQ>(numerator, c.c2.q(), st);
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
