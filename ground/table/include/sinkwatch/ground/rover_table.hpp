// rover_table.hpp: the parameter table's rover section (section 6: the
// rover's mass, gravity, centre of mass and rocker-bogie geometry,
// flight/rover_geometry.hpp) written from the operator's numbers, and a table
// file read back and shown in human units (docs/rover-table.md).
//
// A table this code hands out is one the flight loader has accepted: the
// rover passes the flight code's validate_rover_params(), section 6 is
// the table's typed RoverSection, the whole table written by flight::encode()
// with its CRC, and the bytes are loaded back through flight::load() (the
// one path from bytes to parameters the rover and the replay use) before
// they are returned. Every section other than 6 is the base table's.
//
// The rover's wheel radius must be the table's (section 1): load() refuses a
// table whose two radii differ (rover_radius_mismatch), because the statics
// and Eq. 15 must describe the same wheel. The radius is therefore taken from
// the base table, and a different one asked for is refused with that reason.
#pragma once

#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/rover_geometry.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sinkwatch::ground {

/// One RoverParams field in SI units: its option name (also the name in
/// messages and in table-info), unit and meaning, and how to read it from
/// and write it into the flight struct (set: false when the value does not
/// fit the field's Q format).
struct RoverField {
  const char* name;  // "mass-kg", "com-x-m", ...
  const char* unit;  // "kg", "m", "rad", ...
  const char* help;
  double (*get)(const flight::RoverParams& p);
  bool (*set)(flight::RoverParams& p, double value);
};

/// Every field of RoverParams, in the declaration order (that of section 6).
const std::vector<RoverField>& rover_fields();

/// A refused request: a value outside the flight code's range, a wheel
/// radius that is not the table's, a base table the loader refuses.
class RoverTableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A table file as the flight code loads it.
struct LoadedTable {
  std::string source;  // the path, or "built-in default"
  flight::ParameterTable table = flight::default_parameter_table();
  std::optional<flight::RoverParams> rover;  // section 6, when the table has one
  std::uint32_t crc = 0;                     // 0 for the built-in default
  std::size_t bytes = 0;
};

/// Reads a table file through flight::load(). Throws RoverTableError naming
/// the file and the loader's reason.
LoadedTable read_table_file(const std::string& path);

/// The built-in default table (no section 6).
LoadedTable default_table();

/// A table as written: its bytes (flight::encode(), with the CRC) and what
/// flight::load() made of them.
struct EncodedTable {
  flight::ParameterTable table{};            // as loaded back from the bytes
  std::optional<flight::RoverParams> rover;  // section 6, when the table has one
  std::vector<std::uint8_t> bytes;
  std::uint32_t crc = 0;
};

/// The one table writer of the ground tools that hand out a whole table
/// (rover-table, campaign --choose-levels): encodes `table` and loads the
/// bytes back through flight::load(). Throws RoverTableError with the
/// encoder's or the loader's reason.
EncodedTable encode_table(const flight::ParameterTable& table);

struct RoverTable {
  flight::ParameterTable table{};  // as loaded back from the bytes
  flight::RoverParams rover{};     // as loaded back
  std::vector<std::uint8_t> bytes;
  std::uint32_t crc = 0;
};

/// The base's rover (its section 6, else the Yutu-like rover on the Moon with
/// the base table's wheel radius), each (field name, value) of `settings`
/// applied in turn, validated, encoded into section 6 and the table, and
/// loaded back. Throws RoverTableError naming the refused field.
RoverTable build_rover_table(const LoadedTable& base, const std::vector<std::pair<std::string, double>>& settings);

/// The rover's fields, one line each ("  mass-kg  140 kg  whole rover ...").
std::string describe_rover(const flight::RoverParams& rover);

/// Every section of a table in human units (table-info).
std::string describe_table(const LoadedTable& t);

}  // namespace sinkwatch::ground
