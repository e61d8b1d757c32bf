// Reference wheel–soil simulator: a rigid wheel driving on deformable soil
// (Wong–Reece), with switchable effects from the terramechanics literature.
//
// It computes, for a wheel load W and a slip ratio s, the sinkage z, the drive
// torque T and the drawbar pull DP that the paper's Eq. 1–2 integrate (and the
// torque integral beside them), without the triangle approximation of Eq. 3–4:
//   sigma(theta)  Bekker pressure–sinkage, Wong–Reece front/rear regions,
//   tau(theta)    Janosi–Hanamoto shear, shear displacement from slip,
//   W  = r b Int (sigma cos + tau sin),  DP = r b Int (tau cos - sigma sin) - Rb,
//   T  = r r_s b Int tau,                integrated from theta2 to theta1,
// with the sinkage solved so that W equals the load. docs/simulator.md gives
// the equations, sources, defaults, numerical tolerances and limits.
//
// Ground code: double precision, host only. It is the "truth" the calibration,
// the sim-to-real diagnosis and the replay traverse are generated from.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sinkwatch::ground {

// Soil constants in SI units. kc and kphi carry the Bekker units
// N/m^(n+1) and N/m^(n+2) (so kc/b + kphi times m^n is a pressure).
struct SoilParameters {
  std::string name;
  double kc = 0.0;                    // cohesive modulus of deformation, N/m^(n+1)
  double kphi = 0.0;                  // frictional modulus of deformation, N/m^(n+2)
  double n = 1.0;                     // sinkage exponent (static: n0)
  double cohesion_pa = 0.0;           // c
  double friction_angle_rad = 0.0;    // phi
  double shear_modulus_m = 0.01;      // Janosi–Hanamoto K
  double density_kg_m3 = 1600.0;      // bulk density (only bulldozing uses it, via gamma = rho g)
};

struct WheelGeometry {
  double radius_m = 0.15;
  double width_m = 0.15;
};

// The effects. Each is off by default; its parameters hold the documented
// default size (docs/simulator.md, "Effects"), used when it is switched on.
enum class Effect {
  slip_sinkage,
  stress_peak_shift,
  rear_contact,
  grouser,
  bulldozing,
  load_dependence,
  drive_friction,
};
inline constexpr std::array<Effect, 7> kAllEffects{
    Effect::slip_sinkage, Effect::stress_peak_shift, Effect::rear_contact, Effect::grouser,
    Effect::bulldozing,   Effect::load_dependence,   Effect::drive_friction};

std::string_view effect_name(Effect effect);
// Throws std::invalid_argument naming the valid effects when `name` is unknown.
Effect effect_from_name(std::string_view name);

// The literature forms of the effects that have more than one
// (docs/simulator.md, "Effects"; issue 16). The first enumerator of each is
// the default: the form the simulator had before forms existed, so a setting
// without a form computes what it always did. The last form of slip_sinkage,
// grouser and drive_friction is a flexible one: a shape parameter spans the
// family's literature forms (exactly or approximately, docs/simulator.md).
enum class SlipSinkageForm { exponent, lyasko, power };
enum class GrouserForm { shear_radius, lug_tip, lug_face, engagement };
enum class BulldozingForm { bekker, hegedus };
enum class LoadDependenceForm { friction_angle, stiffness };
enum class DriveFrictionForm { constant, speed, power };

struct EffectSettings {
  // slip_sinkage, form exponent: n = n0 + n1 s (Ding et al. 2011/2015);
  // form lyasko: z = z0 (1 + ks s)/(1 - 0.5 ks s) (Lyasko 2010 with ks = 1),
  // through the Bekker modulus k / f(s)^(n + 1/2); form power: the same
  // load-independent multiplier with f(s) = 1 + gain s^power (flexible:
  // power 1 is the linear form, other powers approach Lyasko's and others).
  struct SlipSinkage {
    bool enabled = false;
    SlipSinkageForm form = SlipSinkageForm::exponent;
    double n1 = 0.5;
    double ks = 1.0;
    double gain = 2.0;
    double power = 1.0;
  } slip_sinkage;
  // stress_peak_shift: theta_m = (a0 + a1 s) theta1 (Wong & Reece 1967).
  struct StressPeakShift { bool enabled = false; double a1 = 0.32; } stress_peak_shift;
  // rear_contact: theta2 = -arccos(1 - lambda_r z / r) (Ishigami et al. 2007).
  struct RearContact { bool enabled = false; double lambda_r = 0.9; } rear_contact;
  // grouser, form shear_radius: r_s = r + lambda h in j(theta) and the torque arm;
  // form lug_tip: j = r_s (theta1 - theta) - r (1 - s)(sin theta1 - sin theta),
  // the slip of the lug tip (radius r_s) against the ground (speed set by r);
  // form lug_face: the rim shears as without lugs, plus the passive
  // resistance of the engaged lug faces (lug_count lugs per turn, h x b each);
  // form engagement (flexible): j = r_s (theta1 - theta) - (r + (1 - e) lambda h)
  // (1 - s)(sin theta1 - sin theta): e = 0 is shear_radius, e = 1 lug_tip.
  struct Grouser {
    bool enabled = false;
    GrouserForm form = GrouserForm::shear_radius;
    double height_m = 0.01;
    double lambda = 1.0;
    double lug_count = 15.0;
    double engagement = 0.5;
  } grouser;
  // bulldozing, form bekker: Rb = scale b (0.67 c z Kpc + 0.5 z^2 gamma Kpgamma)
  // (Bekker/Wong, Terzaghi factors); form hegedus: Rb = scale b D1 (c z + D2
  // gamma z^2 / 2) (Hegedus 1960 as used by Ishigami et al. 2007); subtracted
  // from the drawbar pull.
  struct Bulldozing {
    bool enabled = false;
    BulldozingForm form = BulldozingForm::bekker;
    double scale = 1.0;
  } bulldozing;
  // load_dependence, form friction_angle: phi(sigma) = phi0 (1 + sigma/sigma_ref)^(-dphi/phi0),
  // which is phi0 - dphi ln(1 + sigma/sigma_ref) to first order (after Bolton 1986);
  // form stiffness: sigma = sigma_B (1 + sigma_B/sigma_ref)^m, the Bekker
  // modulus rising with stress (after Janbu 1963).
  struct LoadDependence {
    bool enabled = false;
    LoadDependenceForm form = LoadDependenceForm::friction_angle;
    double dphi_deg = 1.5;
    double sigma_ref_pa = 1000.0;
    double stiffening = 0.5;
  } load_dependence;
  // drive_friction, form constant: T_measured = T_soil + t0 + k_w W (gearbox
  // drag + bearing load term); form speed: T_soil + tv/(1 - s) + k_w W, a
  // viscous drag proportional to the wheel's angular speed at a fixed vehicle
  // speed; form power (flexible): T_soil + tv (1/(1 - s))^p + k_w W, p = 0 the
  // constant form, p = 1 the speed form.
  struct DriveFriction {
    bool enabled = false;
    DriveFrictionForm form = DriveFrictionForm::constant;
    double t0_nm = 0.1;
    double k_w_m = 1.0e-3;
    double tv_nm = 0.1;
    double speed_exponent = 1.0;
  } drive_friction;
  // Not an effect of the catalogue: no Effect value, no named parameters, so
  // never a diagnosis candidate. It is the "form the library does not have" of
  // the cross-form check (host_tests/diagnose/test_diagnosis_crossform.cpp):
  // Wong's hump-shaped shear curve, tau = tau_max K_r {1 + [1/(K_r (1 - 1/e))
  // - 1] e^(1 - j/K_w)} (1 - e^(-j/K_w)), peak tau_max at j = K_w, falling to
  // K_r tau_max (Wong, Theory of Ground Vehicles), in place of Janosi–Hanamoto.
  struct ShearSoftening {
    bool enabled = false;
    double residual_ratio = 0.75;      // K_r
    double peak_displacement_m = 0.02;  // K_w
  } shear_softening;
  // Held-out forms of three families, data only like shear_softening (no
  // Effect value, no named parameters, never fitted): the cross-form check's
  // test of the flexible forms (docs/simulator.md, "Held-out forms").
  // Grousers whose tips (radius r + h) shear the soil from where the tip
  // circle enters it, theta1t = arccos((r - z)/(r + h)), ahead of the rim's
  // entry: j = r_s (theta1t - theta) - r (1 - s)(sin theta1t - sin theta),
  // torque arm r + h. Not together with the grouser effect.
  struct LugEntry {
    bool enabled = false;
    double height_m = 0.02;
  } lug_entry;
  // Linear slip-sinkage with saturation, z = z0 (1 + gain min(s, s_sat)),
  // as a load-independent multiplier (through k / f^(n + 1/2), as lyasko).
  struct SaturatingSlipSinkage {
    bool enabled = false;
    double gain = 1.5;
    double saturation_slip = 0.5;
  } saturating_slip_sinkage;
  // Coulomb plus viscous drive drag: t_c + t_v/(1 - s) + k_w W (the speed
  // form's cap at s = 0.95).
  struct CoulombViscousDrag {
    bool enabled = false;
    double coulomb_nm = 0.3;
    double viscous_nm = 0.3;
    double k_w_m = 1.0e-3;
  } coulomb_viscous_drag;

  bool enabled(Effect effect) const;
  void set_enabled(Effect effect, bool on);
};

// The forms of an effect by name, the default first; one name for an effect
// with a single form ("linear" for stress_peak_shift, "rebound" for rear_contact).
std::vector<std::string> effect_forms(Effect effect);
std::string effect_form(const EffectSettings& settings, Effect effect);
// Throws std::invalid_argument naming the effect's forms when `form` is unknown.
void set_effect_form(EffectSettings& settings, Effect effect, std::string_view form);

// Tolerances of the numerics (docs/simulator.md, "Numerical methods").
// Quadrature: a 21-point Gauss–Kronrod rule is accepted when |K21 - G10| is
// below 1e3 x this goal relative to the integral's L1 norm; otherwise
// tanh-sinh integrates to the goal on its error estimate (the difference
// between its last two levels). At the default the outputs agree with
// tanh-sinh at 1e-13 to 2e-10 with one effect, 4e-9 at worst with all seven
// (test_sim_wheel_soil_model, KronrodRuleAgreesWithTightTanhSinh).
inline constexpr double kDefaultQuadratureRelTol = 1e-9;
inline constexpr int kRootBits = 44;  // toms748 bracket width ~ 2^(1-44) ~ 1e-13 relative in ln z

// Everything the model needs besides (load, slip).
struct SimParameters {
  SoilParameters soil;
  WheelGeometry wheel;
  double gravity_m_s2 = 9.81;
  double a0 = 0.43;  // theta_m = a0 theta1 (Wong–Reece c1; stress_peak_shift adds a1 s)
  EffectSettings effects;
  double quadrature_rel_tol = kDefaultQuadratureRelTol;  // numerics, not a model parameter
};

// ---------------------------------------------------------------------------
// Flat, named parameter vector, for fitting (issue 8: Ceres with numeric
// derivatives). Names are "soil.kphi", "model.a0", "grouser.height_m", ...
// Effect parameters are named "<effect>.<param>" with the effect's exact name.

struct ParameterInfo {
  std::string name;
  std::string unit;
  std::string description;
  bool is_effect_parameter = false;
  Effect effect = Effect::slip_sinkage;  // meaningful only when is_effect_parameter
  std::vector<std::string> forms;  // the effect forms it belongs to; empty: every form of the effect
  bool primary = false;  // the one parameter that sets the size of its form (fit this one)
  bool shape = false;    // a flexible form's shape parameter: fitted with the primary one
  double lower = 0.0;    // physically admissible range, for bounded fits
  double upper = 0.0;
};

// Every parameter the model has, in a fixed order.
const std::vector<ParameterInfo>& parameter_catalogue();
// The parameters of the base model plus those of the enabled effects (of
// each enabled effect, the parameters of its selected form).
std::vector<std::string> active_parameter_names(const SimParameters& params);
// The parameters of one form of an effect, primary first; without a form,
// the default form's.
std::vector<std::string> effect_parameter_names(Effect effect);
std::vector<std::string> effect_parameter_names(Effect effect, std::string_view form);
// The parameter that sets the size of an effect form (e.g. "bulldozing.scale").
std::string primary_parameter_name(Effect effect);
std::string primary_parameter_name(Effect effect, std::string_view form);
// A base-model set that is identifiable from soil-bin rows at one wheel width:
// kc and kphi only appear as kc/b + kphi, so only kphi is in it.
std::vector<std::string> suggested_base_fit_parameters();

// Throw std::invalid_argument for an unknown name.
double get_parameter(const SimParameters& params, std::string_view name);
void set_parameter(SimParameters& params, std::string_view name, double value);
std::vector<double> get_parameters(const SimParameters& params, const std::vector<std::string>& names);
void set_parameters(SimParameters& params, const std::vector<std::string>& names,
                    const std::vector<double>& values);

// ---------------------------------------------------------------------------
// Evaluation.

enum class SimStatus {
  ok,
  bad_input,      // a parameter, the load or the slip is outside the model's domain
  no_solution,    // no sinkage 0 < z <= r carries the load (the wheel sinks past its axle)
  numerical_failure,  // quadrature or root finder did not reach its tolerance
};
std::string_view status_name(SimStatus status);

struct WheelSoilState {
  double sinkage_m = 0.0;
  double entry_angle_rad = 0.0;       // theta1
  double exit_angle_rad = 0.0;        // theta2 (0 unless rear_contact)
  double max_stress_angle_rad = 0.0;  // theta_m
  double sinkage_exponent = 0.0;      // n actually used (n0 + n1 s with slip_sinkage)
  double shear_radius_m = 0.0;        // r_s
  double torque_nm = 0.0;             // what a drive-torque sensor would read (soil + drive friction)
  double soil_torque_nm = 0.0;        // r r_s b Int tau
  double drive_friction_torque_nm = 0.0;
  double drawbar_pull_n = 0.0;        // gross thrust - compaction - bulldozing
  double gross_thrust_n = 0.0;        // H  = r b Int tau cos (+ lug-face thrust)
  double lug_face_thrust_n = 0.0;     // grouser form lug_face: the part of H on the lug faces
  double compaction_resistance_n = 0.0;  // Rc = r b Int sigma sin
  double bulldozing_resistance_n = 0.0;  // Rb
  double vertical_force_n = 0.0;      // W recomputed at the solution (check: equals the load)
  int root_iterations = 0;
  double sinkage_log_slope = 0.0;     // d ln W / d ln z at the solution (a warm start's first slope)
};

struct Evaluation {
  SimStatus status = SimStatus::ok;
  std::string message;  // empty when ok; says what was wrong otherwise
  WheelSoilState state;
  bool ok() const { return status == SimStatus::ok; }
};


// Solve the wheel state for a load (N, > 0) and a slip ratio in [0, 1].
// Never throws for bad numbers: the status says what happened.
Evaluation evaluate(const SimParameters& params, double load_n, double slip);

// A solution of a nearby problem (the same row with slightly different
// parameters), to start the sinkage search from: its sinkage and its
// sinkage_log_slope. A zero sinkage means none (the bracketing search).
struct SinkageHint {
  double sinkage_m = 0.0;
  double log_slope = 0.0;
};
// evaluate() with a warm start: secant steps from the hint to a step of 1e-12
// in ln z (tighter than the cold search's bracket), the cold search when they
// do not settle. Same results to ~1e-12 relative (docs/simulator.md,
// "Numerical methods"); a fit's repeated evaluations of one row take 2-3
// vertical-force integrals instead of 5-6.
Evaluation evaluate(const SimParameters& params, double load_n, double slip, const SinkageHint& hint);

// The vertical force the soil exerts at a given sinkage (the function whose
// root is the sinkage). Exposed for tests and for diagnosis plots.
double vertical_force_at_sinkage(const SimParameters& params, double sinkage_m, double slip);

struct SimError : std::runtime_error {
  SimError(SimStatus status_in, const std::string& what) : std::runtime_error(what), status(status_in) {}
  SimStatus status;
};
// evaluate(), throwing SimError when the status is not ok.
WheelSoilState evaluate_or_throw(const SimParameters& params, double load_n, double slip);

// Terzaghi bearing-capacity factors (closed-form Nq, Nc; Coduto's Ngamma) and
// the Bekker/Wong passive-pressure factors used by bulldozing.
struct BearingFactors {
  double nq, nc, ngamma, kpc, kpgamma;
};
BearingFactors terzaghi_factors(double friction_angle_rad);

}  // namespace sinkwatch::ground
