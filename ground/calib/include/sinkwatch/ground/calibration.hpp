// calibration.hpp: least-squares calibration of the corrected sinkage
// estimation function, the paper's Eq. 11,
//
//     DP/W = C1 * T/(rW) - C2 * z/r - C3,
//
// from soil-bin data, as in its Eq. 12/13: one row [T/(rW), -z/r, -1] of A and
// one entry DP/W of B per run, C minimising |A C - B|. The paper writes the
// solution through the normal equations C = (A'A)^-1 A'B; this code solves the
// same problem by an SVD of A, which works on A itself instead of A'A and so
// loses half as many digits to ill-conditioning (cond(A'A) = cond(A)^2). The
// normal-equation solution is computed as well and reported beside it.
//
// Any subset of C1..C3 can be held fixed (the paper's Table 2 fixes C1 = C2 = 1
// and fits C3 alone); the fixed terms move to the right-hand side.
//
// Host only, double precision. Bad input (too few rows, collinear columns)
// throws CalibrationError.
#ifndef SINKWATCH_GROUND_CALIBRATION_HPP
#define SINKWATCH_GROUND_CALIBRATION_HPP

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sinkwatch/ground/soil_bin_csv.hpp"

namespace sinkwatch {
namespace ground {

class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Index of C1, C2, C3 in the arrays below.
inline constexpr std::size_t kCoefficientCount = 3;
using Coefficients = std::array<double, kCoefficientCount>;

/// Coefficients held at a given value instead of fitted (--fix c1=1,c2=1).
struct FixedCoefficients {
  std::array<std::optional<double>, kCoefficientCount> value;

  [[nodiscard]] std::size_t free_count() const noexcept;
};

/// Parses "c1=1,c2=1" (keys c1, c2, c3, case-insensitive; finite values).
/// An empty string fixes nothing. Throws std::invalid_argument with the reason.
[[nodiscard]] FixedCoefficients parse_fixed_coefficients(const std::string& spec);

/// One soil-bin run in the dimensionless quantities of Eq. 11.
struct Observation {
  std::size_t line = 0;  // line in the source file
  double slip = 0.0;
  double drive_coeff = 0.0;     // T/(rW)
  double sinkage_ratio = 0.0;   // z/r
  double traction_coeff = 0.0;  // DP/W, the measured left-hand side
};

[[nodiscard]] std::vector<Observation> observations_of(const SoilBinDataset& dataset);

/// Eq. 11's right-hand side: the predicted DP/W.
[[nodiscard]] double predicted_traction(const Coefficients& c, const Observation& o) noexcept;

/// Root mean square of measured minus predicted DP/W for given coefficients.
[[nodiscard]] double residual_rms(const std::vector<Observation>& data, const Coefficients& c);

struct Residual {
  std::size_t line = 0;
  double slip = 0.0;
  double measured = 0.0;      // DP/W
  double fitted = 0.0;        // Eq. 11 with the fitted C
  double residual = 0.0;      // measured - fitted
  // measured - prediction of a fit without this row, e_i / (1 - h_ii); NaN
  // for a row of leverage h_ii = 1 (not cross-validated: see loo_undefined).
  double loo_residual = 0.0;
};

struct CalibrationFit {
  Coefficients c{};                        // fitted or fixed
  std::array<bool, kCoefficientCount> free{};
  std::size_t rows = 0;
  std::size_t free_count = 0;
  std::size_t dof = 0;                     // rows - free_count
  // For free coefficients; NaN for fixed ones.
  Coefficients std_err{};
  Coefficients ci_low{};                   // 95 % two-sided, Student t with dof
  Coefficients ci_high{};
  double t_quantile = 0.0;                 // t_{0.975, dof}; NaN when nothing is free
  std::array<Coefficients, kCoefficientCount> correlation{};  // NaN where fixed
  // 2-norm condition number of the matrix actually solved (free columns of
  // A), and of the same columns scaled to unit length, which measures
  // collinearity alone, independent of the columns' units. NaN if none free.
  double condition_number = 0.0;
  double condition_number_scaled = 0.0;
  double rms = 0.0;                        // sqrt(SSR / rows)
  double residual_std = 0.0;               // sqrt(SSR / dof), the sigma behind std_err
  // Leave-one-out RMS over all rows, from the closed form e_i / (1 - h_ii)
  // with the leverages h_ii of the SVD (linear in rows, no refits). A row of
  // leverage 1 (1 - h_ii <= 16 max(rows, free_count) eps) is the only one
  // fixing some combination of the free coefficients: without it the fit is
  // singular, so it has no leave-one-out prediction. Such rows are counted in
  // loo_undefined, their loo_residual is NaN, and loo_rms is then NaN too.
  double loo_rms = 0.0;
  std::size_t loo_undefined = 0;           // rows not cross-validated (leverage 1)
  // The paper's route, (A'A)^-1 A'B, on the same problem.
  Coefficients normal_equations_c{};
  double normal_equations_max_diff = 0.0;  // max |C_normal - C_svd| over free coefficients
  std::vector<Residual> residuals;         // sorted by slip
};

/// Fits Eq. 11 to the data with the given coefficients held fixed.
/// Needs rows > number of free coefficients (at least one degree of freedom
/// for the standard errors) and full column rank.
[[nodiscard]] CalibrationFit fit_sinkage_function(const std::vector<Observation>& data,
                                                  const FixedCoefficients& fixed = {});

/// One row of the C(W) table: a fit of the runs at one load.
struct LoadFit {
  double load_n = 0.0;
  CalibrationFit fit;
};

/// Groups the rows by load_N (rows whose loads agree to 1e-9 relative form a
/// group) and fits each group; sorted by load. Needs a load_N column.
[[nodiscard]] std::vector<LoadFit> fit_per_load(const SoilBinDataset& dataset,
                                                const FixedCoefficients& fixed = {});

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_CALIBRATION_HPP
