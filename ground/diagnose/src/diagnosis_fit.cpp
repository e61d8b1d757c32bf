// diagnosis_fit.cpp: the fits of the diagnosis (Ceres), their residuals and
// RMS, the pooled held-out score and the noise estimate per channel.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <ceres/ceres.h>

#include "diagnosis_internal.hpp"
#include "sinkwatch/ground/diagnosis.hpp"

namespace sinkwatch {
namespace ground {

namespace detail {

std::vector<DiagnosisRow> select(const std::vector<DiagnosisRow>& rows, const std::vector<std::size_t>& idx) {
  std::vector<DiagnosisRow> out;
  out.reserve(idx.size());
  for (std::size_t i : idx) {
    out.push_back(rows[i]);
  }
  return out;
}

RowNoise row_noise(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                   const std::vector<ChannelNoiseEstimate>& noise) {
  // A fitted floor of zero would otherwise give rows near zero an unbounded weight.
  RowNoise out;
  out.reserve(rows.size());
  for (const DiagnosisRow& row : rows) {
    const std::vector<double> measured = model.measured(row);
    std::vector<double> s(noise.size());
    for (std::size_t c = 0; c < noise.size(); ++c) {
      const double modelled = std::hypot(noise[c].floor, noise[c].relative * measured[c]);
      s[c] = std::max(modelled, 0.05 * noise[c].sigma);
    }
    out.push_back(s);
  }
  return out;
}

std::vector<double> scaled_rms(const std::vector<std::vector<double>>& residuals, const std::vector<std::size_t>& idx,
                               const RowNoise& noise) {
  const std::size_t channels = noise.front().size();
  std::vector<double> out(channels, 0.0);
  bool failed = false;
  for (std::size_t i : idx) {
    if (std::isnan(residuals[i][0])) {
      failed = true;
      continue;
    }
    for (std::size_t c = 0; c < channels; ++c) {
      const double r = residuals[i][c] / noise[i][c];
      out[c] += r * r;
    }
  }
  for (double& v : out) {
    v = failed || idx.empty() ? kInf : std::sqrt(v / static_cast<double>(idx.size()));
  }
  return out;
}

double combined(const std::vector<double>& scaled) {
  double sum = 0.0;
  for (double r : scaled) {
    sum += r * r;
  }
  return std::sqrt(sum / static_cast<double>(scaled.size()));
}

}  // namespace detail

namespace {

using detail::kInf;
using detail::kNaN;
using detail::RowNoise;

std::vector<ParameterSpec> all_parameters(const DiagnosisModel& model, const Candidate* candidate,
                                          const std::vector<DiagnosisRow>& train) {
  std::vector<ParameterSpec> specs = model.base_parameters(train);
  if (candidate != nullptr) {
    specs.insert(specs.end(), candidate->extra.begin(), candidate->extra.end());
  }
  return specs;
}

// Noise-scaled residuals of one row. The parameters come in up to two blocks
// (the first `first_size` of them, then the rest) so that a block held
// constant is not differentiated; they are clamped into their admissible
// range first, because numeric differentiation steps across the bounds that
// Ceres enforces on the iterates.
class RowResidual {
 public:
  RowResidual(const DiagnosisModel& model, const Candidate* candidate, const DiagnosisRow& row,
              std::vector<double> sigma, std::vector<ParameterSpec> specs, std::size_t first_size)
      : model_(model), candidate_(candidate), row_(row), measured_(model.measured(row)), sigma_(std::move(sigma)),
        specs_(std::move(specs)), first_size_(first_size) {}

  bool operator()(double const* const* parameters, double* residuals) const {
    std::vector<double> p(specs_.size());
    for (std::size_t i = 0; i < specs_.size(); ++i) {
      const double v = i < first_size_ ? parameters[0][i] : parameters[1][i - first_size_];
      p[i] = std::clamp(v, specs_[i].lower, specs_[i].upper);
    }
    // Ceres evaluates an accepted trial point twice (residuals alone, then
    // with the Jacobian, whose forward differences start from it): the second
    // time the simulator is not run again. Each functor belongs to one
    // problem, solved on one thread.
    if (!cache_.valid || p != cache_.parameters) {
      cache_.parameters = p;
      cache_.ok = model_.predict_warm(candidate_, p, row_, cache_.predicted, cache_.warm);
      cache_.valid = true;
    }
    if (!cache_.ok) {
      return false;
    }
    for (std::size_t c = 0; c < measured_.size(); ++c) {
      residuals[c] = (cache_.predicted[c] - measured_[c]) / sigma_[c];
      if (!std::isfinite(residuals[c])) {
        return false;
      }
    }
    return true;
  }

 private:
  const DiagnosisModel& model_;
  const Candidate* candidate_;
  DiagnosisRow row_;
  std::vector<double> measured_;
  std::vector<double> sigma_;
  std::vector<ParameterSpec> specs_;
  std::size_t first_size_;
  struct Cache {
    bool valid = false;
    bool ok = false;
    std::vector<double> parameters;
    std::vector<double> predicted;
    std::vector<double> warm;  // the model's start for the next prediction (predict_warm)
  };
  mutable Cache cache_;  // the last prediction, by its (clamped) parameters
};

// Plain RMS per channel of the residuals over `idx`, in the channel's unit
// (inf when the model failed on one of the rows); counts the failures.
std::vector<double> unit_rms(const std::vector<std::vector<double>>& residuals, const std::vector<std::size_t>& idx,
                             std::size_t channels, std::size_t& failures) {
  std::vector<double> rms(channels, 0.0);
  failures = 0;
  for (std::size_t i : idx) {
    if (std::isnan(residuals[i][0])) {
      ++failures;
      continue;
    }
    for (std::size_t c = 0; c < channels; ++c) {
      rms[c] += residuals[i][c] * residuals[i][c];
    }
  }
  for (double& v : rms) {
    // No rows (the base condition of a two-condition run has no held-out
    // rows): no RMS, NaN as the scaled figure gives, not 0/0.
    if (failures > 0) {
      v = kInf;
    } else {
      v = idx.empty() ? kNaN : std::sqrt(v / static_cast<double>(idx.size()));
    }
  }
  return rms;
}

// Residuals (measured - predicted) of every row; NaN where the model fails.
std::vector<std::vector<double>> residuals_of(const DiagnosisModel& model, const Candidate* candidate,
                                              const std::vector<double>& values, const std::vector<DiagnosisRow>& rows,
                                              std::size_t channels) {
  std::vector<std::vector<double>> out(rows.size(), std::vector<double>(channels, kNaN));
  std::vector<double> predicted;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (model.predict(candidate, values, rows[i], predicted)) {
      const std::vector<double> measured = model.measured(rows[i]);
      for (std::size_t c = 0; c < channels; ++c) {
        out[i][c] = measured[c] - predicted[c];
      }
    }
  }
  return out;
}

// Fills residuals, RMS and information criteria of a fit from its parameters.
// k counts the fitted parameters only (`fixed` ones are not free).
void evaluate_into(FitResult& fit, const detail::FitRequest& request, const RowNoise& noise) {
  const std::vector<DiagnosisRow>& rows = *request.rows;
  const DataSplit& split = *request.split;
  const std::size_t channels = noise.front().size();
  fit.residuals = residuals_of(*request.model, request.candidate, fit.values, rows, channels);
  std::size_t train_failures = 0;
  fit.train_rms = unit_rms(fit.residuals, split.train, channels, train_failures);
  fit.heldout_rms = unit_rms(fit.residuals, split.heldout, channels, fit.heldout_failures);
  fit.train_rows = split.train.size();
  fit.train_rms_scaled = split.train.empty() ? kNaN : detail::combined(detail::scaled_rms(fit.residuals, split.train, noise));
  fit.heldout_rms_scaled =
      split.heldout.empty() ? kNaN : detail::combined(detail::scaled_rms(fit.residuals, split.heldout, noise));
  fit.train_chi2 = 0.0;
  for (std::size_t i : split.train) {
    for (std::size_t c = 0; c < channels; ++c) {
      const double r = fit.residuals[i][c] / noise[i][c];
      fit.train_chi2 += r * r;
    }
  }
  const double n = static_cast<double>(split.train.size() * channels);
  const double k = static_cast<double>(fit.values.size() - std::min(request.fixed, fit.values.size()));
  const double chi2 = std::max(fit.train_chi2, 1e-300);
  fit.aic = n * std::log(chi2 / n) + 2.0 * k;
  fit.bic = n * std::log(chi2 / n) + k * std::log(n);
}

bool evaluates_everywhere(const detail::FitRequest& request, const std::vector<DiagnosisRow>& train,
                          const std::vector<double>& start) {
  std::vector<double> predicted;
  return std::all_of(train.begin(), train.end(), [&](const DiagnosisRow& row) {
    return request.model->predict(request.candidate, start, row, predicted);
  });
}

// Ceres needs a start where every training row evaluates. Tried in order: the
// given start; the candidate's terms at a tenth of their initial value; the
// model's own initial values (the fixed parameters kept). Throws otherwise.
std::vector<double> start_point(const detail::FitRequest& request, const std::vector<ParameterSpec>& specs,
                                const std::vector<DiagnosisRow>& train, const std::string& label) {
  const std::size_t given = request.initial_base.size();
  std::vector<double> x(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    x[i] = std::clamp(i < given ? request.initial_base[i] : specs[i].initial, specs[i].lower, specs[i].upper);
  }
  if (evaluates_everywhere(request, train, x)) {
    return x;
  }
  std::vector<double> small = x;
  std::vector<double> own = x;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (i >= given) {
      small[i] = std::clamp(0.1 * specs[i].initial, specs[i].lower, specs[i].upper);
    }
    if (i >= request.fixed) {
      own[i] = specs[i].initial;
    }
  }
  if (evaluates_everywhere(request, train, small)) {
    return small;
  }
  if (evaluates_everywhere(request, train, own)) {
    return own;
  }
  throw DiagnosisError("the " + label + " model has no solution at its starting point on some training rows");
}

ceres::Solver::Options solver_options(const DiagnosisSettings& settings) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = settings.max_iterations;
  options.function_tolerance = settings.function_tolerance;
  options.gradient_tolerance = 1e-12;
  options.parameter_tolerance = settings.parameter_tolerance;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.num_threads = 1;  // the candidate stage runs fits in parallel
  return options;
}

// Fits x (the first `fixed` held constant) to the training rows.
void solve(const detail::FitRequest& request, const std::vector<ParameterSpec>& specs, const RowNoise& row_sigma,
           std::vector<double>& x, FitResult& fit) {
  const std::size_t fixed = std::min(request.fixed, specs.size());
  // Two blocks when some parameters are fixed: Ceres differentiates only the free one.
  const std::size_t first_size = fixed > 0 ? fixed : specs.size();
  double* blocks[2] = {x.data(), x.data() + first_size};
  const int block_count = first_size < specs.size() ? 2 : 1;
  ceres::Problem problem;
  for (std::size_t i : request.split->train) {
    auto* cost = new ceres::DynamicNumericDiffCostFunction<RowResidual, ceres::FORWARD>(new RowResidual(
        *request.model, request.candidate, (*request.rows)[i], row_sigma[i], specs, first_size));
    cost->AddParameterBlock(static_cast<int>(first_size));
    if (block_count == 2) {
      cost->AddParameterBlock(static_cast<int>(specs.size() - first_size));
    }
    cost->SetNumResiduals(static_cast<int>(row_sigma[i].size()));
    problem.AddResidualBlock(cost, nullptr, std::vector<double*>(blocks, blocks + block_count));
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const int b = i < first_size ? 0 : 1;
    const int k = static_cast<int>(i < first_size ? i : i - first_size);
    problem.SetParameterLowerBound(blocks[b], k, specs[i].lower);
    problem.SetParameterUpperBound(blocks[b], k, specs[i].upper);
  }
  if (fixed > 0) {
    problem.SetParameterBlockConstant(blocks[0]);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options(*request.settings), &problem, &summary);
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.solver_message = summary.message;
  fit.iterations = static_cast<int>(summary.iterations.size());
  if (!summary.IsSolutionUsable()) {
    throw DiagnosisError("the " + fit.label + " fit failed: " + summary.message);
  }
}

// Noise-scaled predictions of `rows` at x, one entry per row and channel;
// false when the model fails on one of them.
bool scaled_predictions(const detail::FitRequest& request, const std::vector<std::size_t>& rows,
                        const RowNoise& row_sigma, const std::vector<double>& x, std::vector<double>& out) {
  out.clear();
  std::vector<double> predicted;
  for (std::size_t i : rows) {
    if (!request.model->predict(request.candidate, x, (*request.rows)[i], predicted)) {
      return false;
    }
    for (std::size_t c = 0; c < predicted.size(); ++c) {
      out.push_back(predicted[c] / row_sigma[i][c]);
    }
  }
  return true;
}

// Forward-difference Jacobian (rows: the entries of scaled_predictions;
// columns: the free parameters, each divided by its column's norm, which
// leaves leverages unchanged) of the training rows (first) and the held-out
// rows. Free: past `fixed` and not at a bound (a parameter held by its bound
// does not move with the noise).
bool scaled_jacobians(const detail::FitRequest& request, const std::vector<ParameterSpec>& specs,
                      const RowNoise& row_sigma, const std::vector<double>& x,
                      std::vector<std::vector<double>>& train_columns, std::vector<std::vector<double>>& heldout_columns) {
  std::vector<double> train0;
  std::vector<double> heldout0;
  if (!scaled_predictions(request, request.split->train, row_sigma, x, train0) ||
      !scaled_predictions(request, request.split->heldout, row_sigma, x, heldout0)) {
    return false;
  }
  for (std::size_t j = request.fixed; j < specs.size(); ++j) {
    const double range = specs[j].upper - specs[j].lower;
    if (x[j] <= specs[j].lower + 1e-9 * range || x[j] >= specs[j].upper - 1e-9 * range) {
      continue;
    }
    const double step = 1e-5 * std::max(std::abs(x[j]), 1e-2 * range);
    std::vector<double> moved = x;
    moved[j] = x[j] + step <= specs[j].upper ? x[j] + step : x[j] - step;
    std::vector<double> train1;
    std::vector<double> heldout1;
    if (!scaled_predictions(request, request.split->train, row_sigma, moved, train1) ||
        !scaled_predictions(request, request.split->heldout, row_sigma, moved, heldout1)) {
      return false;
    }
    double norm = 0.0;
    for (std::size_t e = 0; e < train1.size(); ++e) {
      train1[e] = (train1[e] - train0[e]) / (moved[j] - x[j]);
      norm += train1[e] * train1[e];
    }
    if (!(norm > 0.0)) {
      continue;  // no training row depends on it: the fit did not set it
    }
    norm = std::sqrt(norm);
    for (std::size_t e = 0; e < train1.size(); ++e) {
      train1[e] /= norm;
    }
    for (std::size_t e = 0; e < heldout1.size(); ++e) {
      heldout1[e] = (heldout1[e] - heldout0[e]) / (moved[j] - x[j]) / norm;
    }
    train_columns.push_back(std::move(train1));
    heldout_columns.push_back(std::move(heldout1));
  }
  return true;
}

// Cholesky factor L (row-major, lower) of A + ridge I, A symmetric k x k.
// The ridge (1e-10 of the unit diagonal the column scaling gives) keeps two
// near-collinear parameters from an unbounded inverse.
std::vector<double> cholesky(std::vector<double> a, std::size_t k) {
  for (std::size_t i = 0; i < k; ++i) {
    a[i * k + i] += 1e-10;
  }
  for (std::size_t j = 0; j < k; ++j) {
    double d = a[j * k + j];
    for (std::size_t p = 0; p < j; ++p) {
      d -= a[j * k + p] * a[j * k + p];
    }
    a[j * k + j] = std::sqrt(std::max(d, 1e-300));
    for (std::size_t i = j + 1; i < k; ++i) {
      double v = a[i * k + j];
      for (std::size_t p = 0; p < j; ++p) {
        v -= a[i * k + p] * a[j * k + p];
      }
      a[i * k + j] = v / a[j * k + j];
    }
  }
  return a;
}

}  // namespace

namespace detail {

double heldout_leverage(const FitRequest& request, const std::vector<double>& values) {
  const std::vector<ParameterSpec> specs =
      all_parameters(*request.model, request.candidate, select(*request.rows, request.split->train));
  const RowNoise row_sigma = row_noise(*request.model, *request.rows, *request.noise);
  std::vector<std::vector<double>> train;
  std::vector<std::vector<double>> heldout;
  if (!scaled_jacobians(request, specs, row_sigma, values, train, heldout)) {
    return kNaN;
  }
  const std::size_t k = train.size();
  if (k == 0) {
    return 0.0;
  }
  std::vector<double> normal(k * k, 0.0);  // J_t' J_t
  for (std::size_t a = 0; a < k; ++a) {
    for (std::size_t b = 0; b < k; ++b) {
      for (std::size_t e = 0; e < train[a].size(); ++e) {
        normal[a * k + b] += train[a][e] * train[b][e];
      }
    }
  }
  const std::vector<double> l = cholesky(normal, k);
  // h = g' (J_t' J_t)^-1 g = |L^-1 g|^2 for each held-out entry's gradient g.
  double sum = 0.0;
  std::vector<double> y(k);
  for (std::size_t e = 0; e < heldout.front().size(); ++e) {
    for (std::size_t a = 0; a < k; ++a) {
      double v = heldout[a][e];
      for (std::size_t p = 0; p < a; ++p) {
        v -= l[a * k + p] * y[p];
      }
      y[a] = v / l[a * k + a];
      sum += y[a] * y[a];
    }
  }
  return sum;
}

FitResult run_fit(const FitRequest& request) {
  const std::vector<DiagnosisRow> train = select(*request.rows, request.split->train);
  const std::vector<ParameterSpec> specs = all_parameters(*request.model, request.candidate, train);
  const RowNoise row_sigma = row_noise(*request.model, *request.rows, *request.noise);
  FitResult fit;
  fit.label = request.candidate != nullptr ? request.candidate->name : "base";
  for (const ParameterSpec& spec : specs) {
    fit.names.push_back(spec.name);
  }
  std::vector<double> x = start_point(request, specs, train, fit.label);
  if (request.fixed >= specs.size()) {
    fit.converged = true;
    fit.solver_message = "not fitted (every parameter held fixed)";
  } else {
    solve(request, specs, row_sigma, x, fit);
  }
  fit.values = x;
  evaluate_into(fit, request, row_sigma);
  return fit;
}

}  // namespace detail

FitResult evaluate_model(const DiagnosisModel& model, const Candidate* candidate, const std::vector<double>& params,
                         const std::vector<DiagnosisRow>& rows, const DataSplit& split,
                         const std::vector<ChannelNoiseEstimate>& noise) {
  const DiagnosisSettings settings;
  detail::FitRequest request{&model, candidate, &rows, &split, &noise, params, 0, &settings};
  FitResult fit;
  fit.label = candidate != nullptr ? candidate->name : "base";
  for (const ParameterSpec& spec : all_parameters(model, candidate, detail::select(rows, split.train))) {
    fit.names.push_back(spec.name);
  }
  fit.values = params;
  fit.converged = true;
  fit.solver_message = "not fitted (given parameters)";
  evaluate_into(fit, request, detail::row_noise(model, rows, noise));
  return fit;
}

FitResult fit_model(const DiagnosisModel& model, const Candidate* candidate, const std::vector<DiagnosisRow>& rows,
                    const DataSplit& split, const std::vector<ChannelNoiseEstimate>& noise,
                    const std::vector<double>& initial_base, const DiagnosisSettings& settings) {
  return detail::run_fit({&model, candidate, &rows, &split, &noise, initial_base, 0, &settings});
}

PooledHeldout pooled_heldout(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                             const std::vector<FitResult>& fits, const std::vector<DataSplit>& folds,
                             const std::vector<ChannelNoiseEstimate>& noise) {
  const RowNoise row_sigma = detail::row_noise(model, rows, noise);
  const std::size_t channels = noise.size();
  std::vector<double> sum(channels, 0.0);
  std::vector<double> sum_scaled(channels, 0.0);
  std::size_t count = 0;
  bool failed = false;
  for (std::size_t f = 0; f < folds.size(); ++f) {
    for (std::size_t i : folds[f].heldout) {
      ++count;
      if (std::isnan(fits[f].residuals[i][0])) {
        failed = true;
        continue;
      }
      for (std::size_t c = 0; c < channels; ++c) {
        const double r = fits[f].residuals[i][c];
        sum[c] += r * r;
        sum_scaled[c] += (r / row_sigma[i][c]) * (r / row_sigma[i][c]);
      }
    }
  }
  PooledHeldout pooled;
  std::vector<double> scaled;
  for (std::size_t c = 0; c < channels; ++c) {
    const bool bad = failed || count == 0;
    pooled.rms.push_back(bad ? kInf : std::sqrt(sum[c] / static_cast<double>(count)));
    scaled.push_back(bad ? kInf : std::sqrt(sum_scaled[c] / static_cast<double>(count)));
  }
  pooled.scaled = detail::combined(scaled);
  return pooled;
}

namespace {

// The model-free estimate of channel c, or a placeholder (1 % of the
// channel's RMS, method "fit_residual") for the preliminary fit to replace.
ChannelNoiseEstimate channel_noise(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                                   const ChannelInfo& channel, std::size_t c) {
  std::vector<double> values;
  double scale = 0.0;
  for (const DiagnosisRow& row : rows) {
    values.push_back(model.measured(row)[c]);
    scale += values.back() * values.back();
  }
  const NoiseEstimate e = estimate_noise(rows, values);
  ChannelNoiseEstimate out{channel.name, e.sigma, e.method, e.dof, e.floor, e.relative};
  if (e.method == "none" || !(e.sigma > 0.0)) {
    out.sigma = std::max(0.01 * std::sqrt(scale / static_cast<double>(rows.size())), 1e-12);
    out.method = "fit_residual";
    out.floor = out.sigma;
    out.relative = 0.0;
  }
  return out;
}

}  // namespace

std::vector<ChannelNoiseEstimate> estimate_channel_noise(const DiagnosisModel& model,
                                                         const std::vector<DiagnosisRow>& rows,
                                                         const DataSplit& split, const DiagnosisSettings& settings) {
  const std::vector<ChannelInfo> channels = model.channels();
  std::vector<ChannelNoiseEstimate> noise;
  bool need_fit = false;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    noise.push_back(channel_noise(model, rows, channels[c], c));
    need_fit = need_fit || noise.back().method == "fit_residual";
  }
  if (!need_fit) {
    return noise;
  }
  const FitResult pre = fit_model(model, nullptr, rows, split, noise, {}, settings);
  const double n = static_cast<double>(split.train.size());
  const double k = static_cast<double>(pre.values.size()) / static_cast<double>(channels.size());
  for (std::size_t c = 0; c < channels.size(); ++c) {
    if (noise[c].method == "fit_residual") {
      // Residual standard deviation with the degrees of freedom the fit used.
      noise[c].sigma = std::max(pre.train_rms[c] * std::sqrt(n / std::max(n - k, 1.0)), 1e-12);
      noise[c].floor = noise[c].sigma;
      noise[c].dof = static_cast<std::size_t>(std::max(n - k, 1.0));
    }
  }
  return noise;
}

}  // namespace ground
}  // namespace sinkwatch
