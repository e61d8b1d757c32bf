// Soil-bin style datasets from the reference simulator: a grid of loads x
// slips, evaluated with the chosen effects, plus seeded Gaussian measurement
// noise, written as CSV in the calibration tool's dimensional columns
//   slip,load_N,sinkage_m,torque_Nm,drawbar_pull_N,wheel_radius_m,wheel_width_m
// with '#' comment lines on top that record how the file was made.
// Same parameters, grid, noise and seed -> byte-identical output.
#pragma once

#include "sinkwatch/ground/wheel_soil_model.hpp"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace sinkwatch::ground {

// Standard deviation sigma = hypot(absolute, relative * |clean value|).
struct ChannelNoise {
  double absolute = 0.0;  // in the channel's unit (m, N m, N)
  double relative = 0.0;  // fraction of the clean value (0.02 = 2 %)
  double sigma(double clean) const;
};

struct NoiseModel {
  ChannelNoise sinkage_m;
  ChannelNoise torque_nm;
  ChannelNoise drawbar_pull_n;
  bool any() const;
};

struct DatasetRow {
  double slip = 0.0;
  double load_n = 0.0;
  double sinkage_m = 0.0;       // measured (clean + noise)
  double torque_nm = 0.0;       // measured
  double drawbar_pull_n = 0.0;  // measured
  double wheel_radius_m = 0.0;
  double wheel_width_m = 0.0;
  WheelSoilState clean;         // the model's noiseless state for this row
};

// Rows in load-major order (every slip for the first load, then the next).
// Noise draws are taken in that order, three per row (sinkage, torque, drawbar
// pull), from mt19937_64(seed) through a portable Box–Muller transform, so the
// numbers do not depend on the standard library's distributions.
// Throws SimError naming the load and slip if a row has no solution.
std::vector<DatasetRow> generate_dataset(const SimParameters& params, const std::vector<double>& loads_n,
                                         const std::vector<double>& slips, const NoiseModel& noise,
                                         std::uint64_t seed);

// Column names, in order.
const std::vector<std::string>& soil_bin_columns();
// Writes "# " + each comment line, the header and the rows (%.9g).
void write_soil_bin_csv(std::ostream& out, const std::vector<DatasetRow>& rows,
                        const std::vector<std::string>& comment_lines);

// Human-readable one-liners for the CSV comments.
std::string describe_soil(const SimParameters& params);
std::string describe_effects(const SimParameters& params);
std::string describe_noise(const NoiseModel& noise);

// Parsers shared by the CLI and the tests. All throw std::invalid_argument
// with a message that names the offending token.
// "0.1,0.2,0.3" or "start:step:stop" (inclusive, computed as start + i step).
std::vector<double> parse_number_list(std::string_view text);
// "NAME" or "NAME:param=value,param=value": enables the effect in params and
// sets its parameters (param names without the "NAME." prefix).
void apply_effect_spec(std::string_view spec, SimParameters& params);
// "CHANNEL=VALUE[%][,CHANNEL=VALUE[%]...]": channels sinkage, torque,
// drawbar_pull; VALUE is absolute in m, N m, N, or relative with '%'.
void apply_noise_spec(std::string_view spec, NoiseModel& noise);
// "NAME=VALUE" for any name of parameter_catalogue().
void apply_parameter_assignment(std::string_view assignment, SimParameters& params);

}  // namespace sinkwatch::ground
