#pragma once

#include <string>
#include <vector>

#include "core/nonlinearity.h"
#include "nonlinearities/dlft_rows.h"
#include "nonlinearities/return_mapping.h"

namespace nfrc {

// Coulomb friction (one tangential direction, constant normal load) by the dynamic
// Lagrangian frequency–time method (Nacivet, Pierre, Thouverez & Jézéquel 2003), the
// classical cross-check of the equality-based law. The unknowns are displacements only.
// Each evaluation predicts the force from the condensed linear equations of the friction
// DOF, λ_u = −(Z x − F)_dof (half the difference of the two DOFs' rows for a pair), and
// corrects it sample by sample with the penalty-like weight ε: stick is predicted as
// λ_j = λ_u,j + ε(u_j − w_{j−1}) (u the relative displacement, w the contact point), slip
// where |λ_j| > μN clamps it to ±μN and moves w. This is the return mapping of a spring ε in
// series with a slider μN driven by z = u + λ_u/ε (two passes for a periodic state). λ acts
// as +λ on `dof` and −λ on `other`: the friction force on `dof` is r = −λ. At a solution
// λ = λ_u and u = w: Coulomb's law holds up to the truncation of λ's series. The residual
// maps the band-limited z(θ) with its switches resolved between the samples and λ projected
// exactly (ResolveReturnMapping): sampled, each sample switching is a kink of size ~2ε/N_t in
// the Jacobian, and ε of the order of the condensed stiffness of the top harmonics (needed for
// accuracy: ε ≳ (Hω)²m) stalled Newton and the arclength steps at N_φ = 60. Samples, phases
// and diagnostics come from the sampled return mapping on the N_t samples.
//
// Hill's method: the force's dependence on the linear residual is LinearResidualPart and the
// rest is LinearizeForStability's; the stick pieces' memory (the anchor's Floquet factor, as
// for the Jenkins element, on z) is Memory's.
class DlftFriction : public Nonlinearity {
 public:
  // limit: μN (N) ≥ 0; epsilon: N/m, > 0 (the spec resolves its default). other < 0: ground.
  DlftFriction(int dof, int other, double limit, double epsilon);

  std::string type() const override { return "dlft_friction"; }
  std::vector<int> Dofs() const override;
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // The ∂/∂x part through u (P J E on the relative coefficients).
  void LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                             Eigen::MatrixXd* jacobian,
                             Eigen::MatrixXd* velocity_jacobian) const override;
  // The stick pieces of z's return mapping, stiffness ε, on z = u − (A x − b)/ε.
  std::optional<LinearizationMemory> Memory(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega) const override;
  // The part through λ_u: W = P J E / ε on −(A x − b) of the DOF (or the pair's half rows).
  std::optional<LinearResidualDependence> LinearResidualPart(const NonlinearityContext& ctx,
                                                             const Eigen::VectorXd& y,
                                                             double omega) const override;
  // "force" r = −λ (on `dof`, the convention of coulomb_friction) and "velocity" v on the fine
  // grid (λ's truncated series).
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  // On the N_t samples: "force_raw" (−λ before truncation), "force" (after) and "slip" (1 on
  // slip samples).
  std::vector<LawSignal> RawSamples(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  // "stick_phases", "stick_fraction", "max_force_ratio" (max |λ| on the samples / μN) and
  // "epsilon".
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  // The return mapping's input z = u + λ_u/ε on the N_t samples (m), for tests and outputs.
  Eigen::VectorXd Input(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                        double omega) const;

  double epsilon() const { return epsilon_; }
  double limit() const { return limit_; }

 private:
  struct Prediction {
    DlftRows rows;          // A, b of λ_u = −(A x − b)
    Eigen::VectorXd input;  // z on the samples (sampled)
    SlipHistory history;    // the sampled return mapping of z (sampled)
    ResolvedSlip resolved;  // the return mapping of z(θ) with its switches resolved (resolve)
  };
  // With `resolve` the residual's return mapping (and its Jacobian if `with_jacobian`), else
  // the sampled one.
  Prediction Predict(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                     bool resolve, bool with_jacobian = true) const;

  int dof_;
  int other_;
  double limit_;    // μN, N
  double epsilon_;  // N/m
};

}  // namespace nfrc
