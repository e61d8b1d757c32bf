// diagnosis_internal.hpp: what the stages of the diagnosis (diagnosis.cpp)
// share with the fitting code (diagnosis_fit.cpp): the per-row noise, the
// noise-scaled RMS, and one fit request (base + candidate, some leading
// parameters optionally held fixed). Not installed; host only.
#ifndef SINKWATCH_GROUND_DIAGNOSIS_INTERNAL_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_INTERNAL_HPP

#include <cstddef>
#include <limits>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"

namespace sinkwatch {
namespace ground {
namespace detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The noise of every row and channel, [row][channel].
using RowNoise = std::vector<std::vector<double>>;

/// hypot(floor, relative |measured|) per row and channel, never below 5 % of
/// the channel's RMS noise.
[[nodiscard]] RowNoise row_noise(const DiagnosisModel& model, const std::vector<DiagnosisRow>& rows,
                                 const std::vector<ChannelNoiseEstimate>& noise);

/// RMS over `idx` of residual / row noise per channel (inf when the model
/// failed on one of the rows).
[[nodiscard]] std::vector<double> scaled_rms(const std::vector<std::vector<double>>& residuals,
                                             const std::vector<std::size_t>& idx, const RowNoise& noise);

/// sqrt(mean of squares) over the channels.
[[nodiscard]] double combined(const std::vector<double>& scaled);

[[nodiscard]] std::vector<DiagnosisRow> select(const std::vector<DiagnosisRow>& rows,
                                               const std::vector<std::size_t>& idx);

/// One fit: base (+ candidate) on split.train, every row evaluated. The first
/// `fixed` parameters (the base ones in a two-condition diagnosis) are held
/// at initial_base; with every parameter fixed nothing is fitted.
struct FitRequest {
  const DiagnosisModel* model = nullptr;
  const Candidate* candidate = nullptr;
  const std::vector<DiagnosisRow>* rows = nullptr;
  const DataSplit* split = nullptr;
  const std::vector<ChannelNoiseEstimate>* noise = nullptr;
  std::vector<double> initial_base;
  std::size_t fixed = 0;
  const DiagnosisSettings* settings = nullptr;
};

[[nodiscard]] FitResult run_fit(const FitRequest& request);

/// The fit's extrapolation to the held-out rows: the sum over the held-out
/// residuals (rows x channels, noise-scaled) of their leverage
/// g' (J' J)^-1 g, J the training rows' Jacobian in the free parameters
/// (past `fixed`, off their bounds) and g the held-out entry's gradient, at
/// `values`. A model that leaves only noise has an expected held-out mean
/// square of 1 + this sum / n (n held-out residuals). NaN when the model
/// fails on a row.
[[nodiscard]] double heldout_leverage(const FitRequest& request, const std::vector<double>& values);

}  // namespace detail
}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_INTERNAL_HPP
