// diagnosis_models.hpp: the two models the diagnosis can take as its base.
//
// EstimatorModel: the paper's corrected sinkage estimation function, Eq. 11,
//     DP/W = C1 T/(rW) - C2 z/r - C3,
// one channel (the traction coefficient DP/W; an error in it is an error of
// C2 z/r, i.e. of the sinkage the flight code infers). Candidate terms that fit
// that form (docs/diagnosis.md derives each):
//   entry_angle_geometry  - C4 arccos(1 - z/r): the exact entry angle, which
//                         Eq. 9 -> 10 replaced by a term linear in z/r;
//   load_offset           - C5 (W/W_ref - 1): C3 varying with the load
//                         (Table 2 shows C3 falling from 0.20 to 0.13);
//   slip_shear            - C6 exp(-s/s0): shear still developing at low slip
//                         (Janosi–Hanamoto, j grows with s);
//   bulldozing_z2         - C7 (z/r)^2: frontal bulldozing ~ z^2 (Bekker/Wong).
// Its gap components include the flight code's fixed-point quantisation: the
// flight functions (flight/estimator.hpp) against Eq. 11 in double on the same
// rows with the same coefficients.
//
// WongReeceModel: the reference simulator (ground/sim, Wong–Reece with
// Bekker and Janosi–Hanamoto), three channels sinkage_m, torque_nm,
// drawbar_pull_n. Base: the simulator with every effect off and the soil
// parameters kphi, n, c, phi, K free (default_base_parameters()). Candidates: each form
// of each effect of the simulator's catalogue (effect_forms: one candidate
// "<family>.<form>" per form, or "<family>" for an effect with one form), with
// the form's primary parameter free and its other parameters at the
// simulator's documented defaults (a reduced parameter set).
#ifndef SINKWATCH_GROUND_DIAGNOSIS_MODELS_HPP
#define SINKWATCH_GROUND_DIAGNOSIS_MODELS_HPP

#include <string>
#include <vector>

#include "sinkwatch/ground/diagnosis.hpp"
#include "sinkwatch/ground/wheel_soil_model.hpp"

namespace sinkwatch {
namespace ground {

class EstimatorModel final : public DiagnosisModel {
 public:
  [[nodiscard]] std::string name() const override { return "estimator"; }
  [[nodiscard]] std::vector<ChannelInfo> channels() const override;
  [[nodiscard]] std::vector<double> measured(const DiagnosisRow& row) const override;
  [[nodiscard]] std::vector<ParameterSpec> base_parameters(const std::vector<DiagnosisRow>& train) const override;
  [[nodiscard]] std::vector<Candidate> candidates(const std::vector<DiagnosisRow>& train) const override;
  [[nodiscard]] bool predict(const Candidate* candidate, const std::vector<double>& params, const DiagnosisRow& row,
                             std::vector<double>& out) const override;
  [[nodiscard]] std::vector<GapComponent> gap_components(const std::vector<DiagnosisRow>& rows,
                                                         const std::vector<double>& base_params,
                                                         const std::vector<double>& sigma) const override;
};

class WongReeceModel final : public DiagnosisModel {
 public:
  /// `start`: the simulator parameters the fit starts from (soil preset,
  /// gravity); every effect in it is switched off for the base.
  /// `base_names`: the base parameters to fit (default_base_parameters()).
  explicit WongReeceModel(SimParameters start, std::vector<std::string> base_names = default_base_parameters());

  /// The soil parameters of the simulator's suggested_base_fit_parameters()
  /// without model.a0 (theta_m = a0 theta1): a0 is a constant of the
  /// Wong–Reece stress profile, not a soil property, and left free it trades
  /// off against the candidates (stress_peak_shift, bulldozing,
  /// drive_friction) so that the fit picks a wrong combination on training
  /// rows (docs/diagnosis.md, "Base parameters").
  [[nodiscard]] static std::vector<std::string> default_base_parameters();

  [[nodiscard]] std::string name() const override { return "wong-reece"; }
  [[nodiscard]] std::vector<ChannelInfo> channels() const override;
  [[nodiscard]] std::vector<double> measured(const DiagnosisRow& row) const override;
  [[nodiscard]] std::vector<ParameterSpec> base_parameters(const std::vector<DiagnosisRow>& train) const override;
  [[nodiscard]] std::vector<Candidate> candidates(const std::vector<DiagnosisRow>& train) const override;
  [[nodiscard]] bool predict(const Candidate* candidate, const std::vector<double>& params, const DiagnosisRow& row,
                             std::vector<double>& out) const override;
  /// `warm` holds the row's last sinkage and log-log slope: the sinkage
  /// search starts there (evaluate() with a SinkageHint).
  [[nodiscard]] bool predict_warm(const Candidate* candidate, const std::vector<double>& params,
                                  const DiagnosisRow& row, std::vector<double>& out,
                                  std::vector<double>& warm) const override;

  /// The candidate of one effect form, as candidates() builds it; without a
  /// form, the effect's default form.
  [[nodiscard]] Candidate candidate_for(Effect effect) const;
  [[nodiscard]] Candidate candidate_for(Effect effect, const std::string& form) const;

  /// The same model without the named candidates (e.g. "grouser.lug_tip"):
  /// the cross-form check holds out the form that made the data.
  [[nodiscard]] WongReeceModel excluding(std::vector<std::string> candidate_names) const;

 private:
  SimParameters start_;
  std::vector<std::string> base_names_;
  std::vector<std::string> excluded_;
};

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_DIAGNOSIS_MODELS_HPP
