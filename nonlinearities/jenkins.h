#pragma once

#include <string>
#include <vector>

#include "core/nonlinearity.h"
#include "nonlinearities/return_mapping.h"

namespace nfrc {

// The Jenkins element (elastic dry friction): a tangential spring k_t in series with a
// Coulomb slider of limit μN, on u = x_dof − x_other (or x_dof against ground). Its force
// f = k_t(u − w), w the slider's position, acts as +f on `dof` and −f on `other`, like a
// spring k_t·u. The law is hysteretic: it is evaluated by alternating frequency–time with
// the exact stick/slip update on the N_t samples (return mapping of the slider), two passes
// over the period so that the second is periodic. With no slip at all the slider stays at
// the origin and the element is the linear spring k_t; as k_t → ∞ it tends to Coulomb's law.
//
// Jacobian: on a stick sample f_j = f_a + k_t(u_j − u_a), a the last slip sample before j
// (f_a = ±μN), or f_j = k_t u_j if the slider never moved; on a slip sample f_j = ±μN. It is
// exact on the active branch of every sample. The law is rate independent: ∂/∂ω = 0.
//
// Hill's method sees the same Jacobian (no velocity dependence): the exact linearisation of
// a stick sample, δf(t) = k_t(δu(t) − δu(t_a)), carries the Floquet factor e^{−s(t−t_a)} on
// the anchor's term, which is taken as 1. This is exact for s = 0 (folds and branch points,
// multipliers at +1) and approximate elsewhere; the monodromy matrix of `nfrc validate`
// gives the exact multipliers.
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

  // The force f_j (N) on samples u of one period and, per sample, what it depends on.
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
