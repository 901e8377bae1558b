#pragma once

#include <Eigen/Dense>

#include "continuation/branch.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace nfrc {

// Receives points and folds as they are found, so callers can stream them to disk.
class ContinuationObserver {
 public:
  virtual ~ContinuationObserver() = default;
  // Called for every accepted point (index in the branch); returning false stops the run.
  virtual bool OnPoint(const BranchPoint& /*point*/, int /*index*/) { return true; }
  virtual void OnFold(const Fold& /*fold*/) {}
};

// Follows R(y, λ) = 0 from (y_guess, options.lambda_start) by pseudo-arclength continuation:
// Newton at fixed λ for the first point, then tangent predictor and a corrector on the
// augmented system [[R_y, R_λ], [t_yᵀ, t_λ]] (scaled) solved by one LU of the whole
// augmented matrix, which stays regular at simple folds where R_y is singular. Numerical
// failures end up in the summary, never as exceptions; invalid options throw.
Branch Continue(ContinuationProblem& problem, const Eigen::VectorXd& y_guess,
                const ContinuationOptions& options, ContinuationObserver* observer = nullptr,
                PlotCurve* plot = nullptr);

}  // namespace nfrc
