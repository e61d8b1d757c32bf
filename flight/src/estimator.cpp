// Eq. 11 in both directions (estimator.hpp); docs/flight.md has the error
// bound per step.
#include "sinkwatch/flight/estimator.hpp"

#include "sinkwatch/fixedpoint/normalised_quotient.hpp"
#include "sinkwatch/fixedpoint/wide.hpp"

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
  // z = (C1 T - r C3 W - r DP) / (C2 W): one division, its operands in
  // Q23.40 on 64 bits (docs/flight.md, "Sinkage"). C1 T, r DP and C2 W are
  // exact products; r C3 is rounded to Q2.29 before it meets W, so r C3 W is
  // one product rounded to Q23.40. For inputs check_estimator_inputs()
  // accepts (0 < C1, C2 <= 4, |C3| <= 1, 0 < r <= 2 m, W > 0; T and DP any
  // 32-bit value) the terms are at most 2^57, 2^56 and 2^56 + 1 raw
  // (|r C3| <= 2, 2^30 in Q2.29), their sum below 2^58: no intermediate can
  // overflow, so the sum is plain 64-bit arithmetic without saturation
  // tests, and each product is fx::mul's rounding of the exact product
  // (ties away from zero), bit for bit the checked chain it replaced. r, W,
  // C1 and C2 are positive, so only T, DP and C3 have a sign to take off and
  // put back (r |C3| and its product with W as magnitudes, C3's sign put
  // back once).
  const std::int32_t r = radius_m.raw();
  const std::int32_t w = load_n.raw();
  const std::int64_t drive = with_sign(
      torque_nm.raw() < 0,
      fx::wide::mul_32x32_64(fx::detail::magnitude32(torque_nm.raw()), static_cast<std::uint32_t>(c.c1.raw())));
  const std::int64_t pull_moment = with_sign(
      drawbar_pull_n.raw() < 0,
      fx::wide::mul_32x32_64(fx::detail::magnitude32(drawbar_pull_n.raw()), static_cast<std::uint32_t>(r)));
  const auto r_c3 = static_cast<std::uint32_t>(fx::detail::round_shift_const<(2 * LengthQ::frac_bits) - 29>(
      fx::wide::mul_32x32_64(static_cast<std::uint32_t>(r), fx::detail::magnitude32(c.c3.raw()))));  // <= 2^30
  const std::int64_t offset_moment =
      with_sign(c.c3.raw() < 0, fx::detail::round_shift_const<(29 + LoadQ::frac_bits) - 40>(
                                    fx::wide::mul_32x32_64(r_c3, static_cast<std::uint32_t>(w))));  // < 2^56

  using Moment = fx::Q<std::int64_t, 40>;
  const Moment numerator = Moment::from_raw((drive - pull_moment) - offset_moment);
  const fx::ScaledMagnitude denominator{
      false, fx::wide::mul_32x32_64(static_cast<std::uint32_t>(c.c2.raw()), static_cast<std::uint32_t>(w)), 40};
  fx::Status st;
  const LengthQ z = fx::divide_normalised<LengthQ>(fx::to_scaled(numerator), denominator, st);
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
