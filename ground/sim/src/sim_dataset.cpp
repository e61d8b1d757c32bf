// Dataset generation, noise, CSV writing and the spec parsers of `simulate`.
#include "sinkwatch/ground/sim_dataset.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sinkwatch::ground {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;

// Gaussian draws that are the same on every platform: mt19937_64's output
// sequence is fixed by the standard, std::normal_distribution's is not.
class PortableNormal {
 public:
  explicit PortableNormal(std::uint64_t seed) : engine_(seed) {}
  double next() {
    const double u1 = uniform_open();
    const double u2 = uniform_open();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  }

 private:
  // (0, 1), 53 random bits, never 0 (log) and never 1.
  double uniform_open() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }
  std::mt19937_64 engine_;
};

std::string trim(std::string_view s) {
  std::size_t a = 0;
  std::size_t b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  return std::string(s.substr(a, b - a));
}

double parse_number(std::string_view token, std::string_view what) {
  const std::string t = trim(token);
  if (t.empty()) throw std::invalid_argument("empty number in " + std::string(what));
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) {
    throw std::invalid_argument("'" + t + "' is not a finite number (in " + std::string(what) + ")");
  }
  return v;
}

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = s.find(sep, start);
    parts.push_back(std::string(s.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return parts;
}

std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

double ChannelNoise::sigma(double clean) const { return std::hypot(absolute, relative * std::fabs(clean)); }

bool NoiseModel::any() const {
  for (const ChannelNoise* c : {&sinkage_m, &torque_nm, &drawbar_pull_n}) {
    if (c->absolute != 0.0 || c->relative != 0.0) return true;
  }
  return false;
}

std::vector<DatasetRow> generate_dataset(const SimParameters& params, const std::vector<double>& loads_n,
                                         const std::vector<double>& slips, const NoiseModel& noise,
                                         std::uint64_t seed) {
  PortableNormal normal(seed);
  std::vector<DatasetRow> rows;
  rows.reserve(loads_n.size() * slips.size());
  for (double load : loads_n) {
    for (double slip : slips) {
      DatasetRow row;
      row.slip = slip;
      row.load_n = load;
      row.wheel_radius_m = params.wheel.radius_m;
      row.wheel_width_m = params.wheel.width_m;
      row.clean = evaluate_or_throw(params, load, slip);
      // Always three draws per row, so that a channel's noise setting never
      // shifts the draws of another channel or row.
      const double e_z = normal.next();
      const double e_t = normal.next();
      const double e_dp = normal.next();
      row.sinkage_m = row.clean.sinkage_m + noise.sinkage_m.sigma(row.clean.sinkage_m) * e_z;
      row.torque_nm = row.clean.torque_nm + noise.torque_nm.sigma(row.clean.torque_nm) * e_t;
      row.drawbar_pull_n = row.clean.drawbar_pull_n + noise.drawbar_pull_n.sigma(row.clean.drawbar_pull_n) * e_dp;
      rows.push_back(row);
    }
  }
  return rows;
}

const std::vector<std::string>& soil_bin_columns() {
  static const std::vector<std::string> cols = {"slip",           "load_N",         "sinkage_m",    "torque_Nm",
                                                "drawbar_pull_N", "wheel_radius_m", "wheel_width_m"};
  return cols;
}

void write_soil_bin_csv(std::ostream& out, const std::vector<DatasetRow>& rows,
                        const std::vector<std::string>& comment_lines) {
  for (const std::string& line : comment_lines) out << "# " << line << '\n';
  const auto& cols = soil_bin_columns();
  for (std::size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i];
  out << '\n';
  for (const DatasetRow& r : rows) {
    out << fmt(r.slip) << ',' << fmt(r.load_n) << ',' << fmt(r.sinkage_m) << ',' << fmt(r.torque_nm) << ','
        << fmt(r.drawbar_pull_n) << ',' << fmt(r.wheel_radius_m) << ',' << fmt(r.wheel_width_m) << '\n';
  }
}

std::string describe_soil(const SimParameters& p) {
  std::ostringstream s;
  s << "soil " << p.soil.name << ": kc=" << fmt(p.soil.kc) << " N/m^(n+1) kphi=" << fmt(p.soil.kphi)
    << " N/m^(n+2) n=" << fmt(p.soil.n) << " c=" << fmt(p.soil.cohesion_pa)
    << " Pa phi=" << fmt(get_parameter(p, "soil.phi_deg")) << " deg K=" << fmt(p.soil.shear_modulus_m)
    << " m rho=" << fmt(p.soil.density_kg_m3) << " kg/m^3; a0=" << fmt(p.a0) << "; gravity "
    << fmt(p.gravity_m_s2) << " m/s^2; wheel r=" << fmt(p.wheel.radius_m) << " m b=" << fmt(p.wheel.width_m) << " m";
  return s.str();
}

namespace {

// The forms that exist only as data (no Effect value, never fitted): the
// cross-form check's held-out forms.
void describe_data_only_forms(const EffectSettings& e, std::ostringstream& s, bool& first) {
  if (e.shear_softening.enabled) {
    s << (first ? "" : " ") << "shear_softening(residual_ratio=" << fmt(e.shear_softening.residual_ratio)
      << ",peak_displacement_m=" << fmt(e.shear_softening.peak_displacement_m) << ')';
    first = false;
  }
  // The held-out forms (data only, like shear_softening).
  if (e.lug_entry.enabled) {
    s << (first ? "" : " ") << "lug_entry(height_m=" << fmt(e.lug_entry.height_m) << ')';
    first = false;
  }
  if (e.saturating_slip_sinkage.enabled) {
    s << (first ? "" : " ") << "saturating_slip_sinkage(gain=" << fmt(e.saturating_slip_sinkage.gain)
      << ",saturation_slip=" << fmt(e.saturating_slip_sinkage.saturation_slip) << ')';
    first = false;
  }
  if (e.coulomb_viscous_drag.enabled) {
    s << (first ? "" : " ") << "coulomb_viscous_drag(coulomb_nm=" << fmt(e.coulomb_viscous_drag.coulomb_nm)
      << ",viscous_nm=" << fmt(e.coulomb_viscous_drag.viscous_nm)
      << ",k_w_m=" << fmt(e.coulomb_viscous_drag.k_w_m) << ')';
    first = false;
  }
}

}  // namespace

std::string describe_effects(const SimParameters& p) {
  std::ostringstream s;
  bool first = true;
  for (Effect e : kAllEffects) {
    if (!p.effects.enabled(e)) continue;
    s << (first ? "" : " ") << effect_name(e) << '(';
    const std::string form = effect_form(p.effects, e);
    // The default form is not named, so that files from before forms read the same.
    bool first_param = form == effect_forms(e).front();
    if (!first_param) s << "form=" << form;
    for (const std::string& name : effect_parameter_names(e, form)) {
      s << (first_param ? "" : ",") << name.substr(name.find('.') + 1) << '=' << fmt(get_parameter(p, name));
      first_param = false;
    }
    s << ')';
    first = false;
  }
  describe_data_only_forms(p.effects, s, first);
  return first ? std::string("none") : s.str();
}

std::string describe_noise(const NoiseModel& noise) {
  if (!noise.any()) return "none";
  std::ostringstream s;
  auto one = [&s](const char* name, const char* unit, const ChannelNoise& c) {
    s << name << " sigma=hypot(" << fmt(c.absolute) << ' ' << unit << ", " << fmt(100.0 * c.relative) << " %)";
  };
  one("sinkage", "m", noise.sinkage_m);
  s << "; ";
  one("torque", "N m", noise.torque_nm);
  s << "; ";
  one("drawbar_pull", "N", noise.drawbar_pull_n);
  s << " (Gaussian)";
  return s.str();
}

std::vector<double> parse_number_list(std::string_view text) {
  const std::string t = trim(text);
  if (t.empty()) throw std::invalid_argument("empty list");
  std::vector<double> values;
  if (t.find(':') != std::string::npos) {
    const auto parts = split(t, ':');
    if (parts.size() != 3) throw std::invalid_argument("range '" + t + "' must be start:step:stop");
    const double start = parse_number(parts[0], t);
    const double step = parse_number(parts[1], t);
    const double stop = parse_number(parts[2], t);
    if (!(step > 0.0)) throw std::invalid_argument("range '" + t + "': step must be > 0");
    if (stop < start) throw std::invalid_argument("range '" + t + "': stop is below start");
    // Count first and multiply, so that the values do not accumulate rounding.
    const double count = std::floor((stop - start) / step + 1e-9) + 1.0;
    if (count > 100000.0) throw std::invalid_argument("range '" + t + "' has more than 100000 values");
    for (int i = 0; i < static_cast<int>(count); ++i) values.push_back(start + i * step);
    return values;
  }
  for (const std::string& part : split(t, ',')) values.push_back(parse_number(part, t));
  return values;
}

// "form=NAME" may stand anywhere in the list; it is applied first, so that
// the parameters are checked against that form's.
void apply_effect_spec(std::string_view spec, SimParameters& params) {
  const std::string s = trim(spec);
  const std::size_t colon = s.find(':');
  const Effect effect = effect_from_name(trim(s.substr(0, colon)));
  params.effects.set_enabled(effect, true);
  if (colon == std::string::npos) return;
  const std::string prefix = std::string(effect_name(effect)) + ".";
  const std::vector<std::string> items = split(std::string_view(s).substr(colon + 1), ',');
  for (const std::string& item : items) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument("effect " + prefix.substr(0, prefix.size() - 1) + ": '" + item +
                                  "' is not param=value");
    }
    if (trim(item.substr(0, eq)) == "form") set_effect_form(params.effects, effect, trim(item.substr(eq + 1)));
  }
  const std::vector<std::string> known = effect_parameter_names(effect, effect_form(params.effects, effect));
  for (const std::string& item : items) {
    const std::size_t eq = item.find('=');
    if (trim(item.substr(0, eq)) == "form") continue;
    const std::string full = prefix + trim(item.substr(0, eq));
    bool found = false;
    for (const std::string& k : known) found = found || k == full;
    if (!found) {
      std::string msg = "effect " + std::string(effect_name(effect)) + " (form " +
                        effect_form(params.effects, effect) + ") has no parameter '" + trim(item.substr(0, eq)) +
                        "'; its parameters: form";
      for (const std::string& k : known) msg += " " + k.substr(prefix.size());
      throw std::invalid_argument(msg);
    }
    set_parameter(params, full, parse_number(item.substr(eq + 1), full));
  }
}

void apply_noise_spec(std::string_view spec, NoiseModel& noise) {
  for (const std::string& raw : split(spec, ',')) {
    const std::string item = trim(raw);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("noise '" + item + "' is not CHANNEL=VALUE[%]");
    const std::string channel = trim(item.substr(0, eq));
    std::string value = trim(item.substr(eq + 1));
    ChannelNoise* target = nullptr;
    if (channel == "sinkage") target = &noise.sinkage_m;
    if (channel == "torque") target = &noise.torque_nm;
    if (channel == "drawbar_pull") target = &noise.drawbar_pull_n;
    if (target == nullptr) {
      throw std::invalid_argument("unknown noise channel '" + channel + "'; channels: sinkage torque drawbar_pull");
    }
    const bool relative = !value.empty() && value.back() == '%';
    if (relative) value.pop_back();
    const double v = parse_number(value, "noise " + channel);
    if (v < 0.0) throw std::invalid_argument("noise " + channel + " must be >= 0");
    (relative ? target->relative : target->absolute) = relative ? v / 100.0 : v;
  }
}

void apply_parameter_assignment(std::string_view assignment, SimParameters& params) {
  const std::string s = trim(assignment);
  const std::size_t eq = s.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("'" + s + "' is not NAME=VALUE");
  const std::string name = trim(s.substr(0, eq));
  const double value = parse_number(s.substr(eq + 1), name);
  (void)get_parameter(params, name);  // throws, listing the known names, if unknown
  set_parameter(params, name, value);
}

}  // namespace sinkwatch::ground
