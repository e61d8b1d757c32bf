// diagnosis.hpp: the sim-to-real gap diagnosis (issue 8). Given a model of the
// soil-bin measurements (the Wong–Reece simulator, or the paper's Eq. 11
// estimation function) and a catalogue of candidate effects the model lacks,
// it answers three questions on rows the fit has not seen:
//
//   WHERE      the base model is fitted to the training rows by nonlinear
//              least squares (Ceres, each residual divided by its row's
//              measurement noise, a floor plus a relative part estimated
//              from the data, so that channels and rows are comparable); its
//              residuals are broken down per channel and per regime (slip,
//              load and sinkage bins), each against the noise;
//   WHICH      for each candidate, base + candidate is refitted to the
//              training rows of each cross-validation fold and its held-out
//              RMS pooled over the folds; candidates are ranked by that,
//              near-ties broken by the training BIC (which charges each extra
//              parameter ln n);
//   HOW FAR    held-out RMS per channel before and after, in the channel's
//              unit and as a percentage, with the candidate's fitted size.
//
// The stages (diagnose()): input sufficiency (not_enough_data with a campaign
// suggestion), noise, base fit, candidates (each fitted on every fold, on all
// cores), ranking (candidates, then families each by its best form) and the
// verdict (an enum, Verdict). With a base condition (diagnose_against_base):
// the base parameters are fitted once on another data set (a smooth wheel, a
// reference simulant) and held fixed; candidates fit their own terms only.
//
// docs/diagnosis.md gives the method, the split and ranking rules and their
// thresholds. Host only, double precision.
#ifndef SINKWATCH_GROUND_DIAGNOSIS_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_HPP

#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis_data.hpp"

namespace sinkwatch {
namespace ground {

class DiagnosisError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ChannelInfo {
  std::string name;  // e.g. "sinkage_m", "traction_coeff"
  std::string unit;  // "m", "N m", "N", "DP/W" (a fraction of the wheel load)
};

/// One fitted parameter with its admissible range.
struct ParameterSpec {
  std::string name;
  double initial = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};

/// A candidate effect: extra parameters on top of the base model.
struct Candidate {
  std::string name;             // unique: "<family>" or "<family>.<form>"
  // The effect family the candidate belongs to (e.g. "grouser") and the
  // literature form of it (e.g. "lug_tip"); several forms of one family
  // compete and the ranking reports families, each by its best form.
  // Empty family: the candidate is a family of its own (family = name).
  std::string family;
  std::string form;
  std::string description;
  std::vector<ParameterSpec> extra;
  double nominal_size = 0.0;    // a typical size of the primary parameter, for scale in reports
  bool identifiable = true;     // false: cannot be fitted on these data (the note says why)
  std::string note;
  double reference = 0.0;       // a constant of the term fixed by the training rows (e.g. W_ref)
};

/// The family a candidate belongs to: its `family`, or its name when empty.
[[nodiscard]] std::string family_of(const Candidate& candidate);

/// A further component of the gap that is not a model effect (e.g. the flight
/// code's fixed-point quantisation), in a channel's unit.
struct GapComponent {
  std::string name;
  std::string channel;
  double rms = 0.0;
  double max_abs = 0.0;
  double over_noise = 0.0;
  std::string note;
};

/// What the diagnosis needs of a model. Parameters are the base ones followed
/// by the candidate's extra ones, in the order the model declares them.
class DiagnosisModel {
 public:
  virtual ~DiagnosisModel() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual std::vector<ChannelInfo> channels() const = 0;
  /// The measured values of the channels for a row.
  [[nodiscard]] virtual std::vector<double> measured(const DiagnosisRow& row) const = 0;
  [[nodiscard]] virtual std::vector<ParameterSpec> base_parameters(const std::vector<DiagnosisRow>& train) const = 0;
  /// Candidates, given the training rows (some are not identifiable on them).
  [[nodiscard]] virtual std::vector<Candidate> candidates(const std::vector<DiagnosisRow>& train) const = 0;
  /// Predicts the channels of `row`; false when the model has no answer there
  /// (e.g. the wheel sinks past its axle). `candidate` is null for the base.
  [[nodiscard]] virtual bool predict(const Candidate* candidate, const std::vector<double>& params,
                                     const DiagnosisRow& row, std::vector<double>& out) const = 0;
  /// predict() for a caller that calls it again and again for the same row
  /// with nearby parameters (a fit): `warm` is the model's scratch for that
  /// row, empty at first and kept by the caller between the calls; a model
  /// may start from it (the simulator from the last sinkage). The answer is
  /// predict()'s to the model's numerical tolerance. The default ignores it.
  [[nodiscard]] virtual bool predict_warm(const Candidate* candidate, const std::vector<double>& params,
                                          const DiagnosisRow& row, std::vector<double>& out,
                                          std::vector<double>& warm) const {
    (void)warm;
    return predict(candidate, params, row, out);
  }
  /// Parts of the gap that are not model effects, computed with the fitted
  /// base parameters; `sigma` is the noise per channel. None by default.
  [[nodiscard]] virtual std::vector<GapComponent> gap_components(const std::vector<DiagnosisRow>& rows,
                                                                 const std::vector<double>& base_params,
                                                                 const std::vector<double>& sigma) const {
    (void)rows;
    (void)base_params;
    (void)sigma;
    return {};
  }
};

/// Per-channel noise used to scale residuals: a row's noise is
/// hypot(floor, relative |measured value|) (estimate_noise); `sigma` is its
/// RMS over the rows, the one number reports show.
struct ChannelNoiseEstimate {
  std::string channel;
  double sigma = 0.0;
  std::string method;  // "replicates", "neighbour_scatter_load", "neighbour_scatter", "fit_residual"
  std::size_t dof = 0;
  double floor = 0.0;
  double relative = 0.0;
};

/// Result of one fit (base or base + candidate).
struct FitResult {
  std::string label;                   // "base" or the candidate's name
  std::vector<std::string> names;      // parameter names
  std::vector<double> values;          // fitted values
  bool converged = false;
  std::string solver_message;
  int iterations = 0;
  std::size_t train_rows = 0;
  double train_chi2 = 0.0;             // sum of squared noise-scaled residuals
  double aic = 0.0;                    // n ln(chi2/n) + 2k, n = rows x channels
  double bic = 0.0;                    // n ln(chi2/n) + k ln n
  std::vector<double> train_rms;       // per channel, channel unit
  std::vector<double> heldout_rms;     // per channel, channel unit (inf if the model failed there)
  double train_rms_scaled = 0.0;       // sqrt(mean over rows and channels of (residual / row noise)^2)
  double heldout_rms_scaled = 0.0;
  std::size_t heldout_failures = 0;    // held-out rows where the model had no answer
  std::vector<std::vector<double>> residuals;  // [row][channel], measured - predicted; NaN if failed
};

/// One bin of the WHERE breakdown.
struct RegimeBin {
  std::string regime;   // "slip", "load", "sinkage"
  std::string label;    // e.g. "0.06-0.22"
  double low = 0.0;
  double high = 0.0;
  std::size_t rows = 0;
  std::size_t heldout_rows = 0;
  std::vector<double> rms;        // per channel
  std::vector<double> mean;       // per channel (bias)
  std::vector<double> rms_over_noise;
};

struct ChannelGap {
  std::string channel;
  std::string unit;
  double noise_sigma = 0.0;
  std::string noise_method;
  double train_rms = 0.0;
  double heldout_rms = 0.0;
  double heldout_bias = 0.0;
  double train_over_noise = 0.0;
  double heldout_over_noise = 0.0;
};

struct WhereBreakdown {
  std::vector<ChannelGap> channels;
  std::vector<RegimeBin> bins;
  std::vector<GapComponent> components;
  std::string largest;  // one sentence: where the gap is largest
};

/// heldout_rms_* and channel_* are pooled over the cross-validation folds
/// (each fold refitted); `fit` is the fit on the first fold, whose values are
/// the reported sizes.
struct RankedEffect {
  std::string effect;
  std::string family;               // family_of(candidate)
  std::string form;                 // the candidate's form ("" for a one-form family)
  std::string description;
  bool identifiable = true;
  std::string note;
  double heldout_rms_before = 0.0;  // noise-scaled, combined over channels
  double heldout_rms_after = 0.0;
  double shrink_pct = 0.0;          // 100 (before - after) / before
  std::vector<double> channel_before;  // per channel, channel unit
  std::vector<double> channel_after;
  std::vector<double> channel_shrink_pct;
  std::map<std::string, double> fitted;  // the candidate's extra parameters
  double nominal_size = 0.0;
  double train_bic = 0.0;
  double delta_bic = 0.0;           // candidate BIC - base BIC (negative: supported)
  FitResult fit;
  std::vector<std::vector<double>> fold_values;  // the parameters fitted on each cross-validation fold
};

/// One form's score within its family (RankedFamily::forms).
struct FormScore {
  std::string effect;               // the candidate's name
  std::string form;
  bool identifiable = true;
  double heldout_rms_after = 0.0;   // noise-scaled, pooled over the folds
  double shrink_pct = 0.0;
  std::string note;
};

/// An effect family, scored by its best form: the identifiable form with the
/// lowest pooled held-out RMS (the ranking's order, near-ties by BIC).
struct RankedFamily {
  std::string family;
  std::string best_effect;          // candidate name of the best form
  std::string best_form;
  std::size_t best_rank = 0;        // index of the best form in DiagnosisResult::ranking
  bool identifiable = true;         // some form could be fitted
  double heldout_rms_after = 0.0;
  double shrink_pct = 0.0;
  double delta_bic = 0.0;
  std::vector<FormScore> forms;     // every form, best first
};

/// The outcome of the diagnosis (docs/diagnosis.md, "Verdicts").
enum class Verdict {
  no_gap,            // base held-out RMS below gap_threshold x noise
  weak_gap,          // between gap_threshold and residual_threshold x noise
  explained,         // the best family leaves a held-out residual the noise allows (residual_bound)
  partly_explained,  // the best family takes at least partial_threshold_pct of it, the rest stays above
  ambiguous,         // two or more families tie on held-out rows: the data cannot tell them apart
  not_explained,     // no family shrinks the gap enough (explain / partial thresholds)
  not_enough_data,   // too few rows to fit and hold out: verdict_text suggests rows to add
};

/// The verdict's name in reports and JSON ("no_gap", "explained", ...).
[[nodiscard]] const char* verdict_name(Verdict verdict);

/// A setting of the run the caller describes for the report (e.g. gravity,
/// soil preset), as text.
struct NamedSetting {
  std::string name;
  std::string value;
};

/// Progress of the candidate stage: called with (fits done, fits in all)
/// after every candidate, from the worker threads under one lock.
using DiagnosisProgress = std::function<void(std::size_t done, std::size_t total)>;

struct DiagnosisSettings {
  double tie_fraction = 0.02;           // near-tie: held-out scores within 2 % of the base's
  double explain_threshold_pct = 10.0;  // best shrink below this: nothing explains the gap
  double gap_threshold = 1.5;           // base held-out below 1.5x noise: no significant gap
  double residual_threshold = 2.0;      // best still above 2x noise: only partly explained
  // The best family's held-out residual is noise when its mean square is
  // below the upper quantile of F(n, m) at this standard normal quantile
  // (n held-out residuals, m the noise estimate's degrees of freedom): 2.326,
  // one-sided 1 %. Above it (or above residual_threshold) the residual is
  // significant and the verdict is not `explained`.
  double residual_z = 2.326;
  int max_iterations = 100;
  // Score the ranking by cross-validation over the folds of
  // cross_validation_folds (several loads: the highest and the lowest held
  // out in turn); false: the first split only (faster, noisier).
  bool cross_validate = true;
  // With three or more loads: hold out every load in turn, not only the two
  // extreme ones (cross_validation_folds).
  bool every_load_fold = false;
  // Starts of each candidate fit: its terms at these multiples of their
  // initial value (the Wong–Reece candidates start at half their documented
  // default size, so 1 and 4 mean half and twice that size).
  std::vector<double> start_multiples{1.0, 4.0};
  // With the best family's residual above residual_threshold: it is named
  // (partly_explained) only when it takes at least this share of the gap;
  // below, the verdict is not_explained (no family describes the gap).
  double partial_threshold_pct = 50.0;
  // Fewer rows than this: not_enough_data (a campaign suggestion, no fit).
  std::size_t min_rows = 8;
  // Ceres stopping rules of every fit.
  double function_tolerance = 1e-10;
  double parameter_tolerance = 1e-10;
  // Threads of the candidate stage; 0: std::thread::hardware_concurrency().
  // The results do not depend on it (each candidate is fitted alone and
  // written to its own slot).
  std::size_t threads = 0;
  DiagnosisProgress progress;
  // Settings of the caller, stated in the report (gravity, soil preset, ...).
  std::vector<NamedSetting> inputs;
};

/// The base condition of a two-condition diagnosis (diagnose_against_base).
struct BaseCondition {
  std::vector<DiagnosisRow> rows;
  std::string source;
};

struct DiagnosisResult {
  std::string model;
  std::string source;
  std::vector<ChannelInfo> channels;
  std::string split_rule;
  std::vector<std::size_t> train;
  std::vector<std::size_t> heldout;
  // Cross-validation folds of the ranking; folds[0] is the split above
  // (train, heldout), on which WHERE, base and each effect's `fit` are shown.
  std::vector<DataSplit> folds;
  std::string cv_rule;
  // The base model's held-out RMS pooled over all folds (per channel, channel
  // unit; and noise-scaled, combined): the "before" of the ranking.
  std::vector<double> cv_heldout_rms;
  double cv_heldout_rms_scaled = 0.0;
  std::vector<DiagnosisRow> rows;
  std::vector<ChannelNoiseEstimate> noise;
  std::vector<std::vector<double>> row_noise;  // [row][channel]: the noise each residual is divided by
  FitResult base;
  WhereBreakdown where;
  std::vector<RankedEffect> ranking;  // best first; non-identifiable ones last
  std::vector<RankedFamily> families; // best first, each by its best form
  // The best family's extrapolation: the mean leverage of its fits over the
  // pooled held-out residuals (a model that leaves only noise has an expected
  // held-out mean square of 1 + this; docs/diagnosis.md, "Verdicts").
  double heldout_leverage = 0.0;
  // The largest held-out RMS (noise units) the noise allows the best family:
  // min(residual_threshold, sqrt((1 + heldout_leverage) x F(n, m)'s quantile
  // at residual_z)).
  double residual_bound = 0.0;
  Verdict verdict = Verdict::not_enough_data;
  std::string verdict_text;
  std::vector<std::string> notes;
  DiagnosisSettings settings;         // as used (progress not shown)
  // Two-condition diagnosis: the base condition's data, the base fitted on all
  // of its rows (then held fixed), and the reference pseudo-candidate
  // "base_refit_on_data" (the base parameters refitted on this data: a soil
  // change) scored like a candidate. Empty / false otherwise.
  bool two_condition = false;
  std::string base_source;
  std::size_t base_rows = 0;
  FitResult base_condition_fit;
  std::vector<RankedEffect> references;
};

/// Estimates the noise of each channel (model-free when possible, else from a
/// preliminary fit's training residual).
[[nodiscard]] std::vector<ChannelNoiseEstimate> estimate_channel_noise(
    const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows, const DataSplit& split,
    const DiagnosisSettings& settings);

/// Fits base (+ candidate) to the training rows and evaluates every row.
[[nodiscard]] FitResult fit_model(const DiagnosisModel& model, const Candidate* candidate,
                                  const std::vector<DiagnosisRow>& rows, const DataSplit& split,
                                  const std::vector<ChannelNoiseEstimate>& noise,
                                  const std::vector<double>& initial_base, const DiagnosisSettings& settings);

/// Residuals of fixed parameters on every row (no fit): used for the "true"
/// model in the withheld-effect check.
[[nodiscard]] FitResult evaluate_model(const DiagnosisModel& model, const Candidate* candidate,
                                       const std::vector<double>& params, const std::vector<DiagnosisRow>& rows,
                                       const DataSplit& split, const std::vector<ChannelNoiseEstimate>& noise);

/// Held-out residuals of per-fold fits pooled over the folds: RMS per channel
/// (channel unit; inf when the model failed on a held-out row) and the
/// noise-scaled combination. fits[f] must be a fit on folds[f].
struct PooledHeldout {
  std::vector<double> rms;
  double scaled = 0.0;
};
[[nodiscard]] PooledHeldout pooled_heldout(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                                           const std::vector<FitResult>& fits, const std::vector<DataSplit>& folds,
                                           const std::vector<ChannelNoiseEstimate>& noise);

/// The whole diagnosis. Too few rows give Verdict::not_enough_data (no
/// exception): verdict_text says which loads and slips to add.
[[nodiscard]] DiagnosisResult diagnose(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                                       const std::string& source, const DiagnosisSettings& settings = {});

/// Two-condition diagnosis: the base parameters are fitted on every row of
/// `base` and held fixed; the gap is that base model on the held-out rows of
/// `rows`; each candidate fits only its own terms on the training rows of
/// each fold. `references` holds "base_refit_on_data".
[[nodiscard]] DiagnosisResult diagnose_against_base(const DiagnosisModel& model, const BaseCondition& base,
                                                    const std::vector<DiagnosisRow>& rows, const std::string& source,
                                                    const DiagnosisSettings& settings = {});

/// The campaign suggestion of not_enough_data: which loads and slips to add.
[[nodiscard]] std::string campaign_suggestion(const std::vector<DiagnosisRow>& rows, std::size_t min_rows);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_HPP
