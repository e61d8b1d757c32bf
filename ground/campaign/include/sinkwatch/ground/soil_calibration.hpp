// soil_calibration.hpp: the flight table calibrated to a traverse's soil, as
// the paper advises (its sections 5-7: C3 of Eq. 11 and DP_max/W of the
// section-7 current limit from soil-bin tests of the expected soil), for the
// campaign's `--calibrate` runs (issue 14; docs/campaign.md, "A table
// calibrated to the soil").
//
// The soil-bin test is simulated: one wheel of the reference simulator on the
// traverse's soil (scenario_soil(): its preset or drawn soil at a soil scale,
// its effects, its gravity), six loads around the rover's m g / 6 and slips
// 0.05 .. 0.60, with measurement noise. The rows take the path of
// `sinkwatch simulate` | `sinkwatch calibrate --per-load --fix c1=1,c2=1
// --table`: written as soil-bin CSV, read back, fitted per load in the form of
// the paper's Table 2 (C1 = C2 = 1, C3 fitted; DP_max/W the largest measured
// pull), and built into the base table by build_flight_table(), which hands
// out only tables the flight loader accepts. Every other section (levels,
// motor, section 8, rover) is the base table's.
#pragma once

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/ground/scenario.hpp"

#include <cstdint>
#include <string>

namespace sinkwatch::ground {

/// Which soil of a traverse the soil bin holds.
enum class CalibrationSoil {
  none,     // no calibration: the campaign's table as given
  site,     // the traverse's soil at scale 1: the site's material as a soil bin prepares it
  softest,  // the traverse's softest soil a soil-bin wheel still gets a pull from (below)
};
const char* calibration_soil_name(CalibrationSoil s);
/// Throws std::invalid_argument for a name other than none, site or softest.
CalibrationSoil calibration_soil_from_name(const std::string& name);

/// The soil-bin grid: loads as multiples of the rover's m g / 6 (the rear
/// wheels carry up to ~1.4 of it on slopes and in soft soil, rover-loads.md
/// 12.6) and the slips of the paper's tests.
inline constexpr double kCalibrationLoadFactors[] = {0.6, 0.8, 1.0, 1.2, 1.4, 1.6};
inline constexpr double kCalibrationSlips[] = {0.05, 0.10, 0.15, 0.20, 0.25, 0.30,
                                              0.35, 0.40, 0.45, 0.50, 0.55, 0.60};
/// `softest`: a soil so soft that the soil-bin wheel gets no positive pull at
/// some load cannot give DP_max (the flight loader refuses DP_max <= 0); the
/// scale is then doubled, at most this many times (0.005 * 2^8 > 1).
inline constexpr int kSoftestScaleDoublings = 8;

/// What a calibration fitted, in the numbers the campaign reports.
struct SoilBinFit {
  double soil_scale = 1.0;       // the scale of the soil the bin held
  double c3_at_mean_load = 0.0;  // the fitted C3 at m g / 6 (the grid's load factor 1.0)
  double dp_max_at_mean_load = 0.0;
};

struct SoilCalibration {
  flight::ParameterTable table;  // the base table with the fitted C(W) rows
  SoilBinFit fit;
};

/// The table calibrated to `soil` (not none) of the traverse `spec`, whose
/// softest soil scale is `min_soil_scale`, for its mass and gravity; the
/// noise draws come from `seed` (deterministic). Throws CalibrationError when
/// no scale up to 1 gives a table the flight loader accepts.
SoilCalibration calibrate_to_soil(const ScenarioSpec& spec, double min_soil_scale, CalibrationSoil soil,
                                  const flight::ParameterTable& base, std::uint64_t seed);

}  // namespace sinkwatch::ground
