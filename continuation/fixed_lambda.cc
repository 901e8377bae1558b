#include "continuation/fixed_lambda.h"

#include <algorithm>
#include <cmath>

#include "continuation/corrector.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

namespace {

// Regula falsi steps on the chord before SolveAlongChord gives up; each is one arclength
// correction. The Illinois rule converges superlinearly, so a handful usually suffices.
constexpr int kMaxChordSteps = 40;
// |λ* − λ| relative to max(1, |λ|) at which a corrected point counts as the one at λ: a few
// roundings of λ, so that the residual at exactly λ meets the residual tolerance.
constexpr double kCrossingTolerance = 1e-13;

// The scaling and Newton settings of a solve near `typical_y` and `y_guess`, the residual
// measured against ‖R(0, options.lambda_start)‖ as in Continue.
struct SolveSetup {
  Scaling scaling;
  NewtonSettings settings;
};

SolveSetup MakeSetup(ContinuationProblem& problem, Evaluator& evaluator,
                     const Eigen::VectorXd& y_guess, const Eigen::VectorXd& typical_y,
                     const ContinuationOptions& options) {
  SolveSetup setup{Scaling(problem.ScaleGroups(), LambdaScale(options), options.scale_floor), {}};
  setup.scaling.Include(typical_y);
  setup.scaling.Include(y_guess);
  NewtonSettings& settings = setup.settings;
  settings.max_iterations = options.max_start_iterations;
  settings.update_tolerance = options.newton_tolerance;
  settings.residual_tolerance = options.residual_tolerance;
  settings.line_search = options.line_search;
  settings.stop = options.stop;
  Eigen::VectorXd residual;
  settings.residual_scale = 1.0;
  if (evaluator.Residual(Eigen::VectorXd::Zero(y_guess.size()), options.lambda_start, &residual) &&
      residual.norm() > 0.0 && std::isfinite(residual.norm())) {
    settings.residual_scale = residual.norm();
  }
  return setup;
}

// The branch's point at λ between `previous` and `point` followed along the branch itself:
// arclength corrections on hyperplanes normal to the chord, moved along it by regula falsi
// (Illinois) on where the corrected point's λ* falls, until |λ* − λ| is at rounding level.
// Where Newton at fixed λ stalls at a kink of a nonsmooth residual (no fraction of its step
// decreases ‖R‖), λ free gets past it, as it does for the engine. Nullopt where a correction
// fails or the bracket does not close.
std::optional<FixedLambdaSolution> SolveAlongChord(ContinuationProblem& problem,
                                                   const BranchPoint& previous,
                                                   const BranchPoint& point, double lambda,
                                                   const ContinuationOptions& options) {
  Evaluator evaluator(problem);
  SolveSetup setup = MakeSetup(problem, evaluator, previous.y, point.y, options);
  const int n = static_cast<int>(point.y.size());
  Eigen::VectorXd u_low(n + 1), u_high(n + 1);
  u_low << previous.y, previous.lambda;
  u_high << point.y, point.lambda;
  const Eigen::VectorXd normal = setup.scaling.ToScaled(u_high - u_low).normalized();
  // g(s) = λ*(s) − λ along the chord u(s) = u_low + s (u_high − u_low): opposite signs at 0, 1.
  double s_low = 0.0, g_low = previous.lambda - lambda;
  double s_high = 1.0, g_high = point.lambda - lambda;
  int side = 0;  // the side kept last (Illinois: halve the other's g when kept twice)
  FixedLambdaSolution solution;
  for (int step = 0; step < kMaxChordSteps; ++step) {
    const double s = s_low - g_low * (s_high - s_low) / (g_high - g_low);
    const CorrectorResult corrected = CorrectOnArclength(evaluator, setup.scaling, setup.settings,
                                                         u_low + s * (u_high - u_low), normal);
    solution.iterations += corrected.iterations;
    if (!corrected.converged) return std::nullopt;
    const double g = corrected.u(n) - lambda;
    if (std::abs(g) <= kCrossingTolerance * std::max(1.0, std::abs(lambda))) {
      solution.y = corrected.u.head(n);
      Eigen::VectorXd residual;
      if (!evaluator.Residual(solution.y, lambda, &residual)) return std::nullopt;
      solution.residual_norm = residual.norm();
      solution.converged = solution.residual_norm <=
                           setup.settings.residual_tolerance * setup.settings.residual_scale;
      if (!solution.converged) return std::nullopt;
      return solution;
    }
    if ((g < 0.0) == (g_low < 0.0)) {
      s_low = s;
      g_low = g;
      if (side == -1) g_high *= 0.5;
      side = -1;
    } else {
      s_high = s;
      g_high = g;
      if (side == 1) g_low *= 0.5;
      side = 1;
    }
  }
  return std::nullopt;
}

}  // namespace

FixedLambdaSolution SolveAtFixedLambda(ContinuationProblem& problem, const Eigen::VectorXd& y_guess,
                                       double lambda, const Eigen::VectorXd& typical_y,
                                       const ContinuationOptions& options) {
  Evaluator evaluator(problem);
  const SolveSetup setup = MakeSetup(problem, evaluator, y_guess, typical_y, options);
  Eigen::VectorXd u_guess(y_guess.size() + 1);
  u_guess << y_guess, lambda;
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, setup.scaling, setup.settings, u_guess);
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
  FixedLambdaSolution solved = SolveAtFixedLambda(problem, guess, lambda, point.y, options);
  if (solved.converged) return solved;
  if (std::optional<FixedLambdaSolution> along =
          SolveAlongChord(problem, *previous, point, lambda, options)) {
    along->iterations += solved.iterations;
    return along;
  }
  return solved;
}

}  // namespace nfrc
