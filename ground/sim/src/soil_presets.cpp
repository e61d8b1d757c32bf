// Soil presets with their sources; docs/simulator.md repeats them with notes.
#include "sinkwatch/ground/soil_presets.hpp"

#include <sstream>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A preset's values in the units the sources print (phi in degrees).
struct PresetValues {
  double kc, kphi, n, c_pa, phi_deg, k_m, density;
};

SoilParameters make(std::string name, const PresetValues& v) {
  SoilParameters s;
  s.name = std::move(name);
  s.kc = v.kc;
  s.kphi = v.kphi;
  s.n = v.n;
  s.cohesion_pa = v.c_pa;
  s.friction_angle_rad = v.phi_deg * kDeg;
  s.shear_modulus_m = v.k_m;
  s.density_kg_m3 = v.density;
  return s;
}
}  // namespace

const std::vector<SoilPreset>& soil_presets() {
  static const std::vector<SoilPreset> presets = {
      // Apollo-era lunar soil: Bekker values of the Lunar Sourcebook (Carrier,
      // Olhoeft & Mendell 1991, ch. 9) as used by the NASA LTV white paper
      // (NTRS 20220010732); gamma = 2470 N/m^3 on the Moon -> rho ~ 1525 kg/m^3.
      {make("lunar-soil", {1.4e3, 820e3, 1.0, 170.0, 35.0, 0.018, 1525.0}),
       "Lunar Sourcebook (Carrier et al. 1991) / NASA LTV white paper NTRS 20220010732"},
      // HIT-LSS1 lunar soil simulant (Harbin Institute of Technology), the kind
      // of simulant of the Chinese lunar-rover wheel tests: Ding et al. 2015
      // (J. Field Robotics 32(6)) Table I as transcribed by gz-terramechanics.
      // Density not given there: 1600 kg/m^3 is an assumption.
      {make("hit-lss1", {15.6e3, 2407.4e3, 1.1, 250.0, 31.9, 0.010, 1600.0}),
       "Ding et al. 2015, J. Field Robotics 32(6):827-859, Table I (via gz-terramechanics)"},
      // Dry sand (Land Locomotion Lab) from Wong, Theory of Ground Vehicles,
      // terrain-value table, as also transcribed by gz-terramechanics; K = 10 mm
      // (firm end of the 10-25 mm range noted there); density 1600 kg/m^3 is
      // an assumption.
      {make("dry-sand", {0.99e3, 1528.43e3, 1.1, 1040.0, 28.0, 0.010, 1600.0}),
       "Wong, Theory of Ground Vehicles, terrain values, dry sand (LLL) (via gz-terramechanics)"},
  };
  return presets;
}

std::vector<std::string> soil_preset_names() {
  std::vector<std::string> names;
  for (const SoilPreset& p : soil_presets()) names.push_back(p.soil.name);
  return names;
}

SoilParameters soil_preset(std::string_view name) {
  for (const SoilPreset& p : soil_presets()) {
    if (p.soil.name == name) return p.soil;
  }
  std::ostringstream msg;
  msg << "unknown soil '" << name << "'; known soils:";
  for (const SoilPreset& p : soil_presets()) msg << ' ' << p.soil.name;
  throw std::invalid_argument(msg.str());
}

const std::vector<Body>& bodies() {
  static const std::vector<Body> list = {{"earth", 9.81}, {"moon", 1.62}, {"mars", 3.71}};
  return list;
}

double body_gravity(std::string_view name) {
  for (const Body& b : bodies()) {
    if (b.name == name) return b.gravity_m_s2;
  }
  throw std::invalid_argument("unknown body '" + std::string(name) + "'; known bodies: earth moon mars");
}

WheelGeometry default_wheel() { return WheelGeometry{0.15, 0.15}; }

SimParameters default_parameters(std::string_view soil_name) {
  SimParameters p;
  p.soil = soil_preset(soil_name);
  p.wheel = default_wheel();
  p.gravity_m_s2 = body_gravity("earth");
  return p;
}

}  // namespace sinkwatch::ground
