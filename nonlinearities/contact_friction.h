#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"
#include "nonlinearities/friction_equality.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

// Unilateral contact with Coulomb friction under the normal force it carries, both by the
// equality-based weighted-residual formulation (Legrand & Pierre 2024's framework, extended to
// combined contact and friction): the normal contact force λ(t) and the friction force r(t)
// are expanded on the harmonic set and their coefficients are this law's own unknowns
// [λ̃ | r̃]. Their equations are the Galerkin projections, on the N_t samples, of
//   Signorini:  min(λ, ρ g) = 0,                     g = g0(θ) − n (x_dof − x_other),
//   Coulomb:    Ψ_minmax(v, r; μ·max(0, λ − ρg)) = 0,  v = ẋ_t − ẋ_t_other,
// so the friction limit follows the contact force and vanishes while the contact is open.
// The limit reads the augmented force λ − ρg (Alart & Curnier's choice), which equals λ
// wherever Signorini holds (λ > 0 ⇒ g = 0; λ = 0 ⇒ g ≥ 0) and switches on the same surface
// λ = ρg as the normal equality: one kink per sample instead of two close ones, which the
// semismooth Newton iteration otherwise cycles between.
// λ acts as ContactGeometry says (+n·λ̃ on the normal DOF's rows), r as CoulombFriction's r
// (−r̃ on the tangent DOF's rows). The normal load is the whole contact force: a preload is a
// static force in the model's forcing (harmonic 0) pressing the DOF onto the obstacle, which λ
// then carries. A flexible obstacle is condensed as for equality_contact (so a preload is
// shared between the obstacle and the structure as the condensation of F says); it carries no
// tangential motion.
class ContactFriction : public Nonlinearity {
 public:
  struct Parameters {
    ContactGeometry geometry;         // the normal gap
    double obstacle_stiffness = 0.0;  // N/m, 0 = rigid
    int tangent_dof = -1;
    int tangent_other = -1;     // −1: sliding against the (fixed) obstacle
    double mu = 0.0;            // friction coefficient
    double rho = 0.0;           // N/m, scales the gap against λ; 0 = default (as equality_contact)
    double friction_rho = 1.0;  // ρ of the min_max friction equality (velocity / force)
  };

  // Throws std::invalid_argument naming the field for a bad value or repeated DOFs.
  explicit ContactFriction(Parameters parameters);

  std::string type() const override { return "contact_friction"; }
  // The normal DOF(s), then the tangent DOF(s).
  std::vector<int> Dofs() const override;
  std::vector<double> ObstacleCompliance() const override;
  // Checks the gap against the harmonic set and resolves the default ρ.
  void Bind(const NonlinearityContext& ctx) override;
  int NumOwnUnknowns(const HarmonicSet& set) const override { return 2 * set.NumCoefficients(); }
  // Both forces enter the equations of motion linearly: no ∂/∂x there.
  bool WritesDisplacementBlock() const override { return false; }
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // The Evaluate Jacobian, and the velocity part P diag(Ψ_v) E in the friction rows.
  void LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                             Eigen::MatrixXd* jacobian,
                             Eigen::MatrixXd* velocity_jacobian) const override;
  // λ from the penalty max(0, −ρg); r sliding at −μλ sign(v).
  void InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                          Eigen::Ref<Eigen::VectorXd> own) const override;

  // "gap", "force" (normal), "friction_force" and "velocity" on the fine grid.
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  // The stick phases (samples in contact on the stick branch; the phase the time-domain law
  // reports), min_gap and min_force.
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  // The contact diagnostics, "stick_phases"/"stick_fraction" (samples in contact on the stick
  // branch), "max_friction_ratio" = max |r| / (μ max λ) on the samples, and "rho".
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  // ρ (N/m) for an evaluation in `ctx`: the configured one or the default.
  double RhoFor(const NonlinearityContext& ctx) const;
  const Parameters& parameters() const { return parameters_; }
  // Index into Dofs() of the tangent DOF.
  int TangentIndex() const { return parameters_.geometry.other >= 0 ? 2 : 1; }
  // Sliding-velocity coefficients ω D (x_t − x_t_other).
  Eigen::VectorXd VelocityCoefficients(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                       double omega) const;

  // The sampled state at y: gap g, normal force λ, friction force r, velocity v and the
  // augmented normal force λ − ρg (N_t samples).
  struct Samples {
    Eigen::VectorXd gap, normal, friction, velocity, augmented;
  };
  Samples Sample(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega) const;

 private:
  // The friction equality at a sample, with the limit μ·max(0, λ − ρg); d_limit is the
  // derivative in λ − ρg.
  FrictionResidual Friction(double velocity, double force, double augmented) const;
  ContactState State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const;
  // Stick phases per period: runs of samples in contact (λ > ρg) on the stick branch, ripple
  // shorter than the highest harmonic's period not counted (CountPhases).
  PhaseCount StickPhases(const NonlinearityContext& ctx, const Samples& s) const;

  Parameters parameters_;
  double resolved_rho_ = 0.0;  // N/m, set by Bind when rho is 0
};

}  // namespace nfrc
