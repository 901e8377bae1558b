#pragma once

#include <string>
#include <vector>

#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"

namespace nfrc {

// Unilateral contact by the equality-based weighted-residual formulation, the contact twin of
// CoulombFriction (Legrand & Pierre 2024's framework applied to Signorini's conditions): the
// contact force λ(t) is expanded on the harmonic set and its coefficients are this law's own
// unknowns; its equations are the Galerkin projection of
//   Φ(g, λ) = λ − max(0, λ − ρ g) = min(λ, ρ g),
// whose zero set is exactly g ≥ 0, λ ≥ 0, g·λ = 0, sampled on the N_t points (oversampling
// allowed, no square-grid restriction, no ε). ρ (N/m) only scales the gap against the force;
// the solutions do not depend on it. λ acts as +n·λ on `dof` and −n·λ on `other`, linearly,
// so the law writes no ∂f/∂x block. The projection enforces Φ = 0 in the weighted mean of
// each harmonic, not sample by sample: between (and on) samples the gap and force satisfy
// the law up to the truncation of λ's series.
//
// A flexible obstacle (obstacle_stiffness) is condensed into relative coordinates, as for
// DLFT: the gap is then measured to the obstacle's surface.
class EqualityContact : public Nonlinearity {
 public:
  // obstacle_stiffness: N/m, 0 = rigid. rho: N/m, 0 = default (the obstacle stiffness, else
  // the static condensed stiffness at the contact, as DLFT's default ε).
  EqualityContact(ContactGeometry geometry, double obstacle_stiffness, double rho);

  std::string type() const override { return "equality_contact"; }
  std::vector<int> Dofs() const override { return spec_.geometry.Dofs(); }
  std::vector<double> ObstacleCompliance() const override { return spec_.ObstacleCompliance(); }
  // Checks the gap against the harmonic set and resolves the default ρ.
  void Bind(const NonlinearityContext& ctx) override;
  int NumOwnUnknowns(const HarmonicSet& set) const override { return set.NumCoefficients(); }
  // The force enters the equations of motion as ±n·λ̃: no ∂/∂x there.
  bool WritesDisplacementBlock() const override { return false; }
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // Starts from the penalty force max(0, −ρ g) of the given displacements.
  void InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                          Eigen::Ref<Eigen::VectorXd> own) const override;

  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  // On the N_t samples: "gap", "force_raw" (λ where the active branch is contact, λ > ρg,
  // else 0) and "force" (λ).
  std::vector<LawSignal> RawSamples(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  // The contact diagnostics (ContactDiagnostics) and "rho".
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  // The gap and force on the N_t samples at y (force_raw as in RawSamples).
  ContactState State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const;
  // ρ in use (N/m): the configured one, or the default once Bind resolved it (0 before).
  double rho() const { return rho_ > 0.0 ? rho_ : resolved_rho_; }
  // ρ for an evaluation in `ctx` (N/m): rho(), or the default computed from ctx.
  double RhoFor(const NonlinearityContext& ctx) const {
    return rho() > 0.0 ? rho() : spec_.DefaultEpsilon(ctx);
  }
  const ContactGeometry& geometry() const { return spec_.geometry; }

 private:
  // The geometry and obstacle as the DLFT spec holds them (epsilon unused).
  LagrangianContactSpec spec_;
  double rho_;                 // N/m, 0 = default
  double resolved_rho_ = 0.0;  // N/m, set by Bind
};

}  // namespace nfrc
