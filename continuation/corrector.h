#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <memory>
#include <string>

#include "continuation/augmented_system.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

struct NewtonSettings {
  int max_iterations = 15;
  double update_tolerance = 1e-10;   // on the scaled Newton update ‖Δu ./ scales‖
  double residual_tolerance = 1e-8;  // on ‖R‖ / residual_scale
  double residual_scale = 1.0;       // r: the size of R that counts as "large"
  bool line_search = true;           // backtracking on the scaled merit
  // Raised: the correction fails at once ("interrupted") before its next iteration.
  const std::atomic<bool>* stop = nullptr;
};

// The failure message of a correction the stop flag ended.
inline constexpr const char* kInterrupted = "interrupted";

struct CorrectorResult {
  bool converged = false;
  Eigen::VectorXd u;            // last iterate (y, λ)
  Linearization linearization;  // R and its Jacobians at u
  int iterations = 0;           // linear solves done
  // Of those, solved by a low-rank update of an earlier LU (fixed λ: ReusedFactorization).
  int low_rank_updates = 0;
  double residual_norm = 0.0;  // ‖R(u)‖, unscaled
  // Converged above residual_tolerance, within kNoiseFactor of the problem's estimate of
  // the residual's rounding floor (ContinuationProblem::ResidualNoise), which is recorded.
  bool at_noise_floor = false;
  double noise_floor = 0.0;
  // Accepted on the contraction of two full steps (see below): their estimate of the scaled
  // error left in u, at most update_tolerance; negative if accepted otherwise.
  double error_estimate = -1.0;
  std::string failure;  // why it did not converge
  // CorrectOnArclength: the factorisation of the last Newton iteration's scaled bordered
  // matrix (R's Jacobians at the iterate before u, the border the tangent given; null where
  // none is kept), from which NextTangent refines the next tangent.
  std::shared_ptr<const AugmentedSolver> last_step;
};

// Newton stops when the scaled update and the residual are below their tolerances; when the
// residual is, and two full steps contracted by θ ≤ 1/4 with θ‖Δu‖/(1 − θ) below
// update_tolerance (the error that update leaves, so the confirming iteration is saved); or, where
// the residual stalls above its tolerance (falls by less than half in an iteration), when it
// lies within kNoiseFactor of the rounding floor the problem estimates: λ moves at every
// arclength iteration, and a condensed operator whose rounding moves with λ (a fine mesh)
// sets a floor no Newton step can go below. Within kNoiseFactor of that floor the line search
// is off (a damped step would only halve into the noise).
inline constexpr double kNoiseFactor = 10.0;

// Pseudo-arclength corrector: Newton on R(u) = 0, τᵀ D⁻¹(u − u_pred) = 0 from u_pred, with
// τ the unit scaled tangent, each step solving the whole scaled bordered system by one LU.
// Unlike CorrectAtFixedLambda it gives up early ("stagnating") where the line search has
// cut every step of three iterations and the merit fell by less than half over them: the
// caller has fallbacks (a fixed-λ step, a shorter step) that beat such a crawl.
CorrectorResult CorrectOnArclength(Evaluator& evaluator, const Scaling& scaling,
                                   const NewtonSettings& settings, const Eigen::VectorXd& u_pred,
                                   const Eigen::VectorXd& tangent_scaled);

// Newton at the fixed λ = u_guess(n) from u_guess; λ stays exactly at that value. With the
// problem's elimination blocks, an iteration whose Schur complement differs from the last one
// factorised by a low rank solves through that LU (ReusedFactorization).
CorrectorResult CorrectAtFixedLambda(Evaluator& evaluator, const Scaling& scaling,
                                     const NewtonSettings& settings,
                                     const Eigen::VectorXd& u_guess);

}  // namespace nfrc
