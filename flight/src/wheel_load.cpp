// Quasi-static rocker-bogie wheel loads in fixed point; see wheel_load.hpp and
// docs/rover-loads.md (sections 3 and 7). The double twin is
// ground/reference/src/rover_loads.cpp: the two follow the same steps in the
// same order so that a difference points at one line.
#include "sinkwatch/flight/wheel_load.hpp"

#include "sinkwatch/flight/rover_limits.hpp"

#include "sinkwatch/fixedpoint/bounded.hpp"
#include "sinkwatch/fixedpoint/inline.hpp"
#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/reciprocal.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

#include <type_traits>

namespace sinkwatch {
namespace flight {
namespace {

using detail::SignOf;

/// Front, middle and rear: each side's wheels (wheel i = 3 s + k).
constexpr std::uint32_t kWheelsPerSide = kWheelCount / kSideCount;

/// The statics' format P: metres, and every force and moment as a fraction
/// of the normal weight m g cos(pitch) cos(roll) (docs/rover-loads.md,
/// section 7.4). Q6.25 first: the projected coordinates stay within +-31 m
/// and the shares of a stable rover within [0, 1], so one 32-bit format with
/// 64-bit products carries the balance whatever the rover's mass. Only a
/// quotient by a lever of a few millimetres leaves it, far beyond the
/// stability limit; that evaluation is repeated in Q15.16, which decides the
/// tip-over there (section 7.4).
using Fine = StaticsQ;
using Mid = StaticsMidQ;
using Coarse = StaticsCoarseQ;
/// Q3.28: the projection slopes tan(pitch) / cos(roll) and tan(roll), at
/// most 3.5 within the attitude limit of 1.05 rad.
using K = fx::Q<std::int32_t, 28>;
/// |tan(pitch) / cos(roll)| <= sin(1.05) / cos^2(1.05) = 3.5034 and
/// |tan(roll)| <= tan(1.05) = 1.7433 within kMaxAttitudeLimitRad; the
/// bounds leave room for their rounding (about 10^-8), so gravity_frame
/// takes the slopes as bounded without a test (StaticsArithmetic.
/// GravitySlopesAreWithinTheirBounds samples the limit's corners).
constexpr std::uint32_t kKxBound = static_cast<std::uint32_t>(fx::constant<K>(3.51).raw());
constexpr std::uint32_t kKyBound = static_cast<std::uint32_t>(fx::constant<K>(1.75).raw());
using Kx = fx::Bounded<K, kKxBound>;
using Ky = fx::Bounded<K, kKyBound>;

constexpr MassKg kMaxMass{fx::constant<MassQ>(limits::kMaxMassKg)};
constexpr AccelMps2 kMaxGravity{fx::constant<AccelQ>(limits::kMaxGravityMps2)};
constexpr LengthM kMinWheelRadius{fx::constant<LengthQ>(limits::kMinWheelRadiusM)};
constexpr LengthM kMaxWheelRadius{fx::constant<LengthQ>(limits::kMaxWheelRadiusM)};
constexpr LengthM kMaxTrack{fx::constant<LengthQ>(limits::kMaxTrackWidthM)};
constexpr LengthM kMaxLink{fx::constant<LengthQ>(limits::kMaxLinkM)};
constexpr AngleRad kMaxJointLimit{fx::constant<AngleQ>(limits::kMaxJointLimitRad)};
constexpr AngleRad kMaxAttitudeLimit{fx::constant<AngleQ>(limits::kMaxAttitudeLimitRad)};
/// A projected lever below 1 mm means the suspension has folded onto itself
/// (never inside the validated envelope of a sane geometry): report it rather
/// than divide by it.
template <typename P>
constexpr P kMinLever{fx::constant<P>(0.001)};
/// The guard of the rocker's lever and the bogie's span in each pass. The
/// Q6.25 pass decides both against 1 mm before anything can overflow
/// (loads_in), so a wider pass runs only on levers of at least 1 mm; its own
/// rounding (a few 2^-16 m in Q15.16) must not decide them again, as it did
/// for a lever of 1.003 mm that Q15.16 rounded to 0.992 mm (the fuzz finding
/// of session 13, docs/rover-loads.md 7.4). Half a millimetre there only
/// keeps the quotients by them finite.
template <typename P>
constexpr P kLeverGuard{fx::constant<P>(std::is_same<P, Fine>::value ? 0.001 : 0.0005)};
/// Whether the lateral span's quotients always fit P: in Q15.16 they do.
/// Z_s = (y~_front - y~_bogie) / (a + b) is a height difference on one side
/// (at most 4 m) times tan(roll) (at most 1.8) over a lever of at least
/// 0.9 mm (1 mm decided in Q6.25, less a few 2^-16 m of rounding): below
/// 8,000, and Y_s = y~_bogie + b Z_s below 16,010 (b <= 2 m, |y~| <= 10 m),
/// within +-32,768. In range is not precise: with a bogie span of 1 to 2 mm
/// the middle wheel's share beta is in the hundreds and the Q15.16 span can
/// be off by a decimetre (the sixth fuzz finding of session 14), which is
/// why loads_of_valid prefers Q10.21's verdict where that pass had one.
template <typename P>
constexpr bool kSpanFits{std::is_same<P, Coarse>::value};
template <typename P>
constexpr P kHalf{fx::constant<P>(0.5)};
template <typename P>
constexpr P kOne{fx::constant<P>(1.0)};
constexpr Ratio kMaxHighSlip{fx::constant<RatioQ>(limits::kMaxHighSlip)};

bool within(LengthM v, LengthM limit) noexcept { return (v <= limit) && (v.raw() >= -limit.raw()); }
bool positive_at_most(AngleRad v, AngleRad limit) noexcept { return (v.raw() > 0) && (v <= limit); }

template <typename P>
P length(LengthM v, fx::Status& st) noexcept { return fx::rescale<P>(v.q(), st); }
template <typename P>
StaticsLength<P> link_length(LengthM v, fx::Status& st) noexcept {
  return fx::bound_to<kLinkBound<P>>(length<P>(v, st), st);
}
template <typename P>
StaticsLink<P> link(SidePointM p, fx::Status& st) noexcept {
  return StaticsLink<P>{link_length<P>(p.x_m, st), link_length<P>(p.z_m, st)};
}

/// The rover's constants in P (rover_statics.hpp). Within every format for
/// validated parameters (lengths of at most 4 m, a weight of at most 10 kN);
/// `st` carries a saturation all the same.
template <typename P>
StaticsConstants<P> constants_in(const RoverParams& params, fx::Status& st) noexcept {
  // Both are positive after validation; their product is exact in 64 bits.
  constexpr std::int32_t kWeightFracBits = MassQ::frac_bits + AccelQ::frac_bits;
  return StaticsConstants<P>{
      link<P>(params.rocker_front_axle, st),
      link<P>(params.rocker_bogie_pivot, st),
      link<P>(params.bogie_middle_axle, st),
      link<P>(params.bogie_rear_axle, st),
      fx::bound_to<kRadiusBound<P>>(length<P>(params.wheel_radius_m, st), st),
      fx::bound_to<kLinkBound<P>>(fx::mul(kHalf<P>, length<P>(params.track_width_m, st), st), st),
      link_length<P>(params.com_x_m, st),
      link_length<P>(params.com_y_m, st),
      link_length<P>(params.com_z_m, st),
      fx::bound_to<kWeightBound>(fx::mul<LoadQ>(params.mass_kg.q(), params.gravity_mps2.q(), st), st),
      fx::normalised_reciprocal(
          static_cast<std::uint64_t>(params.mass_kg.raw()) * static_cast<std::uint64_t>(params.gravity_mps2.raw()),
          kWeightFracBits)};
}

/// Whether P is the format of every cycle's pass (Q6.25): the wider passes
/// run only far beyond the stability limit.
template <typename P>
constexpr bool kEveryCycle{std::is_same<P, Fine>::value};

/// Where the joints' rotations round their products in P (fx::Rounding):
/// in the caller in every cycle's pass (the Cortex-M0 runs 186 instructions
/// fewer per step for 780 bytes of flash and 24 B of stack, the M4 most of
/// its 193), in fx's one function per shift in the wider passes, so that
/// they add no flash.
template <typename P>
constexpr fx::Rounding kRotationRounding{kEveryCycle<P> ? fx::Rounding::inlined : fx::Rounding::called};
/// The projections' and the centre of mass's: the same where the core has
/// SMULL; calls on ARMv6-M, where the words' form inlined there too took
/// side_levers' registers (45 instructions more per step than the calls,
/// 448 bytes and 40 B of stack more).
template <typename P>
constexpr fx::Rounding kProjectionRounding{fx::wide::kMul32x32BySoftware ? fx::Rounding::called
                                                                          : kRotationRounding<P>};

/// fx::rotated's point (x cos - z sin, x sin + z cos), its products as
/// fx::mul<P, Where>'s. Where the products are inlined as SMULL forms (the
/// every-cycle pass on a core with a widening multiply, the host), with what
/// the caller knows of x's and cos's signs (detail::product_of_signs): 22
/// instructions per step fewer on the Cortex-M4 (round 16).
template <fx::Rounding Where, SignOf XSign, SignOf CosSign, typename P, std::uint32_t M>
SW_FX_INLINE void rotate(fx::BoundedPoint<P, M> p, fx::BoundedSinCos sc,
                         fx::BoundedPoint<P, static_cast<std::uint32_t>(fx::detail::kRotatedBound<M>)>& out) noexcept {
  using Out = fx::Bounded<P, static_cast<std::uint32_t>(fx::detail::kRotatedBound<M>)>;
  if constexpr ((Where == fx::Rounding::inlined) && !fx::wide::kMul32x32BySoftware) {
    constexpr std::int32_t kShift = fx::Q1_30::frac_bits;
    const std::int32_t x_raw = p.x.raw();
    const std::int32_t z_raw = p.z.raw();
    const std::int32_t sin_raw = sc.sin.raw();
    const std::int32_t cos_raw = sc.cos.raw();
    // |x cos - z sin| and |x sin + z cos| are within Out's bound (fx::rotated).
    out.x = Out::trusted(detail::product_of_signs<kShift, XSign, CosSign>(x_raw, cos_raw) -
                         detail::product_of_signs<kShift, SignOf::any, SignOf::any>(z_raw, sin_raw));
    out.z = Out::trusted(detail::product_of_signs<kShift, XSign, SignOf::any>(x_raw, sin_raw) +
                         detail::product_of_signs<kShift, SignOf::any, CosSign>(z_raw, cos_raw));
  } else {
    out.x = Out::trusted(fx::sub(fx::mul<P, Where>(p.x, sc.cos), fx::mul<P, Where>(p.z, sc.sin)).raw());
    out.z = Out::trusted(fx::add(fx::mul<P, Where>(p.x, sc.sin), fx::mul<P, Where>(p.z, sc.cos)).raw());
  }
}

/// fx::mul<Out, Where>(a, b)'s bits for operands the caller knows are at
/// least zero, whose bounds keep the product within Out: where the products
/// are inlined as SMULL forms (as in rotate), detail::product_of_signs with
/// both sign bits known zero, so that the rounding term is a constant (two
/// instructions fewer per product on the Cortex-M4); elsewhere fx::mul.
template <typename Out, fx::Rounding Where, typename A, std::uint32_t MA, typename B, std::uint32_t MB>
SW_FX_INLINE Out product_of_non_negative(fx::Bounded<A, MA> a, fx::Bounded<B, MB> b) noexcept {
  if constexpr ((Where == fx::Rounding::inlined) && !fx::wide::kMul32x32BySoftware) {
    constexpr std::int32_t kShift = (A::frac_bits + B::frac_bits) - Out::frac_bits;
    return Out::from_raw(detail::product_of_signs<kShift, SignOf::positive, SignOf::positive>(a.raw(), b.raw()));
  } else {
    return fx::mul<Out, Where>(a, b).q();
  }
}

/// v - z k: the coordinate of a point projected along gravity (section 3.2).
template <typename P, std::uint32_t V, std::uint32_t Z, std::uint32_t KB>
auto project(fx::Bounded<P, V> v, fx::Bounded<P, Z> z, fx::Bounded<K, KB> k) noexcept {
  return fx::sub(v, fx::mul<P, kProjectionRounding<P>>(z, k));
}

WheelLoadResult failed(WheelLoadStatus status) noexcept {
  WheelLoadResult r{};
  r.lifting_wheel = kWheelCount;
  r.status = status;
  return r;
}

/// Mass, gravity, wheel, track and centre of mass.
RoverParamStatus validate_body(const RoverParams& p) noexcept {
  if ((p.mass_kg.raw() <= 0) || (p.mass_kg > kMaxMass)) {
    return RoverParamStatus::bad_mass;
  }
  if ((p.gravity_mps2.raw() <= 0) || (p.gravity_mps2 > kMaxGravity)) {
    return RoverParamStatus::bad_gravity;
  }
  if ((p.wheel_radius_m < kMinWheelRadius) || (p.wheel_radius_m > kMaxWheelRadius)) {
    return RoverParamStatus::bad_wheel_radius;
  }
  if ((p.track_width_m.raw() <= 0) || (p.track_width_m > kMaxTrack)) {
    return RoverParamStatus::bad_track_width;
  }
  // |com_y| < track / 2, compared as 2 |com_y| < track without overflow
  // (both are at most 2^7 in Q7.24 magnitude here because track <= 4 m).
  if (!within(p.com_x_m, kMaxLink) || !within(p.com_z_m, kMaxLink) || !within(p.com_y_m, kMaxLink)) {
    return RoverParamStatus::bad_com;
  }
  const std::int64_t twice_com_y = 2 * static_cast<std::int64_t>(p.com_y_m.raw());
  const std::int64_t track = static_cast<std::int64_t>(p.track_width_m.raw());
  if ((twice_com_y >= track) || (twice_com_y <= -track)) {
    return RoverParamStatus::bad_com;
  }
  return RoverParamStatus::ok;
}

/// Link lengths and order, joint and attitude limits, the high-slip level.
RoverParamStatus validate_suspension(const RoverParams& p) noexcept {
  const SidePointM links[4] = {p.rocker_front_axle, p.rocker_bogie_pivot, p.bogie_middle_axle, p.bogie_rear_axle};
  for (const SidePointM& l : links) {
    if (!within(l.x_m, kMaxLink) || !within(l.z_m, kMaxLink)) {
      return RoverParamStatus::bad_link_length;
    }
  }
  if ((p.rocker_front_axle.x_m.raw() <= 0) || (p.rocker_bogie_pivot.x_m.raw() >= 0) ||
      (p.bogie_middle_axle.x_m.raw() <= 0) || (p.bogie_rear_axle.x_m.raw() >= 0)) {
    return RoverParamStatus::bad_link_order;
  }
  if (!positive_at_most(p.rocker_limit_rad, kMaxJointLimit) || !positive_at_most(p.bogie_limit_rad, kMaxJointLimit)) {
    return RoverParamStatus::bad_joint_limit;
  }
  if (!positive_at_most(p.attitude_limit_rad, kMaxAttitudeLimit)) {
    return RoverParamStatus::bad_attitude_limit;
  }
  if ((p.high_slip.raw() <= 0) || (p.high_slip > kMaxHighSlip)) {
    return RoverParamStatus::bad_high_slip;
  }
  return RoverParamStatus::ok;
}

/// a + b, checked: forced inline in every cycle's pass, where about 30 sums
/// and differences follow the first quotient (each a call before, docs/
/// performance.md session 18), and fx::add's call in the wider passes, so
/// that they add no flash. fx::add's own 32-bit form either way
/// (fx::detail::add_word).
template <typename P>
SW_FX_INLINE P plus(P a, P b, fx::Status& st) noexcept {
  if constexpr (kEveryCycle<P>) {
    return fx::detail::add_word(a, b, st);
  } else {
    return fx::add(a, b, st);
  }
}

/// a - b, checked, as plus() (fx::detail::sub_word).
template <typename P>
SW_FX_INLINE P minus(P a, P b, fx::Status& st) noexcept {
  if constexpr (kEveryCycle<P>) {
    return fx::detail::sub_word(a, b, st);
  } else {
    return fx::sub(a, b, st);
  }
}

/// a b, checked: fx::mul's bits and flags. In every cycle's pass on ARMv6-M
/// by 32-bit words (detail::product_checked_by_words: the Cortex-M0 runs 106
/// instructions fewer per step), elsewhere by fx::mul's word product in
/// place (fx::detail::mul_word: one multiply-accumulate and a test of its
/// high word; 13 products, about 110 instructions fewer per step on the
/// Cortex-M4 than fx::mul's call); in the wider passes fx::mul's call.
template <typename P>
SW_FX_INLINE P times(P a, P b, fx::Status& st) noexcept {
  if constexpr (kEveryCycle<P>) {
    if constexpr (fx::wide::kMul32x32BySoftware) {
      return P::from_raw(detail::product_checked_by_words<P::frac_bits>(a.raw(), b.raw(), st));
    } else {
      return fx::detail::mul_word<P, P::frac_bits>(a.raw(), b.raw(), st);
    }
  } else {
    return fx::mul(a, b, st);
  }
}

/// Whether the every-cycle quotients run in their caller
/// (detail::quotient_raw_in_range): where the core has a widening multiply,
/// whose quotient is about 20 instructions in place against 27 and a call's
/// arguments (the Cortex-M4); the one function on ARMv6-M, whose
/// quotient_raw is too large to copy.
constexpr bool kQuotientsInline{!fx::wide::kMul32x32BySoftware};

/// x / d in Out from d's reciprocal r (detail::quotient's bits and flags)
/// for a divisor the statics guard: a lever, a bogie span or
/// the lateral span of at least 1 mm in every cycle's pass (side_levers,
/// left_side_total), the normal fraction cos(pitch) cos(roll) >= 0.24 or
/// cos(roll) >= 0.49 (attitudes within 1.05 rad). Its reciprocal exists and
/// the shift F_x + scale - F_out is within 1 to 63: 22 to 37 for a length in
/// Q6.25 over Q6.25 (a raw divisor of 2^15 to 2^31), 29 to 34 for the
/// cosines, so in every cycle's pass in place the quotient goes without
/// testing either (detail::quotient_raw_in_range, the same bits and flags).
template <typename Out, bool EveryCycle, std::int32_t Fx>
SW_FX_INLINE Out guarded_quotient_in(fx::Q<std::int32_t, Fx> x, fx::NormalisedReciprocal r, fx::Status& st) noexcept {
  if constexpr (EveryCycle && kQuotientsInline) {
    const std::int32_t shift = (Fx + r.scale) - Out::frac_bits;
    return Out::from_raw(detail::quotient_raw_in_range(x.raw(), r.mantissa, static_cast<std::uint32_t>(shift), st));
  } else {
    return detail::quotient<Out>(x, r, st);
  }
}

/// x / d in the pass's format P for a guarded divisor (guarded_quotient_in).
template <typename P>
SW_FX_INLINE P over(P x, fx::NormalisedReciprocal r, fx::Status& st) noexcept {
  return guarded_quotient_in<P, kEveryCycle<P>>(x, r, st);
}

/// The lever quantities of one side (sections 3.3 to 3.5 and 12), in the
/// units of section 7.4: metres, and forces as fractions of the normal weight.
/// Built whole by side_levers (a zeroed record filled in is a memset).
template <typename P>
struct SideLevers {
  P b;                             ///< x~_pivot - x~_bogie
  fx::NormalisedReciprocal lever;  ///< 1 / (a + b), a = x~_front - x~_pivot; mantissa 0: a lever collapsed
  P beta;                          ///< the middle wheel's share of the bogie
  P yt_front;                      ///< y~ of the front contact
  P yt_bogie;                      ///< y~ of the bogie's resultant
  P front_couple;                  ///< t_front: the front wheel's couple (section 7.4)
  P bogie_shift;                   ///< (t_middle + t_rear) / span: moved from middle to rear
  P yt_rear_minus_middle;          ///< y~_rear - y~_middle
};

/// Whether side_levers found the rocker's lever or the bogie's span collapsed.
template <typename P>
bool collapsed(const SideLevers<P>& side) noexcept {
  return side.lever.mantissa == 0U;
}

/// One side's couples T_i / (m g cos(pitch) cos(roll)) in metres (zero where
/// not usable) and whether each wheel is projected from its axle (its torque
/// is usable). Built whole by side_torques.
template <typename P>
struct SideTorques {
  P couple[3];
  bool from_axle[3];
};

/// The rotated links' bound (fx::rotated): about 1.414 times a link's.
template <typename P>
constexpr std::uint32_t kRotatedLink = static_cast<std::uint32_t>(fx::detail::kRotatedBound<kLinkBound<P>>);
template <typename P>
using Radius = fx::Bounded<P, kRadiusBound<P>>;

/// One side's axles and bogie pivot in the body frame (the contacts lie one
/// wheel radius below the axles along the body z axis, section 2).
template <typename P>
struct SideAxles {
  fx::BoundedPoint<P, kRotatedLink<P>> pivot;
  fx::BoundedPoint<P, kRotatedLink<P>> front;
  fx::BoundedPoint<P, 2U * kRotatedLink<P>> middle;  ///< the pivot plus its rotated link
  fx::BoundedPoint<P, 2U * kRotatedLink<P>> rear;
};

/// a + b for two points.
template <typename P, std::uint32_t A, std::uint32_t B>
fx::BoundedPoint<P, A + B> sum(fx::BoundedPoint<P, A> a, fx::BoundedPoint<P, B> b) noexcept {
  return fx::BoundedPoint<P, A + B>{fx::add(a.x, b.x), fx::add(a.z, b.z)};
}

/// One side's joints as the sines and cosines of the rocker's angle and of
/// the bogie's angle to the body (rocker + bogie), as fx::sincos gives them
/// (side_joints: each written where fx::sincos returns it, not copied
/// there from a bounded pair; side_axles bounds them, unit_sincos).
struct SideJoints {
  fx::SinCos rocker;
  fx::SinCos bogie;
};

/// fx::sincos's sine and cosine as the bounded values of fx::bound_sincos,
/// without its four tests: fx::sincos gives magnitudes of at most 2^30
/// (fx::detail::trig::signed_q1_30's contract), so the tests never fire. A
/// run over every Q3.28 angle of the joints' range (|rocker + bogie| <= 1.6
/// rad, 8.6 10^8 angles, round 14) found none beyond; test_wheel_load
/// (StaticsArithmetic.JointSinesAndCosinesAreWithinOne) samples it. 64
/// instructions per step fewer on the Cortex-M4.
fx::BoundedSinCos unit_sincos(fx::SinCos sc) noexcept {
  using Unit = fx::Bounded<fx::Q1_30, 0x40000000U>;
  return fx::BoundedSinCos{Unit::trusted(sc.sin.raw()), Unit::trusted(sc.cos.raw())};
}


template <typename P>
SideAxles<P> side_axles(const StaticsConstants<P>& k, const SideJoints& joints) noexcept {
  const fx::BoundedSinCos rocker_sc = unit_sincos(joints.rocker);
  const fx::BoundedSinCos bogie_sc = unit_sincos(joints.bogie);
  // Built whole from its points (a zeroed record filled in is a memset).
  fx::BoundedPoint<P, kRotatedLink<P>> pivot{};
  fx::BoundedPoint<P, kRotatedLink<P>> front{};
  fx::BoundedPoint<P, kRotatedLink<P>> middle{};
  fx::BoundedPoint<P, kRotatedLink<P>> rear{};
  // The bogie's angle to the body (up to 1.6 rad) may have a negative cosine.
  rotate<kRotationRounding<P>, SignOf::negative, SignOf::positive>(k.rocker_bogie, rocker_sc, pivot);
  rotate<kRotationRounding<P>, SignOf::positive, SignOf::positive>(k.rocker_front, rocker_sc, front);
  rotate<kRotationRounding<P>, SignOf::positive, SignOf::any>(k.bogie_middle, bogie_sc, middle);
  rotate<kRotationRounding<P>, SignOf::negative, SignOf::any>(k.bogie_rear, bogie_sc, rear);
  return SideAxles<P>{pivot, front, sum(middle, pivot), sum(rear, pivot)};
}

/// Gravity's direction in the body frame (section 3.2).
struct GravityFrame {
  fx::Q1_30 sin_pitch;        ///< kept for the drawbar pulls (WheelLoadResult::sin_pitch)
  fx::Q1_30 normal_fraction;  ///< cos(pitch) cos(roll): the weight's share normal to the ground
  fx::NormalisedReciprocal inv_normal_fraction;
  Kx kx;  ///< tan(pitch) / cos(roll)
  Ky ky;  ///< tan(roll)
};

/// z of a wheel's contact, one radius below its axle.
template <typename P, std::uint32_t M>
auto contact_z(fx::BoundedPoint<P, M> axle, Radius<P> radius) noexcept {
  return fx::sub(axle.z, radius);
}

/// x~ of a wheel: from its axle when its torque is used (the soil force
/// reaches the link there, section 12), else from its contact.
template <typename P, std::uint32_t M>
auto wheel_xt(fx::BoundedPoint<P, M> axle, bool from_axle, Radius<P> radius, Kx kx) noexcept {
  const auto below = contact_z(axle, radius);
  using Z = decltype(below);
  const Z z = from_axle ? fx::widen<Z::max_mag>(axle.z) : below;
  return project(axle.x, z, kx);
}

/// One side's projected levers, built whole; a lever's reciprocal of
/// mantissa 0 when the rocker's lever or the bogie's span collapsed
/// (collapsed()). The positions are bounded (fx::Bounded): every projected
/// coordinate within +-30 m, a span or lever within +-59 m, inside Q6.25's
/// +-64 m. Out of line: inlined into the three passes, its values took
/// loads_of_valid's frame from 512 to 600 bytes on the Cortex-M0 and
/// sw_step's stack to 1,064 B, beyond the 1 KiB budget; out of line it is
/// 1,024 B (docs/performance.md, session 17).
template <typename P>
[[gnu::noinline]] SideLevers<P> side_levers(const StaticsConstants<P>& k, const SideJoints& joints,
                                            StaticsLength<P> y_side, const GravityFrame& g, const SideTorques<P>& tq,
                                            fx::Status& st) noexcept {
  const SideAxles<P> axles = side_axles(k, joints);
  const auto xt_f = wheel_xt(axles.front, tq.from_axle[0], k.wheel_radius, g.kx);
  const auto xt_m = wheel_xt(axles.middle, tq.from_axle[1], k.wheel_radius, g.kx);
  const auto xt_r = wheel_xt(axles.rear, tq.from_axle[2], k.wheel_radius, g.kx);
  const auto xt_b = project(axles.pivot.x, axles.pivot.z, g.kx);
  const P span = fx::sub(xt_m, xt_r).q();
  const P lever = fx::sub(xt_f, xt_b).q();
  if ((lever < kLeverGuard<P>) || (span < kLeverGuard<P>)) {
    return SideLevers<P>{};
  }
  // The lateral positions (section 3.5) before the divisions, so that the
  // contacts' heights, the radius, y_side and ky are not kept across the
  // reciprocals' calls (round 16).
  const auto yt_m = project(y_side, contact_z(axles.middle, k.wheel_radius), g.ky);
  const auto yt_r = project(y_side, contact_z(axles.rear, k.wheel_radius), g.ky);
  const P yt_front = project(y_side, contact_z(axles.front, k.wheel_radius), g.ky).q();
  // One division per lever, its quotients as products (section 12.5). The
  // span is at least the guard: in every cycle's pass on the Cortex-M4 both
  // in place without the reciprocal's and the shift's tests (over; with
  // them, in place took no more than 1 instruction per side off the step,
  // without them 25), elsewhere quotient_raw's call.
  const fx::NormalisedReciprocal inv_span = detail::reciprocal_of(span);
  const P beta = over(fx::sub(xt_b, xt_r).q(), inv_span, st);
  const P bogie_shift = over(plus(tq.couple[1], tq.couple[2], st), inv_span, st);
  // beta yt_m + (1 - beta) yt_r, written so that beta multiplies a difference.
  return SideLevers<P>{fx::neg(xt_b).q(),
                       detail::reciprocal_of(lever),
                       beta,
                       yt_front,
                       plus(yt_r.q(), times(beta, fx::sub(yt_m, yt_r).q(), st), st),
                       tq.couple[0],
                       bogie_shift,
                       fx::sub(yt_r, yt_m).q()};
}

/// Whether |v| <= limit for a validated limit (0 < limit <= 1.05 rad, so
/// 2 limit < 2^31): v + limit in [0, 2 limit] as a wrapping 32-bit sum, one
/// comparison (a v beyond either end wraps above 2 limit). within()'s
/// verdict.
bool within_limit(AngleRad v, AngleRad limit) noexcept {
  const auto l = static_cast<std::uint32_t>(limit.raw());
  return (static_cast<std::uint32_t>(v.raw()) + l) <= (2U * l);
}

/// The attitude and joint angles against the (already validated) limits.
WheelLoadStatus check_inputs(const RoverParams& params, const RoverAttitude& attitude,
                             const JointAnglesRad& joints) noexcept {
  if (!within_limit(attitude.pitch_rad, params.attitude_limit_rad) ||
      !within_limit(attitude.roll_rad, params.attitude_limit_rad)) {
    return WheelLoadStatus::attitude_out_of_range;
  }
  for (std::uint32_t s = 0U; s < kSideCount; ++s) {
    if (!within_limit(joints.rocker_rad[s], params.rocker_limit_rad) ||
        !within_limit(joints.bogie_rad[s], params.bogie_limit_rad)) {
      return WheelLoadStatus::joint_out_of_range;
    }
  }
  return WheelLoadStatus::ok;
}

GravityFrame gravity_frame(const RoverAttitude& attitude, fx::Status& st) noexcept {
  // Both angles are within the attitude limit (check_inputs), at most 1.05
  // rad (kMaxAttitudeLimit): fx::sincos's bounded form, the same bits.
  using Attitude =
      fx::Bounded<fx::Q3_28, static_cast<std::uint32_t>(fx::constant<fx::Q3_28>(limits::kMaxAttitudeLimitRad).raw())>;
  const fx::SinCos pitch_sc = fx::sincos(Attitude::trusted(attitude.pitch_rad.raw()), st);
  const fx::SinCos roll_sc = fx::sincos(Attitude::trusted(attitude.roll_rad.raw()), st);
  // cos(pitch) cos(roll) >= cos^2(1.05 rad) > 0.24: the reciprocals exist.
  // Built whole (no zeroed frame filled in: a memset on the Cortex-M0).
  // Two cosines of magnitude at most one (unit_sincos): their product is
  // at most one, fx::mul's bits as a bounded product without its check.
  const fx::Q1_30 normal_fraction =
      product_of_non_negative<fx::Q1_30, kProjectionRounding<Fine>>(unit_sincos(pitch_sc).cos, unit_sincos(roll_sc).cos);
  const fx::NormalisedReciprocal inv_normal_fraction = detail::reciprocal_of_positive(normal_fraction);
  // Within kKxBound and kKyBound (their comment) for attitudes within the
  // validated limit, rounding included: trusted, not tested per cycle.
  const Kx kx = Kx::trusted(guarded_quotient_in<K, true>(pitch_sc.sin, inv_normal_fraction, st).raw());
  const Ky ky =
      Ky::trusted(guarded_quotient_in<K, true>(roll_sc.sin, detail::reciprocal_of_positive(roll_sc.cos), st).raw());
  return GravityFrame{pitch_sc.sin, normal_fraction, inv_normal_fraction, kx, ky};
}

/// The trigonometry of one cycle: gravity's direction and both sides'
/// joints, and the flags their operations raised. The same in every pass and
/// both balances (with and without the torques), so computed once per call
/// of wheel_loads(): before session 18 each pass took its own, up to 36
/// sines and cosines in a call that falls back to the loads without torques
/// after three passes with them.
struct CycleTrig {
  GravityFrame gravity;
  SideJoints side[kSideCount];
  fx::Status status;
};

SideJoints side_joints(AngleRad rocker_rad, AngleRad bogie_rad, fx::Status& st) noexcept {
  // Both angles are within their limits (check_inputs), at most 0.8 rad
  // (kMaxJointLimit): the sum is within 1.6 rad, far inside Q3.28's 8 rad,
  // so fx::add's overflow test (which never raised) is left out.
  using Joint = fx::Bounded<fx::Q3_28, static_cast<std::uint32_t>(fx::constant<fx::Q3_28>(limits::kMaxJointLimitRad).raw())>;
  const Joint rocker = Joint::trusted(rocker_rad.raw());
  // One range reduction per angle (fx::sincos), the bits of sin and cos
  // apart; the bounded form, both angles within 1.6 rad.
  return SideJoints{fx::sincos(rocker, st), fx::sincos(fx::add(rocker, Joint::trusted(bogie_rad.raw())), st)};
}

/// Out of line: its sines and cosines stay off the stack of the passes.
[[gnu::noinline]] CycleTrig cycle_trig(const RoverAttitude& attitude, const JointAnglesRad& joints) noexcept {
  fx::Status st;
  // Built whole (the elements of a braced list are evaluated in order, so
  // the status comes after the flags it collects).
  return CycleTrig{gravity_frame(attitude, st),
                   {side_joints(joints.rocker_rad[0], joints.bogie_rad[0], st),
                    side_joints(joints.rocker_rad[1], joints.bogie_rad[1], st)},
                   st};
}

/// The weight and where it acts. Every balance is solved in fractions of the
/// normal weight m g cos(pitch) cos(roll) (section 7.4): the weight is 1, a
/// moment is a length and a couple is T / (m g cos(pitch) cos(roll)).
template <typename P>
struct Body {
  WheelLoadN weight_normal_n;  ///< m g cos(pitch) cos(roll), newtons
  fx::NormalisedReciprocal inv_weight;   ///< 1 / (m g), from the exact product of mass and gravity
  P com_yt;                    ///< projected lateral position of the centre of mass
  P pivot_moment;              ///< each rocker pivot's moment, equal by the differential (3.4)
};

template <typename P>
Body<P> body_of(const StaticsConstants<P>& k, const GravityFrame& g) noexcept {
  // The weight (at most 10 kN) times any Q1.30 value fits Q15.16: fx::mul's
  // bits as a bounded product, with no check of the format's limits.
  using Fraction = fx::Bounded<fx::Q1_30, fx::kMaxBound>;
  const WheelLoadN weight_normal_n{
      product_of_non_negative<LoadQ, kRotationRounding<P>>(k.weight_n, Fraction::trusted(g.normal_fraction.raw()))};
  const auto com_xt = project(k.com_x, k.com_z, g.kx);
  const auto com_yt = project(k.com_y, k.com_z, g.ky);
  constexpr auto kHalfRaw = static_cast<std::int32_t>(1U << static_cast<std::uint32_t>(P::frac_bits - 1));
  return Body<P>{weight_normal_n, k.inv_weight, com_yt.q(),
                 fx::mul<P, kProjectionRounding<P>>(fx::bounded_raw<P, kHalfRaw>(), com_xt).q()};
}

/// Each side's pivot moment less its front couple, M - t_front (section 12).
template <typename P>
P side_moment(const Body<P>& body, const SideLevers<P>& side, fx::Status& st) noexcept {
  return minus(body.pivot_moment, side.front_couple, st);
}

/// One side's Z_s and Y_s (section 3.5).
template <typename P>
struct Lateral {
  P z;
  P y;
};

/// Forced inline, as plus_torque_terms: the two of them in their caller took
/// 31 instructions off the Cortex-M4's step and 63 off the Cortex-M0's, with
/// the same stack (side_shares inlined too: 10 fewer on the M4, 1 more on the
/// M0 and 32 B more stack: not done).
template <typename P>
SW_FX_INLINE Lateral<P> lateral_of(const SideLevers<P>& side, fx::Status& st) noexcept {
  // Y_s = (b y~_F + a y~_bog) / (a + b) = y~_bog + b Z_s: no product of two
  // lengths is formed (section 7.4), so Y_s stays within Q6.25.
  const P z = over(minus(side.yt_front, side.yt_bogie, st), side.lever, st);
  return Lateral<P>{z, plus(side.yt_bogie, times(side.b, z, st), st)};
}

/// The torque terms so far plus side s's q_s - t_front,s Z_s, added in that
/// order (each step saturates).
template <typename P>
SW_FX_INLINE P plus_torque_terms(P terms, const SideLevers<P>& side, P z, fx::Status& st) noexcept {
  const P with_shift = plus(terms, times(side.bogie_shift, side.yt_rear_minus_middle, st), st);
  return minus(with_shift, times(side.front_couple, z, st), st);
}

/// The left side's share of the weight from the roll balance; `collapsed`
/// when the lateral span did. `clean_to_shares`: the status was still clean
/// after the roll moment, so whatever overflows later is a side's total or
/// a share.
template <typename P>
struct LeftTotal {
  P total;
  bool collapsed;
  bool clean_to_shares;
};

/// Roll balance (sections 3.5, 7.4 and 12).
template <typename P>
LeftTotal<P> left_side_total(const SideLevers<P> (&side)[kSideCount], const Body<P>& body, fx::Status& st) noexcept {
  // sum_s (q_s - t_front,s Z_s): exactly zero without torques, so that the
  // loads then keep the bits of the statics without torques.
  const Lateral<P> left = lateral_of(side[0], st);
  const P left_terms = plus_torque_terms(P::zero(), side[0], left.z, st);
  const Lateral<P> right = lateral_of(side[1], st);
  const P torque_terms = plus_torque_terms(left_terms, side[1], right.z, st);
  const P lateral_span = minus(left.y, right.y, st);
  if (lateral_span < kMinLever<P>) {
    return LeftTotal<P>{P::zero(), true, false};
  }
  const P roll_moment =
      minus(minus(minus(body.com_yt, times(body.pivot_moment, plus(left.z, right.z, st), st), st), torque_terms, st),
            right.y, st);
  const bool clean_to_shares = st.ok();
  return LeftTotal<P>{over(roll_moment, detail::reciprocal_of(lateral_span), st), false,
                      clean_to_shares};
}

/// One side's wheels' shares of the normal weight: front, middle, rear.
template <typename P>
struct SideShares {
  P wheel[kWheelsPerSide];
};

/// The rocker and the bogie of one side carrying `side_total`.
template <typename P>
SideShares<P> side_shares(const SideLevers<P>& side, const Body<P>& body, P side_total, fx::Status& st) noexcept {
  const P front = over(
      plus(side_moment(body, side, st), times(side.b, side_total, st), st), side.lever, st);
  const P bogie = minus(side_total, front, st);
  const P middle = minus(times(side.beta, bogie, st), side.bogie_shift, st);
  return SideShares<P>{{front, middle, minus(bogie, middle, st)}};
}

/// Each wheel's share of the normal weight (wheel i = 3 s + k: side s's
/// wheel k), each side's as side_shares returns it, so that it is built in
/// place (a copy of the six shares per cycle before, round 16).
template <typename P>
struct Shares {
  SideShares<P> side[kSideCount];
};

/// Wheel i's share.
template <typename P>
P share_of(const Shares<P>& support, std::uint32_t i) noexcept {
  return support.side[i / kWheelsPerSide].wheel[i % kWheelsPerSide];
}

/// The rockers and the bogies, from the left side's total.
template <typename P>
Shares<P> support_forces(const SideLevers<P> (&side)[kSideCount], const Body<P>& body, P left_total,
                         fx::Status& st) noexcept {
  const P right_total = minus(kOne<P>, left_total, st);
  return Shares<P>{{side_shares(side[0], body, left_total, st), side_shares(side[1], body, right_total, st)}};
}

/// Bit i of fallback_mask: set when wheel i's torque is not usable.
constexpr std::uint32_t fallback_bit(const DriveTorques& torques, std::uint32_t i) noexcept {
  return torques.usable[i] ? 0U : (1U << i);
}

/// The wheels whose torque is not usable (bit i: wheel i). The six bits as
/// one expression, not a loop that tests and branches per wheel.
std::uint8_t fallback_mask(const DriveTorques& torques) noexcept {
  static_assert(kWheelCount == 6U, "one bit per wheel");
  return static_cast<std::uint8_t>(fallback_bit(torques, 0U) | fallback_bit(torques, 1U) | fallback_bit(torques, 2U) |
                                   fallback_bit(torques, 3U) | fallback_bit(torques, 4U) | fallback_bit(torques, 5U));
}

/// Wheel i's couple T / (m g cos(pitch) cos(roll)) in metres; zero where its
/// torque is not usable. Raises overflow in `st` when it leaves P (in Q6.25:
/// more than 64 m times the normal weight). One function per format: every
/// cycle's pass takes it only where couples_of cannot take couple_in_range.
template <typename P>
P couple_of(const DriveTorques& torques, std::uint32_t i, const Body<P>& body, const GravityFrame& g,
            fx::Status& st) noexcept {
  if (!torques.usable[i]) {
    return P::zero();
  }
  // The every-cycle pass comes here only when couples_of finds a reciprocal
  // or shift out of range, which no valid rover reaches: the called
  // quotient, not one in place.
  const P per_weight = detail::quotient<P>(torques.torque_nm[i].q(), body.inv_weight, st);
  return over(per_weight, g.inv_normal_fraction, st);
}

/// The couples of the side whose first wheel is `first`, each projected from
/// its axle where its torque is usable, from its contact where not.
template <typename P>
SideTorques<P> side_torques(const DriveTorques& torques, std::uint32_t first, const Body<P>& body,
                            const GravityFrame& g, fx::Status& st) noexcept {
  return SideTorques<P>{{couple_of(torques, first, body, g, st), couple_of(torques, first + 1U, body, g, st),
                         couple_of(torques, first + 2U, body, g, st)},
                        {torques.usable[first], torques.usable[first + 1U], torques.usable[first + 2U]}};
}

/// Both sides' couples (side_torques), the left side's first.
template <typename P>
struct Couples {
  SideTorques<P> side[kSideCount];
};

/// The couples' two reciprocals, 1 / (m g) and 1 / (cos(pitch) cos(roll)),
/// as the mantissas and shifts of detail::quotient_raw_in_range, tested once
/// per cycle.
struct CoupleDivisors {
  std::uint32_t weight_mantissa;
  std::uint32_t weight_shift;
  std::uint32_t normal_mantissa;
  std::uint32_t normal_shift;
};

/// couple_of with its two quotients' reciprocals and shifts tested by the
/// caller (couples_of): the same bits and flags.
template <typename P>
SW_FX_INLINE P couple_in_range(const DriveTorques& torques, std::uint32_t i, const CoupleDivisors& d,
                               fx::Status& st) noexcept {
  if (!torques.usable[i]) {
    return P::zero();
  }
  const std::int32_t per_weight =
      detail::quotient_raw_in_range(torques.torque_nm[i].raw(), d.weight_mantissa, d.weight_shift, st);
  return P::from_raw(detail::quotient_raw_in_range(per_weight, d.normal_mantissa, d.normal_shift, st));
}

/// side_torques from couple_in_range. Called (twice per cycle): in place,
/// the twelve quotients cost 1.1 KiB of flash for 25 instructions per step.
template <typename P>
SideTorques<P> side_torques_in_range(const DriveTorques& torques, std::uint32_t first, const CoupleDivisors& divisors,
                                     fx::Status& st) noexcept {
  // Read once into values of its own: a raised flag is a byte's store, which
  // may alias the caller's record, so each couple read it again (round 16:
  // 4 instructions per step fewer on the Cortex-M4).
  const CoupleDivisors d = divisors;
  return SideTorques<P>{{couple_in_range<P>(torques, first, d, st), couple_in_range<P>(torques, first + 1U, d, st),
                         couple_in_range<P>(torques, first + 2U, d, st)},
                        {torques.usable[first], torques.usable[first + 1U], torques.usable[first + 2U]}};
}

/// Both sides' couples. In every cycle's pass where the quotients are in
/// place, whether 1 / (m g) exists and its shift is within 1 to 63 is
/// tested once for the six wheels, not in each of the twelve quotients: it
/// is for every valid rover (m g > 0; the weight's shift leaves the range
/// only for a weight below about 2^-7 N or above 2^33 N), and elsewhere
/// side_torques decides each quotient as before. 1 / (cos(pitch)
/// cos(roll)) needs no test (below).
template <typename P>
Couples<P> couples_of(const DriveTorques& torques, const Body<P>& body, const GravityFrame& g,
                      fx::Status& st) noexcept {
  if constexpr (kEveryCycle<P> && kQuotientsInline) {
    constexpr std::int32_t kTorqueFracBits = TorqueNm::q_type::frac_bits;
    const std::int32_t weight_shift = (kTorqueFracBits + body.inv_weight.scale) - P::frac_bits;
    const std::int32_t normal_shift = (P::frac_bits + g.inv_normal_fraction.scale) - P::frac_bits;
    // 1 / (cos(pitch) cos(roll)) exists and its shift is 29 to 32: the
    // normal fraction is within [cos^2(1.05), 1] = [0.2476, 1] for attitudes
    // within the validated limit, a positive raw Q1.30 value of 28 to 31 bits
    // (gravity_frame; StaticsArithmetic.GravitySlopesAreWithinTheirBounds
    // checks the shift at the limit's corners): only the weight's is tested.
    if ((body.inv_weight.mantissa != 0U) && detail::shift_in_range(weight_shift)) {
      const CoupleDivisors d{body.inv_weight.mantissa, static_cast<std::uint32_t>(weight_shift),
                             g.inv_normal_fraction.mantissa, static_cast<std::uint32_t>(normal_shift)};
      return Couples<P>{{side_torques_in_range<P>(torques, 0U, d, st), side_torques_in_range<P>(torques, 3U, d, st)}};
    }
  }
  return Couples<P>{{side_torques(torques, 0U, body, g, st), side_torques(torques, 3U, body, g, st)}};
}

/// The wheel of the smallest share (the first of equal ones).
template <typename P>
std::uint32_t lowest_share(const Shares<P>& support) noexcept {
  std::uint32_t lowest = 0U;
  for (std::uint32_t i = 1U; i < kWheelCount; ++i) {
    if (share_of(support, i) < share_of(support, lowest)) {
      lowest = i;
    }
  }
  return lowest;
}

/// Whether a share is negative (then the lowest is): the sign bit of the
/// six shares' bitwise OR, one test where lowest_share's search costs about
/// 50 instructions per cycle; the search runs only for a tip-over.
template <typename P>
constexpr std::uint32_t share_bits(const Shares<P>& support, std::uint32_t i) noexcept {
  return static_cast<std::uint32_t>(share_of(support, i).raw());
}
template <typename P>
bool any_negative(const Shares<P>& support) noexcept {
  static_assert(kWheelCount == 6U, "six shares");
  const std::uint32_t ored = share_bits(support, 0U) | share_bits(support, 1U) | share_bits(support, 2U) |
                             share_bits(support, 3U) | share_bits(support, 4U) | share_bits(support, 5U);
  return (ored >> 31U) != 0U;
}

/// A wheel's share times the normal weight, for a share in [0, 1] (a clean
/// pass's: normal_loads) and a weight of at least zero. The product is then
/// at most the weight, within Q15.16 whatever it is: fx::mul's bits as a
/// bounded product (fx::Bounded), with no check of the format's limits and,
/// in every cycle's pass, no call (fx::mul<LoadQ>'s call and check were six
/// per cycle before). Forced inline: called, the six products cost the
/// Cortex-M4 12 instructions and the Cortex-M0 39 more per step.
template <typename P>
SW_FX_INLINE WheelLoadN load_of(P share, LoadQ weight_normal) noexcept {
  using Share = fx::Bounded<P, bound_in<P>(1.0)>;
  using Weight = fx::Bounded<LoadQ, fx::kMaxBound>;
  return WheelLoadN{
      product_of_non_negative<LoadQ, kRotationRounding<P>>(Share::trusted(share.raw()), Weight::trusted(weight_normal.raw()))};
}

/// The normal loads (each wheel's share times the normal weight): tip_over
/// when a share is negative.
template <typename P>
WheelLoadResult normal_loads(const Shares<P>& support, const Body<P>& body, const GravityFrame& g,
                             AngleRad pitch_rad, fx::Status& st) noexcept {
  if (any_negative(support)) {
    WheelLoadResult r = failed(WheelLoadStatus::tip_over);
    r.lifting_wheel = lowest_share(support);
    return r;
  }
  if (!st.ok()) {
    // Only the Q15.16 pass gets here with an earlier overflow and no
    // negative share (loads_in; docs/coverage.md).
    return failed(WheelLoadStatus::overflow);  // GCOVR_EXCL_LINE
  }
  // After a clean pass the shares are at least zero and sum to one exactly
  // (a side's three to its total, the two totals to one), so each is at most
  // one and its load at most the normal weight: the products cannot
  // overflow, and the result is built whole (a zeroed one filled in is a
  // memset).
  const LoadQ weight = body.weight_normal_n.q();
  const SideShares<P>& left = support.side[0];
  const SideShares<P>& right = support.side[1];
  return WheelLoadResult{{load_of(left.wheel[0], weight), load_of(left.wheel[1], weight),
                          load_of(left.wheel[2], weight), load_of(right.wheel[0], weight),
                          load_of(right.wheel[1], weight), load_of(right.wheel[2], weight)},
                         body.weight_normal_n,
                         kWheelCount,
                         pitch_rad,
                         g.sin_pitch,
                         0U,
                         false,
                         WheelLoadStatus::ok};
}

/// The loads in the format P from the constants `k` in P (of parameters
/// that passed validate_rover_params()) and the cycle's trigonometry, at
/// attitude and joint angles within their limits.
template <typename P>
WheelLoadResult loads_in(const StaticsConstants<P>& k, const CycleTrig& trig, AngleRad pitch_rad,
                         const DriveTorques& torques) noexcept {
  // The flags of the trigonometry first, as when each pass computed its own.
  fx::Status st = trig.status;
  const GravityFrame& g = trig.gravity;
  const Body<P> body = body_of<P>(k, g);
  fx::Status couple_st;
  const Couples<P> tq = couples_of(torques, body, g, couple_st);
  // The left side's contacts lie half a track to the left (+y), the right
  // side's to the right.
  const SideLevers<P> side[kSideCount] = {side_levers(k, trig.side[0], k.half_track, g, tq.side[0], st),
                                          side_levers(k, trig.side[1], fx::neg(k.half_track), g, tq.side[1], st)};
  // The levers come from positions, which never leave P: a collapsed one is
  // degenerate whatever else overflowed, the couples included (they only
  // move the levers' loads, not the levers). The lateral span comes after
  // the quotients by them, and is only trusted when none overflowed.
  if (collapsed(side[0]) || collapsed(side[1])) {
    return failed(WheelLoadStatus::degenerate);
  }
  if (!couple_st.ok()) {
    return failed(WheelLoadStatus::overflow);
  }
  const LeftTotal<P> left = left_side_total(side, body, st);
  if (left.collapsed) {
    // A collapsed lateral span. Where another quantity overflowed, Q6.25 and
    // Q10.21 may have saturated the span's own quotients; Q15.16 cannot
    // (kSpanFits), so its answer names the span whatever else overflowed.
    return failed((st.ok() || kSpanFits<P>) ? WheelLoadStatus::degenerate : WheelLoadStatus::overflow);
  }
  const Shares<P> support = support_forces(side, body, left.total, st);
  // After an overflow, Q15.16 still reads the shares for a tip-over: with
  // the couples within range and the span not collapsed, what overflows
  // there is a share or a side's total beyond +-32,768, and as the shares
  // sum to one, a share that large means another is negative. A negative
  // (saturated) share is then a tip-over; without one it stays an
  // overflow (normal_loads). Q6.25 and Q10.21 leave the decision to the
  // next pass, but where only their side totals or shares overflowed (the
  // same argument) they name the wheel of a negative (saturated) share in
  // lifting_wheel, for loads_of_valid.
  if (!st.ok() && !kSpanFits<P>) {
    WheelLoadResult r = failed(WheelLoadStatus::overflow);
    const std::uint32_t lowest = lowest_share(support);
    r.lifting_wheel = (left.clean_to_shares && (share_of(support, lowest).raw() < 0)) ? lowest : kWheelCount;
    return r;
  }
  return normal_loads(support, body, g, pitch_rad, st);
}

/// What loads_of_valid keeps of a pass whose loads it does not take.
struct PassOutcome {
  WheelLoadStatus status;
  std::uint32_t lifting_wheel;
};

PassOutcome outcome_of(const WheelLoadResult& r) noexcept { return PassOutcome{r.status, r.lifting_wheel}; }

/// The result of a pass that did not give loads: every such result of
/// loads_in is failed(status) with its lifting wheel.
WheelLoadResult failed_at(PassOutcome outcome) noexcept {
  WheelLoadResult r = failed(outcome.status);
  r.lifting_wheel = outcome.lifting_wheel;
  return r;
}

/// The loads in Q6.25 from the prepared constants. Where an intermediate leaves that format (a quotient
/// by a lever of a few millimetres, far beyond the stability limit), the
/// same balance in Q10.21 decides whether a wheel lifts or the lateral span
/// collapsed; its loads are too coarse to be taken, so an ok there stays
/// overflow. Where Q10.21 overflows too, Q15.16 is asked only whether a
/// wheel lifts (its degenerate guard rounds too coarsely to be trusted: an
/// overflow left there is a collapsed lateral span in every sampled case,
/// which the step refuses as it refuses degenerate). Each pass is one
/// bounded evaluation: at most three (section 7.4). Where Q15.16 does not
/// say tip-over but Q10.21 checked its span with a clean status and only
/// its side totals or shares overflowed, that is a tip-over (loads_in).
/// `beyond_every_format` tells an overflow of the Q15.16 pass too (the
/// balance itself is beyond +-32,768 normal weights) from one it took for a
/// collapsed span.
WheelLoadResult loads_of_valid(const RoverStatics& constants, const CycleTrig& trig, AngleRad pitch_rad,
                               const DriveTorques& torques, bool& beyond_every_format) noexcept {
  beyond_every_format = false;
  // Every return is of `fine`, so that it is built in the caller's result
  // (a copy of 44 bytes per cycle on the path of every cycle before).
  WheelLoadResult fine = loads_in<Fine>(constants.fine, trig, pitch_rad, torques);
  if (fine.status != WheelLoadStatus::overflow) {
    return fine;
  }
  // The wider passes' loads are never taken: only their status and lifting
  // wheel are kept (a whole result each stayed on the stack).
  const PassOutcome mid = outcome_of(loads_in<Mid>(constants.mid, trig, pitch_rad, torques));
  if ((mid.status == WheelLoadStatus::tip_over) || (mid.status == WheelLoadStatus::degenerate)) {
    fine = failed_at(mid);
    return fine;
  }
  // Q10.21 ok: its loads are too coarse to be taken, and fine's overflow
  // stands (the coarse pass is not run; fine's outcome is no tip-over).
  const bool coarse_run = mid.status == WheelLoadStatus::overflow;
  const PassOutcome coarse =
      coarse_run ? outcome_of(loads_in<Coarse>(constants.coarse, trig, pitch_rad, torques)) : outcome_of(fine);
  if (coarse.status == WheelLoadStatus::tip_over) {
    fine = failed_at(coarse);
    return fine;
  }
  if ((mid.status == WheelLoadStatus::overflow) && (mid.lifting_wheel < kWheelCount)) {
    // Q10.21 checked its lateral span with a clean status and only its side
    // totals or shares overflowed: a tip-over, whatever Q15.16's coarser
    // span said (with bogie spans of 1.8 mm it read -0.044 m where Q10.21
    // read 0.066 m; the sixth fuzz finding of session 14).
    fine = failed_at(PassOutcome{WheelLoadStatus::tip_over, mid.lifting_wheel});
    return fine;
  }
  beyond_every_format = (mid.status == WheelLoadStatus::overflow) && (coarse.status == WheelLoadStatus::overflow);
  return fine;
}

/// The result for parameters that are not valid (invalid_params) or for an
/// attitude or joint angle beyond its limit. Out of line: built in place,
/// its 48 bytes stayed in the caller's frame, which is on the step's deepest
/// stack path (docs/performance.md, session 13). A call, not a named result
/// of its own in loads_with_torques, so that that function's every other
/// return is of its one named result, built in the caller's (a 44-byte copy
/// per cycle less).
[[gnu::noinline]] WheelLoadResult refused_loads(WheelLoadStatus status, const DriveTorques& torques) noexcept {
  WheelLoadResult r = failed(status);
  r.torque_fallback_mask = fallback_mask(torques);
  return r;
}

/// The loads with the torques; when the torques alone would lift a wheel,
/// or their balance is beyond every format (shares summing to one, a share
/// beyond +-32,768 normal weights lifts another wheel), the loads without
/// them, flagged (section 12.4). An overflow the Q15.16 pass took for a
/// collapsed span stays an overflow, as the twin's degenerate. At most two
/// evaluations of loads_of_valid, on one evaluation of the trigonometry, for
/// attitude and joint angles within their limits. Its one return is of `r`,
/// so that it is built in the caller's result.
WheelLoadResult loads_within_limits(const RoverStatics& constants, const RoverAttitude& attitude,
                                    const JointAnglesRad& joints, const DriveTorques& torques) noexcept {
  const CycleTrig trig = cycle_trig(attitude, joints);
  bool beyond_every_format = false;
  WheelLoadResult r = loads_of_valid(constants, trig, attitude.pitch_rad, torques, beyond_every_format);
  r.torque_fallback_mask = fallback_mask(torques);
  const bool torques_unbalanced = (r.status == WheelLoadStatus::tip_over) || beyond_every_format;
  if (torques_unbalanced && (r.torque_fallback_mask != kEveryTorqueFallsBack)) {
    r = loads_of_valid(constants, trig, attitude.pitch_rad, kNoDriveTorques, beyond_every_format);
    r.torque_fallback_mask = kEveryTorqueFallsBack;
    r.torque_overload = (r.status == WheelLoadStatus::ok);
  }
  return r;
}

/// loads_within_limits, attitude and joint angles beyond their limits
/// refused first.
WheelLoadResult loads_with_torques(const RoverParams& params, const RoverStatics& constants,
                                   const RoverAttitude& attitude, const JointAnglesRad& joints,
                                   const DriveTorques& torques) noexcept {
  const WheelLoadStatus input_status = check_inputs(params, attitude, joints);
  if (input_status != WheelLoadStatus::ok) {
    return refused_loads(input_status, torques);
  }
  return loads_within_limits(constants, attitude, joints, torques);
}

}  // namespace

RoverStatics make_rover_statics(const RoverParams& params) noexcept {
  // Within every format for validated parameters (constants_in): no status to read.
  fx::Status st;
  return RoverStatics{constants_in<Fine>(params, st), constants_in<Mid>(params, st), constants_in<Coarse>(params, st)};
}

RoverParamStatus validate_rover_params(const RoverParams& p) noexcept {
  const RoverParamStatus body = validate_body(p);
  return (body != RoverParamStatus::ok) ? body : validate_suspension(p);
}

WheelLoadResult wheel_loads(const PreparedParameters& prepared, const RoverAttitude& attitude,
                            const JointAnglesRad& joints, const DriveTorques& torques) noexcept {
  if (!prepared.ready()) {
    return refused_loads(WheelLoadStatus::invalid_params, torques);
  }
  return loads_with_torques(prepared.rover(), prepared.rover_statics(), attitude, joints, torques);
}

}  // namespace flight
}  // namespace sinkwatch
