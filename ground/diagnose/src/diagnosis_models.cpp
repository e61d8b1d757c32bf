// diagnosis_models.cpp: Eq. 11 and the Wong–Reece simulator as diagnosis models.
#include "sinkwatch/ground/diagnosis_models.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <utility>

#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/ground/reference.hpp"

namespace sinkwatch {
namespace ground {

// ---------------------------------------------------------------------------
// Eq. 11

namespace {

double mean_load(const std::vector<DiagnosisRow>& rows) {
  double sum = 0.0;
  for (const DiagnosisRow& row : rows) {
    sum += row.load_n;
  }
  return rows.empty() ? 0.0 : sum / static_cast<double>(rows.size());
}

}  // namespace

// DP/W is dimensionless; its unit is the wheel load, so values read "0.024 DP/W".
std::vector<ChannelInfo> EstimatorModel::channels() const { return {{"traction_coeff", "DP/W"}}; }

std::vector<double> EstimatorModel::measured(const DiagnosisRow& row) const { return {row.traction_coeff}; }

std::vector<ParameterSpec> EstimatorModel::base_parameters(const std::vector<DiagnosisRow>& train) const {
  (void)train;
  return {{"c1", 1.0, -10.0, 10.0}, {"c2", 1.0, -10.0, 10.0}, {"c3", 0.0, -5.0, 5.0}};
}

namespace {

// A candidate that is a family of its own (no forms).
Candidate term(std::string name, std::string description, std::vector<ParameterSpec> extra, double nominal_size) {
  Candidate c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.extra = std::move(extra);
  c.nominal_size = nominal_size;
  return c;
}

}  // namespace

std::vector<Candidate> EstimatorModel::candidates(const std::vector<DiagnosisRow>& train) const {
  std::vector<Candidate> out;
  out.push_back(term("entry_angle_geometry",
                     "exact entry angle: - C4 arccos(1 - z/r) beside the linear z/r term (Eq. 9 -> 10 step)",
                     {{"c4", 0.0, -10.0, 10.0}}, 0.1));
  Candidate load = term("load_offset", "load-dependent offset: - C5 (W/W_ref - 1), W_ref = mean training load",
                        {{"c5", 0.0, -5.0, 5.0}}, 0.05);
  load.reference = mean_load(train);
  if (distinct_loads(train).size() < 2) {
    load.identifiable = false;
    load.note = "needs training rows at two or more loads";
  }
  out.push_back(load);
  out.push_back(term("slip_shear", "shear still developing at low slip: - C6 exp(-s/s0) (Janosi-Hanamoto)",
                     {{"c6", 0.0, -5.0, 5.0}, {"s0", 0.1, 0.01, 1.0}}, 0.1));
  out.push_back(term("bulldozing_z2", "frontal bulldozing: - C7 (z/r)^2", {{"c7", 0.0, -100.0, 100.0}}, 1.0));
  // W_ref is a property of the training rows; keep it in the description.
  if (!train.empty()) {
    std::ostringstream os;
    os.precision(4);
    os << out[1].description << " (" << mean_load(train) << " N)";
    out[1].description = os.str();
  }
  return out;
}

bool EstimatorModel::predict(const Candidate* candidate, const std::vector<double>& params, const DiagnosisRow& row,
                             std::vector<double>& out) const {
  double dpw = params[0] * row.drive_coeff - params[1] * row.sinkage_ratio - params[2];
  if (candidate != nullptr) {
    const std::string& name = candidate->name;
    if (name == "entry_angle_geometry") {
      const double x = std::clamp(1.0 - row.sinkage_ratio, -1.0, 1.0);
      dpw -= params[3] * std::acos(x);
    } else if (name == "load_offset") {
      dpw -= params[3] * (row.load_n / candidate->reference - 1.0);
    } else if (name == "slip_shear") {
      dpw -= params[3] * std::exp(-row.slip / params[4]);
    } else if (name == "bulldozing_z2") {
      dpw -= params[3] * row.sinkage_ratio * row.sinkage_ratio;
    } else {
      return false;
    }
  }
  out.assign(1, dpw);
  return std::isfinite(dpw);
}

namespace {

// The coefficients the flight code runs for the quantisation check: the
// fitted ones when inside the flight envelope (estimator.hpp), otherwise the
// paper's Eq. 14 (1, 1, 0.2): the size of the quantisation does not depend on
// the coefficients' values, only on the Q formats.
struct FlightCoefficients {
  std::vector<double> values;
  std::string note;
  flight::Coefficients c;
  bool converted = true;  // every coefficient converted to its Q format
};

flight::Coefficients to_flight(const std::vector<double>& coeff, fx::Status& st) {
  return flight::Coefficients{flight::Ratio(fx::from_double<flight::RatioQ>(coeff[0], st)),
                              flight::Ratio(fx::from_double<flight::RatioQ>(coeff[1], st)),
                              flight::Ratio(fx::from_double<flight::RatioQ>(coeff[2], st))};
}

FlightCoefficients flight_coefficients(const std::vector<double>& base_params, double radius_m) {
  FlightCoefficients fc;
  fc.values.assign(base_params.begin(), base_params.begin() + 3);
  fc.note = "the fitted coefficients";
  fx::Status st;
  fc.c = to_flight(fc.values, st);
  const flight::LengthM probe_r(fx::from_double<flight::LengthQ>(radius_m, st));
  constexpr flight::LoadQ kOneNewton = fx::constant<flight::LoadQ>(1.0);
  const flight::WheelLoadN probe_w(kOneNewton);
  if (!st.ok() ||
      flight::check_estimator_inputs(fc.c, probe_r, probe_w) == flight::EstimateStatus::invalid_coefficient) {
    fc.values = {1.0, 1.0, 0.2};
    fc.note = "Eq. 14's C = (1, 1, 0.2), because the fitted coefficients are outside the flight envelope "
              "(C1, C2 in [0.25, 4], C3 in [-1, 1])";
    st = fx::Status{};
    fc.c = to_flight(fc.values, st);
  }
  fc.converted = st.ok();
  return fc;
}

struct QuantisationSums {
  std::size_t used = 0;
  std::size_t skipped = 0;
  std::string first_problem;
  double sum = 0.0;  // of squared DP/W differences
  double sum_z = 0.0;
  double max_abs = 0.0;
  double max_abs_z = 0.0;
};

// One row: flight Eq. 11 in both directions against the double twin on the
// same quantised inputs.
void add_quantisation_row(const FlightCoefficients& fc, const reference::Coefficients& twin, const DiagnosisRow& row,
                          QuantisationSums& sums) {
  if (!(row.load_n > 0.0)) {
    ++sums.skipped;
    sums.first_problem = "no wheel load (give --load for a file without load_N)";
    return;
  }
  fx::Status in_st;
  const flight::LengthM r(fx::from_double<flight::LengthQ>(row.radius_m, in_st));
  const flight::WheelLoadN w(fx::from_double<flight::LoadQ>(row.load_n, in_st));
  const flight::TorqueNm t(fx::from_double<flight::LoadQ>(row.torque_nm, in_st));
  const flight::SinkageM z(fx::from_double<flight::LengthQ>(row.sinkage_m, in_st));
  const flight::DrawbarPullN dp(fx::from_double<flight::LoadQ>(row.drawbar_pull_n, in_st));
  const flight::DrawbarPullResult pull = flight::pull_from_sinkage(fc.c, r, w, t, z);
  const flight::SinkageResult sink = flight::sinkage_from_pull(fc.c, r, w, t, dp);
  if (!in_st.ok() || !fc.converted || pull.status != flight::EstimateStatus::ok ||
      sink.status != flight::EstimateStatus::ok) {
    ++sums.skipped;
    if (sums.first_problem.empty()) {
      sums.first_problem = "the flight code rejected the inputs or the fitted coefficients (status " +
                           std::to_string(static_cast<int>(pull.status)) + ")";
    }
    return;
  }
  const double r_d = fx::to_double(r.q());
  const double w_d = fx::to_double(w.q());
  const double t_d = fx::to_double(t.q());
  const double dpw_double = reference::drawbar_pull_n(twin, r_d, w_d, t_d, fx::to_double(z.q())) / w_d;
  const double dpw_fixed = fx::to_double(pull.drawbar_pull_n.q()) / w_d;
  const double z_double = reference::sinkage_m(twin, r_d, w_d, t_d, fx::to_double(dp.q()));
  const double z_fixed = fx::to_double(sink.sinkage_m.q());
  const double e = dpw_fixed - dpw_double;
  const double ez = z_fixed - z_double;
  sums.sum += e * e;
  sums.sum_z += ez * ez;
  sums.max_abs = std::max(sums.max_abs, std::abs(e));
  sums.max_abs_z = std::max(sums.max_abs_z, std::abs(ez));
  ++sums.used;
}

}  // namespace

std::vector<GapComponent> EstimatorModel::gap_components(const std::vector<DiagnosisRow>& rows,
                                                         const std::vector<double>& base_params,
                                                         const std::vector<double>& sigma) const {
  GapComponent q;
  q.name = "fixed_point_quantisation";
  q.channel = "traction_coeff";
  GapComponent qz;
  qz.name = "fixed_point_quantisation_sinkage";
  qz.channel = "sinkage_m";
  const FlightCoefficients fc = flight_coefficients(base_params, rows.front().radius_m);
  // The double twin takes the coefficients as the flight code holds them,
  // so that the difference is the arithmetic's rounding alone.
  const reference::Coefficients twin = reference::from_flight(fc.c);
  QuantisationSums sums;
  for (const DiagnosisRow& row : rows) {
    add_quantisation_row(fc, twin, row, sums);
  }
  if (sums.used == 0) {
    q.note = "not computed: " + sums.first_problem;
    q.rms = std::nan("");
    q.over_noise = std::nan("");
    return {q};
  }
  q.max_abs = sums.max_abs;
  qz.max_abs = sums.max_abs_z;
  q.rms = std::sqrt(sums.sum / static_cast<double>(sums.used));
  qz.rms = std::sqrt(sums.sum_z / static_cast<double>(sums.used));
  q.over_noise = q.rms / sigma[0];
  // The traction-coefficient noise seen as sinkage: sigma_z = r sigma / C2.
  const double sigma_z = rows.front().radius_m * sigma[0] / std::abs(fc.values[1]);
  qz.over_noise = qz.rms / sigma_z;
  std::ostringstream os;
  os << "flight Q-format Eq. 11 (pull_from_sinkage) minus its double twin (ground/reference) on the same "
        "quantised inputs, with "
     << fc.note << ", " << sums.used << " rows";
  if (sums.skipped > 0) {
    os << " (" << sums.skipped << " skipped: " << sums.first_problem << ")";
  }
  q.note = os.str();
  qz.note = "flight sinkage_from_pull minus its double twin, in metres; noise = r sigma(DP/W) / C2";
  return {q, qz};
}

// ---------------------------------------------------------------------------
// Wong–Reece

namespace {

const ParameterInfo& info_of(const std::string& name) {
  for (const ParameterInfo& info : parameter_catalogue()) {
    if (info.name == name) {
      return info;
    }
  }
  throw std::invalid_argument("unknown simulator parameter " + name);
}

// The parameters of an effect form the diagnosis fits: the primary one, the
// shape parameters of a flexible form (ParameterInfo::shape: the fit chooses
// the form within the family), plus the load term of drive_friction (linear,
// identifiable whenever there are two loads, and otherwise its default would
// be taken for the truth).
std::vector<std::string> fitted_effect_parameters(Effect effect, const std::string& form) {
  std::vector<std::string> names{primary_parameter_name(effect, form)};
  for (const std::string& n : effect_parameter_names(effect, form)) {
    if (n != names.front() && (effect == Effect::drive_friction || info_of(n).shape)) {
      names.push_back(n);
    }
  }
  return names;
}

// One training load: the drag term and k_w W are collinear, so drive_friction
// fits its drag terms alone.
void hold_drive_load_term(Candidate& c) {
  c.extra.erase(std::remove_if(c.extra.begin(), c.extra.end(),
                               [](const ParameterSpec& spec) { return spec.name == "drive_friction.k_w_m"; }),
                c.extra.end());
  c.note = "one training load: drive_friction.k_w_m held at its default";
}

}  // namespace

WongReeceModel::WongReeceModel(SimParameters start, std::vector<std::string> base_names)
    : start_(std::move(start)), base_names_(std::move(base_names)) {
  for (Effect e : kAllEffects) {
    start_.effects.set_enabled(e, false);
  }
}

std::vector<std::string> WongReeceModel::default_base_parameters() {
  std::vector<std::string> names = suggested_base_fit_parameters();
  names.erase(std::remove(names.begin(), names.end(), std::string("model.a0")), names.end());
  return names;
}

std::vector<ChannelInfo> WongReeceModel::channels() const {
  return {{"sinkage_m", "m"}, {"torque_nm", "N m"}, {"drawbar_pull_n", "N"}};
}

std::vector<double> WongReeceModel::measured(const DiagnosisRow& row) const {
  return {row.sinkage_m, row.torque_nm, row.drawbar_pull_n};
}

std::vector<ParameterSpec> WongReeceModel::base_parameters(const std::vector<DiagnosisRow>& train) const {
  (void)train;
  std::vector<ParameterSpec> specs;
  for (const std::string& name : base_names_) {
    const ParameterInfo& info = info_of(name);
    specs.push_back({name, get_parameter(start_, name), info.lower, info.upper});
  }
  return specs;
}

Candidate WongReeceModel::candidate_for(Effect effect) const {
  return candidate_for(effect, effect_forms(effect).front());
}

Candidate WongReeceModel::candidate_for(Effect effect, const std::string& form) const {
  SimParameters with = start_;
  with.effects = EffectSettings{};  // documented default sizes
  Candidate c;
  c.family = std::string(effect_name(effect));
  c.form = form;
  // A family with one form keeps the family's name, so that reports read as before forms.
  c.name = effect_forms(effect).size() > 1 ? c.family + "." + form : c.family;
  std::ostringstream description;
  description << "simulator effect " << c.family << ", form " << form << " (fitted:";
  for (const std::string& name : fitted_effect_parameters(effect, form)) {
    const ParameterInfo& info = info_of(name);
    const double nominal = get_parameter(with, name);
    // Start half-way to the documented default size: neither at "off" (where
    // some effects have a flat cost) nor at the default itself.
    c.extra.push_back({name, 0.5 * nominal, info.lower, info.upper});
    description << " " << name;
    if (c.extra.size() == 1) {
      c.nominal_size = nominal;
    }
  }
  description << ")";
  c.description = description.str();
  return c;
}

WongReeceModel WongReeceModel::excluding(std::vector<std::string> candidate_names) const {
  WongReeceModel copy = *this;
  copy.excluded_.insert(copy.excluded_.end(), candidate_names.begin(), candidate_names.end());
  return copy;
}

std::vector<Candidate> WongReeceModel::candidates(const std::vector<DiagnosisRow>& train) const {
  std::vector<Candidate> out;
  for (Effect effect : kAllEffects) {
    for (const std::string& form : effect_forms(effect)) {
      Candidate c = candidate_for(effect, form);
      if (std::find(excluded_.begin(), excluded_.end(), c.name) != excluded_.end()) {
        continue;
      }
      if (effect == Effect::drive_friction && distinct_loads(train).size() < 2) {
        hold_drive_load_term(c);
      }
      out.push_back(c);
    }
  }
  return out;
}

namespace {

// Switches a candidate's effect on in its form with the fitted values.
void apply_candidate(const Candidate& candidate, const std::vector<double>& values, std::size_t first,
                     SimParameters& p) {
  const Effect effect = effect_from_name(candidate.family.empty() ? candidate.name : candidate.family);
  p.effects.set_enabled(effect, true);
  if (!candidate.form.empty()) {
    set_effect_form(p.effects, effect, candidate.form);
  }
  for (std::size_t k = 0; k < candidate.extra.size(); ++k) {
    set_parameter(p, candidate.extra[k].name, values[first + k]);
  }
}

}  // namespace

bool WongReeceModel::predict(const Candidate* candidate, const std::vector<double>& params, const DiagnosisRow& row,
                             std::vector<double>& out) const {
  std::vector<double> cold;
  return predict_warm(candidate, params, row, out, cold);
}

bool WongReeceModel::predict_warm(const Candidate* candidate, const std::vector<double>& params,
                                  const DiagnosisRow& row, std::vector<double>& out, std::vector<double>& warm) const {
  SimParameters p = start_;
  p.wheel.radius_m = row.radius_m;
  p.wheel.width_m = row.width_m;
  try {
    for (std::size_t i = 0; i < base_names_.size(); ++i) {
      set_parameter(p, base_names_[i], params[i]);
    }
    if (candidate != nullptr) {
      apply_candidate(*candidate, params, base_names_.size(), p);
    }
  } catch (const std::invalid_argument&) {
    return false;
  }
  SinkageHint hint;
  if (warm.size() == 2) {
    hint.sinkage_m = warm[0];
    hint.log_slope = warm[1];
  }
  const Evaluation e = evaluate(p, row.load_n, row.slip, hint);
  if (!e.ok()) {
    return false;
  }
  warm = {e.state.sinkage_m, e.state.sinkage_log_slope};
  out = {e.state.sinkage_m, e.state.torque_nm, e.state.drawbar_pull_n};
  return true;
}

}  // namespace ground
}  // namespace sinkwatch
