// Quasi-static rocker-bogie wheel loads in fixed point; see wheel_load.hpp and
// docs/rover-loads.md (sections 3 and 7). The double twin is
// ground/reference/src/rover_loads.cpp: the two follow the same steps in the
// same order so that a difference points at one line.
#include "sinkwatch/flight/wheel_load.hpp"

#include "sinkwatch/flight/constant_divisor.hpp"
#include "sinkwatch/flight/rover_limits.hpp"

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using W = WideQ;

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
constexpr W kMinLever{fx::constant<W>(0.001)};
constexpr W kHalf{fx::constant<W>(0.5)};
constexpr Ratio kMaxHighSlip{fx::constant<RatioQ>(limits::kMaxHighSlip)};

bool within(LengthM v, LengthM limit) noexcept { return (v <= limit) && (v.raw() >= -limit.raw()); }
bool within(AngleRad v, AngleRad limit) noexcept { return (v <= limit) && (v.raw() >= -limit.raw()); }
bool positive_at_most(AngleRad v, AngleRad limit) noexcept { return (v.raw() > 0) && (v <= limit); }

struct Point {
  W x;
  W z;
};

W wide(LengthM v, fx::Status& st) noexcept { return fx::rescale<W>(v.q(), st); }
W wide(fx::Q1_30 v, fx::Status& st) noexcept { return fx::rescale<W>(v, st); }
Point wide(SidePointM p, fx::Status& st) noexcept { return Point{wide(p.x_m, st), wide(p.z_m, st)}; }

/// Rotation in a side's plane, positive raising the +x end.
Point rotate(Point p, W c, W s, fx::Status& st) noexcept {
  return Point{fx::sub(fx::mul(p.x, c, st), fx::mul(p.z, s, st), st),
               fx::add(fx::mul(p.x, s, st), fx::mul(p.z, c, st), st)};
}

Point plus(Point a, Point b, fx::Status& st) noexcept {
  return Point{fx::add(a.x, b.x, st), fx::add(a.z, b.z, st)};
}

/// v - z k: the coordinate of a point projected along gravity (section 3.2).
W project(W v, W z, W k, fx::Status& st) noexcept { return fx::sub(v, fx::mul(z, k, st), st); }

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

/// The lever quantities of one side (sections 3.3 to 3.5 and 12).
struct SideLevers {
  W a;          ///< x~_front - x~_pivot
  W b;          ///< x~_pivot - x~_bogie
  W inv_lever;  ///< 1 / (a + b): the rocker's three quotients as products (section 12.5)
  W beta;       ///< the middle wheel's share of the bogie
  W yt_front;   ///< y~ of the front contact
  W yt_bogie;   ///< y~ of the bogie's resultant
  W front_couple;  ///< T_front: the front wheel's torque (normal-load units, section 12.5)
  W bogie_shift;   ///< (t_middle + t_rear) / span: moved from middle to rear
  W yt_rear_minus_middle;  ///< y~_rear - y~_middle
};

/// One side's torques (zero where not usable) and whether each wheel is
/// projected from its axle (its torque is usable). In the normal-load units
/// of the balances (section 12.5) a couple is the torque itself.
struct SideTorques {
  W couple[3];
  bool from_axle[3]{};
};
/// The suspension's link vectors in the wide format, and the contact offset.
struct Links {
  Point rocker_front;
  Point rocker_bogie;
  Point bogie_middle;
  Point bogie_rear;
  Point down;  ///< one wheel radius down the body z axis
};

/// One side's wheel contacts and the bogie pivot, in the body frame.
struct SideContacts {
  Point pivot_b;
  Point front;
  Point middle;
  Point rear;
};

/// The contacts one radius below the axles along the body z axis (section 2).
SideContacts side_contacts(const Links& l, AngleRad rocker_rad, AngleRad bogie_rad, fx::Status& st) noexcept {
  const fx::Q3_28 rocker = rocker_rad.q();
  // Both angles are within 0.8 rad: the sum cannot overflow Q3.28.
  const fx::Q3_28 bogie_abs = fx::add(rocker, bogie_rad.q(), st);
  // One range reduction per angle (fx::sincos), the bits of sin and cos apart.
  const fx::SinCos rocker_sc = fx::sincos(rocker, st);
  const fx::SinCos bogie_sc = fx::sincos(bogie_abs, st);
  const W cr = wide(rocker_sc.cos, st);
  const W sr = wide(rocker_sc.sin, st);
  const W cb = wide(bogie_sc.cos, st);
  const W sb = wide(bogie_sc.sin, st);
  SideContacts c{};
  c.pivot_b = rotate(l.rocker_bogie, cr, sr, st);
  c.front = plus(rotate(l.rocker_front, cr, sr, st), l.down, st);
  c.middle = plus(plus(c.pivot_b, rotate(l.bogie_middle, cb, sb, st), st), l.down, st);
  c.rear = plus(plus(c.pivot_b, rotate(l.bogie_rear, cb, sb, st), st), l.down, st);
  return c;
}

/// Gravity's direction in the body frame (section 3.2).
struct GravityFrame {
  fx::Q1_30 sin_pitch;  ///< kept for the drawbar pulls (WheelLoadResult::sin_pitch)
  W normal_fraction;  ///< cos(pitch) cos(roll): the weight's share normal to the ground
  W kx;               ///< tan(pitch) / cos(roll)
  W ky;               ///< tan(roll)
};

/// x~ of a wheel: from its axle when its torque is used (the soil force
/// reaches the link there, section 12), else from its contact.
W wheel_xt(Point contact, bool from_axle, W radius, W kx, fx::Status& st) noexcept {
  const W z = from_axle ? fx::add(contact.z, radius, st) : contact.z;
  return project(contact.x, z, kx, st);
}

/// The lateral positions and the torque terms of one side (sections 3.5 and
/// 12.2), from its contacts and its bogie's projected span.
void side_lateral(const SideContacts& c, W y_side, W ky, W inv_span, const SideTorques& tq, SideLevers& out,
                  fx::Status& st) noexcept {
  out.yt_front = project(y_side, c.front.z, ky, st);
  const W yt_m = project(y_side, c.middle.z, ky, st);
  const W yt_r = project(y_side, c.rear.z, ky, st);
  // beta yt_m + (1 - beta) yt_r, written so that beta multiplies a difference.
  out.yt_bogie = fx::add(yt_r, fx::mul(out.beta, fx::sub(yt_m, yt_r, st), st), st);
  out.front_couple = tq.couple[0];
  out.bogie_shift = fx::mul(fx::add(tq.couple[1], tq.couple[2], st), inv_span, st);
  out.yt_rear_minus_middle = fx::sub(yt_r, yt_m, st);
}

/// 1 / v for a lever v >= kMinLever: fx::div(1, v)'s bits from one 64-bit
/// division (rounded_reciprocal_q32); v >= 2^22 raw, so 1 / v <= 2^42 raw.
W reciprocal(W v) noexcept {
  return W::from_raw(static_cast<std::int64_t>(rounded_reciprocal_q32(static_cast<std::uint64_t>(v.raw()))));
}

/// One side: its joint angles and the lateral position of its contacts.
struct SidePose {
  AngleRad rocker_rad;
  AngleRad bogie_rad;
  W y_side;
};

/// One side's projected levers; false when a lever collapsed.
bool side_levers(const Links& l, const SidePose& pose, const GravityFrame& g, const SideTorques& tq, SideLevers& out,
                 fx::Status& st) noexcept {
  const W kx = g.kx;
  const W radius = fx::neg(l.down.z, st);
  const SideContacts c = side_contacts(l, pose.rocker_rad, pose.bogie_rad, st);
  const W xt_f = wheel_xt(c.front, tq.from_axle[0], radius, kx, st);
  const W xt_m = wheel_xt(c.middle, tq.from_axle[1], radius, kx, st);
  const W xt_r = wheel_xt(c.rear, tq.from_axle[2], radius, kx, st);
  const W xt_b = project(c.pivot_b.x, c.pivot_b.z, kx, st);
  out.a = xt_f;
  out.b = fx::neg(xt_b, st);
  const W span = fx::sub(xt_m, xt_r, st);
  const W lever = fx::add(out.a, out.b, st);
  if ((lever < kMinLever) || (span < kMinLever)) {
    return false;
  }
  // One division per lever, its quotients as products (section 12.5): both
  // levers are at least 1 mm, so each reciprocal is at most 1000.
  out.inv_lever = reciprocal(lever);
  const W inv_span = reciprocal(span);
  out.beta = fx::mul(fx::sub(xt_b, xt_r, st), inv_span, st);
  side_lateral(c, pose.y_side, g.ky, inv_span, tq, out, st);
  return true;
}

/// The attitude and joint angles against the (already validated) limits.
WheelLoadStatus check_inputs(const RoverParams& params, const RoverAttitude& attitude,
                             const JointAnglesRad& joints) noexcept {
  if (!within(attitude.pitch_rad, params.attitude_limit_rad) || !within(attitude.roll_rad, params.attitude_limit_rad)) {
    return WheelLoadStatus::attitude_out_of_range;
  }
  for (std::uint32_t s = 0U; s < kSideCount; ++s) {
    if (!within(joints.rocker_rad[s], params.rocker_limit_rad) || !within(joints.bogie_rad[s], params.bogie_limit_rad)) {
      return WheelLoadStatus::joint_out_of_range;
    }
  }
  return WheelLoadStatus::ok;
}


GravityFrame gravity_frame(const RoverAttitude& attitude, fx::Status& st) noexcept {
  const fx::SinCos pitch_sc = fx::sincos(attitude.pitch_rad.q(), st);
  const fx::SinCos roll_sc = fx::sincos(attitude.roll_rad.q(), st);
  const W sin_pitch = wide(pitch_sc.sin, st);
  const W cos_pitch = wide(pitch_sc.cos, st);
  const fx::Q1_30 sin_roll = roll_sc.sin;
  const fx::Q1_30 cos_roll_q = roll_sc.cos;
  const W cos_roll = wide(cos_roll_q, st);
  // cos(pitch) cos(roll) >= cos^2(1.05 rad) > 0.24: the divisions are safe.
  GravityFrame g{};
  g.sin_pitch = pitch_sc.sin;
  g.normal_fraction = fx::mul(cos_pitch, cos_roll, st);
  g.kx = fx::div(sin_pitch, g.normal_fraction, st);
  // Directly from Q1.30: the same quotient as of the operands widened to
  // Q31.32 (the common 2^-30 cancels), on 64-bit operands.
  g.ky = fx::div<W>(sin_roll, cos_roll_q, st);
  return g;
}

/// The weight and where it acts. Every balance is solved in normal-load
/// units (section 12.5): the weight's normal component m g cos(pitch)
/// cos(roll) and the torques as they are, so that the support forces are the
/// normal loads themselves (no division of each torque by cos(pitch) cos(roll)
/// and no product of each support force with it).
struct Body {
  W weight_n;      ///< m g cos(pitch) cos(roll)
  W com_yt;        ///< projected lateral position of the centre of mass
  W pivot_moment;  ///< each rocker pivot's moment, equal by the differential (3.4)
};

Body body_of(const RoverParams& params, const GravityFrame& g, fx::Status& st) noexcept {
  Body b{};
  const W weight_n = fx::mul<W>(params.mass_kg.q(), params.gravity_mps2.q(), st);
  b.weight_n = fx::mul(weight_n, g.normal_fraction, st);
  const W com_xt = project(wide(params.com_x_m, st), wide(params.com_z_m, st), g.kx, st);
  b.com_yt = project(wide(params.com_y_m, st), wide(params.com_z_m, st), g.ky, st);
  b.pivot_moment = fx::mul(fx::mul(kHalf, b.weight_n, st), com_xt, st);
  return b;
}

/// Both sides' levers; false when one collapsed.
bool both_sides(const RoverParams& params, const JointAnglesRad& joints, const GravityFrame& g,
                const SideTorques (&tq)[kSideCount], SideLevers (&side)[kSideCount], fx::Status& st) noexcept {
  const W half_track = fx::mul(kHalf, wide(params.track_width_m, st), st);
  const Links links{wide(params.rocker_front_axle, st), wide(params.rocker_bogie_pivot, st),
                    wide(params.bogie_middle_axle, st), wide(params.bogie_rear_axle, st),
                    Point{W::zero(), fx::neg(wide(params.wheel_radius_m, st), st)}};
  for (std::uint32_t s = 0U; s < kSideCount; ++s) {
    const W y_side = (s == 0U) ? half_track : fx::neg(half_track, st);
    const SidePose pose{joints.rocker_rad[s], joints.bogie_rad[s], y_side};
    if (!side_levers(links, pose, g, tq[s], side[s], st)) {
      return false;
    }
  }
  return true;
}

/// Each side's pivot moment less its front couple, M - t_front (section 12).
W side_moment(const Body& body, const SideLevers& side, fx::Status& st) noexcept {
  return fx::sub(body.pivot_moment, side.front_couple, st);
}

/// Roll balance (sections 3.5 and 12): the left side's support force; false
/// when the lateral span collapsed.
bool left_side_total(const SideLevers (&side)[kSideCount], const Body& body, W& left, fx::Status& st) noexcept {
  W big_y[kSideCount]{};
  W big_z[kSideCount]{};
  // sum_s (q_s - t_front,s Z_s): exactly zero without torques, so that the
  // loads then keep the bits of the statics without torques.
  W torque_terms = W::zero();
  for (std::uint32_t s = 0U; s < kSideCount; ++s) {
    const W moment = fx::add(fx::mul(side[s].b, side[s].yt_front, st), fx::mul(side[s].a, side[s].yt_bogie, st), st);
    big_y[s] = fx::mul(moment, side[s].inv_lever, st);
    big_z[s] = fx::mul(fx::sub(side[s].yt_front, side[s].yt_bogie, st), side[s].inv_lever, st);
    torque_terms = fx::add(torque_terms, fx::mul(side[s].bogie_shift, side[s].yt_rear_minus_middle, st), st);
    torque_terms = fx::sub(torque_terms, fx::mul(side[s].front_couple, big_z[s], st), st);
  }
  const W lateral_span = fx::sub(big_y[0], big_y[1], st);
  if (lateral_span < kMinLever) {
    return false;
  }
  const W roll_moment = fx::sub(fx::sub(fx::sub(fx::mul(body.weight_n, body.com_yt, st),
                                                fx::mul(body.pivot_moment, fx::add(big_z[0], big_z[1], st), st), st),
                                        torque_terms, st),
                                fx::mul(body.weight_n, big_y[1], st), st);
  left = fx::div(roll_moment, lateral_span, st);
  return true;
}

/// The roll balance, the rockers and the bogies: each wheel's support force
/// along gravity. False when the lateral span collapsed.
bool support_forces(const SideLevers (&side)[kSideCount], const Body& body, W (&support)[kWheelCount],
                    fx::Status& st) noexcept {
  W side_total[kSideCount]{};
  if (!left_side_total(side, body, side_total[0], st)) {
    return false;
  }
  side_total[1] = fx::sub(body.weight_n, side_total[0], st);
  for (std::uint32_t s = 0U; s < kSideCount; ++s) {
    const W front = fx::mul(fx::add(side_moment(body, side[s], st), fx::mul(side[s].b, side_total[s], st), st),
                            side[s].inv_lever, st);
    const W bogie = fx::sub(side_total[s], front, st);
    const W middle = fx::sub(fx::mul(side[s].beta, bogie, st), side[s].bogie_shift, st);
    support[(3U * s) + 0U] = front;
    support[(3U * s) + 1U] = middle;
    support[(3U * s) + 2U] = fx::sub(bogie, middle, st);
  }
  return true;
}

/// The wheels whose torque is not usable (bit i: wheel i).
std::uint8_t fallback_mask(const DriveTorques& torques) noexcept {
  std::uint32_t mask = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if (!torques.usable[i]) {
      mask |= (1U << i);
    }
  }
  return static_cast<std::uint8_t>(mask);
}

/// The usable torques, exact in the normal-load units of the balances
/// (section 12.5); zero and projected from the contact where not usable.
void side_torques(const DriveTorques& torques, SideTorques (&tq)[kSideCount], fx::Status& st) noexcept {
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    SideTorques& side = tq[i / 3U];
    const std::uint32_t k = i % 3U;
    side.from_axle[k] = torques.usable[i];
    side.couple[k] = W::zero();
    if (torques.usable[i]) {
      side.couple[k] = fx::rescale<W>(torques.torque_nm[i].q(), st);
    }
  }
}

/// The normal loads (the support forces in normal-load units): tip_over
/// when one is negative.
WheelLoadResult normal_loads(const W (&support)[kWheelCount], const Body& body, const GravityFrame& g,
                             AngleRad pitch_rad, fx::Status& st) noexcept {
  std::uint32_t lowest = 0U;
  for (std::uint32_t i = 1U; i < kWheelCount; ++i) {
    if (support[i] < support[lowest]) {
      lowest = i;
    }
  }
  if (support[lowest].raw() < 0) {
    WheelLoadResult r = failed(WheelLoadStatus::tip_over);
    r.lifting_wheel = lowest;
    return r;
  }
  WheelLoadResult r{};
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    r.load_n[i] = WheelLoadN{fx::rescale<LoadQ>(support[i], st)};
  }
  r.weight_normal_n = WheelLoadN{fx::rescale<LoadQ>(body.weight_n, st)};
  r.pitch_rad = pitch_rad;
  r.sin_pitch = g.sin_pitch;
  if (!st.ok()) {
    // Defensive, unreachable after the tip-over check (docs/coverage.md).
    return failed(WheelLoadStatus::overflow);  // GCOVR_EXCL_LINE
  }
  r.lifting_wheel = kWheelCount;
  r.status = WheelLoadStatus::ok;
  return r;
}

/// The loads for parameters that passed validate_rover_params().
WheelLoadResult loads_of_valid(const RoverParams& params, const RoverAttitude& attitude, const JointAnglesRad& joints,
                               const DriveTorques& torques) noexcept {
  const WheelLoadStatus input_status = check_inputs(params, attitude, joints);
  if (input_status != WheelLoadStatus::ok) {
    return failed(input_status);
  }
  fx::Status st;
  const GravityFrame g = gravity_frame(attitude, st);
  const Body body = body_of(params, g, st);
  SideTorques tq[kSideCount]{};
  side_torques(torques, tq, st);
  SideLevers side[kSideCount]{};
  W support[kWheelCount]{};
  if (!both_sides(params, joints, g, tq, side, st) || !support_forces(side, body, support, st)) {
    return failed(st.ok() ? WheelLoadStatus::degenerate : WheelLoadStatus::overflow);
  }
  if (!st.ok()) {
    return failed(WheelLoadStatus::overflow);
  }
  return normal_loads(support, body, g, attitude.pitch_rad, st);
}

/// The loads with the torques; when the torques alone would lift a wheel,
/// the loads without them, flagged (section 12.4). At most two evaluations.
WheelLoadResult loads_with_torques(const RoverParams& params, const RoverAttitude& attitude,
                                   const JointAnglesRad& joints, const DriveTorques& torques) noexcept {
  WheelLoadResult r = loads_of_valid(params, attitude, joints, torques);
  r.torque_fallback_mask = fallback_mask(torques);
  if ((r.status == WheelLoadStatus::tip_over) && (r.torque_fallback_mask != kEveryTorqueFallsBack)) {
    r = loads_of_valid(params, attitude, joints, kNoDriveTorques);
    r.torque_fallback_mask = kEveryTorqueFallsBack;
    r.torque_overload = (r.status == WheelLoadStatus::ok);
  }
  return r;
}

}  // namespace

RoverParamStatus validate_rover_params(const RoverParams& p) noexcept {
  const RoverParamStatus body = validate_body(p);
  return (body != RoverParamStatus::ok) ? body : validate_suspension(p);
}

WheelLoadResult wheel_loads(const RoverParams& params, const RoverAttitude& attitude, const JointAnglesRad& joints,
                            const DriveTorques& torques) noexcept {
  if (validate_rover_params(params) != RoverParamStatus::ok) {
    WheelLoadResult r = failed(WheelLoadStatus::invalid_params);
    r.torque_fallback_mask = fallback_mask(torques);
    return r;
  }
  return loads_with_torques(params, attitude, joints, torques);
}

WheelLoadResult wheel_loads(const PreparedParameters& prepared, const RoverAttitude& attitude,
                            const JointAnglesRad& joints, const DriveTorques& torques) noexcept {
  if (!prepared.ready()) {
    WheelLoadResult r = failed(WheelLoadStatus::invalid_params);
    r.torque_fallback_mask = fallback_mask(torques);
    return r;
  }
  return loads_with_torques(prepared.rover(), attitude, joints, torques);
}

}  // namespace flight
}  // namespace sinkwatch
