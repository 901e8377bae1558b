#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/nonlinearity.h"
#include "nonlinearities/return_mapping.h"

namespace nfrc {

// The Jenkins element (elastic dry friction): a tangential spring k_t in series with a
// Coulomb slider of limit μN, on u = x_dof − x_other (or x_dof against ground). Its force
// f = k_t(u − w), w the slider's position, acts as +f on `dof` and −f on `other`, like a
// spring k_t·u. The law is hysteretic: the residual is the slider's return mapping on the
// band-limited u(θ) with its stick/slip switches located between the N_t samples and the
// force projected exactly (ResolveReturnMapping: the N_t → ∞ limit of alternating
// frequency–time, without a kink per sample switch, which at k_t ≳ 0.05 N_t stalled Newton).
// With no slip at all the slider rests where the sampled law's passes from w = 0 leave it
// (the origin for a small u), and the element is the linear spring k_t; as k_t → ∞ it tends
// to Coulomb's law. Time signals and diagnostics come from the sampled return mapping
// (ReturnMapping, two passes) on their fine grid.
//
// Jacobian: on a stick phase f(θ) = f_a + k_t(u(θ) − u(θ_a)), θ_a the turning point of u
// where the last slip ended (f_a = ±μN); on a slip phase f = ±μN. It is exact (continuous
// across the switches). The law is rate independent: ∂/∂ω = 0.
//
// Hill's method sees the same Jacobian (no velocity dependence) and the memory of the stick
// phases: the exact linearisation of a stick phase, δf(t) = k_t(δu(t) − δu(t_a)), carries the
// Floquet factor e^{−s(t−t_a)} on the anchor's term (Memory), which Hill's method restores.
class Jenkins : public Nonlinearity {
 public:
  // stiffness: k_t (N/m), > 0; limit: μN (N), ≥ 0; other < 0: against ground. Throws
  // std::invalid_argument naming the field.
  Jenkins(int dof, int other, double stiffness, double limit);

  std::string type() const override { return "jenkins"; }
  std::vector<int> Dofs() const override;
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;

  // The resolved stick pieces with their anchors, stiffness k_t, on u = x_dof − x_other.
  std::optional<LinearizationMemory> Memory(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega) const override;

  // "force" f(t), "displacement" u(t) and "slider" w(t) on the fine grid (the return mapping
  // run on that grid).
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  // "stick_phases", "stick_fraction" and "max_force_ratio" = max|f| / μN.
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;

  // The sampled return mapping: the force f_j (N) on samples u of one period and, per sample,
  // what it depends on (time signals and diagnostics).
  SlipHistory Sweep(const Eigen::VectorXd& u) const { return ReturnMapping(u, stiffness_, limit_); }

  int dof() const { return dof_; }
  int other() const { return other_; }
  double stiffness() const { return stiffness_; }
  double limit() const { return limit_; }

 private:
  // Relative displacement coefficients u = x_dof − x_other of y.
  Eigen::VectorXd RelativeCoefficients(const NonlinearityContext& ctx,
                                       const Eigen::VectorXd& y) const;

  int dof_;
  int other_;
  double stiffness_;  // k_t, N/m
  double limit_;      // μN, N
};

}  // namespace nfrc
