#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>

#include "continuation/branch.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace nfrc {

// Outcome of a Newton solve of R(y, λ) = 0 at one fixed λ.
struct FixedLambdaSolution {
  bool converged = false;
  Eigen::VectorXd y;
  int iterations = 0;
  double residual_norm = 0.0;
  std::string message;  // why it failed, empty on success
};

// Newton (with the engine's line search and tolerances) at fixed λ from y_guess, e.g. to
// resolve a branch at requested parameter values between two of its points. Updates are
// measured against `typical_y` (per unknown: a branch point near by), the residual against
// ‖R(0, options.lambda_start)‖ as in Continue.
FixedLambdaSolution SolveAtFixedLambda(ContinuationProblem& problem, const Eigen::VectorXd& y_guess,
                                       double lambda, const Eigen::VectorXd& typical_y,
                                       const ContinuationOptions& options);

// The solution at `lambda` if the branch segment from `previous` (may be null: first point)
// to `point` reaches it: `point` itself if it sits exactly there, else a fixed-λ solve from
// the linear interpolation when λ lies strictly between the two points; nullopt otherwise.
// Where that Newton stalls (at a kink of a nonsmooth residual no fraction of its step need
// decrease ‖R‖; seen on the rigid DLFT contact law), the branch is followed instead:
// arclength corrections across the chord, moved by regula falsi until their λ is λ to
// rounding, and accepted where ‖R‖ at exactly λ meets the residual tolerance. The failed
// solve is returned if that fails too.
std::optional<FixedLambdaSolution> SolveAtCrossing(ContinuationProblem& problem,
                                                   const BranchPoint* previous,
                                                   const BranchPoint& point, double lambda,
                                                   const ContinuationOptions& options);

}  // namespace nfrc
