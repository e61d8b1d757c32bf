// Section 7's maximum drive current (current_limit.hpp).
#include "sinkwatch/flight/current_limit.hpp"

namespace sinkwatch {
namespace flight {

TorqueLimitResult torque_limit(const Coefficients& c, Ratio dp_max_ratio, LengthM radius_m, WheelLoadN load_n,
                               SinkageM allowed_sinkage_m) noexcept {
  const EstimateStatus input_status = check_estimator_inputs(c, radius_m, load_n);
  if (input_status != EstimateStatus::ok) {
    return TorqueLimitResult{TorqueNm::zero(), input_status};
  }
  fx::Status st;
  // T_max = (W / C1) * (r * (DP_max/W + C3) + C2 * z_max)
  const WideQ traction = fx::add(fx::rescale<WideQ>(dp_max_ratio.q(), st), fx::rescale<WideQ>(c.c3.q(), st), st);
  const WideQ r_traction = fx::mul<WideQ>(radius_m.q(), traction, st);
  const WideQ sink = fx::mul<WideQ>(c.c2.q(), allowed_sinkage_m.q(), st);
  const WideQ lever = fx::add(r_traction, sink, st);
  const WideQ moment = fx::mul<WideQ>(load_n.q(), lever, st);
  const LoadQ t_max = fx::div<LoadQ>(moment, c.c1.q(), st);
  if (!st.ok()) {
    return TorqueLimitResult{TorqueNm::zero(), EstimateStatus::overflow};
  }
  return TorqueLimitResult{TorqueNm(t_max), EstimateStatus::ok};
}

CurrentLimitResult current_limit(const CorrectionResult& corr, const MotorParams& motor,
                                 const MotorDivisors& divisors, LengthM radius_m, WheelLoadN load_n,
                                 SinkageM allowed_sinkage_m) noexcept {
  // Each return builds the whole result (no zeroed result overwritten
  // field by field: the Cortex-M0 build cleared it with a memset per wheel).
  if (corr.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, corr.status};
  }
  const TorqueLimitResult t = torque_limit(corr.coefficients, corr.dp_max_ratio, radius_m, load_n, allowed_sinkage_m);
  if (t.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, t.status};
  }
  // The limit is a magnitude in the direction of motion: forward, I0 adds.
  const CurrentResult i = current_from_torque(motor, divisors, t.torque_nm, DriveDirection::forward);
  if (i.status != EstimateStatus::ok) {
    return CurrentLimitResult{CurrentA::zero(), TorqueNm::zero(), corr.clamp, i.status};
  }
  return CurrentLimitResult{i.current_a, t.torque_nm, corr.clamp, EstimateStatus::ok};
}

}  // namespace flight
}  // namespace sinkwatch
