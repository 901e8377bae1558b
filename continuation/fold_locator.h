#pragma once

#include <Eigen/Dense>

#include "continuation/branch.h"
#include "continuation/corrector.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

// A step across which the λ component of the tangent changed sign.
struct FoldBracket {
  Eigen::VectorXd u_before;            // accepted point before the fold
  Eigen::VectorXd tangent_before;      // its unit scaled tangent (the step's predictor direction)
  double tangent_lambda_before = 0.0;  // scaled λ components of the unit tangents
  Eigen::VectorXd u_after;             // corrected point after the fold, at arclength `step`
  double tangent_lambda_after = 0.0;
  double step = 0.0;
};

struct FoldSearchResult {
  Fold fold;                  // after_point is left for the caller
  int newton_iterations = 0;  // of all correctors run by the search
};

// Finds the arclength s in (0, step) where τ_λ(s) = 0 by the Illinois variant of regula
// falsi: a trial s is predicted along tangent_before, corrected on the same arclength
// constraint and its tangent computed. Stops when the estimated λ error (see
// Fold::lambda_accuracy) is at most tolerance·max(|λ|, 10⁻³·s_λ): relative to |λ|, and to
// 10⁻³·s_λ for folds near λ = 0 where a relative test could never be met; or at a corner
// (Fold::corner), where τ_λ jumps across zero instead of passing through it.
FoldSearchResult LocateFold(Evaluator& evaluator, const Scaling& scaling,
                            const NewtonSettings& settings, const FoldBracket& bracket,
                            double tolerance, int max_iterations);

}  // namespace nfrc
