#include "continuation/fixed_lambda.h"

#include <cmath>

#include "continuation/corrector.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

FixedLambdaSolution SolveAtFixedLambda(ContinuationProblem& problem, const Eigen::VectorXd& y_guess,
                                       double lambda, const Eigen::VectorXd& typical_y,
                                       const ContinuationOptions& options) {
  Evaluator evaluator(problem);
  Scaling scaling(problem.ScaleGroups(), LambdaScale(options), options.scale_floor);
  scaling.Include(typical_y);
  scaling.Include(y_guess);

  NewtonSettings settings;
  settings.max_iterations = options.max_start_iterations;
  settings.update_tolerance = options.newton_tolerance;
  settings.residual_tolerance = options.residual_tolerance;
  settings.line_search = options.line_search;
  Eigen::VectorXd residual;
  settings.residual_scale = 1.0;
  if (evaluator.Residual(Eigen::VectorXd::Zero(y_guess.size()), options.lambda_start, &residual) &&
      residual.norm() > 0.0 && std::isfinite(residual.norm())) {
    settings.residual_scale = residual.norm();
  }

  Eigen::VectorXd u_guess(y_guess.size() + 1);
  u_guess << y_guess, lambda;
  const CorrectorResult result = CorrectAtFixedLambda(evaluator, scaling, settings, u_guess);
  FixedLambdaSolution solution;
  solution.converged = result.converged;
  solution.y = result.u.head(y_guess.size());
  solution.iterations = result.iterations;
  solution.residual_norm = result.residual_norm;
  solution.message = result.failure;
  return solution;
}

std::optional<FixedLambdaSolution> SolveAtCrossing(ContinuationProblem& problem,
                                                   const BranchPoint* previous,
                                                   const BranchPoint& point, double lambda,
                                                   const ContinuationOptions& options) {
  if (point.lambda == lambda) {
    return FixedLambdaSolution{true, point.y, 0, point.residual_norm, ""};
  }
  if (previous == nullptr || (previous->lambda - lambda) * (point.lambda - lambda) >= 0.0) {
    return std::nullopt;
  }
  const double t = (lambda - previous->lambda) / (point.lambda - previous->lambda);
  const Eigen::VectorXd guess = (1.0 - t) * previous->y + t * point.y;
  return SolveAtFixedLambda(problem, guess, lambda, point.y, options);
}

}  // namespace nfrc
