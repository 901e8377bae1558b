#pragma once

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "core/fourier_transform.h"
#include "core/harmonic_set.h"
#include "core/nonlinearity.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {

// The force of a spring k in series with a Coulomb slider of limit F_s driven by a periodic
// input u on samples of one period (the time signals and diagnostics of the laws, on their
// fine grid; the residual uses ResolveReturnMapping below): the slider's return mapping
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

// The same law on the band-limited input u(θ) = Σ ũ_i φ_i(θ) itself instead of its N_t
// samples, for the harmonic-balance residual. Sampled, the force is piecewise linear in ũ
// with a kink wherever one sample switches between stick and slip, and each kink changes
// ∂f̃/∂ũ by about 2k/N_t (a stick row k(e_j − e_a) of P·J·E appears or vanishes): once k/N_t
// is not small against the linear part (k = 100 at N_t = 1024 on the Fig. 7 oscillator) the
// branch is a staircase of kinks on which Newton cycles and the arclength steps jump. Here
// the switches are located on the trigonometric polynomial (slip → stick where u turns,
// stick → slip where the force reaches ±F_s) and f is projected by exact integrals over the
// pieces: the N_t → ∞ limit of the sampled law, whose force is continuous in θ and C¹ in ũ
// except where a stick or slip phase is born or dies. The samples only bracket the switches.
//
// The period starts at the global maximum of u, where the periodic state is known whatever
// came before (the slider is at u_max − F_s/k once u has also passed its minimum), so one
// pass is periodic. Without slip (k(u_max − u_min) ≤ 2F_s) the slider rests where the sampled
// law's passes from w = 0 leave it: w = clamp(0, u_max − F_s/k, u_min + F_s/k).
//
// ∂f̃/∂ũ is exact: f is continuous across every switch, so moving a switch changes no
// integral to first order, and a stick phase's anchor is an extremum of u (u' = 0), so moving
// it does not change u_a to first order either. On a stick piece ∂f/∂ũ = k(φ(θ) − φ(θ_a)), on a
// slip piece 0.
struct ResolvedSlip {
  Eigen::VectorXd force;     // f̃ (N), the exact Galerkin coefficients of f(θ) in the input's set
  Eigen::MatrixXd jacobian;  // ∂f̃/∂ũ (N/m); empty if not asked for
  int switches = 0;          // stick/slip switches over the period
  // The stick pieces and their anchors (θ in rad, unwrapped: anchor ≤ begin < end ≤ anchor +
  // 2π), for Hill's method (Nonlinearity::Memory); empty without slip.
  std::vector<MemoryPiece> stick_pieces;
};

// `input`: ũ in fourier's harmonic set; its samples (and those of u' and u'') bracket the
// switches. stiffness > 0 and limit ≥ 0 (checked by the laws). Without `with_jacobian` the
// Jacobian is left empty (a residual-only evaluation).
ResolvedSlip ResolveReturnMapping(const FourierTransform& fourier, const Eigen::VectorXd& input,
                                  double stiffness, double limit, bool with_jacobian = true);

// The memory of a slider law for Hill's method (Nonlinearity::Memory): the resolved stick
// pieces with stiffness k, on u = x_dof − x_other (`pair`) or x_dof, the force +f on `dof` and
// −f on `other`. None without stick pieces (no slip, or no stick).
std::optional<LinearizationMemory> SliderMemory(ResolvedSlip slip, double stiffness, bool pair);

}  // namespace nfrc
