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
// docs/diagnosis.md gives the method, the split and ranking rules and their
// thresholds. Host only, double precision.
#ifndef SINKWATCH_GROUND_DIAGNOSIS_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_HPP

#include <cstddef>
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
};

struct DiagnosisSettings {
  double tie_fraction = 0.02;           // near-tie: held-out scores within 2 % of the base's
  double explain_threshold_pct = 10.0;  // best shrink below this: nothing explains the gap
  double gap_threshold = 1.5;           // base held-out below 1.5x noise: no significant gap
  double residual_threshold = 2.0;      // best still above 2x noise: only partly explained
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
  std::string verdict;                // "explained", "partly_explained", "not_explained", "no_gap"
  std::string verdict_text;
  std::vector<std::string> notes;
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

/// The whole diagnosis.
[[nodiscard]] DiagnosisResult diagnose(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                                       const std::string& source, const DiagnosisSettings& settings = {});

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_HPP
