// diagnosis.cpp: the stages of the diagnosis: enough data, noise, base fit
// (with the WHERE breakdown), candidates (on all cores), ranking (candidates
// and families) and verdict. The fits themselves are in diagnosis_fit.cpp.
#include "sinkwatch/ground/diagnosis.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <utility>

#include "diagnosis_internal.hpp"

namespace sinkwatch {
namespace ground {

using detail::kInf;
using detail::kNaN;
using detail::RowNoise;

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::no_gap: return "no_gap";
    case Verdict::weak_gap: return "weak_gap";
    case Verdict::explained: return "explained";
    case Verdict::partly_explained: return "partly_explained";
    case Verdict::ambiguous: return "ambiguous";
    case Verdict::not_explained: return "not_explained";
    case Verdict::not_enough_data: return "not_enough_data";
  }
  return "unknown";
}

std::string family_of(const Candidate& candidate) {
  return candidate.family.empty() ? candidate.name : candidate.family;
}

namespace {

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

// Up to `max_bins` bins of near-equal counts of distinct values (so equal
// values never straddle two bins).
std::vector<std::pair<double, double>> value_bins(std::vector<double> values, std::size_t max_bins) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(),
                           [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }),
               values.end());
  std::vector<std::pair<double, double>> bins;
  const std::size_t n = values.size();
  const std::size_t count = std::min(max_bins, n);
  for (std::size_t b = 0; b < count; ++b) {
    bins.emplace_back(values[b * n / count], values[(b + 1) * n / count - 1]);
  }
  return bins;
}

// ---------------------------------------------------------------- WHERE

std::vector<ChannelGap> channel_gaps(const DiagnosisResult& r, const RowNoise& row_sigma) {
  const std::vector<double> train_scaled = detail::scaled_rms(r.base.residuals, r.train, row_sigma);
  const std::vector<double> heldout_scaled = detail::scaled_rms(r.base.residuals, r.heldout, row_sigma);
  std::vector<ChannelGap> gaps;
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    ChannelGap gap;
    gap.channel = r.channels[c].name;
    gap.unit = r.channels[c].unit;
    gap.noise_sigma = r.noise[c].sigma;
    gap.noise_method = r.noise[c].method;
    gap.train_rms = r.base.train_rms[c];
    gap.heldout_rms = r.base.heldout_rms[c];
    double bias = 0.0;
    std::size_t used = 0;
    for (std::size_t i : r.heldout) {
      if (!std::isnan(r.base.residuals[i][c])) {
        bias += r.base.residuals[i][c];
        ++used;
      }
    }
    gap.heldout_bias = used > 0 ? bias / static_cast<double>(used) : kNaN;
    gap.train_over_noise = train_scaled[c];
    gap.heldout_over_noise = heldout_scaled[c];
    gaps.push_back(gap);
  }
  return gaps;
}

// One bin of the base residuals: rows whose key lies in [low, high].
RegimeBin regime_bin(const DiagnosisResult& r, const RowNoise& row_sigma, const std::vector<double>& key,
                     const std::vector<bool>& is_heldout, std::pair<double, double> range) {
  const std::size_t channels = r.channels.size();
  RegimeBin bin;
  bin.low = range.first;
  bin.high = range.second;
  bin.label = format_range(bin.low, bin.high);
  bin.rms.assign(channels, 0.0);
  bin.mean.assign(channels, 0.0);
  bin.rms_over_noise.assign(channels, 0.0);
  const double tol = 1e-9 * std::max(std::abs(bin.low), std::abs(bin.high));
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    if (key[i] < bin.low - tol || key[i] > bin.high + tol || std::isnan(r.base.residuals[i][0])) {
      continue;
    }
    ++bin.rows;
    bin.heldout_rows += is_heldout[i] ? 1U : 0U;
    for (std::size_t c = 0; c < channels; ++c) {
      const double e = r.base.residuals[i][c];
      bin.rms[c] += e * e;
      bin.mean[c] += e;
      bin.rms_over_noise[c] += (e / row_sigma[i][c]) * (e / row_sigma[i][c]);
    }
  }
  const double n = static_cast<double>(std::max<std::size_t>(bin.rows, 1));
  for (std::size_t c = 0; c < channels; ++c) {
    bin.rms[c] = std::sqrt(bin.rms[c] / n);
    bin.mean[c] /= n;
    bin.rms_over_noise[c] = std::sqrt(bin.rms_over_noise[c] / n);
  }
  return bin;
}

std::vector<RegimeBin> regime_bins(const DiagnosisResult& r, const RowNoise& row_sigma) {
  std::vector<bool> is_heldout(r.rows.size(), false);
  for (std::size_t i : r.heldout) {
    is_heldout[i] = true;
  }
  std::vector<double> slip;
  std::vector<double> load;
  std::vector<double> sink;
  for (const DiagnosisRow& row : r.rows) {
    slip.push_back(row.slip);
    load.push_back(row.load_n);
    sink.push_back(row.sinkage_ratio);
  }
  const std::size_t load_count = distinct_loads(r.rows).size();
  const std::vector<std::tuple<std::string, const std::vector<double>*, std::size_t>> regimes = {
      {"slip", &slip, 3}, {"load", &load, load_count <= 6 ? load_count : 3}, {"sinkage_ratio", &sink, 3}};
  std::vector<RegimeBin> bins;
  for (const auto& [regime, key, max_bins] : regimes) {
    for (const auto& range : value_bins(*key, max_bins)) {
      bins.push_back(regime_bin(r, row_sigma, *key, is_heldout, range));
      bins.back().regime = regime;
    }
  }
  return bins;
}

// One sentence on where the gap is largest.
std::string largest_gap(const WhereBreakdown& where) {
  std::size_t worst_channel = 0;
  for (std::size_t c = 1; c < where.channels.size(); ++c) {
    if (where.channels[c].heldout_over_noise > where.channels[worst_channel].heldout_over_noise) {
      worst_channel = c;
    }
  }
  const RegimeBin* worst_bin = nullptr;
  for (const RegimeBin& bin : where.bins) {
    if (bin.rows >= 2 &&
        (worst_bin == nullptr || bin.rms_over_noise[worst_channel] > worst_bin->rms_over_noise[worst_channel])) {
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
  return os.str();
}

WhereBreakdown where_of(const DiagnosisModel& model, const DiagnosisResult& r) {
  const RowNoise row_sigma = detail::row_noise(model, r.rows, r.noise);
  WhereBreakdown where;
  where.channels = channel_gaps(r, row_sigma);
  where.bins = regime_bins(r, row_sigma);
  std::vector<double> sigma;
  for (const ChannelNoiseEstimate& e : r.noise) {
    sigma.push_back(e.sigma);
  }
  where.components = model.gap_components(r.rows, r.base.values, sigma);
  where.largest = largest_gap(where);
  return where;
}

// ---------------------------------------------------------------- fits on folds

// What every fit of one diagnosis shares.
struct Job {
  const DiagnosisModel& model;
  const DiagnosisSettings& settings;
  DiagnosisResult& result;
  std::size_t fixed = 0;  // leading (base) parameters held fixed
};

detail::FitRequest request_for(const Job& job, const Candidate* candidate, const DataSplit& split,
                               const std::vector<double>& start, std::size_t fixed) {
  return {&job.model, candidate, &job.result.rows, &split, &job.result.noise, start, fixed, &job.settings};
}

// Fits on folds 1.. of the cross-validation, each started from the fit on
// fold 0 (a warm start: the optimum moves little when one load of several is
// swapped, and a cold start with several starts per fold would cost the
// diagnosis several times over). Throws DiagnosisError naming the fold.
std::vector<FitResult> fold_fits(const Job& job, const Candidate* candidate, const FitResult& first,
                                 std::size_t fixed) {
  std::vector<FitResult> fits{first};
  const std::vector<DataSplit>& folds = job.result.folds;
  for (std::size_t f = 1; f < folds.size(); ++f) {
    try {
      fits.push_back(detail::run_fit(request_for(job, candidate, folds[f], first.values, fixed)));
    } catch (const DiagnosisError& e) {
      throw DiagnosisError("cross-validation fold (" + folds[f].rule + "): " + e.what());
    }
  }
  return fits;
}

// ---------------------------------------------------------------- stages

std::string cv_rule_text(const DiagnosisResult& r, const DiagnosisSettings& settings) {
  std::ostringstream rule;
  if (r.folds.size() > 1) {
    rule << "held-out RMS pooled over " << r.folds.size() << " cross-validation folds (";
    rule << (distinct_loads(r.rows).size() < 3 ? "every 4th slip-sorted row, 4 offsets"
             : settings.every_load_fold        ? "each load held out once"
                                               : "the highest load held out, then the lowest");
    rule << "), every fit redone on each fold";
  } else {
    rule << "held-out RMS of the split above (one fold)";
  }
  return rule.str();
}

// Stage 0: enough rows to fit and hold out? Sets the folds, or the verdict
// not_enough_data with a campaign suggestion (false).
bool enough_data(const DiagnosisModel& model, DiagnosisResult& r, const DiagnosisSettings& settings,
                 std::size_t free_base) {
  std::string why;
  if (r.rows.size() < settings.min_rows) {
    why = std::to_string(r.rows.size()) + " rows, fewer than the " + std::to_string(settings.min_rows) + " needed";
  } else {
    try {
      r.folds = settings.cross_validate ? cross_validation_folds(r.rows, settings.every_load_fold)
                                        : std::vector<DataSplit>{split_rows(r.rows)};
    } catch (const std::invalid_argument& e) {
      why = e.what();
    }
  }
  // Residuals enough for the free base parameters and a two-term candidate,
  // with two to spare.
  const std::size_t needed = free_base + 4;
  if (why.empty() && r.folds.front().train.size() * model.channels().size() < needed) {
    why = std::to_string(r.folds.front().train.size()) + " training rows for " + std::to_string(free_base) +
          " base parameters and a candidate's";
  }
  if (why.empty()) {
    return true;
  }
  r.folds.clear();
  r.verdict = Verdict::not_enough_data;
  r.verdict_text = "not enough data (" + why + "). " + campaign_suggestion(r.rows, settings.min_rows);
  return false;
}

// Stage 1: the noise of each channel, the yardstick of every residual.
void noise_stage(const DiagnosisModel& model, DiagnosisResult& r, const DiagnosisSettings& settings) {
  const DataSplit& split = r.folds.front();
  r.split_rule = split.rule;
  r.train = split.train;
  r.heldout = split.heldout;
  r.noise = estimate_channel_noise(model, r.rows, split, settings);
  for (const ChannelNoiseEstimate& n : r.noise) {
    if (n.method == "fit_residual") {
      r.notes.push_back("noise of " + n.channel +
                        " estimated from the base fit's training residual (no replicates and too few "
                        "neighbours): gaps are then measured against the base fit itself");
    }
  }
  r.row_noise = detail::row_noise(model, r.rows, r.noise);
}

// Stage 2: the base fit on the first split (or, with `fixed_base`, the base
// condition's parameters evaluated), WHERE, and the pooled "before".
void base_stage(Job& job, const std::vector<double>& fixed_base) {
  DiagnosisResult& r = job.result;
  r.base = detail::run_fit(request_for(job, nullptr, r.folds.front(), fixed_base, fixed_base.size()));
  if (!r.base.converged) {
    r.notes.push_back("base fit did not converge: " + r.base.solver_message);
  }
  r.where = where_of(job.model, r);
  std::vector<FitResult> base_folds{r.base};
  try {
    base_folds = fold_fits(job, nullptr, r.base, fixed_base.size());
  } catch (const DiagnosisError& e) {
    r.notes.push_back(std::string("no cross-validation, the ranking uses the first split only: ") + e.what());
    r.folds.resize(1);
  }
  r.cv_rule = cv_rule_text(r, job.settings);
  const PooledHeldout pooled = pooled_heldout(job.model, r.rows, base_folds, r.folds, r.noise);
  r.cv_heldout_rms = pooled.rms;
  r.cv_heldout_rms_scaled = pooled.scaled;
}

RankedEffect unscored(const Candidate& candidate, const DiagnosisResult& r) {
  RankedEffect effect;
  effect.effect = candidate.name;
  effect.family = family_of(candidate);
  effect.form = candidate.form;
  effect.description = candidate.description;
  effect.identifiable = candidate.identifiable;
  effect.note = candidate.note;
  effect.nominal_size = candidate.nominal_size;
  effect.heldout_rms_before = r.cv_heldout_rms_scaled;
  effect.channel_before = r.cv_heldout_rms;
  return effect;
}

// The starts of a candidate's own terms (multiples of its initial value,
// each from the fitted base; duplicates after clamping dropped): a local
// minimum would otherwise read as "no shrink". Each is fitted on its own
// (candidate_stage runs them as separate tasks) and the lowest training cost
// wins (best_start).
std::vector<Candidate> candidate_starts(const DiagnosisSettings& settings, const Candidate& candidate) {
  std::vector<Candidate> starts;
  std::vector<std::vector<double>> tried;
  for (double multiple : settings.start_multiples) {
    Candidate start = candidate;
    std::vector<double> extra_start;
    for (ParameterSpec& spec : start.extra) {
      spec.initial = std::clamp(multiple * spec.initial, spec.lower, spec.upper);
      extra_start.push_back(spec.initial);
    }
    if (std::find(tried.begin(), tried.end(), extra_start) == tried.end()) {
      tried.push_back(extra_start);
      starts.push_back(std::move(start));
    }
  }
  return starts;
}

// One start's fit on the first split, or why it failed.
struct StartFit {
  bool fitted = false;
  FitResult fit;
  std::string failure;
};

StartFit fit_start(const Job& job, const Candidate& start) {
  StartFit out;
  try {
    out.fit = detail::run_fit(request_for(job, &start, job.result.folds.front(), job.result.base.values, job.fixed));
    out.fitted = true;
  } catch (const DiagnosisError& e) {
    out.failure = e.what();
  }
  return out;
}

// The fitted start with the lowest training cost (the first of equals), in
// the starts' order; false, with the last failure as the note, when none fitted.
bool best_start(std::vector<StartFit>& starts, RankedEffect& effect) {
  std::string failure;
  bool fitted = false;
  for (StartFit& start : starts) {
    if (!start.fitted) {
      failure = start.failure;
    } else if (!fitted || start.fit.train_chi2 < effect.fit.train_chi2) {
      effect.fit = std::move(start.fit);
      fitted = true;
    }
  }
  if (!fitted) {
    effect.note = failure;
  }
  return fitted;
}

// The shrink of the pooled held-out score, combined and per channel.
void set_scores(RankedEffect& effect, const PooledHeldout& after, bool scored, std::size_t channels) {
  effect.heldout_rms_after = scored ? after.scaled : kNaN;
  effect.channel_after = scored ? after.rms : std::vector<double>(channels, kNaN);
  const double before = effect.heldout_rms_before;
  effect.shrink_pct = before > 0.0 ? 100.0 * (before - effect.heldout_rms_after) / before : kNaN;
  effect.channel_shrink_pct.clear();
  for (std::size_t c = 0; c < channels; ++c) {
    const double b = effect.channel_before[c];
    effect.channel_shrink_pct.push_back(b > 0.0 ? 100.0 * (b - effect.channel_after[c]) / b : kNaN);
  }
}

// Stage 3 for one candidate, given its starts' fits on the first split: the
// best start refitted on every other fold, scored on the pooled held-out rows.
RankedEffect assess(const Job& job, const Candidate& candidate, std::vector<StartFit>& starts) {
  const DiagnosisResult& r = job.result;
  RankedEffect effect = unscored(candidate, r);
  if (effect.identifiable) {
    effect.identifiable = best_start(starts, effect);
  }
  PooledHeldout after;
  if (effect.identifiable) {
    try {
      const std::vector<FitResult> folds = fold_fits(job, &candidate, effect.fit, job.fixed);
      after = pooled_heldout(job.model, r.rows, folds, r.folds, r.noise);
      for (const FitResult& fold : folds) {
        effect.fold_values.push_back(fold.values);
      }
    } catch (const DiagnosisError& e) {
      effect.identifiable = false;
      effect.note = e.what();
    }
  }
  if (effect.identifiable) {
    for (std::size_t i = r.base.values.size(); i < effect.fit.values.size(); ++i) {
      effect.fitted[effect.fit.names[i]] = effect.fit.values[i];
    }
    effect.train_bic = effect.fit.bic;
    effect.delta_bic = effect.fit.bic - r.base.bic;
    if (!effect.fit.converged) {
      effect.note += (effect.note.empty() ? "" : "; ") + std::string("fit did not converge: ") + effect.fit.solver_message;
    }
  }
  set_scores(effect, after, effect.identifiable, r.channels.size());
  return effect;
}

// Runs work(i) for i in [0, n) on `threads` threads; each result goes to its
// own slot, so the outcome does not depend on the schedule. The first
// exception (by index) is rethrown after every thread has joined.
template <typename Work>
void parallel_for(std::size_t n, std::size_t threads, Work work) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<std::size_t> next{0};
  auto worker = [&]() {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        work(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < std::min(threads, n); ++t) {
    pool.emplace_back(worker);
  }
  worker();
  for (std::thread& t : pool) {
    t.join();
  }
  for (const std::exception_ptr& e : errors) {
    if (e) {
      std::rethrow_exception(e);
    }
  }
}

std::size_t thread_count(const DiagnosisSettings& settings) {
  if (settings.threads > 0) {
    return settings.threads;
  }
  return std::max<std::size_t>(1, std::thread::hardware_concurrency());
}

// Stage 3: every candidate, in the model's order. The tasks run in parallel
// are the candidates' starts (fit_start), not whole candidates, so that the
// threads run out of work at most one start fit apart; the thread that
// finishes a candidate's last start refits it on the other folds and scores
// it (assess). Every result has its own slot: the outcome does not depend
// on the schedule.
std::vector<RankedEffect> candidate_stage(const Job& job) {
  const std::vector<Candidate> candidates = job.model.candidates(detail::select(job.result.rows, job.result.train));
  constexpr std::size_t kNoStart = static_cast<std::size_t>(-1);
  std::vector<std::vector<Candidate>> starts(candidates.size());
  std::vector<std::vector<StartFit>> fits(candidates.size());
  std::vector<std::pair<std::size_t, std::size_t>> tasks;  // (candidate, start), kNoStart: nothing to fit
  std::vector<std::atomic<std::size_t>> unfinished(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].identifiable) {
      starts[i] = candidate_starts(job.settings, candidates[i]);
    }
    fits[i].resize(starts[i].size());
    unfinished[i] = starts[i].size();
    for (std::size_t k = 0; k < starts[i].size(); ++k) {
      tasks.emplace_back(i, k);
    }
    if (starts[i].empty()) {
      tasks.emplace_back(i, kNoStart);
    }
  }
  std::vector<RankedEffect> effects(candidates.size());
  std::mutex progress_lock;
  std::size_t done = 0;
  parallel_for(tasks.size(), thread_count(job.settings), [&](std::size_t t) {
    const auto [i, k] = tasks[t];
    if (k != kNoStart) {
      fits[i][k] = fit_start(job, starts[i][k]);
      if (--unfinished[i] > 0) {
        return;
      }
    }
    effects[i] = assess(job, candidates[i], fits[i]);
    const std::lock_guard<std::mutex> lock(progress_lock);
    ++done;
    if (job.settings.progress) {
      job.settings.progress(done, candidates.size());
    }
  });
  return effects;
}

// ---------------------------------------------------------------- ranking

// Identifiable first, by held-out score; then adjacent near-ties (within
// tie_fraction of the base's held-out score) go to the lower BIC.
void rank_effects(std::vector<RankedEffect>& ranking, double tie) {
  std::stable_sort(ranking.begin(), ranking.end(), [](const RankedEffect& a, const RankedEffect& b) {
    if (a.identifiable != b.identifiable) {
      return a.identifiable;
    }
    return a.identifiable && a.heldout_rms_after < b.heldout_rms_after;
  });
  for (std::size_t pass = 0; pass < ranking.size(); ++pass) {
    for (std::size_t i = 0; i + 1 < ranking.size(); ++i) {
      RankedEffect& a = ranking[i];
      RankedEffect& b = ranking[i + 1];
      if (a.identifiable && b.identifiable && std::abs(a.heldout_rms_after - b.heldout_rms_after) <= tie &&
          b.train_bic < a.train_bic) {
        std::swap(a, b);
      }
    }
  }
}

// Families in the order of their best form in the ranking.
std::vector<RankedFamily> rank_families(const std::vector<RankedEffect>& ranking) {
  std::vector<RankedFamily> families;
  for (std::size_t k = 0; k < ranking.size(); ++k) {
    const RankedEffect& e = ranking[k];
    auto it = std::find_if(families.begin(), families.end(), [&](const RankedFamily& f) { return f.family == e.family; });
    if (it == families.end()) {
      RankedFamily f;
      f.family = e.family;
      f.best_effect = e.effect;
      f.best_form = e.form;
      f.best_rank = k;
      f.identifiable = e.identifiable;
      f.heldout_rms_after = e.heldout_rms_after;
      f.shrink_pct = e.shrink_pct;
      f.delta_bic = e.delta_bic;
      families.push_back(f);
      it = families.end() - 1;
    }
    it->forms.push_back({e.effect, e.form, e.identifiable, e.heldout_rms_after, e.shrink_pct, e.note});
  }
  return families;
}

// ---------------------------------------------------------------- verdict

std::string family_label(const RankedFamily& f) {
  return f.best_form.empty() ? f.family : f.family + " (form " + f.best_form + ")";
}

// Families other than the best whose held-out score is within `tie` of it.
std::string tied_families(const std::vector<RankedFamily>& families, double tie) {
  std::string tied;
  for (std::size_t i = 1; i < families.size(); ++i) {
    const RankedFamily& other = families[i];
    if (other.identifiable && std::abs(other.heldout_rms_after - families.front().heldout_rms_after) <= tie) {
      tied += (tied.empty() ? "" : ", ") + family_label(other);
    }
  }
  return tied;
}

struct VerdictInputs {
  double before = 0.0;
  double tie = 0.0;
  double residual_bound = 0.0;  // the held-out RMS the noise allows (DiagnosisResult::residual_bound)
  const RankedFamily* best = nullptr;
  std::string tied;
};

// The mean leverage of the best family's best form over the pooled held-out
// residuals (detail::heldout_leverage on each fold's fit); 0 when there is
// no identifiable family or the model fails on a row.
double best_family_leverage(const Job& job) {
  const DiagnosisResult& r = job.result;
  if (r.families.empty() || !r.families.front().identifiable) {
    return 0.0;
  }
  const RankedEffect& best = r.ranking[r.families.front().best_rank];
  const std::vector<Candidate> candidates = job.model.candidates(detail::select(r.rows, r.train));
  const auto candidate = std::find_if(candidates.begin(), candidates.end(),
                                      [&](const Candidate& c) { return c.name == best.effect; });
  if (candidate == candidates.end() || best.fold_values.size() != r.folds.size()) {
    return 0.0;
  }
  double sum = 0.0;
  std::size_t residuals = 0;
  for (std::size_t f = 0; f < r.folds.size(); ++f) {
    sum += detail::heldout_leverage(request_for(job, &*candidate, r.folds[f], {}, job.fixed), best.fold_values[f]);
    residuals += r.folds[f].heldout.size() * r.channels.size();
  }
  return std::isfinite(sum) && residuals > 0 ? sum / static_cast<double>(residuals) : 0.0;
}

// Upper quantile of F(n, m) at the standard normal quantile z, by Paulson's
// cube-root approximation (z = (a u - b) / sqrt(c u^2 + d), u = F^(1/3),
// solved for u; within 1 % of the exact quantile for n, m >= 10). Infinite
// when m is too small for the approximation to bound it.
double f_quantile(double n, double m, double z) {
  const double c = 2.0 / (9.0 * m);
  const double d = 2.0 / (9.0 * n);
  const double a = 1.0 - c;
  const double b = 1.0 - d;
  const double quadratic = a * a - z * z * c;
  const double discriminant = a * a * b * b - quadratic * (b * b - z * z * d);
  if (quadratic <= 0.0 || discriminant < 0.0) {
    return kInf;
  }
  const double u = (a * b + std::sqrt(discriminant)) / quadratic;
  return u * u * u;
}

// The held-out RMS (noise units) a model that leaves only noise stays below
// but for residual_z's tail: its mean square over the n pooled held-out
// residuals, each divided by an estimated noise, is F(n, m)-distributed,
// with m the noise estimate's degrees of freedom combined over the channels
// (the combined score averages the channels' mean squares: m = C^2 / sum
// 1/m_c), times 1 + the mean leverage (the fitted parameters' own noise,
// carried to the held-out rows: a prediction's variance is sigma^2 (1 + h)).
// Capped at residual_threshold.
double residual_bound(const DiagnosisResult& r, const DiagnosisSettings& s) {
  std::size_t heldout_rows = 0;
  for (const DataSplit& fold : r.folds) {
    heldout_rows += fold.heldout.size();
  }
  const double channels = static_cast<double>(r.noise.size());
  double inverse_dof = 0.0;
  for (const ChannelNoiseEstimate& e : r.noise) {
    inverse_dof += e.dof > 0 ? 1.0 / static_cast<double>(e.dof) : 0.0;
  }
  const double n = static_cast<double>(heldout_rows) * channels;
  const double m = inverse_dof > 0.0 ? channels * channels / inverse_dof : kInf;
  if (!(n > 0.0)) {
    return s.residual_threshold;
  }
  return std::min(s.residual_threshold, std::sqrt((1.0 + r.heldout_leverage) * f_quantile(n, m, s.residual_z)));
}

Verdict choose_verdict(const VerdictInputs& in, const DiagnosisSettings& s) {
  if (in.before < s.gap_threshold) {
    return Verdict::no_gap;
  }
  if (in.before <= s.residual_threshold) {
    return Verdict::weak_gap;
  }
  if (in.best == nullptr || !(in.best->shrink_pct >= s.explain_threshold_pct)) {
    return Verdict::not_explained;
  }
  const bool residual_high = in.best->heldout_rms_after > in.residual_bound;
  if (residual_high && in.best->shrink_pct < s.partial_threshold_pct) {
    return Verdict::not_explained;
  }
  if (!in.tied.empty()) {
    return Verdict::ambiguous;
  }
  return residual_high ? Verdict::partly_explained : Verdict::explained;
}

std::string verdict_text(Verdict v, const VerdictInputs& in, const DiagnosisSettings& s) {
  std::ostringstream os;
  os.precision(3);
  const RankedFamily* b = in.best;
  switch (v) {
    case Verdict::no_gap:
      os << "no significant gap: the base model's held-out RMS is " << in.before << "x the measurement noise (threshold "
         << s.gap_threshold << "x); the ranking below is not evidence";
      break;
    case Verdict::weak_gap:
      os << "weak gap: the base model's held-out RMS is " << in.before << "x the measurement noise, between "
         << s.gap_threshold << "x and " << s.residual_threshold << "x";
      if (b != nullptr) {
        os << "; the best family, " << family_label(*b) << ", takes it to " << b->heldout_rms_after << "x ("
           << b->shrink_pct << " % shrink), which on so small a gap is weak evidence for it";
      }
      break;
    case Verdict::not_explained:
      os << "no candidate family explains the gap: held-out RMS " << in.before << "x noise";
      if (b != nullptr) {
        os << "; the nearest, " << family_label(*b) << ", shrinks it by only " << b->shrink_pct << " % to "
           << b->heldout_rms_after << "x noise (a family is named when it shrinks the gap by "
           << s.explain_threshold_pct << " % to " << in.residual_bound << "x noise, what the noise allows, or by "
           << s.partial_threshold_pct << " % or more): the missing effect is not among the candidates";
      }
      break;
    case Verdict::ambiguous:
      os << family_label(*b) << " and " << in.tied << " explain the held-out gap equally well (" << in.before << " -> "
         << b->heldout_rms_after << "x noise, within " << 100.0 * s.tie_fraction
         << " % of the base's held-out RMS): these data cannot tell the families apart; rows at other loads and "
            "slips, or a base condition (--base), can";
      break;
    case Verdict::partly_explained:
      os << family_label(*b) << " shrinks the held-out gap by " << b->shrink_pct << " % (" << in.before << " -> "
         << b->heldout_rms_after << "x noise) but the rest is more than the noise allows (" << in.residual_bound
         << "x noise on these held-out rows): its form misses part of the effect, or something else is missing too";
      break;
    default:
      os << family_label(*b) << " explains the gap: held-out RMS " << in.before << " -> " << b->heldout_rms_after
         << "x noise (" << b->shrink_pct << " % shrink; the noise allows " << in.residual_bound << "x)";
  }
  return os.str();
}

// Stage 5: the verdict on the families.
void verdict_stage(DiagnosisResult& r, const DiagnosisSettings& s) {
  VerdictInputs in;
  in.before = r.cv_heldout_rms_scaled;
  in.tie = s.tie_fraction * in.before;
  r.residual_bound = residual_bound(r, s);
  in.residual_bound = r.residual_bound;
  if (!r.families.empty() && r.families.front().identifiable) {
    in.best = &r.families.front();
    in.tied = tied_families(r.families, in.tie);
  }
  r.verdict = choose_verdict(in, s);
  r.verdict_text = verdict_text(r.verdict, in, s);
  const RankedEffect* soil = r.references.empty() ? nullptr : &r.references.front();
  if (soil != nullptr && soil->identifiable && r.verdict != Verdict::no_gap) {
    std::ostringstream os;
    os.precision(3);
    os << "; a soil change (the base refitted on this data) reaches " << soil->heldout_rms_after << "x noise ("
       << soil->shrink_pct << " % shrink)";
    if (in.best != nullptr) {
      const double d = soil->heldout_rms_after - in.best->heldout_rms_after;
      os << (std::abs(d) <= in.tie ? ", as well as " : d < 0.0 ? ", better than " : ", worse than ")
         << family_label(*in.best);
    }
    r.verdict_text += os.str();
  }
}

// Stages 3-5 on a result whose base stage is done.
void rank_and_judge(Job& job) {
  DiagnosisResult& r = job.result;
  r.ranking = candidate_stage(job);
  rank_effects(r.ranking, job.settings.tie_fraction * r.cv_heldout_rms_scaled);
  r.families = rank_families(r.ranking);
  r.heldout_leverage = best_family_leverage(job);
  verdict_stage(r, job.settings);
}

DiagnosisResult start_result(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                             const std::string& source, const DiagnosisSettings& settings) {
  DiagnosisResult r;
  r.model = model.name();
  r.source = source;
  r.channels = model.channels();
  r.rows = rows;
  r.settings = settings;
  r.settings.progress = nullptr;
  return r;
}

// The reference pseudo-candidate of the two-condition diagnosis: the base
// parameters refitted on this data (fold by fold, from the base condition's).
RankedEffect soil_change_reference(const Job& job) {
  const DiagnosisResult& r = job.result;
  RankedEffect e;
  e.effect = "base_refit_on_data";
  e.family = "soil_change";
  e.description = "the base model's parameters refitted on this data (the soil, not an effect, changed)";
  e.heldout_rms_before = r.cv_heldout_rms_scaled;
  e.channel_before = r.cv_heldout_rms;
  PooledHeldout after;
  try {
    e.fit = detail::run_fit(request_for(job, nullptr, r.folds.front(), r.base.values, 0));
    after = pooled_heldout(job.model, r.rows, fold_fits(job, nullptr, e.fit, 0), r.folds, r.noise);
    for (std::size_t i = 0; i < e.fit.values.size(); ++i) {
      e.fitted[e.fit.names[i]] = e.fit.values[i];
    }
    e.train_bic = e.fit.bic;
    e.delta_bic = e.fit.bic - r.base.bic;
  } catch (const DiagnosisError& error) {
    e.identifiable = false;
    e.note = error.what();
  }
  set_scores(e, after, e.identifiable, r.channels.size());
  return e;
}

}  // namespace

std::string campaign_suggestion(const std::vector<DiagnosisRow>& rows, std::size_t min_rows) {
  const std::vector<double> loads = distinct_loads(rows);
  std::ostringstream os;
  os.precision(3);
  os << "The data: " << rows.size() << " row(s) at " << loads.size() << " load(s)";
  for (std::size_t i = 0; i < loads.size(); ++i) {
    os << (i == 0 ? " (" : ", ") << loads[i] << " N" << (i + 1 == loads.size() ? ")" : "");
  }
  os << ". To resolve it, ";
  std::vector<double> add;
  if (loads.empty()) {
    os << "measure at least three loads";
  } else if (loads.size() < 3) {
    // Spread the loads over a factor of four (the withheld-effect check spans 12).
    add = loads.size() == 1 ? std::vector<double>{0.5 * loads[0], 2.0 * loads[0]}
                            : std::vector<double>{2.0 * loads.back()};
    os << "add rows at load" << (add.size() > 1 ? "s " : " ");
    for (std::size_t i = 0; i < add.size(); ++i) {
      os << (i > 0 ? " and " : "") << add[i] << " N";
    }
    os << " and ";
  } else {
    os << "add rows at ";
  }
  const std::size_t total_loads = std::max<std::size_t>(loads.size() + add.size(), 1);
  os << "slips 0.05, 0.15, 0.3, 0.45, 0.6 and 0.75 at every load (" << total_loads << " loads x 6 slips = "
     << 6 * total_loads << " rows: a held-out load and cross-validation folds need three loads or more; at one load, "
     << "at least " << min_rows << " slips spread over 0.05..0.75, a quarter of them held out by slip range)";
  return os.str();
}

DiagnosisResult diagnose(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows, const std::string& source,
                         const DiagnosisSettings& settings) {
  DiagnosisResult r = start_result(model, rows, source, settings);
  if (!enough_data(model, r, settings, model.base_parameters(rows).size())) {
    return r;
  }
  Job job{model, settings, r, 0};
  noise_stage(model, r, settings);
  base_stage(job, {});
  rank_and_judge(job);
  return r;
}

DiagnosisResult diagnose_against_base(const DiagnosisModel& model, const BaseCondition& base,
                                      const std::vector<DiagnosisRow>& rows, const std::string& source,
                                      const DiagnosisSettings& settings) {
  DiagnosisResult r = start_result(model, rows, source, settings);
  r.two_condition = true;
  r.base_source = base.source;
  r.base_rows = base.rows.size();
  if (!enough_data(model, r, settings, 0)) {
    return r;
  }
  const std::size_t base_parameters = model.base_parameters(base.rows).size();
  if (base.rows.size() * r.channels.size() < base_parameters + 2) {
    r.folds.clear();
    r.verdict = Verdict::not_enough_data;
    r.verdict_text = "not enough data in the base condition (" + std::to_string(base.rows.size()) + " rows for " +
                     std::to_string(base_parameters) + " base parameters). " +
                     campaign_suggestion(base.rows, settings.min_rows);
    return r;
  }
  // The base condition: every row of it trains, none is held out; its noise
  // is its own.
  DataSplit all;
  for (std::size_t i = 0; i < base.rows.size(); ++i) {
    all.train.push_back(i);
  }
  all.rule = "every row of the base condition";
  const std::vector<ChannelNoiseEstimate> base_noise = estimate_channel_noise(model, base.rows, all, settings);
  r.base_condition_fit = fit_model(model, nullptr, base.rows, all, base_noise, {}, settings);
  Job job{model, settings, r, r.base_condition_fit.values.size()};
  noise_stage(model, r, settings);
  base_stage(job, r.base_condition_fit.values);
  r.references.push_back(soil_change_reference(job));
  rank_and_judge(job);
  return r;
}

}  // namespace ground
}  // namespace sinkwatch
