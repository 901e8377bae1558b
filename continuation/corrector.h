#pragma once

#include <Eigen/Dense>
#include <string>

#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

struct NewtonSettings {
  int max_iterations = 15;
  double update_tolerance = 1e-10;   // on the scaled Newton update ‖Δu ./ scales‖
  double residual_tolerance = 1e-8;  // on ‖R‖ / residual_scale
  double residual_scale = 1.0;       // r: the size of R that counts as "large"
  bool line_search = true;           // backtracking on the scaled merit
};

struct CorrectorResult {
  bool converged = false;
  Eigen::VectorXd u;            // last iterate (y, λ)
  Linearization linearization;  // R and its Jacobians at u
  int iterations = 0;           // linear solves done
  double residual_norm = 0.0;   // ‖R(u)‖, unscaled
  std::string failure;          // why it did not converge
};

// Pseudo-arclength corrector: Newton on R(u) = 0, τᵀ D⁻¹(u − u_pred) = 0 from u_pred, with
// τ the unit scaled tangent, each step solving the whole scaled bordered system by one LU.
CorrectorResult CorrectOnArclength(Evaluator& evaluator, const Scaling& scaling,
                                   const NewtonSettings& settings, const Eigen::VectorXd& u_pred,
                                   const Eigen::VectorXd& tangent_scaled);

// Newton at the fixed λ = u_guess(n) from u_guess; λ stays exactly at that value.
CorrectorResult CorrectAtFixedLambda(Evaluator& evaluator, const Scaling& scaling,
                                     const NewtonSettings& settings,
                                     const Eigen::VectorXd& u_guess);

}  // namespace nfrc
