#pragma once

#include <Eigen/Dense>
#include <vector>

#include "core/linear_model.h"

namespace nfrc {

// The external force of a transient run: the case's forcing terms evaluated at a phase φ(t),
//   f_dof(t) = Σ cos·cos(kφ) + sin·sin(kφ).
// Harmonic: φ = ωt. Chirp (Vadcard et al. 2022, eq. 66): φ = (ω1 + (ω2 − ω1) t / (2 T_s)) t,
// whose instantaneous frequency dφ/dt runs linearly from ω1 at t = 0 to ω2 at t = T_s.
struct Excitation {
  std::vector<ForcingTerm> terms;
  double omega = 1.0;  // ω (harmonic) or ω1 (chirp), rad per time unit
  bool chirp = false;
  double omega_end = 0.0;  // ω2 of a chirp
  double duration = 0.0;   // T_s of a chirp, time units

  static Excitation Harmonic(std::vector<ForcingTerm> terms, double omega);
  static Excitation Chirp(std::vector<ForcingTerm> terms, double omega_start, double omega_end,
                          double duration);

  double Phase(double t) const;
  double InstantaneousOmega(double t) const;
  // Adds f(t) to `force` (size of the model).
  void AddForce(double t, Eigen::Ref<Eigen::VectorXd> force) const;
  // Adds ḟ(t), the time derivative of f(t), to `rate` (for a differentiated momentum row).
  void AddForceRate(double t, Eigen::Ref<Eigen::VectorXd> rate) const;
};

}  // namespace nfrc
