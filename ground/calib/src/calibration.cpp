// calibration.cpp: least squares of Eq. 11 (see the header).
#include "sinkwatch/ground/calibration.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Dense>
#include <boost/math/distributions/students_t.hpp>

namespace sinkwatch {
namespace ground {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::array<const char*, kCoefficientCount> kNames = {"C1", "C2", "C3"};
// A row whose leverage h_ii is within kLeverageTolerance * max(n, p) * eps of
// 1 has no leave-one-out prediction (see fit_sinkage_function). A computed
// h_ii = |U_i|^2 of an exactly leverage-1 row misses 1 by at most about
// 2 n eps in experiments with n from 4 to 10^5; 16 leaves a margin.
constexpr double kLeverageTolerance = 16.0;

// Eq. 12's row of A for one run, all three columns: [T/(rW), -z/r, -1].
Coefficients design_row(const Observation& o) noexcept {
  return {o.drive_coeff, -o.sinkage_ratio, -1.0};
}

struct Problem {
  Eigen::MatrixXd a;  // free columns of A
  Eigen::VectorXd b;  // DP/W minus the fixed terms
  std::vector<std::size_t> free_index;  // column of A -> coefficient index
};

Problem build_problem(const std::vector<Observation>& data, const FixedCoefficients& fixed) {
  Problem p;
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (!fixed.value[k]) {
      p.free_index.push_back(k);
    }
  }
  const auto n = static_cast<Eigen::Index>(data.size());
  const auto m = static_cast<Eigen::Index>(p.free_index.size());
  p.a.resize(n, m);
  p.b.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Observation& o = data[static_cast<std::size_t>(i)];
    const Coefficients row = design_row(o);
    double rhs = o.traction_coeff;
    for (std::size_t k = 0; k < kCoefficientCount; ++k) {
      if (fixed.value[k]) {
        rhs -= *fixed.value[k] * row[k];
      }
    }
    for (Eigen::Index j = 0; j < m; ++j) {
      p.a(i, j) = row[p.free_index[static_cast<std::size_t>(j)]];
    }
    p.b(i) = rhs;
  }
  return p;
}

// Full column rank in the sense of the SVD: the smallest singular value is
// more than rounding noise relative to the largest.
bool full_rank(const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, Eigen::Index rows) {
  const Eigen::VectorXd& s = svd.singularValues();
  if (s.size() == 0) {
    return true;
  }
  const double tolerance = static_cast<double>(std::max(rows, s.size())) *
                           std::numeric_limits<double>::epsilon() * s(0);
  return s(0) > 0.0 && s(s.size() - 1) > tolerance;
}

double condition_of(const Eigen::JacobiSVD<Eigen::MatrixXd>& svd) {
  const Eigen::VectorXd& s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

std::string lowercase(std::string text) {
  for (char& ch : text) {
    ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  }
  return text;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) {
    return {};
  }
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

}  // namespace

std::size_t FixedCoefficients::free_count() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(value.begin(), value.end(), [](const auto& v) { return !v.has_value(); }));
}

FixedCoefficients parse_fixed_coefficients(const std::string& spec) {
  FixedCoefficients fixed;
  if (trimmed(spec).empty()) {
    return fixed;
  }
  std::istringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto equals = item.find('=');
    if (equals == std::string::npos) {
      throw std::invalid_argument("--fix: '" + trimmed(item) + "' is not of the form cN=value");
    }
    const std::string key = lowercase(trimmed(item.substr(0, equals)));
    const std::string text = trimmed(item.substr(equals + 1));
    std::size_t index = kCoefficientCount;
    for (std::size_t k = 0; k < kCoefficientCount; ++k) {
      if (key == lowercase(kNames[k])) {
        index = k;
      }
    }
    if (index == kCoefficientCount) {
      throw std::invalid_argument("--fix: unknown coefficient '" + key + "' (use c1, c2, c3)");
    }
    if (fixed.value[index]) {
      throw std::invalid_argument("--fix: " + key + " is given twice");
    }
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (text.empty() || used != text.size() || !std::isfinite(value)) {
      throw std::invalid_argument("--fix: " + key + "='" + text + "' is not a finite number");
    }
    fixed.value[index] = value;
  }
  return fixed;
}

std::vector<Observation> observations_of(const SoilBinDataset& dataset) {
  std::vector<Observation> data;
  data.reserve(dataset.rows.size());
  for (const SoilBinRow& row : dataset.rows) {
    data.push_back({row.line, row.slip, row.drive_coeff, row.sinkage_ratio, row.traction_coeff});
  }
  return data;
}

double predicted_traction(const Coefficients& c, const Observation& o) noexcept {
  const Coefficients row = design_row(o);
  return c[0] * row[0] + c[1] * row[1] + c[2] * row[2];
}

double residual_rms(const std::vector<Observation>& data, const Coefficients& c) {
  if (data.empty()) {
    return kNaN;
  }
  double sum = 0.0;
  for (const Observation& o : data) {
    const double r = o.traction_coeff - predicted_traction(c, o);
    sum += r * r;
  }
  return std::sqrt(sum / static_cast<double>(data.size()));
}

namespace {

// A fit with the fixed coefficients in place and every statistic NaN until
// computed; refuses data without a degree of freedom.
CalibrationFit unfitted(std::size_t rows, const FixedCoefficients& fixed) {
  CalibrationFit fit;
  fit.rows = rows;
  fit.free_count = fixed.free_count();
  if (fit.rows < fit.free_count + 1 || fit.rows == 0) {
    throw CalibrationError("too few rows: a fit of " + std::to_string(fit.free_count) +
                           " free coefficient(s) needs at least " +
                           std::to_string(fit.free_count + 1) + " rows, the data has " +
                           std::to_string(fit.rows));
  }
  fit.dof = fit.rows - fit.free_count;
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    fit.free[k] = !fixed.value[k].has_value();
    fit.c[k] = fixed.value[k].value_or(kNaN);
    fit.std_err[k] = kNaN;
    fit.ci_low[k] = kNaN;
    fit.ci_high[k] = kNaN;
    fit.normal_equations_c[k] = fit.c[k];
    fit.correlation[k].fill(kNaN);
  }
  fit.t_quantile = kNaN;
  fit.condition_number = kNaN;
  fit.condition_number_scaled = kNaN;
  fit.normal_equations_max_diff = kNaN;
  return fit;
}

using Svd = Eigen::JacobiSVD<Eigen::MatrixXd>;

// Refuses a rank-deficient A, naming the free coefficients it cannot separate.
void require_full_rank(const Svd& svd, const Problem& p) {
  if (full_rank(svd, p.a.rows())) {
    return;
  }
  std::string names;
  for (std::size_t k : p.free_index) {
    names += names.empty() ? "" : ", ";
    names += kNames[k];
  }
  throw CalibrationError("the columns of A for " + names +
                         " are linearly dependent on this data (e.g. every run at the same "
                         "slip and sinkage): the coefficients are not identifiable");
}

// Standard errors, 95 % intervals and correlations of the free coefficients
// from the covariance sigma^2 (A'A)^-1, formed from the SVD as V S^-2 V' so
// that A'A itself is never inverted.
void fill_uncertainty(const Svd& svd, const Problem& p, const Eigen::VectorXd& solution,
                      CalibrationFit& fit) {
  const Eigen::Index m = p.a.cols();
  const Eigen::VectorXd residual = p.b - p.a * solution;
  const double sigma2 = residual.squaredNorm() / static_cast<double>(fit.dof);
  const Eigen::MatrixXd& v = svd.matrixV();
  const Eigen::VectorXd inv_s2 = svd.singularValues().array().square().inverse().matrix();
  const Eigen::MatrixXd covariance = sigma2 * v * inv_s2.asDiagonal() * v.transpose();
  const boost::math::students_t t_dist(static_cast<double>(fit.dof));
  fit.t_quantile = boost::math::quantile(boost::math::complement(t_dist, 0.025));
  for (Eigen::Index j = 0; j < m; ++j) {
    const std::size_t k = p.free_index[static_cast<std::size_t>(j)];
    fit.std_err[k] = std::sqrt(covariance(j, j));
    fit.ci_low[k] = fit.c[k] - fit.t_quantile * fit.std_err[k];
    fit.ci_high[k] = fit.c[k] + fit.t_quantile * fit.std_err[k];
    for (Eigen::Index l = 0; l < m; ++l) {
      const std::size_t q = p.free_index[static_cast<std::size_t>(l)];
      // A perfect fit (zero residual) has no spread to correlate.
      const double scale = std::sqrt(covariance(j, j) * covariance(l, l));
      fit.correlation[k][q] = scale > 0.0 ? covariance(j, l) / scale : kNaN;
    }
  }
}

// Solves the free columns by SVD (at least one free), fills the
// coefficients, conditioning, the normal-equations comparison and the
// uncertainties, and returns the leverages h_ii = |U_i|^2 for the
// leave-one-out residuals.
Eigen::VectorXd solve_free(const Problem& p, CalibrationFit& fit) {
  const Svd svd(p.a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  require_full_rank(svd, p);
  const Eigen::VectorXd solution = svd.solve(p.b);
  fit.condition_number = condition_of(svd);

  const Eigen::VectorXd norms = p.a.colwise().norm();
  const Eigen::MatrixXd scaled = p.a * norms.cwiseInverse().asDiagonal();
  fit.condition_number_scaled = condition_of(Svd(scaled));

  // The paper's route, kept for comparison only.
  const Eigen::MatrixXd ata = p.a.transpose() * p.a;
  const Eigen::VectorXd normal = ata.inverse() * (p.a.transpose() * p.b);
  fit.normal_equations_max_diff = (normal - solution).cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < p.a.cols(); ++j) {
    const std::size_t k = p.free_index[static_cast<std::size_t>(j)];
    fit.c[k] = solution(j);
    fit.normal_equations_c[k] = normal(j);
  }
  fill_uncertainty(svd, p, solution, fit);
  return svd.matrixU().rowwise().squaredNorm();
}

// Residuals and leave-one-out residuals. The leave-one-out residual of row
// i is B_i - A_i C_(-i), C_(-i) the fit without row i; it has the closed
// form e_i / (1 - h_ii), h_ii = A_i (A'A)^-1 A_i' the row's leverage, the
// diagonal of the hat matrix A (A'A)^-1 A' = U U'. So h_ii = |U_i|^2, the
// squared norm of row i of the SVD's thin U (n x p, already computed):
// linear in n, no refit and no n x n matrix. A row with leverage 1 is the
// only one that pins some direction of C: without it the columns are
// dependent and there is no refit, so it is not cross-validated (NaN, and
// the LOO RMS is NaN), as for a refit that loses rank. "Leverage 1" is 1 -
// h_ii within the rounding of a computed h_ii, which grows with n like the
// rank tolerance: 1 - h_ii <= kLeverageTolerance * max(n, p) * eps.
void fill_residuals(const std::vector<Observation>& data, const Eigen::VectorXd& leverage,
                    Eigen::Index free_columns, CalibrationFit& fit) {
  const Eigen::Index n = leverage.size();
  double ssr = 0.0;
  double loo_ssr = 0.0;
  fit.residuals.reserve(data.size());
  const double leverage_tolerance = kLeverageTolerance *
                                    static_cast<double>(std::max(n, free_columns)) *
                                    std::numeric_limits<double>::epsilon();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Observation& o = data[static_cast<std::size_t>(i)];
    Residual r;
    r.line = o.line;
    r.slip = o.slip;
    r.measured = o.traction_coeff;
    r.fitted = predicted_traction(fit.c, o);
    r.residual = r.measured - r.fitted;
    ssr += r.residual * r.residual;

    // With nothing fitted (m == 0) the leverage is 0 and this is the residual.
    const double one_minus_h = 1.0 - leverage(i);
    if (one_minus_h > leverage_tolerance) {
      r.loo_residual = r.residual / one_minus_h;
    } else {
      r.loo_residual = kNaN;
      ++fit.loo_undefined;
    }
    loo_ssr += r.loo_residual * r.loo_residual;
    fit.residuals.push_back(r);
  }
  fit.rms = std::sqrt(ssr / static_cast<double>(n));
  fit.residual_std = std::sqrt(ssr / static_cast<double>(fit.dof));
  fit.loo_rms = std::sqrt(loo_ssr / static_cast<double>(n));  // NaN propagates
}

}  // namespace

CalibrationFit fit_sinkage_function(const std::vector<Observation>& data,
                                    const FixedCoefficients& fixed) {
  CalibrationFit fit = unfitted(data.size(), fixed);
  const Problem p = build_problem(data, fixed);
  const Eigen::Index m = p.a.cols();
  // h_ii; zero when nothing is fitted (every coefficient fixed).
  const Eigen::VectorXd leverage =
      m > 0 ? solve_free(p, fit) : Eigen::VectorXd(Eigen::VectorXd::Zero(p.a.rows()));
  fill_residuals(data, leverage, m, fit);
  std::stable_sort(fit.residuals.begin(), fit.residuals.end(),
                   [](const Residual& x, const Residual& y) { return x.slip < y.slip; });
  return fit;
}

std::vector<LoadFit> fit_per_load(const SoilBinDataset& dataset, const FixedCoefficients& fixed) {
  if (!dataset.has_load) {
    throw CalibrationError(dataset.source + ": --per-load needs a load_N column");
  }
  std::vector<Observation> all = observations_of(dataset);
  std::vector<std::pair<double, Observation>> by_load;
  for (std::size_t i = 0; i < all.size(); ++i) {
    by_load.emplace_back(*dataset.rows[i].load_n, all[i]);
  }
  std::stable_sort(by_load.begin(), by_load.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });

  std::vector<LoadFit> table;
  std::size_t start = 0;
  while (start < by_load.size()) {
    const double load = by_load[start].first;
    std::size_t end = start;
    std::vector<Observation> group;
    while (end < by_load.size() && std::abs(by_load[end].first - load) <= 1e-9 * load) {
      group.push_back(by_load[end].second);
      ++end;
    }
    LoadFit entry;
    entry.load_n = load;
    try {
      entry.fit = fit_sinkage_function(group, fixed);
    } catch (const CalibrationError& e) {
      std::ostringstream message;
      message << dataset.source << ": load " << load << " N: " << e.what();
      throw CalibrationError(message.str());
    }
    table.push_back(std::move(entry));
    start = end;
  }
  return table;
}

}  // namespace ground
}  // namespace sinkwatch
