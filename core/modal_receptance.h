#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "core/linear_model.h"

// Internal to core/: condensation through the modes of the whole model, used by Condensation
// for small proportionally damped models.
namespace nfrc::internal {

// With the mass-normalised modes Φ of (K, M) diagonalising C as well (ΦᵀKΦ = diag λ,
// ΦᵀCΦ = diag c), the receptance is H(Ω) = Φ diag(1/d) Φᵀ with d_m = λ_m − Ω² + iΩc_m, and
// the condensed operator is Z_red = H_rr⁻¹, F_red = Z_red (HF)_r. Per harmonic this costs
// n_r²·n products and an n_r × n_r inverse instead of an LU of Z_ll (n_l × n_l) and its
// condition estimate: on the 20-element rod the trace without stability spent 72 % in those.
class ModalReceptance {
 public:
  // Models up to this many DOFs are decomposed (a dense generalised eigenproblem, ~10n³ flop
  // once: 8e7 at 200, against an LU of Z_ll per harmonic and frequency).
  static constexpr int kMaxDofs = 200;

  // The modal form of `model` with `retained` DOFs, or nullptr with the reason in *reason
  // when the model does not qualify: more than kMaxDofs DOFs, M or K not symmetric, M not
  // positive definite, K not positive definite (a rigid-body mode makes H(0) infinite) or C
  // not diagonal in the modes (relative to its largest modal entry).
  static std::unique_ptr<ModalReceptance> Make(const LinearModel& model,
                                               const std::vector<int>& retained,
                                               std::string* reason);

  int num_dofs() const { return static_cast<int>(modes_.rows()); }

  // Φᵀ F of a full complex forcing vector (one entry per DOF): independent of ω.
  Eigen::VectorXcd Project(const Eigen::VectorXcd& forcing) const;

  // Z_red, dZ_red/dω, F_red and dF_red/dω of harmonic k at ω, with modal_forcing = Φᵀ F_k,
  // and the 1/d_m that Recover and Rounding take. False, leaving the outputs unspecified,
  // where the modal form is unusable: a d_m or a pivot of H_rr at the rounding level of its
  // terms (an undamped resonance of the whole model, or Z_ll singular); the direct form
  // decides those. Not thread-safe (work arrays).
  bool Condense(int k, double omega, const Eigen::VectorXcd& modal_forcing,
                Eigen::VectorXcd* inverse, Eigen::MatrixXcd* z, Eigen::MatrixXcd* dz,
                Eigen::VectorXcd* f, Eigen::VectorXcd* df) const;

  // Complex amplitudes of every DOF given the retained DOFs' amplitudes x_r (absolute) and
  // inverse, z, f of Condense: x = H (F − P_rᵀ g) with the interface force
  // g = F_red − Z_red x_r. Into x (resized to num_dofs()); not thread-safe (work arrays).
  void Recover(const Eigen::VectorXcd& inverse, const Eigen::VectorXcd& modal_forcing,
               const Eigen::MatrixXcd& z, const Eigen::VectorXcd& f, const Eigen::VectorXcd& x_r,
               Eigen::VectorXcd* x) const;

  // Entry-wise rounding estimates of z (from Condense, with its inverse) and of f, in
  // Condensation::EstimateRounding's units: the modal sums carry n·eps of the sum of their
  // terms' magnitudes, δH; the inverse turns it into |Z| δH |Z|, and F_red = Z (HF)_r adds
  // |Z| δ(HF)_r.
  void Rounding(const Eigen::VectorXcd& inverse, const Eigen::VectorXcd& modal_forcing,
                const Eigen::MatrixXcd& z, Eigen::MatrixXd* z_rounding,
                Eigen::VectorXd* f_rounding) const;

 private:
  ModalReceptance() = default;
  // 1/d_m with d_m = λ_m − Ω² + iΩc_m at Ω = kω; false if a d_m is at its rounding level.
  bool Inverses(int k, double omega, Eigen::VectorXcd* inverse) const;
  // h = Φ_r diag(weights) Φ_rᵀ (symmetric) and u = Φ_r (weights ⊙ modal_forcing), by loops:
  // n_r is 1–10 and Eigen's expression temporaries cost more than the sums on 2-DOF models.
  void Sum(const Eigen::VectorXcd& weights, Eigen::MatrixXcd* h) const;
  void Respond(const Eigen::VectorXcd& weights, const Eigen::VectorXcd& modal_forcing,
               Eigen::VectorXcd* u) const;

  Eigen::MatrixXd modes_;                 // n × n, columns mass-normalised
  Eigen::MatrixXd retained_modes_;        // n_r × n: the retained DOFs' rows of modes_
  Eigen::MatrixXcd retained_modes_t_;     // n × n_r: its complex transpose, for Recover
  Eigen::VectorXd stiffness_;             // λ_m = ω_m²
  Eigen::VectorXd damping_;               // c_m = φ_mᵀ C φ_m
  double largest_retained_square_ = 0.0;  // max φ_rm², for the pivot floor of H_rr
  // Work arrays of Condense and Recover.
  mutable Eigen::MatrixXcd h_;
  mutable Eigen::VectorXcd rate_, response_, d_response_, interface_, modal_;
};

}  // namespace nfrc::internal
