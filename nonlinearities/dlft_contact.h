#pragma once

#include <memory>
#include <string>

#include "core/linear_model.h"
#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"
#include "nonlinearities/dlft_rows.h"

namespace nfrc {

// Unilateral contact by the dynamic Lagrangian frequency–time method (Vadcard, Batailly &
// Thouverez 2022, Sec. 2.4 and App. A). The unknowns are displacements only. Each
// evaluation predicts the contact force from the condensed linear equations of the
// contact DOF, λ̃_x = −n(Z_r x − F_r)_dof − ε g̃, samples it, keeps it where positive
// (contact) and zeroes it elsewhere (separation), and adds n·λ̃ back. At a solution gap
// and force satisfy the contact law up to O(1/ε) on the samples.
//
// The obstacle is rigid or, with obstacle_stiffness k_obs, a massless spring condensed
// into relative coordinates (the system's unknown at the DOF is then x − x_obs). With
// `other`, the contact is between two model DOFs and the prediction uses half the
// difference of their linear equations, which equals λ at any solution.
class DlftContact : public Nonlinearity {
 public:
  // obstacle_stiffness: N/m, 0 = rigid. epsilon: N/m, 0 = default (DefaultEpsilon).
  DlftContact(ContactGeometry geometry, double obstacle_stiffness, double epsilon);

  std::string type() const override { return "dlft_contact"; }
  std::vector<int> Dofs() const override { return spec_.geometry.Dofs(); }
  std::vector<double> ObstacleCompliance() const override { return spec_.ObstacleCompliance(); }
  // Checks the gap against the harmonic set and resolves the default ε once the system's
  // condensation is known.
  void Bind(const NonlinearityContext& ctx) override {
    spec_.geometry.GapCoefficients(ctx.harmonic_set());
    resolved_epsilon_ = spec_.EpsilonFor(ctx);
  }
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // Hill's method: the ε part of Evaluate's Jacobian, ε·W on the law's DOFs with W = P
  // diag(mask) E; the part through the condensed operator is LinearResidualPart, so that the
  // full-model pencil condenses back to Evaluate's Jacobian (its folds are Hill's +1 crossings).
  void LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                             Eigen::MatrixXd* jacobian,
                             Eigen::MatrixXd* velocity_jacobian) const override;
  // λ̃ = W(−n(A x − b) − ε g): force n·λ̃ on the DOF (−n·λ̃ on the other), rows (A_a − A_b)/2
  // for a pair.
  std::optional<LinearResidualDependence> LinearResidualPart(const NonlinearityContext& ctx,
                                                             const Eigen::VectorXd& y,
                                                             double omega) const override;
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  std::vector<LawSignal> RawSamples(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const override;
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  // The default ε (LagrangianContactSpec::DefaultEpsilon). A smaller ε lets the sampled gap
  // drift from the contact law (2 % on NLvib's two-DOF case at H = 21 with ε = the static
  // 0.5 instead of k_obs = 100).
  double DefaultEpsilon(const NonlinearityContext& ctx) const { return spec_.DefaultEpsilon(ctx); }

  // ε in use (the configured one, or the default once Bind resolved it; 0 before).
  double epsilon() const { return spec_.epsilon > 0.0 ? spec_.epsilon : resolved_epsilon_; }
  // ε for an evaluation in `ctx` (N/m).
  double EpsilonFor(const NonlinearityContext& ctx) const {
    if (spec_.epsilon > 0.0) return spec_.epsilon;
    return resolved_epsilon_ > 0.0 ? resolved_epsilon_ : spec_.EpsilonFor(ctx);
  }
  // For ε-refinement: sets ε (N/m, > 0) for later evaluations.
  void set_epsilon(double epsilon);
  // Gap (m) and contact force before truncation (N) on the N_t samples and the truncated
  // force's coefficients at solution y: the typed form of RawSamples, for comparisons with
  // LCP-HBM on the same samples (ε-refinement) without looking signals up by name.
  ContactState State(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega) const {
    return PredictAt(ctx, y, omega).state;
  }
  const ContactGeometry& geometry() const { return spec_.geometry; }
  double obstacle_stiffness() const { return spec_.obstacle_stiffness; }

 private:
  struct Prediction {
    Eigen::VectorXd gap;   // gap coefficients g̃
    Eigen::VectorXd mask;  // 1 where the sample is in contact (λ_x > 0), else 0
    ContactState state;
  };
  // The condensed linear equations the prediction reads (PredictionRows).
  DlftRows Rows(const NonlinearityContext& ctx, double omega, bool derivative) const {
    return PredictionRows(ctx, omega, spec_.geometry.other >= 0, derivative, "dlft_contact");
  }
  Prediction Predict(const NonlinearityContext& ctx, const Eigen::VectorXd& y, const DlftRows& rows,
                     double epsilon) const;
  // Predict with the rows at ω (for outputs).
  Prediction PredictAt(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                       double omega) const;

  LagrangianContactSpec spec_;
  double resolved_epsilon_ = 0.0;  // N/m, set by Bind when ε is the default
};

}  // namespace nfrc
