#pragma once

#include <memory>
#include <string>
#include <vector>

#include "validation/central_difference_scheme.h"
#include "validation/stepper.h"
#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// Explicit central differences with Lagrange multipliers for rigid unilateral contacts
// (validation/central_difference_scheme.h; the reference scheme of Vadcard et al. 2022) as a
// TransientStepper. A contact node arrives with a perfectly inelastic impact and is released
// when its multiplier would turn negative. Other laws must have an explicit force: springs and
// penalty contacts, not exact friction.
//
// Conventions:
// - Time step: harmonic excitation, explicit_step_fraction × 2/ω_max rounded down so that a
//   whole number of steps makes one period (ω_max the largest natural frequency, the laws'
//   stiffness bounds included; without stiffness, one step per sample); chirp, the smaller of
//   that limit and one step per sample at its highest frequency, rounded to the duration.
// - The state between nodes is interpolated linearly; asked at a node (to 1e-6 h), it is the
//   node's: period boundaries are nodes.
// - A contact is "in phase" at t_n while λ_c > 0: from the step before an impact through the
//   sticking phase to the first step whose multiplier vanishes. An event is a node at which a
//   contact's phase differs from the node before. Phase logs list rigid contacts first, then
//   the explicit laws (whose phases are not tracked: empty logs); so do the signals.
// - Powers at the nodes use v_n = (x_{n+1} − x_{n−1})/2h and are integrated by the
//   trapezoidal rule. h·(f − Cv − f_nl − Gᵀλ)ᵀv_n is exactly the change of the scheme's
//   half-step energy ½v_{n+½}ᵀMv_{n+½} + ½x_nᵀKx_{n+1} (symmetric M, K), so input − damping −
//   laws equals the change of the mean of the two half-step energies around t0 and t0 + T:
//   it matches the nodal energy change to O(h²) for a smooth motion and exactly on a periodic
//   orbit, and the kinetic energy an impact destroys appears in work_laws.
// - Statistics: steps and events only (no residual, Jacobian, Newton or error test).
class CentralDifferenceStepper : public TransientStepper {
 public:
  // Throws InputError naming the law (model.law_paths) if it has no explicit force, and
  // naming model.M if the mass matrix is not positive definite.
  CentralDifferenceStepper(const TransientModel& model, const TransientOptions& options);
  ~CentralDifferenceStepper() override;

  // The time step at ω (s) for a steady-state run sampled `samples` times per period.
  double StepFor(double omega, int samples) const;

  std::string method() const override { return "central_difference"; }
  bool Start(const StepperStart& start) override;
  bool BeginSegment(double t_end) override;
  StepOutcome AdvanceTo(double t) override;
  bool ResetQuadratures() override;
  double t() const override { return t_; }
  Eigen::Ref<const Eigen::VectorXd> x() const override { return x_; }
  Eigen::Ref<const Eigen::VectorXd> v() const override { return v_; }
  LawSignalValues Signals() const override;
  const std::vector<LawPhaseLog>& PhaseLogs() const override { return logs_; }
  StepperQuadratures Quadratures() const override;
  TransientStatistics Statistics() const override { return statistics_; }
  const std::string& message() const override { return message_; }

 private:
  // Computes the next node; previous_ ← current_ ← it, with quadratures, events and logs.
  bool StepOnce();
  // The trapezoidal integral of the powers and energy from t_ to current_.t (the part of the
  // latest interval not yet reached).
  StepperQuadratures Remainder() const;

  const TransientModel& model_;
  TransientOptions options_;
  double omega_max_ = 0.0;  // largest undamped natural frequency (rad/s)

  // The current run.
  Excitation excitation_;
  double h_ = 0.0;  // s
  std::unique_ptr<CentralDifferenceScheme> scheme_;
  long next_ = 0;  // index of the next node to compute
  CentralDifferenceNode previous_, current_;
  double t_ = 0.0;
  double theta_ = 1.0;  // t_ = previous_.t + θh; 1: at current_
  Eigen::VectorXd x_, v_;
  StepperQuadratures to_current_;  // from the last reset to current_.t
  std::vector<LawPhaseLog> logs_;
  double segment_end_ = 0.0;
  TransientStatistics statistics_;
  std::chrono::steady_clock::time_point deadline_;
  std::string message_;
};

}  // namespace nfrc
