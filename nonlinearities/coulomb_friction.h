#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/linear_model.h"
#include "core/nonlinearity.h"
#include "nonlinearities/friction_equality.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

// Coulomb friction under a constant normal load, on a DOF against ground or between two
// DOFs (sliding velocity v = ẋ_dof − ẋ_other), by the equality-based weighted-residual
// formulation (Legrand & Pierre 2024): the friction force r(t) is expanded on the harmonic
// set and its coefficients are this law's own unknowns; its equations are the Galerkin
// projection of Ψ(v(t), r(t)) sampled on N_t points. r acts on `dof` (and −r on `other`),
// so the displacement rows get −r̃ (resp. +r̃). Jacobians are exact on the active branch of
// every sample (semismooth).
class CoulombFriction : public Nonlinearity {
 public:
  // other < 0: against ground. Throws std::invalid_argument for μN < 0 or a parameter of the
  // chosen equality that is not positive.
  CoulombFriction(int dof, int other, FrictionParameters parameters);

  std::string type() const override { return "coulomb_friction"; }
  std::vector<int> Dofs() const override;
  int NumOwnUnknowns(const HarmonicSet& set) const override { return set.NumCoefficients(); }
  // The force enters the equations of motion as −r̃ (+r̃ on `other`): no ∂/∂x there.
  bool WritesDisplacementBlock() const override { return false; }
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  // The Evaluate Jacobian, and the velocity part P diag(Ψ_v) E in the equality's rows.
  void LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                             Eigen::MatrixXd* jacobian,
                             Eigen::MatrixXd* velocity_jacobian) const override;
  // Starts from the sliding force r = −μN sign(v) of the given displacements.
  void InitialOwnUnknowns(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                          Eigen::Ref<Eigen::VectorXd> own) const override;

  // "force" r(t) and "velocity" v(t) on the fine grid.
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  // "stick_phases" and "stick_fraction" (laws with a stick branch; phases shorter than the
  // period of the highest harmonic are ripple and not counted, see CountPhases), and
  // "max_force_ratio" = max|r(t)| / μN.
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  // Stick phases (laws with a stick branch) and their fraction.
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  // Both from one evaluation of the signals.
  LawReport Report(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                   const FourierTransform& fine) const override;

  const FrictionParameters& parameters() const { return parameters_; }
  int dof() const { return dof_; }
  int other() const { return other_; }

  // Sliding-velocity coefficients v = ω D (x_dof − x_other) of a solution y.
  Eigen::VectorXd VelocityCoefficients(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                       double omega) const;

 private:
  // Stick phases of the force r and sliding velocity v samples; nullopt for a law without a
  // stick branch. Phases shorter than the period of the highest harmonic are ripple.
  std::optional<PhaseCount> StickPhases(const NonlinearityContext& ctx, const Eigen::VectorXd& r,
                                        const Eigen::VectorXd& v) const;

  int dof_;
  int other_;
  FrictionParameters parameters_;
};

}  // namespace nfrc
