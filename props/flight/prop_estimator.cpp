// Fixed point against the reference twin over the whole valid envelope, with
// the error bounds derived in docs/flight.md ("Error budget") asserted per
// case; saturation and status at the envelope's edges.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdint>

#include "estimator_bounds.hpp"
#include "prepared_support.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/reference.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;
namespace ref = sinkwatch::ground::reference;

const double k2m33 = std::ldexp(1.0, -33);  // half an LSB of the Q31.32 intermediates
const double kLsbZ = std::ldexp(1.0, -24);  // Q7.24
const double kLsbT = std::ldexp(1.0, -16);  // Q15.16
const double kLsbI = std::ldexp(1.0, -20);  // Q11.20
const double kEps = std::ldexp(1.0, -52);

template <typename Qty>
double d(Qty v) {
  return fx::to_double(v.q());
}

/// A raw value between lo and hi whose magnitude is spread over the binary
/// orders (uniform raw bits would almost never give small values).
std::int32_t raw_in(std::int64_t lo, std::int64_t hi) {
  const int order = *rc::gen::inRange(0, 32);
  const std::int64_t span = hi - lo;
  const std::int64_t cap = order >= 62 ? span : std::min<std::int64_t>(span, (std::int64_t{1} << order));
  const std::int64_t off = *rc::gen::inRange<std::int64_t>(0, cap + 1);
  const bool from_top = *rc::gen::arbitrary<bool>();
  return static_cast<std::int32_t>(from_top ? hi - off : lo + off);
}
template <typename Qt>
std::int64_t raw_of(double v) {
  fx::Status st;
  return fx::from_double<Qt>(v, st).raw();
}

Coefficients gen_coefficients() {
  return Coefficients{Ratio::from_raw(raw_in(raw_of<RatioQ>(0.25), raw_of<RatioQ>(4.0))),
                      Ratio::from_raw(raw_in(raw_of<RatioQ>(0.25), raw_of<RatioQ>(4.0))),
                      Ratio::from_raw(raw_in(raw_of<RatioQ>(-1.0), raw_of<RatioQ>(1.0)))};
}
LengthM gen_radius() { return LengthM::from_raw(raw_in(raw_of<LengthQ>(0.01), raw_of<LengthQ>(2.0))); }
WheelLoadN gen_load() { return WheelLoadN::from_raw(raw_in(1, INT32_MAX)); }
TorqueNm gen_torque() { return TorqueNm::from_raw(raw_in(INT32_MIN, INT32_MAX)); }

constexpr double kQ31Max = 2147483648.0;  // |Q31.32| limit
constexpr double kZMax = 128.0;           // |Q7.24| limit
constexpr double kTMax = 32768.0;         // |Q15.16| limit

RC_GTEST_PROP(FlightVsReference, SinkageWithinBoundOrOverflowOnlyBeyondTheFormats, ()) {
  const Coefficients c = gen_coefficients();
  const LengthM r = gen_radius();
  const WheelLoadN w = gen_load();
  const TorqueNm t = gen_torque();
  const DrawbarPullN dp = DrawbarPullN::from_raw(raw_in(INT32_MIN, INT32_MAX));
  const SinkageResult got = sinkage_from_pull(c, r, w, t, dp);
  const ref::Coefficients rc_ = ref::from_flight(c);
  const double rr = d(r), ww = d(w), tt = d(t), pp = d(dp);
  const double drive = rc_.c1 * tt / ww;
  const double offset = rr * (rc_.c3 + pp / ww);
  const double expected = ref::sinkage_m(rc_, rr, ww, tt, pp);
  // docs/flight.md, "Sinkage".
  const double bound = test::sinkage_error_bound_m(rc_.c2, ww, expected) +
                       8.0 * kEps * (std::fabs(drive) + std::fabs(offset)) / rc_.c2;
  if (got.status == EstimateStatus::ok) {
    RC_ASSERT(std::fabs(d(got.sinkage_m) - expected) <= bound);
    // The documented worst case over the envelope (|z| < 128 m, C2 >= 1/4,
    // W >= 1 LSB): below 0.001 mm, a hundredth of issue 15's 0.1 mm.
    RC_ASSERT(std::fabs(d(got.sinkage_m) - expected) <= 1e-6);
  } else {
    // No intermediate can overflow: only a sinkage beyond Q7.24 is refused.
    RC_ASSERT(got.status == EstimateStatus::overflow);
    RC_ASSERT(got.sinkage_m == SinkageM::zero());
    RC_ASSERT(std::fabs(expected) + bound >= kZMax - kLsbZ);
  }
  if (std::fabs(expected) + bound < kZMax - kLsbZ) {
    RC_ASSERT(got.status == EstimateStatus::ok);
  }
}

RC_GTEST_PROP(FlightVsReference, DrawbarPullWithinBound, ()) {
  const Coefficients c = gen_coefficients();
  const LengthM r = gen_radius();
  const WheelLoadN w = gen_load();
  const TorqueNm t = gen_torque();
  const SinkageM z = SinkageM::from_raw(raw_in(INT32_MIN, INT32_MAX));
  const DrawbarPullResult got = pull_from_sinkage(c, r, w, t, z);
  const ref::Coefficients rc_ = ref::from_flight(c);
  const double rr = d(r), ww = d(w), tt = d(t), zz = d(z);
  const double expected = ref::drawbar_pull_n(rc_, rr, ww, tt, zz);
  const double drive = rc_.c1 * tt / rr;
  const double resistance = ww * (rc_.c2 * zz / rr + rc_.c3);
  const double largest =
      std::max({std::fabs(tt / rr), std::fabs(drive), std::fabs(zz / rr), std::fabs(resistance), std::fabs(drive - resistance)});
  if (got.status == EstimateStatus::ok) {
    const double bound = 0.5 * kLsbT + (rc_.c1 + 2.0 + ww * (rc_.c2 + 1.0)) * k2m33 +
                         8.0 * kEps * (std::fabs(drive) + std::fabs(resistance));
    RC_ASSERT(std::fabs(d(got.drawbar_pull_n) - expected) <= bound);
  } else {
    RC_ASSERT(got.status == EstimateStatus::overflow);
    RC_ASSERT((std::fabs(expected) >= kTMax - kLsbT) || (largest >= kQ31Max * (1.0 - 1e-9)));
  }
  if ((std::fabs(expected) < kTMax - 1.0) && (largest < kQ31Max / 2.0)) {
    RC_ASSERT(got.status == EstimateStatus::ok);
  }
}

MotorParams gen_motor() {
  MotorParams m{};
  m.gear_ratio = GearRatio::from_raw(raw_in(raw_of<GearQ>(1.0), raw_of<GearQ>(10000.0)));
  m.efficiency = Efficiency::from_raw(raw_in(raw_of<EfficiencyQ>(0.01), raw_of<EfficiencyQ>(1.0)));
  m.kt_nm_per_a = TorqueConstantNmPerA::from_raw(raw_in(raw_of<KtQ>(0.0001), raw_of<KtQ>(4.0)));
  m.no_load_current_a = CurrentA::from_raw(raw_in(0, raw_of<CurrentQ>(100.0)));
  m.current_abs_max_a =
      CurrentA::from_raw(raw_in(static_cast<std::int64_t>(m.no_load_current_a.raw()) + 1, raw_of<CurrentQ>(1000.0)));
  return m;
}

RC_GTEST_PROP(FlightVsReference, TorqueFromCurrentWithinBound, ()) {
  const MotorParams m = gen_motor();
  const std::int64_t lim = m.current_abs_max_a.raw();
  const CurrentA i = CurrentA::from_raw(raw_in(-lim, lim));
  const DriveDirection dir = *rc::gen::arbitrary<bool>() ? DriveDirection::forward : DriveDirection::reverse;
  const TorqueResult got = torque_from_current(m, i, dir);
  const ref::Motor rm = ref::from_flight(m);
  const double expected = ref::torque_nm(rm, d(i), dir);
  if (got.status == EstimateStatus::ok) {
    const double bound = 0.5 * kLsbT + rm.gear_ratio * (rm.efficiency + 1.0) * k2m33 + 8.0 * kEps * std::fabs(expected);
    RC_ASSERT(std::fabs(d(got.torque_nm) - expected) <= bound);
  } else {
    RC_ASSERT(got.status == EstimateStatus::overflow);
    RC_ASSERT(std::fabs(expected) >= kTMax - kLsbT);
  }
  if (std::fabs(expected) < kTMax - 1.0) {
    RC_ASSERT(got.status == EstimateStatus::ok);
  }
}

RC_GTEST_PROP(FlightVsReference, CurrentBeyondTheSensorIsRefused, ()) {
  const MotorParams m = gen_motor();
  const std::int64_t lim = m.current_abs_max_a.raw();
  const bool positive = *rc::gen::arbitrary<bool>();
  const CurrentA i = CurrentA::from_raw(positive ? raw_in(lim + 1, INT32_MAX) : raw_in(INT32_MIN, -lim - 1));
  const TorqueResult got = torque_from_current(m, i, DriveDirection::forward);
  RC_ASSERT(got.status == EstimateStatus::invalid_current);
  RC_ASSERT(got.torque_nm == TorqueNm::zero());
}

RC_GTEST_PROP(FlightVsReference, CurrentFromTorqueWithinBound, ()) {
  const MotorParams m = gen_motor();
  const TorqueNm t = gen_torque();
  const DriveDirection dir = *rc::gen::arbitrary<bool>() ? DriveDirection::forward : DriveDirection::reverse;
  const CurrentResult got = test::current_of(m, t, dir);
  const ref::Motor rm = ref::from_flight(m);
  const double expected = ref::current_a(rm, d(t), dir);
  const double driving = d(t) / (rm.gear_ratio * rm.efficiency * rm.kt_nm_per_a);
  // docs/flight.md, "Current from torque": one product with the gain's
  // normalised reciprocal, 0.5 LSB + |T / (N eta Kt)| 2^-29, plus the double
  // reference's own rounding.
  const double bound = 0.5 * kLsbI + std::ldexp(std::fabs(driving), -29) + 8.0 * kEps * std::fabs(driving);
  if (got.status == EstimateStatus::ok) {
    RC_ASSERT(std::fabs(d(got.current_a) - expected) <= bound);
  } else {
    RC_ASSERT(got.status == EstimateStatus::overflow);
    RC_ASSERT(std::fabs(expected) >= 2048.0 - kLsbI - bound);
  }
  if (std::fabs(expected) < 2047.0) {
    RC_ASSERT(got.status == EstimateStatus::ok);
  }
}

RC_GTEST_PROP(FlightVsReference, CorrectionsWithinBoundAndClampReported, ()) {
  const ParameterTable table = default_parameter_table();
  const WheelLoadN w = WheelLoadN::from_raw(raw_in(1, raw_of<LoadQ>(30000.0)));
  const CorrectionResult got = test::corrections_of(table.correction, w);
  const ref::Corrections expected = ref::corrections_at(ref::from_flight(table.correction), d(w));
  RC_ASSERT(got.status == EstimateStatus::ok);
  RC_ASSERT(static_cast<int>(got.clamp) == static_cast<int>(expected.clamp));
  // |span| <= 0.07 between the default rows.
  const double bound = 0.5 * kLsbZ + 2.0 * k2m33;
  RC_ASSERT(std::fabs(d(got.coefficients.c1) - expected.coefficients.c1) <= bound);
  RC_ASSERT(std::fabs(d(got.coefficients.c2) - expected.coefficients.c2) <= bound);
  RC_ASSERT(std::fabs(d(got.coefficients.c3) - expected.coefficients.c3) <= bound);
  RC_ASSERT(std::fabs(d(got.dp_max_ratio) - expected.dp_max_ratio) <= bound);
}

RC_GTEST_PROP(FlightVsReference, CurrentLimitWithinBound, ()) {
  ParameterTable table = default_parameter_table();
  table.motor = gen_motor();
  table.wheel_radius_m = LengthM::from_raw(raw_in(raw_of<LengthQ>(0.05), raw_of<LengthQ>(1.0)));
  const WheelLoadN w = WheelLoadN::from_raw(raw_in(raw_of<LoadQ>(1.0), raw_of<LoadQ>(2000.0)));
  const SinkageM zmax = SinkageM::from_raw(raw_in(1, table.wheel_radius_m.raw()));
  const CurrentLimitResult got = test::current_limit_of(table.correction, table.motor, table.wheel_radius_m, w, zmax);
  const ref::Parameters p = ref::from_flight(table);
  const ref::Corrections corr = ref::corrections_at(p.correction, d(w));
  const double t_max = ref::torque_limit_nm(corr.coefficients, corr.dp_max_ratio, p.wheel_radius_m, d(w), d(zmax));
  const double expected = ref::current_a(p.motor, t_max, DriveDirection::forward);
  const double gain = p.motor.gear_ratio * p.motor.efficiency * p.motor.kt_nm_per_a;
  // The coefficients at W are themselves within e_c of the reference.
  const double e_c = 0.5 * kLsbZ + 2.0 * k2m33;
  const double c1 = corr.coefficients.c1;
  // docs/flight.md, "Current limit": the exact lever's leading 31 bits and
  // the normalised division (|T_max| 2^-28), then the coefficients' own error.
  const double e_t = test::torque_limit_error_bound_nm(t_max) +
                     d(w) * (p.wheel_radius_m * 2.0 * e_c + d(zmax) * e_c) / c1 + std::fabs(t_max) * e_c / c1 +
                     8.0 * kEps * std::fabs(t_max);
  if (got.status == EstimateStatus::ok) {
    RC_ASSERT(std::fabs(d(got.torque_limit_nm) - t_max) <= e_t);
    // The motor model's bound (docs/flight.md, "Current from torque") with
    // the torque limit's error carried through the gain.
    const double bound = e_t / gain + 0.5 * kLsbI + std::fabs(t_max / gain) * std::ldexp(1.0, -29) +
                         8.0 * kEps * std::fabs(expected);
    RC_ASSERT(std::fabs(d(got.current_limit_a) - expected) <= bound);
  } else {
    RC_ASSERT(got.status == EstimateStatus::overflow);
    RC_ASSERT(std::fabs(expected) >= 2048.0 - 1.0 || std::fabs(t_max) >= kTMax - 1.0);
  }
}

}  // namespace
