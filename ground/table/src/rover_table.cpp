// The rover section of a parameter table (rover_table.hpp, docs/rover-table.md).
#include "sinkwatch/ground/rover_table.hpp"

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/load.hpp"
#include "sinkwatch/ground/flight_table.hpp"
#include "sinkwatch/ground/text_input.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <utility>

namespace sinkwatch::ground {
namespace {

using flight::RoverParams;

template <typename Quantity>
double get_q(const Quantity& q) {
  return fx::to_double(q.q());
}

// The value in the field's Q format; false (the field untouched) when it does not fit.
template <typename Quantity>
bool set_q(Quantity& q, double value) {
  fx::Status st;
  const typename Quantity::q_type raw = fx::from_double<typename Quantity::q_type>(value, st);
  if (!st.ok()) return false;
  q = Quantity{raw};
  return true;
}

// Section 6's fields in its order (rover_geometry.hpp).
const std::vector<RoverField> kFields = {
    {"mass-kg", "kg", "whole rover (rockers and bogies lumped into the body)",
     [](const RoverParams& p) { return get_q(p.mass_kg); }, [](RoverParams& p, double v) { return set_q(p.mass_kg, v); }},
    {"gravity-mps2", "m/s^2", "gravity of the body the rover stands on (Moon 1.62, Mars 3.71)",
     [](const RoverParams& p) { return get_q(p.gravity_mps2); },
     [](RoverParams& p, double v) { return set_q(p.gravity_mps2, v); }},
    {"com-x-m", "m", "centre of mass, forward of the rocker pivots' midpoint",
     [](const RoverParams& p) { return get_q(p.com_x_m); }, [](RoverParams& p, double v) { return set_q(p.com_x_m, v); }},
    {"com-y-m", "m", "centre of mass, to the left", [](const RoverParams& p) { return get_q(p.com_y_m); },
     [](RoverParams& p, double v) { return set_q(p.com_y_m, v); }},
    {"com-z-m", "m", "centre of mass, up", [](const RoverParams& p) { return get_q(p.com_z_m); },
     [](RoverParams& p, double v) { return set_q(p.com_z_m, v); }},
    {"track-width-m", "m", "between the left and right wheel contact lines",
     [](const RoverParams& p) { return get_q(p.track_width_m); },
     [](RoverParams& p, double v) { return set_q(p.track_width_m, v); }},
    {"wheel-radius-m", "m", "must be the table's wheel radius (section 1)",
     [](const RoverParams& p) { return get_q(p.wheel_radius_m); },
     [](RoverParams& p, double v) { return set_q(p.wheel_radius_m, v); }},
    {"rocker-front-axle-x-m", "m", "front axle from the rocker pivot, forward",
     [](const RoverParams& p) { return get_q(p.rocker_front_axle.x_m); },
     [](RoverParams& p, double v) { return set_q(p.rocker_front_axle.x_m, v); }},
    {"rocker-front-axle-z-m", "m", "front axle from the rocker pivot, up",
     [](const RoverParams& p) { return get_q(p.rocker_front_axle.z_m); },
     [](RoverParams& p, double v) { return set_q(p.rocker_front_axle.z_m, v); }},
    {"rocker-bogie-pivot-x-m", "m", "bogie pivot from the rocker pivot, forward",
     [](const RoverParams& p) { return get_q(p.rocker_bogie_pivot.x_m); },
     [](RoverParams& p, double v) { return set_q(p.rocker_bogie_pivot.x_m, v); }},
    {"rocker-bogie-pivot-z-m", "m", "bogie pivot from the rocker pivot, up",
     [](const RoverParams& p) { return get_q(p.rocker_bogie_pivot.z_m); },
     [](RoverParams& p, double v) { return set_q(p.rocker_bogie_pivot.z_m, v); }},
    {"bogie-middle-axle-x-m", "m", "middle axle from the bogie pivot, forward",
     [](const RoverParams& p) { return get_q(p.bogie_middle_axle.x_m); },
     [](RoverParams& p, double v) { return set_q(p.bogie_middle_axle.x_m, v); }},
    {"bogie-middle-axle-z-m", "m", "middle axle from the bogie pivot, up",
     [](const RoverParams& p) { return get_q(p.bogie_middle_axle.z_m); },
     [](RoverParams& p, double v) { return set_q(p.bogie_middle_axle.z_m, v); }},
    {"bogie-rear-axle-x-m", "m", "rear axle from the bogie pivot, forward",
     [](const RoverParams& p) { return get_q(p.bogie_rear_axle.x_m); },
     [](RoverParams& p, double v) { return set_q(p.bogie_rear_axle.x_m, v); }},
    {"bogie-rear-axle-z-m", "m", "rear axle from the bogie pivot, up",
     [](const RoverParams& p) { return get_q(p.bogie_rear_axle.z_m); },
     [](RoverParams& p, double v) { return set_q(p.bogie_rear_axle.z_m, v); }},
    {"rocker-limit-rad", "rad", "|rocker angle| the mechanism allows",
     [](const RoverParams& p) { return get_q(p.rocker_limit_rad); },
     [](RoverParams& p, double v) { return set_q(p.rocker_limit_rad, v); }},
    {"bogie-limit-rad", "rad", "|bogie angle| the mechanism allows",
     [](const RoverParams& p) { return get_q(p.bogie_limit_rad); },
     [](RoverParams& p, double v) { return set_q(p.bogie_limit_rad, v); }},
    {"attitude-limit-rad", "rad", "|pitch|, |roll| the load model accepts",
     [](const RoverParams& p) { return get_q(p.attitude_limit_rad); },
     [](RoverParams& p, double v) { return set_q(p.attitude_limit_rad, v); }},
    {"high-slip", "", "slip at or above which every drawbar pull is the table's DP_max",
     [](const RoverParams& p) { return get_q(p.high_slip); }, [](RoverParams& p, double v) { return set_q(p.high_slip, v); }},
};

const char* rover_status_text(flight::RoverParamStatus s) {
  using S = flight::RoverParamStatus;
  switch (s) {
    case S::ok: return "ok";
    case S::bad_mass: return "mass outside (0, 1000] kg";
    case S::bad_gravity: return "gravity outside (0, 10] m/s^2";
    case S::bad_wheel_radius: return "wheel radius outside [0.01, 1] m";
    case S::bad_track_width: return "track width outside (0, 4] m";
    case S::bad_com: return "centre of mass: |y| not inside half the track, or |x|, |z| > 2 m";
    case S::bad_link_order:
      return "link order: the front axle must be ahead of the rocker pivot, the bogie pivot behind it, the middle "
             "axle ahead of the bogie pivot and the rear axle behind it";
    case S::bad_link_length: return "a link coordinate beyond +-2 m";
    case S::bad_joint_limit: return "a joint limit outside (0, 0.8] rad";
    case S::bad_attitude_limit: return "attitude limit outside (0, 1.05] rad";
    case S::bad_high_slip: return "high slip outside (0, 1]";
    case S::bad_encoding: return "section 6 absent or malformed";
  }
  return "unknown";
}

const RoverField& field_named(const std::string& name) {
  for (const RoverField& f : kFields) {
    if (name == f.name) return f;
  }
  throw RoverTableError("no rover field '" + name + "'");
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// The requested radius against the table's, compared on the flight grid.
void check_radius(const LoadedTable& base, const RoverParams& rover) {
  if (rover.wheel_radius_m.q().raw() == base.table.wheel_radius_m.q().raw()) return;
  throw RoverTableError("wheel-radius-m " + short_number(get_q(rover.wheel_radius_m)) +
                        " m is not the table's wheel radius " + short_number(get_q(base.table.wheel_radius_m)) +
                        " m (" + base.source +
                        ", section 1): the flight loader refuses such a table (rover_radius_mismatch). Give a base "
                        "table calibrated for this wheel (sinkwatch calibrate --radius ... --table), or leave "
                        "wheel-radius-m out to take the table's");
}

}  // namespace

const std::vector<RoverField>& rover_fields() { return kFields; }

LoadedTable default_table() {
  LoadedTable t;
  t.source = "built-in default";
  return t;
}

LoadedTable read_table_file(const std::string& path) {
  const std::string problem = text_input::unreadable_reason(path);
  if (!problem.empty()) throw RoverTableError(path + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RoverTableError(path + ": cannot open the parameter table");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  flight::PreparedParameters loaded;
  const flight::RejectReason reason = flight::load(bytes.data(), bytes.size(), loaded);
  if (reason != flight::RejectReason::ok) {
    throw RoverTableError(path + ": the flight code rejects this parameter table: " + reject_reason_name(reason));
  }
  LoadedTable t;
  t.source = path;
  t.table = loaded.table();
  if (t.table.rover_geometry.present) t.rover = loaded.rover();
  t.crc = loaded.table_crc();
  t.bytes = bytes.size();
  return t;
}

EncodedTable encode_table(const flight::ParameterTable& table) {
  EncodedTable out;
  out.bytes.resize(flight::kMaxTableBytes);
  const flight::EncodeResult written = flight::encode(table, out.bytes.data(), out.bytes.size());
  if (written.status != flight::RejectReason::ok) {
    throw RoverTableError(std::string("the table does not encode: ") + reject_reason_name(written.status));
  }
  out.bytes.resize(written.size);
  flight::PreparedParameters loaded;
  const flight::RejectReason reason = flight::load(out.bytes.data(), out.bytes.size(), loaded);
  if (reason != flight::RejectReason::ok) {
    throw RoverTableError(std::string("the flight loader refuses the table written: ") + reject_reason_name(reason));
  }
  out.table = loaded.table();
  if (out.table.rover_geometry.present) out.rover = loaded.rover();
  out.crc = loaded.table_crc();
  return out;
}

RoverTable build_rover_table(const LoadedTable& base, const std::vector<std::pair<std::string, double>>& settings) {
  RoverParams rover = base.rover ? *base.rover : flight::yutu_like_rover_params(flight::kGravityMoon);
  if (!base.rover) rover.wheel_radius_m = base.table.wheel_radius_m;
  for (const auto& [name, value] : settings) {
    if (!field_named(name).set(rover, value)) {
      throw RoverTableError(name + " " + text_input::format_number(value) + " does not fit the flight code's format");
    }
  }
  const flight::RoverParamStatus status = flight::validate_rover_params(rover);
  if (status != flight::RoverParamStatus::ok) {
    throw RoverTableError(std::string("the flight code refuses this rover: ") + rover_status_text(status));
  }
  check_radius(base, rover);
  flight::ParameterTable table = base.table;
  table.rover_geometry = flight::RoverSection{true, rover};
  EncodedTable written = encode_table(table);
  RoverTable out;
  out.table = written.table;
  out.rover = *written.rover;  // present: section 6 was just set
  out.bytes = std::move(written.bytes);
  out.crc = written.crc;
  return out;
}

std::string describe_rover(const RoverParams& rover) {
  std::string text;
  char line[200];
  for (const RoverField& f : kFields) {
    std::snprintf(line, sizeof line, "    %-24s %12.6g %-6s %s\n", f.name, f.get(rover), f.unit, f.help);
    text += line;
  }
  return text;
}

}  // namespace sinkwatch::ground
