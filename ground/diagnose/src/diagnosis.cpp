// diagnosis.cpp: fitting (Ceres), the WHERE breakdown and the ranking.
#include "sinkwatch/ground/diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <utility>

#include <ceres/ceres.h>

namespace sinkwatch {
namespace ground {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<ParameterSpec> all_parameters(const DiagnosisModel& model, const Candidate* candidate,
                                          const std::vector<DiagnosisRow>& train) {
  std::vector<ParameterSpec> specs = model.base_parameters(train);
  if (candidate != nullptr) {
    specs.insert(specs.end(), candidate->extra.begin(), candidate->extra.end());
  }
  return specs;
}

std::vector<DiagnosisRow> select(const std::vector<DiagnosisRow>& rows, const std::vector<std::size_t>& idx) {
  std::vector<DiagnosisRow> out;
  out.reserve(idx.size());
  for (std::size_t i : idx) {
    out.push_back(rows[i]);
  }
  return out;
}

// Noise-scaled residuals of one row; the parameters are clamped into their
// admissible range first, because numeric differentiation steps across the
// bounds that Ceres enforces on the iterates.
class RowResidual {
 public:
  RowResidual(const DiagnosisModel& model, const Candidate* candidate, const DiagnosisRow& row,
              std::vector<double> measured, std::vector<double> sigma, const std::vector<ParameterSpec>& specs)
      : model_(model), candidate_(candidate), row_(row), measured_(std::move(measured)), sigma_(std::move(sigma)),
        specs_(specs) {}

  bool operator()(double const* const* parameters, double* residuals) const {
    std::vector<double> p(specs_.size());
    for (std::size_t i = 0; i < specs_.size(); ++i) {
      p[i] = std::clamp(parameters[0][i], specs_[i].lower, specs_[i].upper);
    }
    std::vector<double> predicted;
    if (!model_.predict(candidate_, p, row_, predicted)) {
      return false;
    }
    for (std::size_t c = 0; c < measured_.size(); ++c) {
      residuals[c] = (predicted[c] - measured_[c]) / sigma_[c];
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
};

// The noise of every row and channel, [row][channel]: hypot(floor,
// relative |measured|), never below 5 % of the channel's RMS noise (a fitted
// floor of zero would otherwise give rows near zero an unbounded weight).
using RowNoise = std::vector<std::vector<double>>;

RowNoise row_noise(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                   const std::vector<ChannelNoiseEstimate>& noise) {
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

// RMS over `idx` of residual / row noise, per channel (inf if the model
// failed on one of the rows), and its combination over channels.
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

// Fills residuals, RMS and information criteria of a fit from its parameters.
void evaluate_into(FitResult& fit, const DiagnosisModel& model, const Candidate* candidate,
                   const std::vector<DiagnosisRow>& rows, const DataSplit& split, const RowNoise& noise) {
  const std::size_t channels = noise.front().size();
  fit.residuals.assign(rows.size(), std::vector<double>(channels, kNaN));
  std::vector<double> predicted;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (model.predict(candidate, fit.values, rows[i], predicted)) {
      const std::vector<double> measured = model.measured(rows[i]);
      for (std::size_t c = 0; c < channels; ++c) {
        fit.residuals[i][c] = measured[c] - predicted[c];
      }
    }
  }
  auto rms_over = [&](const std::vector<std::size_t>& idx, std::vector<double>& rms, std::size_t& failures) {
    rms.assign(channels, 0.0);
    failures = 0;
    for (std::size_t i : idx) {
      if (std::isnan(fit.residuals[i][0])) {
        ++failures;
        continue;
      }
      for (std::size_t c = 0; c < channels; ++c) {
        rms[c] += fit.residuals[i][c] * fit.residuals[i][c];
      }
    }
    for (std::size_t c = 0; c < channels; ++c) {
      rms[c] = failures > 0 ? kInf : std::sqrt(rms[c] / static_cast<double>(idx.size()));
    }
  };
  std::size_t train_failures = 0;
  rms_over(split.train, fit.train_rms, train_failures);
  rms_over(split.heldout, fit.heldout_rms, fit.heldout_failures);
  fit.train_rows = split.train.size();
  fit.train_rms_scaled = combined(scaled_rms(fit.residuals, split.train, noise));
  fit.heldout_rms_scaled = combined(scaled_rms(fit.residuals, split.heldout, noise));
  fit.train_chi2 = 0.0;
  for (std::size_t i : split.train) {
    for (std::size_t c = 0; c < channels; ++c) {
      const double r = fit.residuals[i][c] / noise[i][c];
      fit.train_chi2 += r * r;
    }
  }
  const double n = static_cast<double>(split.train.size() * channels);
  const double k = static_cast<double>(fit.values.size());
  const double chi2 = std::max(fit.train_chi2, 1e-300);
  fit.aic = n * std::log(chi2 / n) + 2.0 * k;
  fit.bic = n * std::log(chi2 / n) + k * std::log(n);
}

std::vector<double> sigmas(const std::vector<ChannelNoiseEstimate>& noise) {
  std::vector<double> s;
  for (const ChannelNoiseEstimate& e : noise) {
    s.push_back(e.sigma);
  }
  return s;
}

std::string format_range(double low, double high) {
  std::ostringstream os;
  os.precision(4);
  if (low == high) {
    os << low;
  } else {
    os << low << "-" << high;
  }
  return os.str();
}

// Splits the rows into up to `max_bins` bins of near-equal counts of distinct
// values of `key` (so equal values never straddle two bins).
std::vector<std::pair<double, double>> value_bins(std::vector<double> values, std::size_t max_bins) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(),
                           [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }),
               values.end());
  std::vector<std::pair<double, double>> bins;
  const std::size_t n = values.size();
  const std::size_t count = std::min(max_bins, n);
  for (std::size_t b = 0; b < count; ++b) {
    const std::size_t first = b * n / count;
    const std::size_t last = (b + 1) * n / count - 1;
    bins.emplace_back(values[first], values[last]);
  }
  return bins;
}

}  // namespace

FitResult evaluate_model(const DiagnosisModel& model, const Candidate* candidate, const std::vector<double>& params,
                         const std::vector<DiagnosisRow>& rows, const DataSplit& split,
                         const std::vector<ChannelNoiseEstimate>& noise) {
  FitResult fit;
  fit.label = candidate != nullptr ? candidate->name : "base";
  for (const ParameterSpec& spec : all_parameters(model, candidate, select(rows, split.train))) {
    fit.names.push_back(spec.name);
  }
  fit.values = params;
  fit.converged = true;
  fit.solver_message = "not fitted (given parameters)";
  evaluate_into(fit, model, candidate, rows, split, row_noise(model, rows, noise));
  return fit;
}

PooledHeldout pooled_heldout(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                             const std::vector<FitResult>& fits, const std::vector<DataSplit>& folds,
                             const std::vector<ChannelNoiseEstimate>& noise) {
  const RowNoise row_sigma = row_noise(model, rows, noise);
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
  pooled.scaled = combined(scaled);
  return pooled;
}

FitResult fit_model(const DiagnosisModel& model, const Candidate* candidate, const std::vector<DiagnosisRow>& rows,
                    const DataSplit& split, const std::vector<ChannelNoiseEstimate>& noise,
                    const std::vector<double>& initial_base, const DiagnosisSettings& settings) {
  const std::vector<DiagnosisRow> train = select(rows, split.train);
  const std::vector<ParameterSpec> specs = all_parameters(model, candidate, train);
  const RowNoise row_sigma = row_noise(model, rows, noise);
  FitResult fit;
  fit.label = candidate != nullptr ? candidate->name : "base";
  std::vector<double> x(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    fit.names.push_back(specs[i].name);
    x[i] = i < initial_base.size() ? initial_base[i] : specs[i].initial;
    x[i] = std::clamp(x[i], specs[i].lower, specs[i].upper);
  }

  // Ceres needs a start where every training row evaluates. Try, in order:
  // the given start; the candidate's terms at their lower end of "small"
  // (a tenth of their initial value); the model's own initial values.
  auto start_ok = [&](const std::vector<double>& start) {
    std::vector<double> predicted;
    return std::all_of(train.begin(), train.end(), [&](const DiagnosisRow& row) {
      return model.predict(candidate, start, row, predicted);
    });
  };
  if (!start_ok(x)) {
    std::vector<double> small = x;
    for (std::size_t i = initial_base.size(); i < specs.size(); ++i) {
      small[i] = std::clamp(0.1 * specs[i].initial, specs[i].lower, specs[i].upper);
    }
    std::vector<double> own(specs.size());
    for (std::size_t i = 0; i < specs.size(); ++i) {
      own[i] = specs[i].initial;
    }
    if (start_ok(small)) {
      x = small;
    } else if (start_ok(own)) {
      x = own;
    } else {
      throw DiagnosisError("the " + fit.label + " model has no solution at its starting point on some training rows");
    }
  }

  ceres::Problem problem;
  for (std::size_t i : split.train) {
    auto* cost = new ceres::DynamicNumericDiffCostFunction<RowResidual, ceres::FORWARD>(
        new RowResidual(model, candidate, rows[i], model.measured(rows[i]), row_sigma[i], specs));
    cost->AddParameterBlock(static_cast<int>(specs.size()));
    cost->SetNumResiduals(static_cast<int>(row_sigma[i].size()));
    problem.AddResidualBlock(cost, nullptr, x.data());
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    problem.SetParameterLowerBound(x.data(), static_cast<int>(i), specs[i].lower);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(i), specs[i].upper);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = settings.max_iterations;
  options.function_tolerance = 1e-10;
  options.gradient_tolerance = 1e-12;
  options.parameter_tolerance = 1e-10;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.solver_message = summary.message;
  fit.iterations = static_cast<int>(summary.iterations.size());
  if (!summary.IsSolutionUsable()) {
    throw DiagnosisError("the " + fit.label + " fit failed: " + summary.message);
  }
  fit.values = x;
  evaluate_into(fit, model, candidate, rows, split, row_sigma);
  return fit;
}

std::vector<ChannelNoiseEstimate> estimate_channel_noise(const DiagnosisModel& model,
                                                         const std::vector<DiagnosisRow>& rows,
                                                         const DataSplit& split, const DiagnosisSettings& settings) {
  const std::vector<ChannelInfo> channels = model.channels();
  std::vector<ChannelNoiseEstimate> noise;
  bool need_fit = false;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    std::vector<double> values;
    double scale = 0.0;
    for (const DiagnosisRow& row : rows) {
      values.push_back(model.measured(row)[c]);
      scale += values.back() * values.back();
    }
    const NoiseEstimate e = estimate_noise(rows, values);
    ChannelNoiseEstimate out{channels[c].name, e.sigma, e.method, e.dof, e.floor, e.relative};
    if (e.method == "none" || !(e.sigma > 0.0)) {
      // Placeholder scale for a preliminary fit: 1 % of the channel's RMS.
      out.sigma = std::max(0.01 * std::sqrt(scale / static_cast<double>(rows.size())), 1e-12);
      out.method = "fit_residual";
      out.floor = out.sigma;
      out.relative = 0.0;
      need_fit = true;
    }
    noise.push_back(out);
  }
  if (need_fit) {
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
  }
  return noise;
}

namespace {

WhereBreakdown where_of(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows, const DataSplit& split,
                        const std::vector<ChannelNoiseEstimate>& noise, const FitResult& base) {
  WhereBreakdown where;
  const std::vector<ChannelInfo> channels = model.channels();
  const std::vector<double> sigma = sigmas(noise);
  const RowNoise row_sigma = row_noise(model, rows, noise);
  const std::vector<double> train_scaled = scaled_rms(base.residuals, split.train, row_sigma);
  const std::vector<double> heldout_scaled = scaled_rms(base.residuals, split.heldout, row_sigma);
  for (std::size_t c = 0; c < channels.size(); ++c) {
    ChannelGap gap;
    gap.channel = channels[c].name;
    gap.unit = channels[c].unit;
    gap.noise_sigma = sigma[c];
    gap.noise_method = noise[c].method;
    gap.train_rms = base.train_rms[c];
    gap.heldout_rms = base.heldout_rms[c];
    double bias = 0.0;
    std::size_t used = 0;
    for (std::size_t i : split.heldout) {
      if (!std::isnan(base.residuals[i][c])) {
        bias += base.residuals[i][c];
        ++used;
      }
    }
    gap.heldout_bias = used > 0 ? bias / static_cast<double>(used) : kNaN;
    gap.train_over_noise = train_scaled[c];
    gap.heldout_over_noise = heldout_scaled[c];
    where.channels.push_back(gap);
  }

  std::vector<bool> is_heldout(rows.size(), false);
  for (std::size_t i : split.heldout) {
    is_heldout[i] = true;
  }
  auto add_regime = [&](const std::string& regime, const std::vector<double>& key, std::size_t max_bins) {
    for (const auto& [low, high] : value_bins(key, max_bins)) {
      RegimeBin bin;
      bin.regime = regime;
      bin.low = low;
      bin.high = high;
      bin.label = format_range(low, high);
      bin.rms.assign(channels.size(), 0.0);
      bin.mean.assign(channels.size(), 0.0);
      bin.rms_over_noise.assign(channels.size(), 0.0);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const double tol = 1e-9 * std::max(std::abs(low), std::abs(high));
        if (key[i] < low - tol || key[i] > high + tol || std::isnan(base.residuals[i][0])) {
          continue;
        }
        ++bin.rows;
        bin.heldout_rows += is_heldout[i] ? 1U : 0U;
        for (std::size_t c = 0; c < channels.size(); ++c) {
          bin.rms[c] += base.residuals[i][c] * base.residuals[i][c];
          bin.mean[c] += base.residuals[i][c];
          const double scaled = base.residuals[i][c] / row_sigma[i][c];
          bin.rms_over_noise[c] += scaled * scaled;
        }
      }
      for (std::size_t c = 0; c < channels.size(); ++c) {
        const double n = static_cast<double>(std::max<std::size_t>(bin.rows, 1));
        bin.rms[c] = std::sqrt(bin.rms[c] / n);
        bin.mean[c] /= n;
        bin.rms_over_noise[c] = std::sqrt(bin.rms_over_noise[c] / n);
      }
      where.bins.push_back(bin);
    }
  };
  std::vector<double> slip;
  std::vector<double> load;
  std::vector<double> sink;
  for (const DiagnosisRow& row : rows) {
    slip.push_back(row.slip);
    load.push_back(row.load_n);
    sink.push_back(row.sinkage_ratio);
  }
  add_regime("slip", slip, 3);
  const std::size_t load_count = distinct_loads(rows).size();
  add_regime("load", load, load_count <= 6 ? load_count : 3);
  add_regime("sinkage_ratio", sink, 3);

  where.components = model.gap_components(rows, base.values, sigma);

  // One sentence on where the gap is largest.
  std::size_t worst_channel = 0;
  for (std::size_t c = 1; c < where.channels.size(); ++c) {
    if (where.channels[c].heldout_over_noise > where.channels[worst_channel].heldout_over_noise) {
      worst_channel = c;
    }
  }
  const RegimeBin* worst_bin = nullptr;
  for (const RegimeBin& bin : where.bins) {
    if (bin.rows >= 2 && (worst_bin == nullptr ||
                          bin.rms_over_noise[worst_channel] > worst_bin->rms_over_noise[worst_channel])) {
      worst_bin = &bin;
    }
  }
  std::ostringstream os;
  os.precision(3);
  const ChannelGap& g = where.channels[worst_channel];
  os << "largest held-out gap in " << g.channel << ": RMS " << g.heldout_rms << " " << g.unit << " = "
     << g.heldout_over_noise << "x noise (bias " << g.heldout_bias << ")";
  if (worst_bin != nullptr) {
    os << "; worst regime " << worst_bin->regime << " " << worst_bin->label << " with "
       << worst_bin->rms_over_noise[worst_channel] << "x noise";
  }
  where.largest = os.str();
  return where;
}

// Fits on folds 1.. of the cross-validation, each started from the fit on
// fold 0 (a warm start: the optimum moves little when one load of several is
// swapped, and a cold start with several starts per fold would cost the
// diagnosis several times over). Throws DiagnosisError naming the fold.
std::vector<FitResult> fold_fits(const DiagnosisModel& model, const Candidate* candidate,
                                 const std::vector<DiagnosisRow>& rows, const std::vector<DataSplit>& folds,
                                 const std::vector<ChannelNoiseEstimate>& noise, const FitResult& first,
                                 const DiagnosisSettings& settings) {
  std::vector<FitResult> fits{first};
  for (std::size_t f = 1; f < folds.size(); ++f) {
    try {
      fits.push_back(fit_model(model, candidate, rows, folds[f], noise, first.values, settings));
    } catch (const DiagnosisError& e) {
      throw DiagnosisError("cross-validation fold (" + folds[f].rule + "): " + e.what());
    }
  }
  return fits;
}

}  // namespace

DiagnosisResult diagnose(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows, const std::string& source,
                         const DiagnosisSettings& settings) {
  DiagnosisResult result;
  result.model = model.name();
  result.source = source;
  result.channels = model.channels();
  result.rows = rows;
  result.folds = settings.cross_validate ? cross_validation_folds(rows, settings.every_load_fold) : std::vector<DataSplit>{split_rows(rows)};
  const DataSplit split = result.folds.front();
  result.split_rule = split.rule;
  result.train = split.train;
  result.heldout = split.heldout;
  result.noise = estimate_channel_noise(model, rows, split, settings);
  for (const ChannelNoiseEstimate& n : result.noise) {
    if (n.method == "fit_residual") {
      result.notes.push_back("noise of " + n.channel +
                             " estimated from the base fit's training residual (no replicates and too few "
                             "neighbours): gaps are then measured against the base fit itself");
    }
  }
  result.row_noise = row_noise(model, rows, result.noise);
  result.base = fit_model(model, nullptr, rows, split, result.noise, {}, settings);
  if (!result.base.converged) {
    result.notes.push_back("base fit did not converge: " + result.base.solver_message);
  }
  result.where = where_of(model, rows, split, result.noise, result.base);
  std::vector<FitResult> base_folds{result.base};
  try {
    base_folds = fold_fits(model, nullptr, rows, result.folds, result.noise, result.base, settings);
  } catch (const DiagnosisError& e) {
    result.notes.push_back(std::string("no cross-validation, the ranking uses the first split only: ") + e.what());
    result.folds.resize(1);
  }
  {
    std::ostringstream rule;
    if (result.folds.size() > 1) {
      rule << "held-out RMS pooled over " << result.folds.size() << " cross-validation folds (";
      rule << (distinct_loads(rows).size() < 3 ? "every 4th slip-sorted row, 4 offsets"
               : settings.every_load_fold     ? "each load held out once"
                                              : "the highest load held out, then the lowest");
      rule << "), every fit redone on each fold";
    } else {
      rule << "held-out RMS of the split above (one fold)";
    }
    result.cv_rule = rule.str();
  }
  const PooledHeldout base_cv = pooled_heldout(model, rows, base_folds, result.folds, result.noise);
  result.cv_heldout_rms = base_cv.rms;
  result.cv_heldout_rms_scaled = base_cv.scaled;

  const std::vector<DiagnosisRow> train = select(rows, split.train);
  const std::vector<double> sigma = sigmas(result.noise);
  const double before = result.cv_heldout_rms_scaled;
  for (const Candidate& candidate : model.candidates(train)) {
    RankedEffect effect;
    effect.effect = candidate.name;
    effect.description = candidate.description;
    effect.identifiable = candidate.identifiable;
    effect.note = candidate.note;
    effect.nominal_size = candidate.nominal_size;
    effect.heldout_rms_before = before;
    effect.channel_before = result.cv_heldout_rms;
    if (candidate.identifiable) {
      // Several starts for the candidate's own terms (multiples of its
      // initial value), each from the fitted base; the lowest training
      // cost wins. A local minimum would otherwise read as "no shrink".
      bool fitted = false;
      std::string failure;
      std::vector<std::vector<double>> tried;
      for (double multiple : settings.start_multiples) {
        Candidate start = candidate;
        std::vector<double> extra_start;
        for (ParameterSpec& spec : start.extra) {
          spec.initial = std::clamp(multiple * spec.initial, spec.lower, spec.upper);
          extra_start.push_back(spec.initial);
        }
        if (std::find(tried.begin(), tried.end(), extra_start) != tried.end()) {
          continue;
        }
        tried.push_back(extra_start);
        try {
          FitResult fit = fit_model(model, &start, rows, split, result.noise, result.base.values, settings);
          if (!fitted || fit.train_chi2 < effect.fit.train_chi2) {
            effect.fit = std::move(fit);
            fitted = true;
          }
        } catch (const DiagnosisError& e) {
          failure = e.what();
        }
      }
      if (!fitted) {
        effect.identifiable = false;
        effect.note = failure;
      }
    }
    PooledHeldout after;
    if (effect.identifiable) {
      try {
        after = pooled_heldout(model, rows, fold_fits(model, &candidate, rows, result.folds, result.noise, effect.fit, settings),
                               result.folds, result.noise);
      } catch (const DiagnosisError& e) {
        effect.identifiable = false;
        effect.note = e.what();
      }
    }
    if (effect.identifiable) {
      effect.heldout_rms_after = after.scaled;
      effect.channel_after = after.rms;
      const std::size_t base_count = result.base.values.size();
      for (std::size_t i = base_count; i < effect.fit.values.size(); ++i) {
        effect.fitted[effect.fit.names[i]] = effect.fit.values[i];
      }
      effect.train_bic = effect.fit.bic;
      effect.delta_bic = effect.fit.bic - result.base.bic;
      if (!effect.fit.converged) {
        effect.note += (effect.note.empty() ? "" : "; ") + std::string("fit did not converge: ") + effect.fit.solver_message;
      }
    } else {
      effect.heldout_rms_after = kNaN;
      effect.channel_after.assign(sigma.size(), kNaN);
    }
    effect.shrink_pct = before > 0.0 ? 100.0 * (before - effect.heldout_rms_after) / before : kNaN;
    for (std::size_t c = 0; c < sigma.size(); ++c) {
      effect.channel_shrink_pct.push_back(
          effect.channel_before[c] > 0.0
              ? 100.0 * (effect.channel_before[c] - effect.channel_after[c]) / effect.channel_before[c]
              : kNaN);
    }
    result.ranking.push_back(std::move(effect));
  }

  // Rank: identifiable first, by held-out score; then adjacent near-ties
  // (within tie_fraction of the base's held-out score) go to the lower BIC.
  std::stable_sort(result.ranking.begin(), result.ranking.end(), [](const RankedEffect& a, const RankedEffect& b) {
    if (a.identifiable != b.identifiable) {
      return a.identifiable;
    }
    if (!a.identifiable) {
      return false;
    }
    return a.heldout_rms_after < b.heldout_rms_after;
  });
  const double tie = settings.tie_fraction * before;
  for (std::size_t pass = 0; pass < result.ranking.size(); ++pass) {
    for (std::size_t i = 0; i + 1 < result.ranking.size(); ++i) {
      RankedEffect& a = result.ranking[i];
      RankedEffect& b = result.ranking[i + 1];
      if (a.identifiable && b.identifiable && std::abs(a.heldout_rms_after - b.heldout_rms_after) <= tie &&
          b.train_bic < a.train_bic) {
        std::swap(a, b);
      }
    }
  }

  std::ostringstream verdict;
  verdict.precision(3);
  const RankedEffect* best = result.ranking.empty() || !result.ranking.front().identifiable ? nullptr
                                                                                            : &result.ranking.front();
  if (before < settings.gap_threshold) {
    result.verdict = "no_gap";
    verdict << "no significant gap: the base model's held-out RMS is " << before
            << "x the measurement noise (threshold " << settings.gap_threshold << "x); the ranking below is not evidence";
  } else if (before <= settings.residual_threshold) {
    result.verdict = "weak_gap";
    verdict << "weak gap: the base model's held-out RMS is " << before << "x the measurement noise, between "
            << settings.gap_threshold << "x and " << settings.residual_threshold << "x";
    if (best != nullptr) {
      verdict << "; the best candidate, " << best->effect << ", takes it to " << best->heldout_rms_after << "x ("
              << best->shrink_pct << " % shrink), which on so small a gap is weak evidence for it";
    }
  } else if (best == nullptr || best->shrink_pct < settings.explain_threshold_pct) {
    result.verdict = "not_explained";
    verdict << "no candidate explains the gap: held-out RMS " << before << "x noise";
    if (best != nullptr) {
      verdict << ", best candidate " << best->effect << " shrinks it by only " << best->shrink_pct << " % (threshold "
              << settings.explain_threshold_pct << " %)";
    }
  } else if (best->heldout_rms_after > settings.residual_threshold) {
    result.verdict = "partly_explained";
    verdict << best->effect << " shrinks the held-out gap by " << best->shrink_pct << " % (" << before << " -> "
            << best->heldout_rms_after << "x noise) but the rest stays above " << settings.residual_threshold
            << "x noise: something else is missing too";
  } else {
    result.verdict = "explained";
    verdict << best->effect << " explains the gap: held-out RMS " << before << " -> " << best->heldout_rms_after
            << "x noise (" << best->shrink_pct << " % shrink)";
  }
  if (best != nullptr && result.verdict != "no_gap") {
    std::string tied;
    for (std::size_t i = 1; i < result.ranking.size(); ++i) {
      const RankedEffect& other = result.ranking[i];
      if (other.identifiable && std::abs(other.heldout_rms_after - best->heldout_rms_after) <= tie) {
        tied += (tied.empty() ? "" : ", ") + other.effect;
      }
    }
    if (!tied.empty()) {
      verdict << "; near-tie on held-out rows with " << tied
              << " (within " << 100.0 * settings.tie_fraction << " % of the base's held-out RMS; ordered by training BIC)";
    }
  }
  result.verdict_text = verdict.str();
  return result;
}

}  // namespace ground
}  // namespace sinkwatch
