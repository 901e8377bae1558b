#pragma once

#include <Eigen/Dense>
#include <vector>

#include "core/fourier_transform.h"
#include "core/harmonic_set.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

// The force of a spring k in series with a Coulomb slider of limit F_s driven by a periodic
// input u on the N_t samples of one period: the slider's return mapping
//   trial_j = k(u_j − w_{j−1}),  f_j = clamp(trial_j, −F_s, F_s),  w_j = u_j − f_j/k,
// from w = 0, twice over the period so that the second pass is periodic (a slip wipes out
// the start). Shared by the Jenkins element (u the relative displacement, k = k_t) and DLFT
// friction (u the predicted position, k = ε).
struct SlipHistory {
  Eigen::VectorXd force;  // f_j of the second pass
  // Per sample: kSlip, or for a stick sample the last slip sample before it (possibly of the
  // first pass), or kOrigin if the slider never moved.
  std::vector<int> anchor;
  static constexpr int kSlip = -2;
  static constexpr int kOrigin = -1;

  bool Slips() const;
  // Whether sample j sticks.
  bool Sticks(int j) const { return anchor[static_cast<size_t>(j)] != kSlip; }
};

// Stick phases of a history sampled on one period of `set` (phases shorter than the period of
// its highest harmonic are ripple, see CountPhases).
PhaseCount StickPhases(const HarmonicSet& set, const SlipHistory& history);

// stiffness > 0 and limit ≥ 0 (checked by the laws).
SlipHistory ReturnMapping(const Eigen::VectorXd& input, double stiffness, double limit);

// ∂f̃/∂ũ = P J E for the coefficients f̃ = P f of the history's force and ũ of its input: on a
// stick sample ∂f_j/∂u = k(e_j − e_a) (k e_j at the origin), 0 on a slip sample. Exact on
// the active branch of every sample.
Eigen::MatrixXd ReturnMappingJacobian(const FourierTransform& fourier, const SlipHistory& history,
                                      double stiffness);

}  // namespace nfrc
