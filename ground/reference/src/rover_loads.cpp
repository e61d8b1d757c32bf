// Reference rover statics; see rover_loads.hpp and docs/rover-loads.md.
#include "sinkwatch/ground/rover_loads.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <cmath>

namespace sinkwatch {
namespace ground {
namespace {

/// Rotation in a side's plane by `a`, positive raising the +x end.
SidePoint rotate(SidePoint p, double a) {
  const double c = std::cos(a);
  const double s = std::sin(a);
  return SidePoint{p.x_m * c - p.z_m * s, p.x_m * s + p.z_m * c};
}

SidePoint plus(SidePoint a, SidePoint b) { return SidePoint{a.x_m + b.x_m, a.z_m + b.z_m}; }

bool finite_all(std::initializer_list<double> values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

/// A lever shorter than this (1 mm) is treated as collapsed.
constexpr double k_min_lever_m = 1e-3;

/// Raises out.largest_term to the largest magnitude of `terms`.
void note_terms(WheelLoads& out, std::initializer_list<double> terms) {
  for (const double t : terms) {
    out.largest_term = std::max(out.largest_term, std::fabs(t));
  }
}

}  // namespace

RoverGeometry yutu_like_geometry(double gravity_mps2) {
  using Yutu = flight::limits::YutuLike;
  RoverGeometry g;
  g.mass_kg = Yutu::kMassKg;
  g.gravity_mps2 = gravity_mps2;
  g.com_x_m = Yutu::kComXM;
  g.com_y_m = Yutu::kComYM;
  g.com_z_m = Yutu::kComZM;
  g.track_width_m = Yutu::kTrackWidthM;
  g.wheel_radius_m = Yutu::kWheelRadiusM;
  g.rocker_front_axle = SidePoint{Yutu::kRockerFrontAxleXM, Yutu::kRockerFrontAxleZM};
  g.rocker_bogie_pivot = SidePoint{Yutu::kRockerBogiePivotXM, Yutu::kRockerBogiePivotZM};
  g.bogie_middle_axle = SidePoint{Yutu::kBogieMiddleAxleXM, Yutu::kBogieMiddleAxleZM};
  g.bogie_rear_axle = SidePoint{Yutu::kBogieRearAxleXM, Yutu::kBogieRearAxleZM};
  g.rocker_limit_rad = Yutu::kRockerLimitRad;
  g.bogie_limit_rad = Yutu::kBogieLimitRad;
  g.attitude_limit_rad = Yutu::kAttitudeLimitRad;
  return g;
}

namespace {

/// v in (0, limit]
bool positive_at_most(double v, double limit) { return v > 0.0 && v <= limit; }

/// Mass, gravity, wheel, track and centre of mass (the flight check's
/// validate_body, same bounds from flight/rover_limits.hpp).
std::string validate_body(const RoverGeometry& g) {
  namespace lim = flight::limits;
  if (!positive_at_most(g.mass_kg, lim::kMaxMassKg)) return "mass must be in (0, 1000] kg";
  if (!positive_at_most(g.gravity_mps2, lim::kMaxGravityMps2)) return "gravity must be in (0, 10] m/s^2";
  if (!(g.wheel_radius_m >= lim::kMinWheelRadiusM && g.wheel_radius_m <= lim::kMaxWheelRadiusM)) {
    return "wheel radius must be in [0.01, 1] m";
  }
  if (!positive_at_most(g.track_width_m, lim::kMaxTrackWidthM)) return "track width must be in (0, 4] m";
  if (!(std::fabs(g.com_y_m) < 0.5 * g.track_width_m)) return "centre of mass must lie between the wheel lines";
  return {};
}

/// Link order and lengths, joint and attitude limits (validate_suspension).
std::string validate_suspension(const RoverGeometry& g) {
  namespace lim = flight::limits;
  if (!(g.rocker_front_axle.x_m > 0.0)) return "front axle must be ahead of the rocker pivot";
  if (!(g.rocker_bogie_pivot.x_m < 0.0)) return "bogie pivot must be behind the rocker pivot";
  if (!(g.bogie_middle_axle.x_m > 0.0)) return "middle axle must be ahead of the bogie pivot";
  if (!(g.bogie_rear_axle.x_m < 0.0)) return "rear axle must be behind the bogie pivot";
  for (const double v : {g.com_x_m, g.com_z_m, g.rocker_front_axle.x_m, g.rocker_front_axle.z_m,
                         g.rocker_bogie_pivot.x_m, g.rocker_bogie_pivot.z_m, g.bogie_middle_axle.x_m,
                         g.bogie_middle_axle.z_m, g.bogie_rear_axle.x_m, g.bogie_rear_axle.z_m}) {
    if (!(std::fabs(v) <= lim::kMaxLinkM)) return "a link length or the centre of mass is beyond 2 m";
  }
  if (!positive_at_most(g.rocker_limit_rad, lim::kMaxJointLimitRad)) return "rocker limit must be in (0, 0.8] rad";
  if (!positive_at_most(g.bogie_limit_rad, lim::kMaxJointLimitRad)) return "bogie limit must be in (0, 0.8] rad";
  if (!positive_at_most(g.attitude_limit_rad, lim::kMaxAttitudeLimitRad)) {
    return "attitude limit must be in (0, 1.05] rad";
  }
  return {};
}

}  // namespace

std::string validate(const RoverGeometry& g) {
  if (!finite_all({g.mass_kg, g.gravity_mps2, g.com_x_m, g.com_y_m, g.com_z_m, g.track_width_m, g.wheel_radius_m,
                   g.rocker_front_axle.x_m, g.rocker_front_axle.z_m, g.rocker_bogie_pivot.x_m,
                   g.rocker_bogie_pivot.z_m, g.bogie_middle_axle.x_m, g.bogie_middle_axle.z_m,
                   g.bogie_rear_axle.x_m, g.bogie_rear_axle.z_m, g.rocker_limit_rad, g.bogie_limit_rad,
                   g.attitude_limit_rad})) {
    return "a geometry value is not finite";
  }
  const std::string body = validate_body(g);
  return body.empty() ? validate_suspension(g) : body;
}

const char* to_string(LoadStatus s) {
  switch (s) {
    case LoadStatus::ok: return "ok";
    case LoadStatus::invalid_geometry: return "invalid geometry";
    case LoadStatus::attitude_out_of_range: return "attitude out of range";
    case LoadStatus::joint_out_of_range: return "joint angle out of range";
    case LoadStatus::degenerate: return "degenerate lever";
    case LoadStatus::tip_over: return "beyond the stability limit";
  }
  return "unknown";
}

SideContacts side_contacts(const RoverGeometry& g, double rocker_rad, double bogie_rad) {
  // The contact is one wheel radius below the axle along the ground normal,
  // taken as the body z axis (small terrain irregularity, section 2).
  const SidePoint down{0.0, -g.wheel_radius_m};
  SideContacts c;
  c.bogie_pivot = rotate(g.rocker_bogie_pivot, rocker_rad);
  c.front = plus(rotate(g.rocker_front_axle, rocker_rad), down);
  c.middle = plus(plus(c.bogie_pivot, rotate(g.bogie_middle_axle, rocker_rad + bogie_rad)), down);
  c.rear = plus(plus(c.bogie_pivot, rotate(g.bogie_rear_axle, rocker_rad + bogie_rad)), down);
  return c;
}

namespace {

// ok, or why the geometry, attitude or joint angles cannot be solved.
LoadStatus check_load_inputs(const RoverGeometry& g, Attitude att, const JointAngles& joints) {
  if (!validate(g).empty()) {
    return LoadStatus::invalid_geometry;
  }
  if (!finite_all({att.pitch_rad, att.roll_rad}) || std::fabs(att.pitch_rad) > g.attitude_limit_rad ||
      std::fabs(att.roll_rad) > g.attitude_limit_rad) {
    return LoadStatus::attitude_out_of_range;
  }
  for (std::size_t s = 0U; s < 2U; ++s) {
    if (!finite_all({joints.rocker_rad[s], joints.bogie_rad[s]}) ||
        std::fabs(joints.rocker_rad[s]) > g.rocker_limit_rad || std::fabs(joints.bogie_rad[s]) > g.bogie_limit_rad) {
      return LoadStatus::joint_out_of_range;
    }
  }
  return LoadStatus::ok;
}

// The projection along gravity onto the ground plane (section 3.2):
//   x~ = x - z kx,  kx = tan(pitch)/cos(roll);  y~ = y - z ky,  ky = tan(roll).
struct GravityProjection {
  double kx;
  double ky;
  double normal_fraction;  // cos(pitch) cos(roll): turns a torque into the support forces' units
};

// One side's levers in projected coordinates: front lever a, bogie lever b,
// the middle wheel's share beta of the bogie's load, and the projected
// lateral positions of the front wheel and of the bogie's load.
struct SideLevers {
  double a, b, beta;
  double yt_front, yt_bogie;
  double front_couple = 0.0;          // t_front = T_front / (cos pitch cos roll)
  double bogie_shift = 0.0;           // (t_middle + t_rear) / bogie span
  double yt_rear_minus_middle = 0.0;
};

// Side s's contacts (recorded in `out`) and levers; false when a lever has
// collapsed (shorter than k_min_lever_m).
bool side_levers(const RoverGeometry& g, const JointAngles& joints, std::size_t s, GravityProjection proj,
                 const DriveTorques& torques, WheelLoads& out, SideLevers& levers) {
  const double y_side = (s == 0U) ? 0.5 * g.track_width_m : -0.5 * g.track_width_m;
  const SideContacts c = side_contacts(g, joints.rocker_rad[s], joints.bogie_rad[s]);
  const std::size_t base = 3U * s;
  const SidePoint pts[3] = {c.front, c.middle, c.rear};
  for (std::size_t k = 0U; k < 3U; ++k) {
    out.contact_x_m[base + k] = pts[k].x_m;
    out.contact_z_m[base + k] = pts[k].z_m;
  }
  // A wheel whose torque is used hands its link the soil force at the axle
  // (section 12); without it the free-rolling couple puts it at the contact.
  const auto lever_z = [&](std::size_t k, double contact_z) {
    return torques.usable[base + k] ? contact_z + g.wheel_radius_m : contact_z;
  };
  const auto couple = [&](std::size_t k) {
    return torques.usable[base + k] ? torques.torque_nm[base + k] / proj.normal_fraction : 0.0;
  };
  const double xt_f = c.front.x_m - lever_z(0U, c.front.z_m) * proj.kx;
  const double xt_m = c.middle.x_m - lever_z(1U, c.middle.z_m) * proj.kx;
  const double xt_r = c.rear.x_m - lever_z(2U, c.rear.z_m) * proj.kx;
  const double xt_b = c.bogie_pivot.x_m - c.bogie_pivot.z_m * proj.kx;
  const double a = xt_f;
  const double b = -xt_b;
  const double bogie_span = xt_m - xt_r;
  out.shortest_lever_m = std::min({out.shortest_lever_m, a + b, bogie_span});
  if (a + b < k_min_lever_m || bogie_span < k_min_lever_m) {
    out.largest_term = std::numeric_limits<double>::infinity();
    return false;
  }
  const double beta = (xt_b - xt_r) / bogie_span;
  const double yt_f = y_side - c.front.z_m * proj.ky;
  const double yt_m = y_side - c.middle.z_m * proj.ky;
  const double yt_r = y_side - c.rear.z_m * proj.ky;
  levers = SideLevers{a, b, beta, yt_f, beta * yt_m + (1.0 - beta) * yt_r,
                      couple(0U), (couple(1U) + couple(2U)) / bogie_span, yt_r - yt_m};
  // Couples in metres (per unit of the weight), as the flight holds them.
  const double w = g.mass_kg * g.gravity_mps2;
  note_terms(out, {beta, 1.0 - beta, beta * (yt_m - yt_r), levers.yt_bogie, couple(0U) / w, couple(1U) / w,
                   couple(2U) / w, levers.bogie_shift / w, levers.bogie_shift * levers.yt_rear_minus_middle / w});
  return true;
}

// The body's weight and where it acts, projected; the moment each side's
// wheels carry about its rocker pivot.
struct BodyLoad {
  double weight_n;
  double com_yt;
  double pivot_moment_nm;
};

// Roll balance (section 3.5): side s carries S_s, and its wheels' roll
// moment is S_s Y_s + M Z_s. Then each side's lever rule splits S_s over its
// wheels (support_n). False when the sides' lateral span has collapsed.
bool split_supports(const std::array<SideLevers, 2>& sides, BodyLoad body, WheelLoads& out) {
  std::array<double, 2> big_y{};
  std::array<double, 2> big_z{};
  double torque_terms = 0.0;  // sum_s (q_s - t_front,s Z_s), section 12
  for (std::size_t s = 0U; s < 2U; ++s) {
    const SideLevers& d = sides[s];
    big_y[s] = (d.b * d.yt_front + d.a * d.yt_bogie) / (d.a + d.b);
    big_z[s] = (d.yt_front - d.yt_bogie) / (d.a + d.b);
    torque_terms += d.bogie_shift * d.yt_rear_minus_middle - d.front_couple * big_z[s];
    note_terms(out, {big_z[s], big_y[s], d.b * big_z[s], d.front_couple * big_z[s] / body.weight_n,
                     torque_terms / body.weight_n});
  }
  note_terms(out, {body.pivot_moment_nm * (big_z[0] + big_z[1]) / body.weight_n});
  const double lateral_span = big_y[0] - big_y[1];
  if (lateral_span < k_min_lever_m) {
    return false;
  }
  std::array<double, 2> side_total{};
  side_total[0] = (body.weight_n * body.com_yt - body.pivot_moment_nm * (big_z[0] + big_z[1]) - torque_terms -
                   body.weight_n * big_y[1]) /
                  lateral_span;
  side_total[1] = body.weight_n - side_total[0];

  for (std::size_t s = 0U; s < 2U; ++s) {
    const SideLevers& d = sides[s];
    const double front = (body.pivot_moment_nm - d.front_couple + d.b * side_total[s]) / (d.a + d.b);
    const double bogie = side_total[s] - front;
    const double middle = d.beta * bogie - d.bogie_shift;
    const double rear = bogie - middle;
    out.support_n[3U * s + 0U] = front;
    out.support_n[3U * s + 1U] = middle;
    out.support_n[3U * s + 2U] = rear;
  }
  return true;
}

}  // namespace

namespace {
WheelLoads loads_of(const RoverGeometry& g, Attitude att, const JointAngles& joints, const DriveTorques& torques);
}  // namespace

WheelLoads wheel_loads(const RoverGeometry& g, Attitude att, const JointAngles& joints, const DriveTorques& torques) {
  // Stability is the weight's decision: torques that alone would lift a
  // wheel are beyond what the links react quasi-statically (section 12.4).
  WheelLoads out = loads_of(g, att, joints, torques);
  const double torque_min_load_n = out.min_load_n;
  const double torque_largest_term = out.largest_term;
  const double torque_shortest_lever_m = out.shortest_lever_m;
  const bool any_torque = std::any_of(torques.usable.begin(), torques.usable.end(), [](bool u) { return u; });
  if (out.status == LoadStatus::tip_over && any_torque) {
    out = loads_of(g, att, joints, k_no_drive_torques);
    out.torque_overload = (out.status == LoadStatus::ok);
    out.largest_term = std::max(out.largest_term, torque_largest_term);
    out.shortest_lever_m = std::min(out.shortest_lever_m, torque_shortest_lever_m);
  }
  out.torque_min_load_n = torque_min_load_n;
  return out;
}

namespace {
WheelLoads loads_of(const RoverGeometry& g, Attitude att, const JointAngles& joints, const DriveTorques& torques) {
  WheelLoads out;
  out.shortest_lever_m = std::numeric_limits<double>::infinity();
  out.status = check_load_inputs(g, att, joints);
  if (out.status != LoadStatus::ok) {
    return out;
  }
  // Every contact force is taken parallel to gravity (section 2), so every
  // moment balance is a planar lever rule in the coordinates of the points
  // projected along gravity onto the ground plane (section 3.2).
  const double cos_pitch = std::cos(att.pitch_rad);
  const double cos_roll = std::cos(att.roll_rad);
  const GravityProjection proj{std::sin(att.pitch_rad) / (cos_pitch * cos_roll), std::tan(att.roll_rad),
                                    cos_pitch * cos_roll};
  const double weight_n = g.mass_kg * g.gravity_mps2;
  const double normal_fraction = cos_pitch * cos_roll;
  out.weight_normal_n = weight_n * normal_fraction;

  const double com_xt = g.com_x_m - g.com_z_m * proj.kx;
  const double com_yt = g.com_y_m - g.com_z_m * proj.ky;
  // Rocker pivots at the origin of x and z: x~ = 0. The differential makes
  // the moment of each side's wheels about its rocker pivot equal (section
  // 3.4); with both pivots on one axis the body's pitch balance fixes it.
  const double pivot_moment_nm = 0.5 * weight_n * com_xt;

  std::array<SideLevers, 2> sides{};
  for (std::size_t s = 0U; s < 2U; ++s) {
    if (!side_levers(g, joints, s, proj, torques, out, sides[s])) {
      out.status = LoadStatus::degenerate;
      return out;
    }
  }
  if (!split_supports(sides, BodyLoad{weight_n, com_yt, pivot_moment_nm}, out)) {
    out.status = LoadStatus::degenerate;
    return out;
  }
  for (std::size_t i = 0U; i < k_wheel_count; ++i) {
    out.load_n[i] = out.support_n[i] * normal_fraction;
  }
  out.min_load_n = *std::min_element(out.load_n.begin(), out.load_n.end());
  out.status = (out.min_load_n < 0.0) ? LoadStatus::tip_over : LoadStatus::ok;
  return out;
}
}  // namespace

const char* to_string(DrawbarStatus s) {
  switch (s) {
    case DrawbarStatus::ok: return "ok";
    case DrawbarStatus::capped: return "capped at DP_max";
    case DrawbarStatus::saturated: return "high slip: DP_max";
    case DrawbarStatus::invalid_input: return "invalid input";
  }
  return "unknown";
}

DrawbarPulls drawbar_pulls(const RoverGeometry& g, const WheelLoads& loads, DrawbarInput in,
                           const DrawbarParams& p) {
  DrawbarPulls out;
  if (loads.status != LoadStatus::ok || !validate(g).empty() || !finite_all({in.accel_mps2, in.pitch_rad, in.slip}) ||
      !(p.high_slip > 0.0 && p.high_slip <= 1.0) || !(in.slip <= 1.0) ||
      std::fabs(in.accel_mps2) > 10.0 || std::fabs(in.pitch_rad) > g.attitude_limit_rad) {
    out.status = DrawbarStatus::invalid_input;
    return out;
  }
  for (const double r : p.dp_max_over_w) {
    if (!(std::isfinite(r) && r > 0.0 && r <= 2.0)) {
      out.status = DrawbarStatus::invalid_input;
      return out;
    }
  }
  double load_sum = 0.0;
  for (const double w : loads.load_n) load_sum += w;
  if (!(load_sum > 0.0)) {
    out.status = DrawbarStatus::invalid_input;
    return out;
  }
  out.total_n = g.mass_kg * (in.accel_mps2 + g.gravity_mps2 * std::sin(in.pitch_rad));
  if (in.slip_known && in.slip >= p.high_slip) {
    for (std::size_t i = 0U; i < k_wheel_count; ++i) out.dp_n[i] = p.dp_max_over_w[i] * loads.load_n[i];
    out.status = DrawbarStatus::saturated;
    return out;
  }
  out.status = DrawbarStatus::ok;
  for (std::size_t i = 0U; i < k_wheel_count; ++i) {
    const double share = out.total_n * loads.load_n[i] / load_sum;
    const double cap = p.dp_max_over_w[i] * loads.load_n[i];
    out.dp_n[i] = std::clamp(share, -cap, cap);
    if (out.dp_n[i] != share) out.status = DrawbarStatus::capped;
  }
  return out;
}


// ------------------------------------------------- fuller quasi-static balance

namespace {

constexpr std::size_t k_balance_rows = k_wheel_count;
using BalanceMatrix = std::array<std::array<double, k_wheel_count + 1U>, k_balance_rows>;

/// Gaussian elimination with partial pivoting on the augmented 6 x 7 system;
/// false when a pivot vanishes (a collapsed lever).
bool solve_balance(BalanceMatrix& m, std::array<double, k_wheel_count>& x) {
  for (std::size_t col = 0U; col < k_wheel_count; ++col) {
    std::size_t best = col;
    for (std::size_t r = col + 1U; r < k_balance_rows; ++r) {
      if (std::fabs(m[r][col]) > std::fabs(m[best][col])) best = r;
    }
    if (std::fabs(m[best][col]) < 1e-12) return false;
    std::swap(m[col], m[best]);
    for (std::size_t r = col + 1U; r < k_balance_rows; ++r) {
      const double f = m[r][col] / m[col][col];
      for (std::size_t c = col; c <= k_wheel_count; ++c) m[r][c] -= f * m[col][c];
    }
  }
  for (std::size_t k = k_wheel_count; k-- > 0U;) {
    double v = m[k][k_wheel_count];
    for (std::size_t c = k + 1U; c < k_wheel_count; ++c) v -= m[k][c] * x[c];
    x[k] = v / m[k][k];
  }
  return true;
}

/// Contact points of the six wheels (body frame) and the bogie pivots.
struct BalancePoints {
  std::array<double, k_wheel_count> x{};
  std::array<double, k_wheel_count> y{};
  std::array<double, k_wheel_count> z{};  // contact; the axle is one radius above
  std::array<SidePoint, 2> bogie_pivot{};
};

BalancePoints balance_points(const RoverGeometry& g, const JointAngles& joints) {
  BalancePoints p;
  for (std::size_t s = 0U; s < 2U; ++s) {
    const SideContacts c = side_contacts(g, joints.rocker_rad[s], joints.bogie_rad[s]);
    const SidePoint pts[3] = {c.front, c.middle, c.rear};
    for (std::size_t k = 0U; k < 3U; ++k) {
      p.x[3U * s + k] = pts[k].x_m;
      p.z[3U * s + k] = pts[k].z_m;
      p.y[3U * s + k] = (s == 0U) ? 0.5 * g.track_width_m : -0.5 * g.track_width_m;
    }
    p.bogie_pivot[s] = c.bogie_pivot;
  }
  return p;
}

/// The rows of the balance (docs/rover-loads.md, section 11.2): unknowns N_i.
BalanceMatrix balance_rows(const RoverGeometry& g, const ForceBalanceInput& in, const BalancePoints& p) {
  const double cp = std::cos(in.attitude.pitch_rad);
  const double sp = std::sin(in.attitude.pitch_rad);
  const double cr = std::cos(in.attitude.roll_rad);
  const double sr = std::sin(in.attitude.roll_rad);
  const double mg = g.mass_kg * g.gravity_mps2;
  const WheelTraction& t = in.traction;
  BalanceMatrix m{};
  // Moment about +y (pitch) of wheel i's tangential force at its axle and its
  // drive-torque reaction on the link, about the point (px, pz).
  const auto pitch_terms = [&](std::size_t i, double pz) {
    return (p.z[i] + g.wheel_radius_m - pz) * t.tangential_n[i] - t.soil_torque_nm[i];
  };
  double pitch_rhs = -(-g.com_z_m * g.mass_kg * (g.gravity_mps2 * sp + in.accel_mps2) + g.com_x_m * mg * cp * cr);
  double diff_rhs = 0.0;
  for (std::size_t i = 0U; i < k_wheel_count; ++i) {
    m[0][i] = 1.0;
    m[1][i] = -p.x[i];
    pitch_rhs -= pitch_terms(i, 0.0);
    m[4][i] = (i < 3U) ? -p.x[i] : p.x[i];
    diff_rhs -= (i < 3U) ? pitch_terms(i, 0.0) : -pitch_terms(i, 0.0);
    m[5][i] = p.y[i] - p.z[i] * (sr / cr);
  }
  m[0][k_wheel_count] = mg * cp * cr;
  m[1][k_wheel_count] = pitch_rhs;
  m[4][k_wheel_count] = diff_rhs;
  m[5][k_wheel_count] = mg * cp * (g.com_y_m * cr - g.com_z_m * sr);
  for (std::size_t s = 0U; s < 2U; ++s) {
    const SidePoint pv = p.bogie_pivot[s];
    double rhs = 0.0;
    for (std::size_t k = 1U; k < 3U; ++k) {
      const std::size_t i = 3U * s + k;
      m[2U + s][i] = -(p.x[i] - pv.x_m);
      rhs -= pitch_terms(i, pv.z_m);
    }
    m[2U + s][k_wheel_count] = rhs;
  }
  return m;
}

}  // namespace

ForceBalanceLoads force_balance_loads(const RoverGeometry& g, const ForceBalanceInput& in) {
  ForceBalanceLoads out;
  out.status = check_load_inputs(g, in.attitude, in.joints);
  if (out.status != LoadStatus::ok) return out;
  for (std::size_t i = 0U; i < k_wheel_count; ++i) {
    if (!finite_all({in.traction.tangential_n[i], in.traction.soil_torque_nm[i], in.accel_mps2})) {
      out.status = LoadStatus::degenerate;
      return out;
    }
  }
  const BalancePoints p = balance_points(g, in.joints);
  BalanceMatrix m = balance_rows(g, in, p);
  if (!solve_balance(m, out.load_n)) {
    out.status = LoadStatus::degenerate;
    return out;
  }
  double along = 0.0;
  for (const double f : in.traction.tangential_n) along += f;
  out.along_residual_n =
      along - g.mass_kg * (g.gravity_mps2 * std::sin(in.attitude.pitch_rad) + in.accel_mps2);
  out.min_load_n = *std::min_element(out.load_n.begin(), out.load_n.end());
  out.status = (out.min_load_n < 0.0) ? LoadStatus::tip_over : LoadStatus::ok;
  return out;
}

double resistance_coefficient(const std::array<double, k_wheel_count>& torque_nm,
                              const std::array<double, k_wheel_count>& drawbar_pull_n,
                              const std::array<double, k_wheel_count>& load_n, double radius_m) {
  double torque = 0.0;
  double pull = 0.0;
  double load = 0.0;
  for (std::size_t i = 0; i < k_wheel_count; ++i) {
    torque += torque_nm[i];
    pull += drawbar_pull_n[i];
    load += load_n[i];
  }
  if (!(radius_m > 0.0) || !(load > 0.0)) throw std::invalid_argument("resistance_coefficient: r and sum W must be > 0");
  return (torque / radius_m - pull) / load;
}

double resistance_ahead(double rho_med, double rho_back, double distance_m, double lookahead_m) {
  if (!(distance_m > 0.0)) throw std::invalid_argument("resistance_ahead: distance must be > 0");
  return rho_med + lookahead_m * std::max(0.0, (rho_med - rho_back) / distance_m);
}

}  // namespace ground
}  // namespace sinkwatch
