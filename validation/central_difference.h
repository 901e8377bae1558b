#pragma once

#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// Explicit central differences with forward-increment Lagrange multipliers (Carpenter, Taylor
// & Katona 1991), the reference scheme of Vadcard et al. 2022, for rigid unilateral contacts:
//   (M/h² + C/2h) x_{n+1} = f_n − K x_n − f_nl(x_n, v_n) + M(2x_n − x_{n−1})/h² + C x_{n−1}/2h
//                           + Σ n_c λ_c
// where the multipliers λ ≥ 0 make every gap at n+1 non-negative and complementary to λ
// (a small LCP solved by Lemke; one contact is a scalar). A contact node thus arrives with a
// perfectly inelastic impact and is released when its multiplier would turn negative. Other
// laws must have an explicit force (TimeLaw::ExplicitForce): springs and penalty contacts,
// not exact friction. The step is explicit_step_fraction × 2/ω_max, rounded so a whole number
// of steps makes one period; energies are accumulated by the trapezoidal rule.
class CentralDifferenceIntegrator : public TransientIntegrator {
 public:
  // Throws InputError naming the law (model.law_paths) if it has no explicit force.
  CentralDifferenceIntegrator(TransientModel& model, TransientOptions options);
  ~CentralDifferenceIntegrator() override;

  TransientResult RunToSteadyState(double omega, const InitialState& start) override;
  ChirpResult RunChirp(const Excitation& chirp, int samples_per_cycle) override;

  // The time step used at ω (s), after rounding to the period.
  double StepFor(double omega) const;

 private:
  TransientModel& model_;
  TransientOptions options_;
  double omega_max_ = 0.0;  // largest undamped natural frequency (rad/s)
};

}  // namespace nfrc
