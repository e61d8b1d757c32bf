// Wong–Reece rigid wheel on Bekker/Janosi–Hanamoto soil; see the header and
// docs/simulator.md for the equations and their sources.
#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/tools/roots.hpp>
#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>

namespace sinkwatch::ground {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// ---------------------------------------------------------------------------
// Parameter catalogue: one row per named parameter, with an accessor.

struct ParameterRow {
  ParameterInfo info;
  std::function<double&(SimParameters&)> ref;
  // Stored value -> exposed value, and back (only phi is converted: the struct
  // keeps radians, the vector exposes degrees, which humans read and type).
  double scale_to_exposed = 1.0;
};

ParameterInfo base_info(std::string name, std::string unit, std::string description, double lower,
                        double upper) {
  ParameterInfo info;
  info.name = std::move(name);
  info.unit = std::move(unit);
  info.description = std::move(description);
  info.lower = lower;
  info.upper = upper;
  return info;
}

ParameterInfo effect_info(Effect effect, bool primary, std::string name, std::string unit,
                          std::string description, double lower, double upper) {
  ParameterInfo info = base_info(std::move(name), std::move(unit), std::move(description), lower, upper);
  info.is_effect_parameter = true;
  info.effect = effect;
  info.primary = primary;
  return info;
}

ParameterInfo in_forms(ParameterInfo info, std::vector<std::string> forms) {
  info.forms = std::move(forms);
  return info;
}

// A flexible form's shape parameter (fitted with the primary one).
ParameterInfo shape_of(ParameterInfo info) {
  info.shape = true;
  return info;
}

using ParameterRef = std::function<double&(SimParameters&)>;

void add_row(std::vector<ParameterRow>& t, ParameterInfo info, ParameterRef ref, double scale = 1.0) {
  t.push_back(ParameterRow{std::move(info), std::move(ref), scale});
}

void add_base_rows(std::vector<ParameterRow>& t) {
  add_row(t, base_info("soil.kc", "N/m^(n+1)", "Bekker cohesive modulus", 0.0, 1e7),
          [](SimParameters& p) -> double& { return p.soil.kc; });
  add_row(t, base_info("soil.kphi", "N/m^(n+2)", "Bekker frictional modulus", 0.0, 1e9),
          [](SimParameters& p) -> double& { return p.soil.kphi; });
  add_row(t, base_info("soil.n", "-", "sinkage exponent (n0 when slip_sinkage is on)", 0.2, 2.5),
          [](SimParameters& p) -> double& { return p.soil.n; });
  add_row(t, base_info("soil.c_pa", "Pa", "cohesion", 0.0, 1e5),
          [](SimParameters& p) -> double& { return p.soil.cohesion_pa; });
  add_row(t, base_info("soil.phi_deg", "deg", "internal friction angle", 0.0, 60.0),
          [](SimParameters& p) -> double& { return p.soil.friction_angle_rad; }, 1.0 / kDegToRad);
  add_row(t, base_info("soil.K_m", "m", "Janosi–Hanamoto shear deformation modulus", 1e-4, 0.2),
          [](SimParameters& p) -> double& { return p.soil.shear_modulus_m; });
  add_row(t, base_info("soil.density_kg_m3", "kg/m^3", "bulk density (bulldozing, lug faces)", 500.0, 3500.0),
          [](SimParameters& p) -> double& { return p.soil.density_kg_m3; });
  add_row(t, base_info("wheel.radius_m", "m", "wheel radius", 0.01, 2.0),
          [](SimParameters& p) -> double& { return p.wheel.radius_m; });
  add_row(t, base_info("wheel.width_m", "m", "wheel width", 0.01, 2.0),
          [](SimParameters& p) -> double& { return p.wheel.width_m; });
  add_row(t, base_info("gravity_m_s2", "m/s^2", "gravity (bulldozing soil weight; --masses)", 0.1, 30.0),
          [](SimParameters& p) -> double& { return p.gravity_m_s2; });
  add_row(t, base_info("model.a0", "-", "maximum-stress angle ratio, theta_m = a0 theta1", 0.0, 0.95),
          [](SimParameters& p) -> double& { return p.a0; });
}

void add_sinkage_and_contact_rows(std::vector<ParameterRow>& t) {
  add_row(t, in_forms(effect_info(Effect::slip_sinkage, true, "slip_sinkage.n1", "-", "n = n0 + n1 s", 0.0, 2.0),
                     {"exponent"}),
          [](SimParameters& p) -> double& { return p.effects.slip_sinkage.n1; });
  add_row(t, in_forms(effect_info(Effect::slip_sinkage, true, "slip_sinkage.ks", "-",
                                 "z = z0 (1 + ks s)/(1 - 0.5 ks s) (Lyasko: ks = 1)", 0.0, 1.9),
                     {"lyasko"}),
          [](SimParameters& p) -> double& { return p.effects.slip_sinkage.ks; });
  add_row(t, in_forms(effect_info(Effect::slip_sinkage, true, "slip_sinkage.gain", "-",
                                 "z = z0 (1 + gain s^power)", 0.0, 20.0),
                     {"power"}),
          [](SimParameters& p) -> double& { return p.effects.slip_sinkage.gain; });
  add_row(t, shape_of(in_forms(effect_info(Effect::slip_sinkage, false, "slip_sinkage.power", "-",
                                          "exponent of the slip in z = z0 (1 + gain s^power)", 0.2, 4.0),
                              {"power"})),
          [](SimParameters& p) -> double& { return p.effects.slip_sinkage.power; });
  add_row(t, effect_info(Effect::stress_peak_shift, true, "stress_peak_shift.a1", "-", "theta_m = (a0 + a1 s) theta1",
                         0.0, 0.6),
          [](SimParameters& p) -> double& { return p.effects.stress_peak_shift.a1; });
  add_row(t, effect_info(Effect::rear_contact, true, "rear_contact.lambda_r", "-",
                         "theta2 = -arccos(1 - lambda_r z / r)", 0.0, 1.0),
          [](SimParameters& p) -> double& { return p.effects.rear_contact.lambda_r; });
  add_row(t, effect_info(Effect::grouser, true, "grouser.height_m", "m", "grouser height h", 0.0, 0.1),
          [](SimParameters& p) -> double& { return p.effects.grouser.height_m; });
  // lambda is no parameter of lug_face (the rim shears at r); lug_count only of lug_face.
  add_row(t, in_forms(effect_info(Effect::grouser, false, "grouser.lambda", "-", "r_s = r + lambda h", 0.0, 1.0),
                      {"shear_radius", "lug_tip", "engagement"}),
          [](SimParameters& p) -> double& { return p.effects.grouser.lambda; });
  add_row(t, in_forms(effect_info(Effect::grouser, false, "grouser.lug_count", "-", "lugs per wheel turn", 1.0, 100.0),
                     {"lug_face"}),
          [](SimParameters& p) -> double& { return p.effects.grouser.lug_count; });
  add_row(t, shape_of(in_forms(effect_info(Effect::grouser, false, "grouser.engagement", "-",
                                          "slip-independent part of the lug shear: 0 shear_radius, 1 lug_tip",
                                          0.0, 1.0),
                              {"engagement"})),
          [](SimParameters& p) -> double& { return p.effects.grouser.engagement; });
}

void add_resistance_rows(std::vector<ParameterRow>& t) {
  add_row(t, effect_info(Effect::bulldozing, true, "bulldozing.scale", "-",
                         "multiplier on the bulldozing resistance (Bekker/Wong or Hegedus)", 0.0, 10.0),
          [](SimParameters& p) -> double& { return p.effects.bulldozing.scale; });
  add_row(t, in_forms(effect_info(Effect::load_dependence, true, "load_dependence.dphi_deg", "deg",
                                 "phi = phi0 (1 + sigma/sigma_ref)^(-dphi/phi0) ~ phi0 - dphi ln(1 + sigma/sigma_ref)",
                                 0.0, 10.0),
                     {"friction_angle"}),
          [](SimParameters& p) -> double& { return p.effects.load_dependence.dphi_deg; });
  add_row(t, in_forms(effect_info(Effect::load_dependence, true, "load_dependence.stiffening", "-",
                                 "sigma = sigma_B (1 + sigma_B/sigma_ref)^m", 0.0, 2.0),
                     {"stiffness"}),
          [](SimParameters& p) -> double& { return p.effects.load_dependence.stiffening; });
  add_row(t, effect_info(Effect::load_dependence, false, "load_dependence.sigma_ref_pa", "Pa",
                         "reference normal stress", 1.0, 1e6),
          [](SimParameters& p) -> double& { return p.effects.load_dependence.sigma_ref_pa; });
  add_row(t, in_forms(effect_info(Effect::drive_friction, true, "drive_friction.t0_nm", "N m",
                                 "load-independent drag torque", 0.0, 10.0),
                     {"constant"}),
          [](SimParameters& p) -> double& { return p.effects.drive_friction.t0_nm; });
  add_row(t, in_forms(effect_info(Effect::drive_friction, true, "drive_friction.tv_nm", "N m",
                                 "speed-dependent drag at zero slip, tv/(1 - s) or tv/(1 - s)^p", 0.0, 10.0),
                     {"speed", "power"}),
          [](SimParameters& p) -> double& { return p.effects.drive_friction.tv_nm; });
  add_row(t, effect_info(Effect::drive_friction, false, "drive_friction.k_w_m", "m",
                         "load-proportional friction torque per newton", 0.0, 0.05),
          [](SimParameters& p) -> double& { return p.effects.drive_friction.k_w_m; });
  add_row(t, shape_of(in_forms(effect_info(Effect::drive_friction, false, "drive_friction.speed_exponent", "-",
                                          "p of tv (omega/omega0)^p: 0 constant, 1 viscous", 0.0, 3.0),
                              {"power"})),
          [](SimParameters& p) -> double& { return p.effects.drive_friction.speed_exponent; });
}

const std::vector<ParameterRow>& rows() {
  static const std::vector<ParameterRow> table = [] {
    std::vector<ParameterRow> t;
    add_base_rows(t);
    add_sinkage_and_contact_rows(t);
    add_resistance_rows(t);
    return t;
  }();
  return table;
}

const ParameterRow& find_row(std::string_view name) {
  for (const ParameterRow& row : rows()) {
    if (row.info.name == name) return row;
  }
  std::ostringstream msg;
  msg << "unknown model parameter '" << name << "'; known:";
  for (const ParameterRow& row : rows()) msg << ' ' << row.info.name;
  throw std::invalid_argument(msg.str());
}

// ---------------------------------------------------------------------------
// The contact problem at a given sinkage.

// The contact patch is integrated in a normalized variable u in [0, 1] that
// runs from a stress-free edge (u = 0) to the stress peak (u = 1), for the
// front region theta = theta1 - u (theta1 - thetam) and for the rear region
// theta = theta2 + u (thetam - theta2) together. Wong–Reece's rear profile is
// the front profile mapped onto [theta2, thetam], so sigma is the same
// function of u in both regions: one pow per node, one quadrature per
// integral, the (theta1 - theta)^n behaviour always at u = 0 and no kink
// inside the interval. A region of zero or tiny width costs nothing and
// cannot upset the quadrature.
struct Contact {
  double r = 0, b = 0, rs = 0;         // radius, width, shear radius (torque arm)
  double j_arc = 0, j_chord = 0;       // j = j0 + j_arc (theta1 - theta) - j_chord (1 - s)(sin theta1 - sin theta)
  double j0 = 0;                       // shear before the rim's entry (lug_entry, held-out form), else 0
  double k = 0, n = 0;                 // kc/b + kphi, exponent
  double c = 0, phi0 = 0, K = 0;       // shear
  double s = 0;                        // slip
  double theta1 = 0, theta2 = 0, thetam = 0;
  double front_width = 0, rear_width = 0;  // theta1 - thetam, thetam - theta2
  double sin1 = 0, cos1 = 0;           // sin(theta1), cos(theta1)
  bool load_dependent = false;         // load_dependence, form friction_angle
  double dphi_rad = 0, sigma_ref = 1;
  bool stiffening = false;             // load_dependence, form stiffness
  double stiffening_m = 0;
  bool softening = false;              // shear_softening (not a catalogue effect)
  double residual_ratio = 1, peak_j = 1, hump = 0;
  double k_rn = 0;                     // k r^n (divided by the Lyasko factor with that form)
  double tan_phi0 = 0;
  double rel_tol = kDefaultQuadratureRelTol;

  struct Side {
    double tau, cos_t, sin_t;
  };
  struct Sample {
    double sigma;
    Side front, rear;
  };

  double shear(double sigma, double j) const {
    double tan_phi = tan_phi0;
    if (load_dependent && phi0 > 0.0) {
      // phi0 (1 + sigma/sigma_ref)^(-dphi/phi0): to first order
      // phi0 - dphi ln(1 + sigma/sigma_ref), but smooth and never negative
      // (a clamp at zero would put a kink inside the integrand).
      const double phi = phi0 * std::exp(-(dphi_rad / phi0) * std::log1p(sigma / sigma_ref));
      tan_phi = std::tan(phi);
    }
    const double tau_max = c + sigma * tan_phi;
    if (softening) {
      // Wong's hump: K_r {1 + hump e^(1 - j/K_w)} (1 - e^(-j/K_w)), 1 at j = K_w.
      const double x = j / peak_j;
      return tau_max * residual_ratio * (1.0 + hump * std::exp(1.0 - x)) * (-std::expm1(-x));
    }
    return tau_max * (-std::expm1(-j / K));
  }

  // Bekker pressure at the rim for cos theta - cos theta1 = d, and its
  // stiffening with stress (load_dependence, form stiffness).
  double pressure(double d) const {
    if (!(d > 0.0)) return 0.0;
    const double sigma_b = k_rn * std::pow(d, n);
    return stiffening ? sigma_b * std::pow(1.0 + sigma_b / sigma_ref, stiffening_m) : sigma_b;
  }

  Sample at(double u) const {
    Sample sm{};
    // theta1 - theta on the front side, exact in u.
    const double gap = u * front_width;
    // cos(theta_f) - cos(theta1) and sin(theta1) - sin(theta_f) as products,
    // so that they keep their relative accuracy as u -> 0. The mid angle
    // theta1 - gap/2 and theta_f = mid - gap/2 come by the angle sum from
    // theta1's and the half gap's sines and cosines: one sincos per node
    // instead of three (mid >= theta1/2, so its sine keeps its relative accuracy).
    const double half_gap_sin = std::sin(0.5 * gap);
    const double half_gap_cos = std::cos(0.5 * gap);
    const double sin_mid = sin1 * half_gap_cos - cos1 * half_gap_sin;
    const double cos_mid = cos1 * half_gap_cos + sin1 * half_gap_sin;
    const double d = 2.0 * sin_mid * half_gap_sin;
    const double dsin = 2.0 * cos_mid * half_gap_sin;
    sm.sigma = pressure(d);
    sm.front.sin_t = sin_mid * half_gap_cos - cos_mid * half_gap_sin;
    sm.front.cos_t = cos_mid * half_gap_cos + sin_mid * half_gap_sin;
    sm.front.tau = shear(sm.sigma, j0 + (j_arc * gap - j_chord * (1.0 - s) * dsin));
    if (rear_width > 0.0) {
      const double theta_r = theta2 + u * rear_width;
      sm.rear.sin_t = std::sin(theta_r);
      sm.rear.cos_t = std::cos(theta_r);
      sm.rear.tau =
          shear(sm.sigma, j0 + (j_arc * (theta1 - theta_r) - j_chord * (1.0 - s) * (sin1 - sm.rear.sin_t)));
    }
    return sm;
  }
};

double sinkage_exponent(const SimParameters& p, double slip) {
  const auto& ss = p.effects.slip_sinkage;
  return p.soil.n + (ss.enabled && ss.form == SlipSinkageForm::exponent ? ss.n1 * slip : 0.0);
}

// The load-independent slip-sinkage multiplier f(s): Lyasko's (1 + ks s)/(1 -
// 0.5 ks s), the power form's 1 + gain s^power, times the held-out
// saturating form's 1 + gain min(s, s_sat); 1 when none is on.
double sinkage_multiplier(const SimParameters& p, double slip) {
  const auto& ss = p.effects.slip_sinkage;
  double f = 1.0;
  if (ss.enabled && ss.form == SlipSinkageForm::lyasko) f = (1.0 + ss.ks * slip) / (1.0 - 0.5 * ss.ks * slip);
  if (ss.enabled && ss.form == SlipSinkageForm::power) f = 1.0 + ss.gain * std::pow(slip, ss.power);
  const auto& sat = p.effects.saturating_slip_sinkage;
  if (sat.enabled) f *= 1.0 + sat.gain * std::min(slip, sat.saturation_slip);
  return f;
}

double max_stress_ratio(const SimParameters& p, double slip) {
  return p.a0 + (p.effects.stress_peak_shift.enabled ? p.effects.stress_peak_shift.a1 * slip : 0.0);
}

double shear_radius(const SimParameters& p) {
  const auto& g = p.effects.grouser;
  const bool lengthens = g.enabled && g.form != GrouserForm::lug_face;
  if (p.effects.lug_entry.enabled) return p.wheel.radius_m + p.effects.lug_entry.height_m;
  return p.wheel.radius_m + (lengthens ? g.lambda * g.height_m : 0.0);
}

// The radius whose rolling the ground's speed subtracts in j: the rim's for
// the lug tip (slip is defined on the rim), r_s for the rim-referenced form,
// in between for the engagement form.
double shear_chord_radius(const SimParameters& p, double rs) {
  const auto& g = p.effects.grouser;
  const double r = p.wheel.radius_m;
  if (p.effects.lug_entry.enabled || (g.enabled && g.form == GrouserForm::lug_tip)) return r;
  if (g.enabled && g.form == GrouserForm::engagement) return r + (1.0 - g.engagement) * (rs - r);
  return rs;
}

// Held-out lug_entry: the shear the tips put into the soil between the tip
// circle's entry theta1t and the rim's theta1 (zero otherwise).
double lug_entry_shear(const SimParameters& p, const Contact& ct, double sinkage_m) {
  if (!p.effects.lug_entry.enabled) return 0.0;
  const double t1t = std::acos(std::clamp((ct.r - sinkage_m) / ct.rs, -1.0, 1.0));
  return ct.rs * (t1t - ct.theta1) - ct.r * (1.0 - ct.s) * (std::sin(t1t) - ct.sin1);
}

void set_shear_law(const SimParameters& p, Contact& ct) {
  const auto& ld = p.effects.load_dependence;
  ct.load_dependent = ld.enabled && ld.form == LoadDependenceForm::friction_angle;
  ct.stiffening = ld.enabled && ld.form == LoadDependenceForm::stiffness;
  ct.dphi_rad = ld.dphi_deg * kDegToRad;
  ct.sigma_ref = ld.sigma_ref_pa;
  ct.stiffening_m = ld.stiffening;
  const auto& soft = p.effects.shear_softening;
  ct.softening = soft.enabled;
  if (soft.enabled) {
    ct.residual_ratio = soft.residual_ratio;
    ct.peak_j = soft.peak_displacement_m;
    ct.hump = 1.0 / (soft.residual_ratio * (1.0 - std::exp(-1.0))) - 1.0;
  }
}

Contact make_contact(const SimParameters& p, double sinkage_m, double slip) {
  Contact ct;
  ct.r = p.wheel.radius_m;
  ct.b = p.wheel.width_m;
  ct.rs = shear_radius(p);
  ct.j_arc = ct.rs;
  // Lug tip: the tip (radius r_s) slips against ground that moves at the
  // vehicle speed, which the rim radius sets (s = 1 - v/(r omega)).
  ct.j_chord = shear_chord_radius(p, ct.rs);
  ct.n = sinkage_exponent(p, slip);
  ct.k = p.soil.kc / ct.b + p.soil.kphi;
  ct.c = p.soil.cohesion_pa;
  ct.phi0 = p.soil.friction_angle_rad;
  ct.tan_phi0 = std::tan(ct.phi0);
  ct.K = p.soil.shear_modulus_m;
  ct.s = slip;
  const double zr = std::min(1.0, std::max(0.0, sinkage_m / ct.r));
  ct.theta1 = std::acos(1.0 - zr);
  ct.theta2 = p.effects.rear_contact.enabled
                  ? -std::acos(1.0 - std::min(1.0, p.effects.rear_contact.lambda_r * zr))
                  : 0.0;
  ct.thetam = max_stress_ratio(p, slip) * ct.theta1;
  ct.front_width = ct.theta1 - ct.thetam;
  ct.rear_width = ct.thetam - ct.theta2;
  ct.sin1 = std::sin(ct.theta1);
  ct.cos1 = std::cos(ct.theta1);
  ct.j0 = lug_entry_shear(p, ct, sinkage_m);
  set_shear_law(p, ct);
  // Lyasko: a softer k by f^(n + 1/2) scales Bekker's wheel sinkage,
  // z ~ (W / (b k sqrt(2r)))^(1/(n + 1/2)), by exactly f.
  ct.k_rn = ct.k * std::pow(ct.r, ct.n) / std::pow(sinkage_multiplier(p, slip), ct.n + 0.5);
  ct.rel_tol = p.quadrature_rel_tol;
  return ct;
}

class QuadratureFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Integral over the contact of g(sample at u), g already weighted by the
// region widths (see Contact). The integrands behave like u^n (and u^2n, ...) times smooth
// functions at u = 0 with non-integer n, and are analytic elsewhere on [0, 1].
//
// First a fixed 21-point Gauss–Kronrod rule in t with u = t^3, which turns
// u^n into the much smoother t^(3n + 2): 21 integrand values instead of
// tanh-sinh's ~75. Its estimate |K21 - G10| is the error of the 10-point
// Gauss rule; the Kronrod value is far better: over the soil presets, every
// effect, n 0.25-2, K / 10 to K x 5, slips 0-1 and loads 2-24 kg, an
// estimate below 1e-6 of the L1 norm went with output errors below 2e-10
// with one effect on, 4e-9 with all seven at extreme n or K
// (docs/simulator.md, "Numerical methods"). So the rule is
// accepted when the estimate is below kKronrodAccept x the tolerance (1e-6 at
// the default 1e-9), else tanh-sinh, which handles the endpoint behaviour with
// double-exponential convergence, integrates to the tolerance. The fixed
// nodes also make the value a smooth function of the parameters, which a
// fit's finite differences need.
constexpr double kKronrodAccept = 1e3;

struct KronrodRule {
  static constexpr std::size_t kNodes = 21;
  std::array<double, kNodes> u{};        // nodes in u = t^3
  std::array<double, kNodes> kronrod{};  // weights in u (with du/dt = 3 t^2)
  std::array<double, kNodes> gauss{};    // zero at the Kronrod-only nodes
};

const KronrodRule& kronrod_rule() {
  static const KronrodRule rule = [] {
    using GK = boost::math::quadrature::gauss_kronrod<double, 21>;
    using G = boost::math::quadrature::gauss<double, 10>;
    KronrodRule r;
    std::size_t k = 0;
    // Abscissae x >= 0 on [-1, 1]; x[0] = 0 is a Kronrod node, the odd ones are Gauss nodes.
    for (std::size_t i = 0; i < GK::abscissa().size(); ++i) {
      for (double sign : {1.0, -1.0}) {
        if (i == 0 && sign < 0.0) continue;
        const double t = 0.5 * (1.0 + sign * GK::abscissa()[i]);
        const double jacobian = 0.5 * 3.0 * t * t;  // dt/dx du/dt
        r.u[k] = t * t * t;
        r.kronrod[k] = GK::weights()[i] * jacobian;
        r.gauss[k] = i % 2 == 1 ? G::weights()[i / 2] * jacobian : 0.0;
        ++k;
      }
    }
    return r;
  }();
  return rule;
}

template <class G>
auto integrate_contact_tanh_sinh(const Contact& ct, G g) {
  thread_local boost::math::quadrature::tanh_sinh<double> integrator(15);
  double error = 0.0;
  double l1 = 0.0;
  const auto value = integrator.integrate([&ct, &g](double u) { return g(ct.at(u)); }, 0.0, 1.0, ct.rel_tol, &error, &l1);
  // tanh-sinh's estimate is the difference between its last two levels, so
  // it overstates the true error; 1e3 x the goal flags a real failure only.
  if (!std::isfinite(std::abs(value)) || error > 1e3 * ct.rel_tol * std::max(l1, 1e-300)) {
    std::ostringstream msg;
    msg << "quadrature did not converge on [" << ct.theta2 << ", " << ct.theta1 << "] rad: error estimate "
        << error << " against L1 norm " << l1;
    throw QuadratureFailure(msg.str());
  }
  return value;
}

using KronrodSamples = std::array<Contact::Sample, KronrodRule::kNodes>;

KronrodSamples kronrod_samples(const Contact& ct) {
  KronrodSamples samples;
  for (std::size_t i = 0; i < KronrodRule::kNodes; ++i) samples[i] = ct.at(kronrod_rule().u[i]);
  return samples;
}

// The size of an integrand value in the Kronrod rule's error test: |v|, and
// |re| + |im| for a pair (the L1 norm on the plane; no hypot per node).
double norm1(double v) { return std::fabs(v); }
double norm1(const std::complex<double>& v) { return std::fabs(v.real()) + std::fabs(v.imag()); }

// The Kronrod value of g over the samples; false when its estimate is not
// below kKronrodAccept x the tolerance (then tanh-sinh).
template <class G, class Value>
bool kronrod_integral(const Contact& ct, const KronrodSamples& samples, G g, Value& out) {
  const KronrodRule& rule = kronrod_rule();
  Value kronrod{};
  Value gauss{};
  double l1 = 0.0;
  for (std::size_t i = 0; i < KronrodRule::kNodes; ++i) {
    const Value v = g(samples[i]);
    kronrod += rule.kronrod[i] * v;
    gauss += rule.gauss[i] * v;
    l1 += rule.kronrod[i] * norm1(v);
  }
  out = kronrod;
  return std::isfinite(norm1(kronrod)) && norm1(kronrod - gauss) <= kKronrodAccept * ct.rel_tol * l1;
}

// Integral over the contact of g(sample); the integrands of one contact share
// the samples at the Kronrod nodes (fill_state's two passes).
template <class G>
auto integrate_contact(const Contact& ct, const KronrodSamples& samples, G g) {
  decltype(g(samples[0])) value{};
  if (kronrod_integral(ct, samples, g, value)) return value;
  return integrate_contact_tanh_sinh(ct, g);
}

double vertical_force(const Contact& ct) {
  const double integral = integrate_contact(ct, kronrod_samples(ct), [&ct](const Contact::Sample& sm) {
    return ct.front_width * (sm.sigma * sm.front.cos_t + sm.front.tau * sm.front.sin_t) +
           ct.rear_width * (sm.sigma * sm.rear.cos_t + sm.rear.tau * sm.rear.sin_t);
  });
  return ct.r * ct.b * integral;
}

using Complaint = std::function<std::string(const char*, double)>;

std::string check_base(const SimParameters& p, double load_n, double slip, const Complaint& bad) {
  if (!(p.wheel.radius_m > 0.0) || !std::isfinite(p.wheel.radius_m)) return bad("wheel radius must be > 0 m", p.wheel.radius_m);
  if (!(p.wheel.width_m > 0.0) || !std::isfinite(p.wheel.width_m)) return bad("wheel width must be > 0 m", p.wheel.width_m);
  if (!(load_n > 0.0) || !std::isfinite(load_n)) return bad("load must be > 0 N", load_n);
  if (!(p.quadrature_rel_tol >= 1e-15 && p.quadrature_rel_tol <= 1e-3)) return bad("quadrature_rel_tol must be in [1e-15, 1e-3]", p.quadrature_rel_tol);
  if (!(slip >= 0.0 && slip <= 1.0)) return bad("slip must be in [0, 1] (driving; skid is not modelled)", slip);
  const double k = p.soil.kc / p.wheel.width_m + p.soil.kphi;
  if (!(k > 0.0) || !std::isfinite(k)) return bad("kc/b + kphi must be > 0", k);
  const double n = sinkage_exponent(p, slip);
  if (!(n > 0.0) || !std::isfinite(n)) return bad("sinkage exponent n (n0 + n1 s) must be > 0", n);
  if (!(p.soil.cohesion_pa >= 0.0) || !std::isfinite(p.soil.cohesion_pa)) return bad("cohesion must be >= 0 Pa", p.soil.cohesion_pa);
  if (!(p.soil.friction_angle_rad >= 0.0 && p.soil.friction_angle_rad < 0.5 * kPi))
    return bad("friction angle must be in [0, 90) deg", p.soil.friction_angle_rad / kDegToRad);
  if (!(p.soil.shear_modulus_m > 0.0) || !std::isfinite(p.soil.shear_modulus_m)) return bad("shear modulus K must be > 0 m", p.soil.shear_modulus_m);
  const double ratio = max_stress_ratio(p, slip);
  if (!(ratio >= 0.0 && ratio < 1.0)) return bad("theta_m/theta1 (a0 + a1 s) must be in [0, 1)", ratio);
  return {};
}

// Soil weight enters bulldozing and the lug faces (gamma = rho g).
std::string check_soil_weight(const SimParameters& p, const char* effect, const Complaint& bad) {
  if (!(p.soil.density_kg_m3 > 0.0)) return bad((std::string("soil density must be > 0 for ") + effect).c_str(), p.soil.density_kg_m3);
  if (!(p.gravity_m_s2 > 0.0)) return bad((std::string("gravity must be > 0 for ") + effect).c_str(), p.gravity_m_s2);
  return {};
}

std::string check_geometry_effects(const SimParameters& p, double slip, const Complaint& bad) {
  const auto& ss = p.effects.slip_sinkage;
  if (ss.enabled && ss.form == SlipSinkageForm::lyasko) {
    if (!(ss.ks >= 0.0 && ss.ks < 2.0)) return bad("slip_sinkage.ks must be in [0, 2)", ss.ks);
    if (!(sinkage_multiplier(p, slip) > 0.0) || !std::isfinite(sinkage_multiplier(p, slip))) return bad("slip_sinkage.ks: 1 - 0.5 ks s must be > 0", ss.ks);
  }
  if (ss.enabled && ss.form == SlipSinkageForm::power) {
    if (!(ss.gain >= 0.0) || !std::isfinite(ss.gain)) return bad("slip_sinkage.gain must be >= 0", ss.gain);
    if (!(ss.power > 0.0) || !std::isfinite(ss.power)) return bad("slip_sinkage.power must be > 0", ss.power);
  }
  const auto& sat = p.effects.saturating_slip_sinkage;
  if (sat.enabled && (!(sat.gain >= 0.0) || !std::isfinite(sat.gain) || !(sat.saturation_slip >= 0.0)))
    return bad("saturating_slip_sinkage gain and saturation slip must be >= 0", sat.gain);
  if (p.effects.lug_entry.enabled) {
    if (p.effects.grouser.enabled) return bad("lug_entry (held-out grouser form) cannot be combined with the grouser effect", 1.0);
    if (!(p.effects.lug_entry.height_m >= 0.0) || !std::isfinite(p.effects.lug_entry.height_m)) return bad("lug_entry.height_m must be >= 0", p.effects.lug_entry.height_m);
  }
  if (p.effects.rear_contact.enabled) {
    const double lr = p.effects.rear_contact.lambda_r;
    if (!(lr >= 0.0 && lr <= 1.0)) return bad("rear_contact.lambda_r must be in [0, 1]", lr);
  }
  if (p.effects.grouser.enabled) {
    const auto& g = p.effects.grouser;
    if (!(g.height_m >= 0.0) || !std::isfinite(g.height_m)) return bad("grouser.height_m must be >= 0", g.height_m);
    if (!(g.lambda >= 0.0 && g.lambda <= 1.0)) return bad("grouser.lambda must be in [0, 1]", g.lambda);
    if (!(g.engagement >= 0.0 && g.engagement <= 1.0)) return bad("grouser.engagement must be in [0, 1]", g.engagement);
    if (g.form == GrouserForm::lug_face) {
      if (!(g.lug_count > 0.0) || !std::isfinite(g.lug_count)) return bad("grouser.lug_count must be > 0", g.lug_count);
      return check_soil_weight(p, "grouser lug faces", bad);
    }
  }
  return {};
}

std::string check_force_effects(const SimParameters& p, const Complaint& bad) {
  if (p.effects.bulldozing.enabled) {
    if (!(p.effects.bulldozing.scale >= 0.0) || !std::isfinite(p.effects.bulldozing.scale)) return bad("bulldozing.scale must be >= 0", p.effects.bulldozing.scale);
    if (std::string problem = check_soil_weight(p, "bulldozing", bad); !problem.empty()) return problem;
  }
  if (p.effects.load_dependence.enabled) {
    const auto& l = p.effects.load_dependence;
    if (!(l.dphi_deg >= 0.0) || !std::isfinite(l.dphi_deg)) return bad("load_dependence.dphi_deg must be >= 0", l.dphi_deg);
    if (!(l.sigma_ref_pa > 0.0) || !std::isfinite(l.sigma_ref_pa)) return bad("load_dependence.sigma_ref_pa must be > 0", l.sigma_ref_pa);
    if (!(l.stiffening >= 0.0) || !std::isfinite(l.stiffening)) return bad("load_dependence.stiffening must be >= 0", l.stiffening);
  }
  if (p.effects.drive_friction.enabled) {
    const auto& d = p.effects.drive_friction;
    if (!std::isfinite(d.t0_nm) || !std::isfinite(d.k_w_m) || !std::isfinite(d.tv_nm)) return bad("drive_friction parameters must be finite", d.t0_nm);
    if (!(d.speed_exponent >= 0.0) || !std::isfinite(d.speed_exponent)) return bad("drive_friction.speed_exponent must be >= 0", d.speed_exponent);
  }
  const auto& cv = p.effects.coulomb_viscous_drag;
  if (cv.enabled && (!std::isfinite(cv.coulomb_nm) || !std::isfinite(cv.viscous_nm) || !std::isfinite(cv.k_w_m)))
    return bad("coulomb_viscous_drag parameters must be finite", cv.coulomb_nm);
  const auto& soft = p.effects.shear_softening;
  if (soft.enabled) {
    if (!(soft.residual_ratio > 0.0 && soft.residual_ratio <= 1.0)) return bad("shear_softening.residual_ratio must be in (0, 1]", soft.residual_ratio);
    if (!(soft.peak_displacement_m > 0.0) || !std::isfinite(soft.peak_displacement_m)) return bad("shear_softening.peak_displacement_m must be > 0", soft.peak_displacement_m);
  }
  return {};
}

std::string check_parameters(const SimParameters& p, double load_n, double slip) {
  std::ostringstream msg;
  const Complaint bad = [&msg](const char* what, double value) {
    msg << what << " (got " << value << ")";
    return msg.str();
  };
  if (std::string problem = check_base(p, load_n, slip, bad); !problem.empty()) return problem;
  if (std::string problem = check_geometry_effects(p, slip, bad); !problem.empty()) return problem;
  return check_force_effects(p, bad);
}

// Static sinkage of Bekker's law under a rigid wheel with the parabolic contact
// approximation: W = b k sqrt(2r) z^(n+1/2) * sqrt(pi) Gamma(n+1) / (2 Gamma(n+3/2)).
// Only the starting bracket of the root finder uses it.
double bekker_sinkage_guess(const Contact& ct, double load_n) {
  const double g = std::sqrt(kPi) * boost::math::tgamma(ct.n + 1.0) / (2.0 * boost::math::tgamma(ct.n + 1.5));
  const double coeff = ct.b * ct.k * std::sqrt(2.0 * ct.r) * g;
  return std::pow(load_n / coeff, 1.0 / (ct.n + 0.5));
}

// Terzaghi's factors are needed by bulldozing; the Hegedus form has its own
// (soil destructive angle X_c = 45 deg - phi/2).
double bulldozing_resistance(const SimParameters& p, double z) {
  const auto& bd = p.effects.bulldozing;
  if (!bd.enabled) return 0.0;
  const double gamma = p.soil.density_kg_m3 * p.gravity_m_s2;
  const double c = p.soil.cohesion_pa;
  const double phi = p.soil.friction_angle_rad;
  if (bd.form == BulldozingForm::hegedus) {
    const double xc = 0.25 * kPi - 0.5 * phi;
    const double cot_xc = 1.0 / std::tan(xc);
    const double d1 = cot_xc + std::tan(xc + phi);
    const double d2 = cot_xc + cot_xc * cot_xc * std::tan(phi);
    return bd.scale * p.wheel.width_m * d1 * (c * z + 0.5 * d2 * gamma * z * z);
  }
  const BearingFactors bf = terzaghi_factors(phi);
  return bd.scale * p.wheel.width_m * (0.67 * c * z * bf.kpc + 0.5 * z * z * gamma * bf.kpgamma);
}

// omega / omega(s = 0) = 1/(1 - s) at a fixed vehicle speed; capped at
// s = 0.95 (20x) so that s = 1 (a stalled vehicle) stays finite.
double relative_wheel_speed(double slip) { return 1.0 / std::max(1.0 - slip, 0.05); }

double coulomb_viscous_torque(const SimParameters& p, double load_n, double slip) {
  const auto& cv = p.effects.coulomb_viscous_drag;
  if (!cv.enabled) return 0.0;
  return cv.coulomb_nm + cv.viscous_nm * relative_wheel_speed(slip) + cv.k_w_m * load_n;
}

double drive_friction_torque(const SimParameters& p, double load_n, double slip) {
  const auto& d = p.effects.drive_friction;
  const double held_out = coulomb_viscous_torque(p, load_n, slip);
  if (!d.enabled) return held_out;
  if (d.form == DriveFrictionForm::speed) {
    return held_out + (d.tv_nm / std::max(1.0 - slip, 0.05) + d.k_w_m * load_n);
  }
  if (d.form == DriveFrictionForm::power) {
    return held_out + (d.tv_nm * std::pow(relative_wheel_speed(slip), d.speed_exponent) + d.k_w_m * load_n);
  }
  return held_out + (d.t0_nm + d.k_w_m * load_n);
}

// Grouser form lug_face: the engaged lugs (lug_count per turn over the
// contact angle theta1 - theta2) each push a face h x b against the soil's
// Rankine passive pressure at the mean depth, (gamma (z + h)/2 N_phi + 2 c
// sqrt(N_phi)) h b, N_phi = tan^2(45 deg + phi/2); mobilised like the shear,
// 1 - e^(-j/K), at half the rim's shear displacement at the exit.
double lug_face_thrust(const SimParameters& p, const Contact& ct, double z) {
  const auto& g = p.effects.grouser;
  if (!g.enabled || g.form != GrouserForm::lug_face) return 0.0;
  const double gamma = p.soil.density_kg_m3 * p.gravity_m_s2;
  const double n_phi = std::pow(std::tan(0.25 * kPi + 0.5 * ct.phi0), 2.0);
  const double h = g.height_m;
  const double per_lug = h * ct.b * (0.5 * gamma * (z + h) * n_phi + 2.0 * ct.c * std::sqrt(n_phi));
  const double engaged = g.lug_count * (ct.theta1 - ct.theta2) / (2.0 * kPi);
  const double j_exit = ct.r * ((ct.theta1 - ct.theta2) - (1.0 - ct.s) * (ct.sin1 - std::sin(ct.theta2)));
  return engaged * per_lug * (-std::expm1(-0.5 * j_exit / ct.K));
}

// The two complex output integrals of fill_state (a complex integrand carries
// two real ones on the same nodes): (thrust, compaction resistance) / (r b),
// and (the shear stress, whose moment is the soil torque, the vertical force
// / (r b)).
struct OutputIntegrals {
  std::complex<double> h_rc;
  std::complex<double> tau_w;
};

struct SinkageRoot {
  SimStatus status = SimStatus::ok;
  std::string message;
  double sinkage_m = 0.0;
  int iterations = 0;
  double log_slope = 0.0;  // d ln W / d ln z near the root
  // The warm search's output integrals at the root, interpolated from its
  // iterates (fill_state then needs no samples at the root); none otherwise.
  bool has_outputs = false;
  OutputIntegrals outputs;
};

// Bracket of ln W(z) = ln load in x = ln z: one residual at Bekker's
// closed-form static sinkage, then a step of 1.2 x the Newton step for
// W ~ z^(n+1/2) (slope n + 1/2 in log-log), which usually brackets at once;
// widened by factors of e if not. W(z) grows with z, from 0 at z = 0 to its
// largest value at z = r. Returns lo, hi, f(lo), f(hi).
template <class F>
std::array<double, 4> bracket_sinkage(const SimParameters& p, double load_n, double slip, F residual) {
  const double r = p.wheel.radius_m;
  const double x_max = std::log(r);
  const Contact probe = make_contact(p, 0.5 * r, slip);
  // Lyasko's factor scales the sinkage by f (make_contact); the guess too.
  const double guess = bekker_sinkage_guess(probe, load_n) * sinkage_multiplier(p, slip);
  const double x0 = std::log(std::min(r, std::max(1e-9 * r, guess)));
  const double f0 = residual(x0);
  const double step = 1.2 * std::fabs(f0) / (probe.n + 0.5) + 1e-6;
  double lo = x0, f_lo = f0, hi = x0, f_hi = f0;
  if (f0 > 0.0) {
    lo = x0 - step;
    f_lo = residual(lo);
    for (int i = 0; i < 40 && f_lo > 0.0; ++i) {
      hi = lo;
      f_hi = f_lo;
      lo -= 1.0;
      f_lo = residual(lo);
    }
  } else {
    hi = std::min(x_max, x0 + step);
    f_hi = residual(hi);
    for (int i = 0; i < 60 && f_hi < 0.0 && hi < x_max; ++i) {
      lo = hi;
      f_lo = f_hi;
      hi = std::min(x_max, hi + 1.0);
      f_hi = residual(hi);
    }
  }
  return {lo, hi, f_lo, f_hi};
}

// Solves ln W(z) = ln load in x = ln z: W grows about like z^(n+1/2), so the
// residual is nearly linear in x and toms748 converges in a few steps.
SinkageRoot solve_sinkage_cold(const SimParameters& p, double load_n, double slip) {
  SinkageRoot root;
  const double r = p.wheel.radius_m;
  const double log_load = std::log(load_n);
  auto residual = [&](double x) {
    const double w = vertical_force(make_contact(p, std::exp(x), slip));
    return std::log(std::max(w, 1e-300)) - log_load;
  };
  const auto [lo, hi, f_lo, f_hi] = bracket_sinkage(p, load_n, slip, residual);
  if (f_lo > 0.0) {
    root.status = SimStatus::numerical_failure;
    root.message = "could not bracket the sinkage from below";
    return root;
  }
  if (f_hi < 0.0) {
    std::ostringstream msg;
    msg << "no equilibrium: at sinkage z = r = " << r << " m the soil carries only " << load_n * std::exp(f_hi)
        << " N of the " << load_n << " N load (the wheel sinks past its axle)";
    root.status = SimStatus::no_solution;
    root.message = msg.str();
    return root;
  }
  std::uintmax_t iterations = 100;
  const auto bracket = boost::math::tools::toms748_solve(residual, lo, hi, f_lo, f_hi,
                                                         boost::math::tools::eps_tolerance<double>(kRootBits), iterations);
  if (iterations >= 100) {
    root.status = SimStatus::numerical_failure;
    root.message = "root finder did not converge in 100 iterations";
    return root;
  }
  root.sinkage_m = std::exp(0.5 * (bracket.first + bracket.second));
  root.iterations = static_cast<int>(iterations);
  // The bracket's own secant: the log-log slope a later warm start begins with.
  root.log_slope = (f_hi - f_lo) / (hi - lo);
  return root;
}

// From a nearby solution (a fit's Jacobian perturbs one parameter by ~1e-6):
// secant steps in x = ln z from the hint, with the hint's slope first. Each
// step shrinks the error by the slope's relative error (~ the last step), so
// from 1e-6 two residuals usually suffice. Stops when the step is below
// kWarmStepTol, far below toms748's bracket (kRootBits); false, and the cold
// path takes over, when the steps do not settle or leave (0, r].
constexpr double kWarmStepTol = 1e-12;
constexpr int kWarmMaxResiduals = 6;
// A root reached from the hint's point itself (one residual) takes that
// point's outputs when the last step is below this: off by the step times
// d ln(output)/d ln z, a few 1e-15 (the cold search's own error is 3e-13).
constexpr double kSingleIterateStep = 1e-15;

// One secant iterate of the warm search: ln W - ln load at x = ln z, and the
// output integrals on the same samples (Kronrod values only: `outputs_ok`
// false when their error test fails, and then the root's own samples decide).
struct WarmIterate {
  double x = 0.0;
  double f = 0.0;
  OutputIntegrals outputs;
  bool outputs_ok = false;
};

template <class G>
std::complex<double> kronrod_pair(const Contact& ct, const KronrodSamples& samples, G g, bool& ok) {
  std::complex<double> value;
  ok = kronrod_integral(ct, samples, g, value) && ok;
  return value;
}

// The integrands of fill_state's two passes.
std::complex<double> h_rc_integrand(const Contact& ct, const Contact::Sample& sm) {
  return {ct.front_width * sm.front.tau * sm.front.cos_t + ct.rear_width * sm.rear.tau * sm.rear.cos_t,
          sm.sigma * (ct.front_width * sm.front.sin_t + ct.rear_width * sm.rear.sin_t)};
}

std::complex<double> tau_w_integrand(const Contact& ct, const Contact::Sample& sm) {
  return {ct.front_width * sm.front.tau + ct.rear_width * sm.rear.tau,
          ct.front_width * (sm.sigma * sm.front.cos_t + sm.front.tau * sm.front.sin_t) +
              ct.rear_width * (sm.sigma * sm.rear.cos_t + sm.rear.tau * sm.rear.sin_t)};
}

WarmIterate warm_iterate(const SimParameters& p, double slip, double log_load, double x) {
  const Contact ct = make_contact(p, std::exp(x), slip);
  const KronrodSamples samples = kronrod_samples(ct);
  WarmIterate it;
  it.x = x;
  const double w = ct.r * ct.b * integrate_contact(ct, samples, [&ct](const Contact::Sample& sm) {
    return ct.front_width * (sm.sigma * sm.front.cos_t + sm.front.tau * sm.front.sin_t) +
           ct.rear_width * (sm.sigma * sm.rear.cos_t + sm.rear.tau * sm.rear.sin_t);
  });
  it.f = std::log(std::max(w, 1e-300)) - log_load;
  it.outputs_ok = true;
  it.outputs.h_rc = kronrod_pair(ct, samples, [&ct](const Contact::Sample& sm) { return h_rc_integrand(ct, sm); },
                                 it.outputs_ok);
  it.outputs.tau_w = kronrod_pair(ct, samples, [&ct](const Contact::Sample& sm) { return tau_w_integrand(ct, sm); },
                                  it.outputs_ok);
  return it;
}

// The outputs at the root x + step: linear in x through the last two
// iterates (their error, step x (x - previous) x the curvature, is far below
// rounding), or the last iterate's own when the step is rounding-sized.
void set_root_outputs(const WarmIterate& last, const WarmIterate* previous, double step, SinkageRoot& root) {
  if (previous != nullptr && previous->outputs_ok && last.outputs_ok) {
    const double t = step / (last.x - previous->x);
    root.outputs.h_rc = last.outputs.h_rc + t * (last.outputs.h_rc - previous->outputs.h_rc);
    root.outputs.tau_w = last.outputs.tau_w + t * (last.outputs.tau_w - previous->outputs.tau_w);
    root.has_outputs = true;
  } else if (previous == nullptr && last.outputs_ok && std::fabs(step) < kSingleIterateStep) {
    root.outputs = last.outputs;
    root.has_outputs = true;
  }
}

bool solve_sinkage_warm(const SimParameters& p, double load_n, double slip, const SinkageHint& hint,
                        SinkageRoot& root) {
  const double x_max = std::log(p.wheel.radius_m);
  const double log_load = std::log(load_n);
  double slope = hint.log_slope;
  const double x0 = std::log(hint.sinkage_m);
  if (!(x0 < x_max) || !std::isfinite(x0) || !(slope > 0.0) || !std::isfinite(slope)) return false;
  WarmIterate previous;
  WarmIterate current = warm_iterate(p, slip, log_load, x0);
  for (int i = 1; i < kWarmMaxResiduals; ++i) {
    const double step = -current.f / slope;
    if (!std::isfinite(step)) return false;
    if (std::fabs(step) < kWarmStepTol) {
      root.sinkage_m = std::exp(current.x + step);
      root.iterations = i;
      root.log_slope = slope;
      set_root_outputs(current, i > 1 ? &previous : nullptr, step, root);
      return true;
    }
    const double x_new = current.x + step;
    if (!(x_new < x_max)) return false;
    previous = current;
    current = warm_iterate(p, slip, log_load, x_new);
    // A secant over a step near the residual's rounding (~1e-15) would be
    // noise: keep the slope then (the next step is rounding-sized anyway).
    if (std::fabs(step) > 1e-10) slope = (current.f - previous.f) / step;
    if (!(slope > 0.0) || !std::isfinite(slope)) return false;
  }
  return false;
}

SinkageRoot solve_sinkage(const SimParameters& p, double load_n, double slip, const SinkageHint* hint) {
  if (hint != nullptr && hint->sinkage_m > 0.0) {
    SinkageRoot root;
    if (solve_sinkage_warm(p, load_n, slip, *hint, root)) return root;
  }
  return solve_sinkage_cold(p, load_n, slip);
}

// The four remaining integrals at the solved sinkage, in two passes: a
// complex integrand carries two real ones on the same nodes (tanh-sinh takes
// any value type).
OutputIntegrals output_integrals(const Contact& ct) {
  const KronrodSamples samples = kronrod_samples(ct);
  return {integrate_contact(ct, samples, [&ct](const Contact::Sample& sm) { return h_rc_integrand(ct, sm); }),
          integrate_contact(ct, samples, [&ct](const Contact::Sample& sm) { return tau_w_integrand(ct, sm); })};
}

// The state at the solved sinkage z: the contact integrals (the warm search's,
// interpolated to the root, or computed there), then the effects' forces
// and torques.
void fill_state(const SimParameters& p, double load_n, double slip, const SinkageRoot& root, WheelSoilState& st) {
  const double z = root.sinkage_m;
  const Contact ct = make_contact(p, z, slip);
  const double rb = ct.r * ct.b;
  const OutputIntegrals integrals = root.has_outputs ? root.outputs : output_integrals(ct);
  const std::complex<double> h_rc = rb * integrals.h_rc;
  const std::complex<double>& tau_w = integrals.tau_w;
  st.sinkage_m = z;
  st.entry_angle_rad = ct.theta1;
  st.exit_angle_rad = ct.theta2;
  st.max_stress_angle_rad = ct.thetam;
  st.sinkage_exponent = ct.n;
  st.shear_radius_m = ct.rs;
  st.lug_face_thrust_n = lug_face_thrust(p, ct, z);
  st.gross_thrust_n = h_rc.real() + st.lug_face_thrust_n;
  st.compaction_resistance_n = h_rc.imag();
  // The lug-face force acts at mid-height of the lugs.
  st.soil_torque_nm = ct.r * ct.rs * ct.b * tau_w.real() +
                      st.lug_face_thrust_n * (ct.r + 0.5 * p.effects.grouser.height_m);
  st.bulldozing_resistance_n = bulldozing_resistance(p, z);
  st.drive_friction_torque_nm = drive_friction_torque(p, load_n, slip);
  st.torque_nm = st.soil_torque_nm + st.drive_friction_torque_nm;
  st.drawbar_pull_n = st.gross_thrust_n - st.compaction_resistance_n - st.bulldozing_resistance_n;
  st.vertical_force_n = rb * tau_w.imag();
}

}  // namespace

// ---------------------------------------------------------------------------

std::string_view effect_name(Effect effect) {
  switch (effect) {
    case Effect::slip_sinkage: return "slip_sinkage";
    case Effect::stress_peak_shift: return "stress_peak_shift";
    case Effect::rear_contact: return "rear_contact";
    case Effect::grouser: return "grouser";
    case Effect::bulldozing: return "bulldozing";
    case Effect::load_dependence: return "load_dependence";
    case Effect::drive_friction: return "drive_friction";
  }
  return "?";
}

Effect effect_from_name(std::string_view name) {
  for (Effect e : kAllEffects) {
    if (effect_name(e) == name) return e;
  }
  std::ostringstream msg;
  msg << "unknown effect '" << name << "'; known effects:";
  for (Effect e : kAllEffects) msg << ' ' << effect_name(e);
  throw std::invalid_argument(msg.str());
}

bool EffectSettings::enabled(Effect effect) const {
  switch (effect) {
    case Effect::slip_sinkage: return slip_sinkage.enabled;
    case Effect::stress_peak_shift: return stress_peak_shift.enabled;
    case Effect::rear_contact: return rear_contact.enabled;
    case Effect::grouser: return grouser.enabled;
    case Effect::bulldozing: return bulldozing.enabled;
    case Effect::load_dependence: return load_dependence.enabled;
    case Effect::drive_friction: return drive_friction.enabled;
  }
  return false;
}

void EffectSettings::set_enabled(Effect effect, bool on) {
  switch (effect) {
    case Effect::slip_sinkage: slip_sinkage.enabled = on; break;
    case Effect::stress_peak_shift: stress_peak_shift.enabled = on; break;
    case Effect::rear_contact: rear_contact.enabled = on; break;
    case Effect::grouser: grouser.enabled = on; break;
    case Effect::bulldozing: bulldozing.enabled = on; break;
    case Effect::load_dependence: load_dependence.enabled = on; break;
    case Effect::drive_friction: drive_friction.enabled = on; break;
  }
}

const std::vector<ParameterInfo>& parameter_catalogue() {
  static const std::vector<ParameterInfo> infos = [] {
    std::vector<ParameterInfo> v;
    for (const ParameterRow& row : rows()) v.push_back(row.info);
    return v;
  }();
  return infos;
}

namespace {

bool parameter_in_form(const ParameterInfo& info, Effect effect, std::string_view form) {
  if (!info.is_effect_parameter || info.effect != effect) return false;
  if (info.forms.empty()) return true;
  for (const std::string& f : info.forms) {
    if (f == form) return true;
  }
  return false;
}

}  // namespace

std::vector<std::string> active_parameter_names(const SimParameters& params) {
  std::vector<std::string> names;
  for (const ParameterInfo& info : parameter_catalogue()) {
    if (!info.is_effect_parameter ||
        (params.effects.enabled(info.effect) &&
         parameter_in_form(info, info.effect, effect_form(params.effects, info.effect)))) {
      names.push_back(info.name);
    }
  }
  return names;
}

std::vector<std::string> effect_parameter_names(Effect effect, std::string_view form) {
  std::vector<std::string> names;
  for (bool primary : {true, false}) {
    for (const ParameterInfo& info : parameter_catalogue()) {
      if (info.primary == primary && parameter_in_form(info, effect, form)) names.push_back(info.name);
    }
  }
  return names;
}

std::vector<std::string> effect_parameter_names(Effect effect) {
  return effect_parameter_names(effect, effect_forms(effect).front());
}

std::string primary_parameter_name(Effect effect, std::string_view form) {
  return effect_parameter_names(effect, form).front();
}

std::string primary_parameter_name(Effect effect) { return effect_parameter_names(effect).front(); }

std::vector<std::string> effect_forms(Effect effect) {
  switch (effect) {
    case Effect::slip_sinkage: return {"exponent", "lyasko", "power"};
    case Effect::stress_peak_shift: return {"linear"};
    case Effect::rear_contact: return {"rebound"};
    case Effect::grouser: return {"shear_radius", "lug_tip", "lug_face", "engagement"};
    case Effect::bulldozing: return {"bekker", "hegedus"};
    case Effect::load_dependence: return {"friction_angle", "stiffness"};
    case Effect::drive_friction: return {"constant", "speed", "power"};
  }
  return {"?"};
}

std::string effect_form(const EffectSettings& settings, Effect effect) {
  std::size_t index = 0;
  switch (effect) {
    case Effect::slip_sinkage: index = static_cast<std::size_t>(settings.slip_sinkage.form); break;
    case Effect::grouser: index = static_cast<std::size_t>(settings.grouser.form); break;
    case Effect::bulldozing: index = static_cast<std::size_t>(settings.bulldozing.form); break;
    case Effect::load_dependence: index = static_cast<std::size_t>(settings.load_dependence.form); break;
    case Effect::drive_friction: index = static_cast<std::size_t>(settings.drive_friction.form); break;
    case Effect::stress_peak_shift:
    case Effect::rear_contact: break;
  }
  return effect_forms(effect).at(index);
}

void set_effect_form(EffectSettings& settings, Effect effect, std::string_view form) {
  const std::vector<std::string> forms = effect_forms(effect);
  std::size_t index = 0;
  while (index < forms.size() && forms[index] != form) ++index;
  if (index == forms.size()) {
    std::string msg = "effect " + std::string(effect_name(effect)) + " has no form '" + std::string(form) + "'; its forms:";
    for (const std::string& f : forms) msg += " " + f;
    throw std::invalid_argument(msg);
  }
  const int i = static_cast<int>(index);
  switch (effect) {
    case Effect::slip_sinkage: settings.slip_sinkage.form = static_cast<SlipSinkageForm>(i); break;
    case Effect::grouser: settings.grouser.form = static_cast<GrouserForm>(i); break;
    case Effect::bulldozing: settings.bulldozing.form = static_cast<BulldozingForm>(i); break;
    case Effect::load_dependence: settings.load_dependence.form = static_cast<LoadDependenceForm>(i); break;
    case Effect::drive_friction: settings.drive_friction.form = static_cast<DriveFrictionForm>(i); break;
    case Effect::stress_peak_shift:
    case Effect::rear_contact: break;
  }
}

std::vector<std::string> suggested_base_fit_parameters() {
  return {"soil.kphi", "soil.n", "soil.c_pa", "soil.phi_deg", "soil.K_m", "model.a0"};
}

double get_parameter(const SimParameters& params, std::string_view name) {
  const ParameterRow& row = find_row(name);
  // The accessor needs a mutable object; reading through a copy keeps params const.
  SimParameters copy = params;
  return row.ref(copy) * row.scale_to_exposed;
}

void set_parameter(SimParameters& params, std::string_view name, double value) {
  const ParameterRow& row = find_row(name);
  row.ref(params) = value / row.scale_to_exposed;
}

std::vector<double> get_parameters(const SimParameters& params, const std::vector<std::string>& names) {
  std::vector<double> values;
  values.reserve(names.size());
  SimParameters copy = params;
  for (const std::string& name : names) {
    const ParameterRow& row = find_row(name);
    values.push_back(row.ref(copy) * row.scale_to_exposed);
  }
  return values;
}

void set_parameters(SimParameters& params, const std::vector<std::string>& names, const std::vector<double>& values) {
  if (names.size() != values.size()) {
    throw std::invalid_argument("set_parameters: " + std::to_string(names.size()) + " names but " +
                                std::to_string(values.size()) + " values");
  }
  for (std::size_t i = 0; i < names.size(); ++i) set_parameter(params, names[i], values[i]);
}

std::string_view status_name(SimStatus status) {
  switch (status) {
    case SimStatus::ok: return "ok";
    case SimStatus::bad_input: return "bad_input";
    case SimStatus::no_solution: return "no_solution";
    case SimStatus::numerical_failure: return "numerical_failure";
  }
  return "?";
}

BearingFactors terzaghi_factors(double phi) {
  BearingFactors f{};
  const double tp = std::tan(phi);
  const double cq = std::cos(0.25 * kPi + 0.5 * phi);
  f.nq = std::exp(2.0 * (0.75 * kPi - 0.5 * phi) * tp) / (2.0 * cq * cq);
  // Nc = (Nq - 1) cot(phi) tends to 3 pi / 2 + 1 as phi -> 0; the series keeps it exact there.
  f.nc = phi > 1e-6 ? (f.nq - 1.0) / tp : 1.5 * kPi + 1.0;
  f.ngamma = 2.0 * (f.nq + 1.0) * tp / (1.0 + 0.4 * std::sin(4.0 * phi));
  const double c2 = std::cos(phi) * std::cos(phi);
  f.kpc = (f.nc - tp) * c2;
  // Ngamma / tan(phi) -> 2 (Nq + 1) / (1 + 0.4 sin 4phi) -> 4 as phi -> 0.
  const double ng_over_tan = phi > 1e-6 ? f.ngamma / tp : 2.0 * (f.nq + 1.0) / (1.0 + 0.4 * std::sin(4.0 * phi));
  f.kpgamma = (2.0 * ng_over_tan + 1.0) * c2;
  return f;
}

double vertical_force_at_sinkage(const SimParameters& params, double sinkage_m, double slip) {
  return vertical_force(make_contact(params, sinkage_m, slip));
}

Evaluation evaluate(const SimParameters& p, double load_n, double slip) {
  return evaluate(p, load_n, slip, SinkageHint{});
}

Evaluation evaluate(const SimParameters& p, double load_n, double slip, const SinkageHint& hint) {
  Evaluation ev;
  if (std::string problem = check_parameters(p, load_n, slip); !problem.empty()) {
    ev.status = SimStatus::bad_input;
    ev.message = problem;
    return ev;
  }
  try {
    const SinkageRoot root = solve_sinkage(p, load_n, slip, &hint);
    if (root.status != SimStatus::ok) {
      ev.status = root.status;
      ev.message = root.message;
      return ev;
    }
    fill_state(p, load_n, slip, root, ev.state);
    ev.state.root_iterations = root.iterations;
    ev.state.sinkage_log_slope = root.log_slope;
  } catch (const QuadratureFailure& e) {
    ev.status = SimStatus::numerical_failure;
    ev.message = e.what();
  } catch (const std::exception& e) {
    // Boost.Math reports domain and evaluation errors by exception.
    ev.status = SimStatus::numerical_failure;
    ev.message = std::string("numerical error: ") + e.what();
  }
  return ev;
}

WheelSoilState evaluate_or_throw(const SimParameters& params, double load_n, double slip) {
  Evaluation ev = evaluate(params, load_n, slip);
  if (!ev.ok()) {
    std::ostringstream msg;
    msg << "load " << load_n << " N, slip " << slip << ": " << status_name(ev.status) << ": " << ev.message;
    throw SimError(ev.status, msg.str());
  }
  return ev.state;
}

}  // namespace sinkwatch::ground
