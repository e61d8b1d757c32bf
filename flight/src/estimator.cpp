// Eq. 11 in both directions (estimator.hpp); docs/flight.md has the error
// bound per step.
#include "sinkwatch/flight/estimator.hpp"

#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

#include "of_valid.hpp"

namespace sinkwatch {
namespace flight {

EstimateStatus check_estimator_inputs(const Coefficients& c, LengthM radius_m, WheelLoadN load_n) noexcept {
  return detail::estimator_inputs_status(c, radius_m, load_n);
}

SinkageResult sinkage_from_pull(const Coefficients& c, LengthM radius_m, WheelLoadN load_n, TorqueNm torque_nm,
                                DrawbarPullN drawbar_pull_n) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return SinkageResult{SinkageM::zero(), input_status};
  }
  return detail::sinkage_of_valid(c, radius_m, load_n, torque_nm, drawbar_pull_n);
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
