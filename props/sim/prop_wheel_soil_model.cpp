// Reference simulator over random admissible parameters (the catalogue's
// bounds, which a bounded fit may visit): evaluate() never throws, a solved
// state carries the load, and the sinkage grows with the load.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sinkwatch/ground/soil_presets.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

namespace sg = sinkwatch::ground;

namespace {

double uniform(double lo, double hi) {
  const int k = *rc::gen::inRange(0, 1000001);
  return lo + (hi - lo) * k / 1e6;
}
double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }

sg::SimParameters random_parameters() {
  sg::SimParameters p = sg::default_parameters("hit-lss1");
  p.soil.kc = log_uniform(1e2, 1e5);
  p.soil.kphi = log_uniform(1e5, 1e7);
  p.soil.n = uniform(0.5, 1.5);
  p.soil.cohesion_pa = uniform(0.0, 3000.0);
  sg::set_parameter(p, "soil.phi_deg", uniform(0.0, 45.0));
  p.soil.shear_modulus_m = log_uniform(1e-3, 5e-2);
  p.wheel.radius_m = uniform(0.05, 0.5);
  p.wheel.width_m = uniform(0.05, 0.5);
  p.a0 = uniform(0.0, 0.9);
  for (sg::Effect e : sg::kAllEffects) p.effects.set_enabled(e, *rc::gen::arbitrary<bool>());
  p.effects.slip_sinkage.n1 = uniform(0.0, 1.0);
  p.effects.stress_peak_shift.a1 = uniform(0.0, 0.09);  // keeps a0 + a1 s < 1 with a0 <= 0.9
  p.effects.rear_contact.lambda_r = uniform(0.0, 1.0);
  p.effects.grouser.height_m = uniform(0.0, 0.03);
  p.effects.load_dependence.dphi_deg = uniform(0.0, 5.0);
  // Every form of every effect (issue 16), the flexible forms' shapes over their ranges.
  for (sg::Effect e : sg::kAllEffects) {
    const std::vector<std::string> forms = sg::effect_forms(e);
    sg::set_effect_form(p.effects, e, forms[*rc::gen::inRange<std::size_t>(0, forms.size())]);
  }
  p.effects.slip_sinkage.ks = uniform(0.0, 1.5);
  p.effects.slip_sinkage.gain = uniform(0.0, 3.0);
  p.effects.slip_sinkage.power = uniform(0.2, 4.0);
  p.effects.grouser.engagement = uniform(0.0, 1.0);
  p.effects.drive_friction.speed_exponent = uniform(0.0, 3.0);
  return p;
}

}  // namespace

RC_GTEST_PROP(WheelSoilProps, EvaluateReturnsAStatusAndSolvedStatesCarryTheLoad, ()) {
  const sg::SimParameters p = random_parameters();
  const double load = log_uniform(0.5, 3000.0);
  const double slip = uniform(0.0, 1.0);
  sg::Evaluation ev;
  try {
    ev = sg::evaluate(p, load, slip);
  } catch (const std::exception& e) {
    RC_FAIL(std::string("evaluate threw: ") + e.what());
  }
  RC_TAG(std::string(sg::status_name(ev.status)));
  RC_LOG() << sg::status_name(ev.status) << ": " << ev.message << " (load " << load << " N, slip " << slip
           << ", r " << p.wheel.radius_m << ", n " << p.soil.n << ", a0 " << p.a0 << ", K " << p.soil.shear_modulus_m
           << ", b " << p.wheel.width_m << ", kc " << p.soil.kc << ", kphi " << p.soil.kphi << ", c " << p.soil.cohesion_pa
           << ", phi " << p.soil.friction_angle_rad << ", effects";
  for (sg::Effect e : sg::kAllEffects) RC_LOG() << ' ' << (p.effects.enabled(e) ? sg::effect_name(e) : "-");
  for (sg::Effect e : sg::kAllEffects) RC_LOG() << ' ' << sg::effect_form(p.effects, e);
  RC_LOG() << ", n1 " << p.effects.slip_sinkage.n1 << ", a1 " << p.effects.stress_peak_shift.a1 << ", lr "
           << p.effects.rear_contact.lambda_r << ", h " << p.effects.grouser.height_m << ", dphi "
           << p.effects.load_dependence.dphi_deg << ")\n";
  RC_ASSERT(ev.status == sg::SimStatus::ok || ev.status == sg::SimStatus::no_solution);
  if (!ev.ok()) return;
  const sg::WheelSoilState& st = ev.state;
  RC_ASSERT(st.sinkage_m > 0.0);
  RC_ASSERT(st.sinkage_m <= p.wheel.radius_m);
  RC_ASSERT(std::fabs(st.vertical_force_n / load - 1.0) < 1e-9);
  RC_ASSERT(st.soil_torque_nm >= 0.0);
  RC_ASSERT(std::isfinite(st.drawbar_pull_n));
  // More load, more sinkage (W(z) grows with z).
  const sg::Evaluation heavier = sg::evaluate(p, 1.5 * load, slip);
  if (heavier.ok()) RC_ASSERT(heavier.state.sinkage_m > st.sinkage_m);
}
