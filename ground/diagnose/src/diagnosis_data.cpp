// diagnosis_data.cpp: reading, splitting and model-free noise estimation.
#include "sinkwatch/ground/diagnosis_data.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "sinkwatch/ground/text_input.hpp"

namespace sinkwatch {
namespace ground {

namespace {

bool same_value(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }

// Third divided differences of every 4 consecutive points (xs ascending):
// d = sum w_j y_j with w_j = 1 / prod_{m != j} (x_j - x_m) is zero for any
// quadratic trend, and E[d^2] = sigma^2 sum w_j^2 for independent noise, so
// each d^2 / sum w_j^2 estimates sigma^2 (plus the cubic part of the trend).
// Each difference is kept as (v, m): v = d^2 / sum w_j^2 and m = the same
// weighted mean of y^2, for the noise model sigma^2(y) = floor^2 + rel^2 y^2,
// under which E[v] = floor^2 + rel^2 m.
struct Difference {
  double v = 0.0;
  double m = 0.0;
};

// w_a = 1 / prod_{m != a} (x_a - x_m) over the four points from j.
double divided_difference_weight(const std::vector<double>& xs, std::size_t j, std::size_t a) {
  double prod = 1.0;
  for (std::size_t m = j; m < j + 4; ++m) {
    if (m != a) {
      prod *= xs[a] - xs[m];
    }
  }
  return 1.0 / prod;
}

void add_third_differences(const std::vector<double>& xs, const std::vector<double>& ys,
                           std::vector<Difference>& out) {
  for (std::size_t j = 0; j + 3 < xs.size(); ++j) {
    double d = 0.0;
    double w2 = 0.0;
    double y2 = 0.0;
    for (std::size_t a = j; a < j + 4; ++a) {
      const double w = divided_difference_weight(xs, j, a);
      d += w * ys[a];
      w2 += w * w;
      y2 += w * w * ys[a] * ys[a];
    }
    out.push_back({d * d / w2, y2 / w2});
  }
}

// Fits E[v] = A + B m (A = floor^2, B = rel^2, both >= 0) by iteratively
// reweighted least squares: each v is its expectation times a chi-square
// with one degree of freedom, so its variance is 2 E[v]^2.
void fit_noise_model(const std::vector<Difference>& diffs, double& floor, double& relative) {
  double mean_v = 0.0;
  for (const Difference& d : diffs) {
    mean_v += d.v;
  }
  mean_v /= static_cast<double>(diffs.size());
  if (!(mean_v > 0.0)) {
    // Data without scatter (exact, or a trend the differences cancel):
    // nothing to fit, and the weights below would divide by zero.
    floor = 0.0;
    relative = 0.0;
    return;
  }
  double a = mean_v;
  double b = 0.0;
  bool first = true;
  for (int iteration = 0; iteration < 30; ++iteration) {
    // Weighted normal equations of v = a + b m.
    double s0 = 0.0;
    double s1 = 0.0;
    double s2 = 0.0;
    double t0 = 0.0;
    double t1 = 0.0;
    for (const Difference& d : diffs) {
      const double e = first ? mean_v : std::max(a + b * d.m, 1e-6 * mean_v);
      const double w = 1.0 / (e * e);
      s0 += w;
      s1 += w * d.m;
      s2 += w * d.m * d.m;
      t0 += w * d.v;
      t1 += w * d.v * d.m;
    }
    first = false;
    const double det = s0 * s2 - s1 * s1;
    double na = det > 0.0 ? (t0 * s2 - t1 * s1) / det : t0 / s0;
    double nb = det > 0.0 ? (s0 * t1 - s1 * t0) / det : 0.0;
    if (nb < 0.0) {
      nb = 0.0;
      na = t0 / s0;
    } else if (na < 0.0) {
      na = 0.0;
      nb = s2 > 0.0 ? t1 / s2 : 0.0;
    }
    const bool settled = std::abs(na - a) <= 1e-9 * std::max(a, 1e-300) && std::abs(nb - b) <= 1e-9 * std::max(b, 1e-300);
    a = na;
    b = nb;
    if (settled) {
      break;
    }
  }
  floor = std::sqrt(a);
  relative = std::sqrt(b);
}

}  // namespace

DiagnosisRow make_row(double slip, double load_n, double sinkage_m, double torque_nm, double drawbar_pull_n,
                      double radius_m, double width_m) {
  DiagnosisRow row;
  row.slip = slip;
  row.load_n = load_n;
  row.load_measured = true;
  row.radius_m = radius_m;
  row.width_m = width_m;
  row.sinkage_m = sinkage_m;
  row.torque_nm = torque_nm;
  row.drawbar_pull_n = drawbar_pull_n;
  row.sinkage_ratio = sinkage_m / radius_m;
  row.drive_coeff = torque_nm / (radius_m * load_n);
  row.traction_coeff = drawbar_pull_n / load_n;
  return row;
}

namespace {

// The row of the diagnosis from a soil-bin row: the geometry from the option
// or the columns (DataError when neither), the dimensional values from the
// ratios for dimensionless input (zero when no load is known; only the
// quantisation check needs them then).
DiagnosisRow to_diagnosis_row(const SoilBinRow& in, const std::string& source, const DiagnosisReadOptions& options) {
  DiagnosisRow row;
  row.line = in.line;
  row.slip = in.slip;
  if (!in.wheel_radius_m) {
    throw DataError(source, in.line, 0, "wheel_radius_m", "no wheel radius: give --radius or a wheel_radius_m column");
  }
  if (!in.wheel_width_m) {
    throw DataError(source, in.line, 0, "wheel_width_m", "no wheel width: give --width or a wheel_width_m column");
  }
  row.radius_m = *in.wheel_radius_m;
  row.width_m = *in.wheel_width_m;
  row.sinkage_ratio = in.sinkage_ratio;
  row.drive_coeff = in.drive_coeff;
  row.traction_coeff = in.traction_coeff;
  if (in.load_n) {
    row.load_n = *in.load_n;
    row.load_measured = true;
  } else if (options.load_n) {
    row.load_n = *options.load_n;
  }
  if (in.sinkage_m && in.torque_nm && in.drawbar_pull_n) {
    row.sinkage_m = *in.sinkage_m;
    row.torque_nm = *in.torque_nm;
    row.drawbar_pull_n = *in.drawbar_pull_n;
  } else {
    row.sinkage_m = row.sinkage_ratio * row.radius_m;
    row.torque_nm = row.drive_coeff * row.radius_m * row.load_n;
    row.drawbar_pull_n = row.traction_coeff * row.load_n;
  }
  return row;
}

// The header's column names of a file, to name columns by number in the
// diagnosis's own checks; empty for standard input (read once, by the
// reader), where messages name the column without its number.
std::vector<std::string> header_columns(const std::string& path) {
  std::vector<std::string> names;
  if (path == "-") {
    return names;
  }
  std::ifstream in(path);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (first) {
      (void)text_input::strip_bom(line);
      first = false;
    }
    const std::size_t body = line.find_first_not_of(" \t\r");
    if (body == std::string::npos || line[body] == '#') {
      continue;
    }
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      const std::size_t a = field.find_first_not_of(" \t\r");
      const std::size_t b = field.find_last_not_of(" \t\r");
      names.push_back(a == std::string::npos ? std::string() : field.substr(a, b - a + 1));
    }
    break;
  }
  return names;
}

std::size_t column_number(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? 0 : static_cast<std::size_t>(it - columns.begin()) + 1;
}

// One measured channel as the file gives it: its column and value per row.
struct MeasuredColumn {
  const char* name;
  double (*value)(const DiagnosisRow&);
};

// Values the diagnosis cannot use although the reader's ranges admit them
// (docs/diagnosis.md, "Input checks"): a negative sinkage (the reader allows
// it for other tools' conventions), and a channel without any scatter (every
// row the same value: a constant filled in or a copied column, no measurement).
void check_rows(const DiagnosisData& data, const std::vector<std::string>& columns) {
  const std::array<MeasuredColumn, 3> measured =
      data.dimensional
          ? std::array<MeasuredColumn, 3>{{{"sinkage_m", [](const DiagnosisRow& r) { return r.sinkage_m; }},
                                           {"torque_Nm", [](const DiagnosisRow& r) { return r.torque_nm; }},
                                           {"drawbar_pull_N", [](const DiagnosisRow& r) { return r.drawbar_pull_n; }}}}
          : std::array<MeasuredColumn, 3>{{{"sinkage_ratio", [](const DiagnosisRow& r) { return r.sinkage_ratio; }},
                                           {"drive_coeff", [](const DiagnosisRow& r) { return r.drive_coeff; }},
                                           {"traction_coeff", [](const DiagnosisRow& r) { return r.traction_coeff; }}}};
  for (const DiagnosisRow& row : data.rows) {
    const double sinkage = measured[0].value(row);
    if (sinkage < 0.0) {
      throw DataError(data.source, row.line, column_number(columns, measured[0].name), measured[0].name,
                      "negative sinkage " + text_input::format_number(sinkage) +
                          " is not physical for the diagnosis (the wheel sinks into the soil; z >= 0)");
    }
  }
  if (data.rows.size() < 2) {
    return;
  }
  for (const MeasuredColumn& column : measured) {
    const double first = column.value(data.rows.front());
    const bool constant = std::all_of(data.rows.begin(), data.rows.end(),
                                      [&](const DiagnosisRow& r) { return column.value(r) == first; });
    if (constant) {
      throw DataError(data.source, data.rows.front().line, column_number(columns, column.name), column.name,
                      "every row has the same value " + text_input::format_number(first) +
                          ": a channel without scatter is not a measurement (a constant filled in, or a copied "
                          "column), and its noise cannot be estimated");
    }
  }
}

}  // namespace

DiagnosisData read_diagnosis_data(const std::string& path, const DiagnosisReadOptions& options) {
  for (const auto& [name, value] : {std::pair<const char*, std::optional<double>>{"--radius", options.radius_m},
                                    {"--width", options.width_m}, {"--load", options.load_n}}) {
    if (value && (!std::isfinite(*value) || *value <= 0.0)) {
      throw DataError(path, 0, 0, "", std::string(name) + " must be a positive number");
    }
  }
  // One pass over the input (which may be standard input): the reader takes
  // the width column too, and refuses a width given twice at its column.
  SoilBinReadOptions read_options;
  read_options.wheel_radius_m = options.radius_m;
  read_options.wheel_width_m = options.width_m;
  const SoilBinDataset dataset = read_soil_bin_csv(path, read_options);

  DiagnosisData data;
  data.source = dataset.source;
  data.dimensional = dataset.form == SoilBinForm::dimensional;
  data.loads_measured = dataset.has_load;
  data.has_loads = dataset.has_load || options.load_n.has_value();
  if (dataset.rows.empty()) {
    throw DataError(dataset.source, 0, 0, "", "no data rows");
  }
  for (const SoilBinRow& in : dataset.rows) {
    data.rows.push_back(to_diagnosis_row(in, dataset.source, options));
  }
  check_rows(data, header_columns(path));
  return data;
}

std::vector<double> distinct_loads(const std::vector<DiagnosisRow>& rows) {
  std::vector<double> loads;
  for (const DiagnosisRow& row : rows) {
    if (std::none_of(loads.begin(), loads.end(), [&](double l) { return same_value(l, row.load_n); })) {
      loads.push_back(row.load_n);
    }
  }
  std::sort(loads.begin(), loads.end());
  return loads;
}

DataSplit split_rows(const std::vector<DiagnosisRow>& rows) {
  constexpr std::size_t kMinRows = 8;
  if (rows.size() < kMinRows) {
    throw std::invalid_argument("the diagnosis needs at least 8 rows (training and held-out), got " +
                                std::to_string(rows.size()));
  }
  DataSplit split;
  const std::vector<double> loads = distinct_loads(rows);
  if (loads.size() >= 2) {
    const double top = loads.back();
    for (std::size_t i = 0; i < rows.size(); ++i) {
      (same_value(rows[i].load_n, top) ? split.heldout : split.train).push_back(i);
    }
    std::ostringstream rule;
    rule << "by load: the " << split.heldout.size() << " rows at the highest load (" << top
         << " N) are held out; the model is fitted to the other " << loads.size() - 1 << " load(s)";
    split.rule = rule.str();
    if (split.train.size() < 4) {
      throw std::invalid_argument("too few training rows below the highest load (" +
                                  std::to_string(split.train.size()) + ")");
    }
    return split;
  }
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return rows[a].slip < rows[b].slip; });
  const std::size_t n = order.size();
  for (std::size_t k = 0; k < n; ++k) {
    const bool held = (n - 1 - k) % 4 == 0;
    (held ? split.heldout : split.train).push_back(order[k]);
  }
  std::sort(split.train.begin(), split.train.end());
  std::sort(split.heldout.begin(), split.heldout.end());
  split.rule = "by slip (one load): rows sorted by slip, every 4th row counting down from the highest slip is held out (" +
               std::to_string(split.heldout.size()) + " held out, " + std::to_string(split.train.size()) +
               " for training)";
  return split;
}

std::vector<DataSplit> cross_validation_folds(const std::vector<DiagnosisRow>& rows, bool every_load) {
  std::vector<DataSplit> folds{split_rows(rows)};
  const std::vector<double> loads = distinct_loads(rows);
  if (loads.size() == 2) {
    return folds;
  }
  if (loads.size() >= 3) {
    const std::size_t last = every_load ? loads.size() - 1 : 1;
    for (std::size_t l = 0; l < last; ++l) {
      DataSplit fold;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        (same_value(rows[i].load_n, loads[l]) ? fold.heldout : fold.train).push_back(i);
      }
      std::ostringstream rule;
      rule << "load " << loads[l] << " N held out";
      fold.rule = rule.str();
      if (fold.train.size() >= 4) {
        folds.push_back(fold);
      }
    }
    return folds;
  }
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return rows[a].slip < rows[b].slip; });
  const std::size_t n = order.size();
  for (std::size_t j = 1; j < 4; ++j) {
    DataSplit fold;
    for (std::size_t k = 0; k < n; ++k) {
      ((n - 1 - k) % 4 == j ? fold.heldout : fold.train).push_back(order[k]);
    }
    std::sort(fold.train.begin(), fold.train.end());
    std::sort(fold.heldout.begin(), fold.heldout.end());
    fold.rule = "every 4th slip-sorted row from the " + std::to_string(j + 1) + "-th highest slip held out";
    folds.push_back(fold);
  }
  return folds;
}

namespace {

// Within each load, rows sorted by slip: the pooled replicate scatter (rows
// at the same slip) and the third differences of the slip-wise values.
struct SlipScatter {
  double replicate_ss = 0.0;
  std::size_t replicate_dof = 0;
  std::vector<Difference> diffs;
};

// One load's rows (sorted by slip): replicate groups and one representative per slip.
void add_load_scatter(const std::vector<DiagnosisRow>& rows, const std::vector<double>& values,
                      const std::vector<std::size_t>& members, SlipScatter& out) {
  std::vector<double> xs;
  std::vector<double> ys;
  std::size_t start = 0;
  while (start < members.size()) {
    std::size_t end = start + 1;
    while (end < members.size() && same_value(rows[members[end]].slip, rows[members[start]].slip)) {
      ++end;
    }
    double mean = 0.0;
    for (std::size_t k = start; k < end; ++k) {
      mean += values[members[k]];
    }
    mean /= static_cast<double>(end - start);
    for (std::size_t k = start; k < end; ++k) {
      out.replicate_ss += (values[members[k]] - mean) * (values[members[k]] - mean);
    }
    out.replicate_dof += end - start - 1;
    xs.push_back(rows[members[start]].slip);
    ys.push_back(values[members[start]]);
    start = end;
  }
  add_third_differences(xs, ys, out.diffs);
}

SlipScatter slip_scatter(const std::vector<DiagnosisRow>& rows, const std::vector<double>& values) {
  std::map<std::size_t, std::vector<std::size_t>> by_load;
  const std::vector<double> loads = distinct_loads(rows);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto it = std::find_if(loads.begin(), loads.end(), [&](double l) { return same_value(l, rows[i].load_n); });
    by_load[static_cast<std::size_t>(it - loads.begin())].push_back(i);
  }
  SlipScatter out;
  for (auto& [load_index, members] : by_load) {
    (void)load_index;
    std::stable_sort(members.begin(), members.end(),
                     [&](std::size_t a, std::size_t b) { return rows[a].slip < rows[b].slip; });
    add_load_scatter(rows, values, members, out);
  }
  return out;
}

// The same along load at each slip: rows with the same slip, one
// representative per load, sorted by load.
std::vector<Difference> load_differences(const std::vector<DiagnosisRow>& rows, const std::vector<double>& values) {
  std::vector<Difference> diffs;
  std::vector<std::size_t> by_slip(rows.size());
  std::iota(by_slip.begin(), by_slip.end(), std::size_t{0});
  std::stable_sort(by_slip.begin(), by_slip.end(), [&](std::size_t a, std::size_t b) {
    return same_value(rows[a].slip, rows[b].slip) ? rows[a].load_n < rows[b].load_n : rows[a].slip < rows[b].slip;
  });
  for (std::size_t start = 0; start < by_slip.size();) {
    std::size_t end = start + 1;
    while (end < by_slip.size() && same_value(rows[by_slip[end]].slip, rows[by_slip[start]].slip)) {
      ++end;
    }
    std::vector<double> xs;
    std::vector<double> ys;
    for (std::size_t k = start; k < end; ++k) {
      const DiagnosisRow& row = rows[by_slip[k]];
      if (xs.empty() || !same_value(xs.back(), row.load_n)) {
        xs.push_back(row.load_n);
        ys.push_back(values[by_slip[k]]);
      }
    }
    add_third_differences(xs, ys, diffs);
    start = end;
  }
  return diffs;
}

// sigma from the differences; with at least 6 of them the floor + relative
// model, whose RMS over the values is then sigma.
void estimate_from_differences(const std::vector<Difference>& diffs, const std::vector<double>& values,
                               NoiseEstimate& estimate) {
  double sum = 0.0;
  for (const Difference& d : diffs) {
    sum += d.v;
  }
  estimate.dof = diffs.size();
  estimate.sigma = std::sqrt(sum / static_cast<double>(diffs.size()));
  estimate.floor = estimate.sigma;
  if (diffs.size() >= 6) {
    fit_noise_model(diffs, estimate.floor, estimate.relative);
    double mean_square = 0.0;
    for (double y : values) {
      mean_square += estimate.floor * estimate.floor + estimate.relative * estimate.relative * y * y;
    }
    estimate.sigma = std::sqrt(mean_square / static_cast<double>(values.size()));
  }
}

}  // namespace

NoiseEstimate estimate_noise(const std::vector<DiagnosisRow>& rows, const std::vector<double>& values) {
  const SlipScatter slip = slip_scatter(rows, values);
  const std::vector<Difference> load_diffs = load_differences(rows, values);
  NoiseEstimate estimate;
  if (slip.replicate_dof >= 3) {
    estimate.sigma = std::sqrt(slip.replicate_ss / static_cast<double>(slip.replicate_dof));
    estimate.floor = estimate.sigma;
    estimate.method = "replicates";
    estimate.dof = slip.replicate_dof;
  } else if (load_diffs.size() >= 3 && load_diffs.size() >= slip.diffs.size()) {
    // Along load when the grid is at least as dense in load as in slip: the
    // forces grow with load as near power laws, whereas the shear curve's
    // steep rise at low slip leaks into wide slip windows
    // (findings-diagnosis.md measures both on noise-free simulator data).
    estimate.method = "neighbour_scatter_load";
    estimate_from_differences(load_diffs, values, estimate);
  } else if (slip.diffs.size() >= 3) {
    estimate.method = "neighbour_scatter";
    estimate_from_differences(slip.diffs, values, estimate);
  } else {
    estimate.method = "none";
  }
  return estimate;
}

}  // namespace ground
}  // namespace sinkwatch
