// rover_loads.hpp: double-precision reference for the rover-level quantities
// the estimation function needs but a rover does not measure (the paper's
// section 7, key technologies 2 and 4):
//
//  * each wheel's normal load W from a quasi-static model of a six-wheel
//    rocker-bogie with a differential, from attitude (pitch, roll), the
//    rocker and bogie joint angles, the geometry and the body's gravity;
//  * each wheel's drawbar pull DP from the vehicle force balance
//    sum(DP) = m (a + g sin(pitch)), split in proportion to the wheel loads
//    and capped at the soil-bin maximum DP_max.
//
// The derivation, the sign conventions and the assumptions are in
// docs/rover-loads.md; this file is the twin of flight/wheel_load.hpp and
// flight/drawbar_pull.hpp and is what an engineer reads when a flight number
// looks wrong. Host only.
#ifndef SINKWATCH_GROUND_ROVER_LOADS_HPP
#define SINKWATCH_GROUND_ROVER_LOADS_HPP

#include <array>
#include <cstddef>
#include <string>

#include "sinkwatch/flight/rover_limits.hpp"

namespace sinkwatch {
namespace ground {

/// Surface gravities [m/s^2] of the bodies the rover is used on.
/// (flight/rover_limits.hpp: the flight code reads the same numbers.)
inline constexpr double k_gravity_moon_mps2 = flight::limits::kGravityMoonMps2;
inline constexpr double k_gravity_mars_mps2 = flight::limits::kGravityMarsMps2;
inline constexpr double k_gravity_earth_mps2 = flight::limits::kGravityEarthMps2;

/// Wheel order used everywhere: left front, middle, rear, then right.
inline constexpr std::size_t k_wheel_count = flight::limits::kWheelCount;
enum class WheelPos : std::size_t { left_front = 0U, left_middle, left_rear, right_front, right_middle, right_rear };

/// A point of one side's suspension in the side's plane, body frame:
/// x forward, z up, origin on the rocker pivot axis.
struct SidePoint {
  double x_m{0.0};
  double z_m{0.0};
};

/// Geometry and mass of the rover. Both sides are mirror images.
/// Body frame: x forward, y left, z up, origin midway between the two
/// rocker pivots (which share the lateral axis y).
struct RoverGeometry {
  double mass_kg{0.0};
  double gravity_mps2{0.0};
  double com_x_m{0.0};  ///< centre of mass, body frame (rockers and bogies lumped in)
  double com_y_m{0.0};
  double com_z_m{0.0};
  double track_width_m{0.0};  ///< between the left and right wheel contact lines
  double wheel_radius_m{0.0};
  SidePoint rocker_front_axle;  ///< front axle from the rocker pivot, rocker angle 0
  SidePoint rocker_bogie_pivot;  ///< bogie pivot from the rocker pivot, rocker angle 0
  SidePoint bogie_middle_axle;   ///< middle axle from the bogie pivot, both angles 0
  SidePoint bogie_rear_axle;     ///< rear axle from the bogie pivot, both angles 0
  double rocker_limit_rad{0.0};  ///< |rocker angle| the mechanism allows
  double bogie_limit_rad{0.0};   ///< |bogie angle| the mechanism allows
  double attitude_limit_rad{0.0};  ///< |pitch|, |roll| the model accepts
};

/// The assumed Yutu-like default (docs/rover-loads.md: 140 kg and the 0.15 m
/// wheel radius are published; the link lengths are assumed).
[[nodiscard]] RoverGeometry yutu_like_geometry(double gravity_mps2 = k_gravity_moon_mps2);

/// Empty when the geometry is usable, else the reason it is not.
[[nodiscard]] std::string validate(const RoverGeometry& g);

/// IMU attitude. Pitch positive nose up, roll positive right side down
/// (right-handed about x forward, y left, z up).
struct Attitude {
  double pitch_rad{0.0};
  double roll_rad{0.0};
};

/// Suspension joint angles, index 0 = left, 1 = right. Rocker: rocker
/// relative to the body; bogie: bogie relative to its rocker. Both positive
/// when the forward end of the link rises.
struct JointAngles {
  std::array<double, 2> rocker_rad{};
  std::array<double, 2> bogie_rad{};
};

enum class LoadStatus {
  ok,
  invalid_geometry,       ///< validate() failed
  attitude_out_of_range,  ///< |pitch| or |roll| beyond attitude_limit_rad, or not finite
  joint_out_of_range,     ///< a joint angle beyond its limit, or not finite
  degenerate,             ///< a lever arm collapsed (wheel contacts coincide in projection)
  tip_over,               ///< some wheel would need a negative load: beyond the stability limit
};

[[nodiscard]] const char* to_string(LoadStatus s);

/// Everything the wheel-load model computes, for diagnosis.
struct WheelLoads {
  LoadStatus status{LoadStatus::invalid_geometry};
  /// Normal load of each wheel (along the body z axis, the ground normal) [N].
  /// Meaningful when status is ok or tip_over (then some are negative).
  std::array<double, k_wheel_count> load_n{};
  /// Each wheel's contact force, parallel to gravity [N]: load / (cos pitch cos roll).
  std::array<double, k_wheel_count> support_n{};
  double weight_normal_n{0.0};  ///< m g cos(pitch) cos(roll): what the loads sum to
  double min_load_n{0.0};
  /// Wheel contact points in the body frame [m], for the diagnosis.
  std::array<double, k_wheel_count> contact_x_m{};
  std::array<double, k_wheel_count> contact_z_m{};
  /// The torques would lift a wheel the weight alone keeps down: the loads are
  /// those without torques (docs/rover-loads.md, section 12.4).
  bool torque_overload{false};
  /// The smallest load the torques gave (equal to min_load_n unless
  /// torque_overload), for the properties' stability band.
  double torque_min_load_n{0.0};
  /// How ill-conditioned the lateral span is, for the differential checks of
  /// the flight's formats (docs/rover-loads.md 7.4): the largest magnitude
  /// among the lever rule's terms up to the lateral span's test, in the units
  /// the flight holds them in (each side's bogie share beta, 1 - beta and
  /// beta's product with the lateral offsets, Z_s in 1/m, Y_s and b Z_s in m,
  /// the couples in m, the torque terms and the pivots' moment as fractions of
  /// the weight), over every evaluation made (with the torques, then without
  /// them after a fallback). The span's rounding in any format scales with it.
  /// Infinite where a lever a + b or a bogie span collapsed, since the
  /// quotients by it are not formed.
  double largest_term{0.0};
  /// The shortest of the levers a + b and the bogie spans of both sides [m].
  double shortest_lever_m{0.0};
};

/// Each wheel's drive torque (+ driving forward) [N m] and whether it is
/// known; the twin of flight::DriveTorques. A wheel whose torque is unknown
/// keeps the free-rolling couple (radius x its share of the pull).
struct DriveTorques {
  std::array<double, k_wheel_count> torque_nm{};
  std::array<bool, k_wheel_count> usable{};
};

/// No torque known for any wheel: the statics of section 3.
inline constexpr DriveTorques k_no_drive_torques{};

/// The quasi-static loads with the drive torques' reactions (docs/rover-loads.md,
/// sections 3 and 12): each wheel's tangential force is its share of
/// m g sin(pitch) split by load, each usable torque acts on its link.
[[nodiscard]] WheelLoads wheel_loads(const RoverGeometry& g, Attitude att, const JointAngles& joints,
                                     const DriveTorques& torques);

/// Wheel contact positions (x, z) of one side in the body frame.
struct SideContacts {
  SidePoint front;
  SidePoint middle;
  SidePoint rear;
  SidePoint bogie_pivot;  ///< the pivot itself, not a contact
};
[[nodiscard]] SideContacts side_contacts(const RoverGeometry& g, double rocker_rad, double bogie_rad);

// ---------------------------------------------------------------- drawbar pull

struct DrawbarInput {
  double accel_mps2{0.0};  ///< acceleration along the path (body x), from odometry or VO
  double pitch_rad{0.0};   ///< path slope: the body pitch
  bool slip_known{false};  ///< whether `slip` holds a measurement
  double slip{0.0};        ///< slip of the rover, 1 - v/(r w), at most 1
};

struct DrawbarParams {
  /// Soil-bin DP_max / W at high slip (Fig. 10 plateau) at each wheel's load,
  /// from the correction table.
  std::array<double, k_wheel_count> dp_max_over_w{};
  double high_slip{1.0};  ///< slip from which every wheel is taken at DP_max
};

enum class DrawbarStatus {
  ok,
  capped,         ///< at least one wheel's share exceeded +-DP_max and was limited
  saturated,      ///< high slip: every wheel taken at DP_max
  invalid_input,  ///< loads not ok, parameters or input out of range
};

[[nodiscard]] const char* to_string(DrawbarStatus s);

struct DrawbarPulls {
  DrawbarStatus status{DrawbarStatus::invalid_input};
  double total_n{0.0};  ///< m (a + g sin(pitch)) before the cap
  std::array<double, k_wheel_count> dp_n{};
};

/// DP_i = m (a + g sin(pitch)) W_i / sum(W), limited to +-dp_max_over_w_i W_i;
/// at slip >= high_slip, DP_i = dp_max_over_w_i W_i (docs/rover-loads.md, section 6).
[[nodiscard]] DrawbarPulls drawbar_pulls(const RoverGeometry& g, const WheelLoads& loads, DrawbarInput in,
                                         const DrawbarParams& p);


// ------------------------------------------------- fuller quasi-static balance
//
// Not a flight twin: the ground's fuller statics (docs/rover-loads.md,
// section 11) for the scenario generator, so that the flight model's
// simplifications (every contact force parallel to gravity, no drive-torque
// reaction) are tested rather than assumed. Each wheel's soil force is split
// into its component along the ground (the wheel's drawbar pull, from the
// simulator) and its normal load; the wheel passes that force to its link at
// the axle together with the reaction of its drive torque (the motor's stator
// is on the link). Lateral forces on a roll slope are shared in proportion to
// the normal loads. Ground plane = the body's x-y plane (planar terrain).

/// Each wheel's soil force along the ground (+ forward, the drawbar pull)
/// and the torque the soil takes from it (+ driving forward) [N, N m].
struct WheelTraction {
  std::array<double, k_wheel_count> tangential_n{};
  std::array<double, k_wheel_count> soil_torque_nm{};
};

struct ForceBalanceInput {
  Attitude attitude;
  JointAngles joints;
  double accel_mps2{0.0};  ///< along the path (body x): the d'Alembert force -m a at the centre of mass
  WheelTraction traction;
};

struct ForceBalanceLoads {
  LoadStatus status{LoadStatus::invalid_geometry};
  std::array<double, k_wheel_count> load_n{};  ///< normal loads (body z) [N]
  /// Sum of the tangential forces minus m (g sin(pitch) + a): zero when the
  /// given pulls carry the rover [N]. The normal balance holds by construction.
  double along_residual_n{0.0};
  double min_load_n{0.0};
};

/// The six normal loads that balance the rover with the given tangential
/// forces and drive torques: total normal force, pitch moment, both bogies,
/// the differential (equal rocker moments) and the roll moment. With zero
/// traction on level ground it equals wheel_loads().
[[nodiscard]] ForceBalanceLoads force_balance_loads(const RoverGeometry& g, const ForceBalanceInput& in);

// ------------------------------------------------- motion-resistance check
// The twin of flight/traction.hpp's arithmetic (docs/traction.md).

/// rho = (sum T / r - sum DP) / sum W over the wheels given (directed torques
/// and pulls). Throws std::invalid_argument when r <= 0 or sum W <= 0.
[[nodiscard]] double resistance_coefficient(const std::array<double, k_wheel_count>& torque_nm,
                                            const std::array<double, k_wheel_count>& drawbar_pull_n,
                                            const std::array<double, k_wheel_count>& load_n, double radius_m);

/// rho_ahead = rho_med + lookahead * max(0, (rho_med - rho_back) / distance).
/// Throws std::invalid_argument when distance <= 0.
[[nodiscard]] double resistance_ahead(double rho_med, double rho_back, double distance_m, double lookahead_m);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_ROVER_LOADS_HPP
