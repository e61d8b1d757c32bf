// Soil presets, planetary gravity and the default (Yutu-like) wheel for the
// reference simulator. Every value's source is in docs/simulator.md
// ("Soil presets"); values marked there as assumptions are not from a source.
#pragma once

#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace sinkwatch::ground {

struct SoilPreset {
  SoilParameters soil;
  std::string source;  // citation, one line
};

// "lunar-soil", "hit-lss1", "dry-sand".
const std::vector<SoilPreset>& soil_presets();
std::vector<std::string> soil_preset_names();
// Throws std::invalid_argument naming the known presets.
SoilParameters soil_preset(std::string_view name);

struct Body {
  std::string name;
  double gravity_m_s2;
};
// "earth" (9.81 m/s^2, the paper's soil bin), "moon" (1.62), "mars" (3.71).
const std::vector<Body>& bodies();
double body_gravity(std::string_view name);  // throws std::invalid_argument

// Radius 0.15 m, width 0.15 m: a Yutu-class wheel (an assumption; see docs).
WheelGeometry default_wheel();

// Default model for a preset: that soil, the default wheel, Earth gravity,
// theta_m = 0.43 theta1, all effects off.
SimParameters default_parameters(std::string_view soil_name = "hit-lss1");

}  // namespace sinkwatch::ground
