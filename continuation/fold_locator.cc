#include "continuation/fold_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "continuation/tangent.h"

namespace nfrc {
namespace {

// Below this fraction of s_λ a fold's λ counts as zero for the relative accuracy test.
constexpr double kLambdaNearZero = 1e-3;
// A corner (Fold::corner): the bracket has shrunk below step/kCornerShrink while τ_λ at each
// of its ends is still at least kCornerFraction of the value on that side at the start. A
// smooth fold cannot pass this: τ_λ is linear near it, so at both ends of such a bracket it
// is at most 1/64 of its spread, while half the larger side's value is at least a quarter of
// the spread. At a corner halving further only locates the switching sample. An iterate that
// keeps that fraction of its side's value suggests a corner, where regula falsi creeps from
// the steep side (τ_λ of 0.06 against 3e-4 on the rod): the next trial bisects.
constexpr double kCornerShrink = 64.0;
constexpr double kCornerFraction = 0.5;

}  // namespace

FoldSearchResult LocateFold(Evaluator& evaluator, const Scaling& scaling,
                            const NewtonSettings& settings, const FoldBracket& bracket,
                            double tolerance, int max_iterations) {
  const int n = scaling.num_unknowns();
  const double lambda_scale = scaling.lambda_scale();
  FoldSearchResult result;
  Fold& fold = result.fold;

  // Until an iterate is found, report the end of the bracket closer to the fold.
  const bool after_closer =
      std::abs(bracket.tangent_lambda_after) < std::abs(bracket.tangent_lambda_before);
  const Eigen::VectorXd& closer = after_closer ? bracket.u_after : bracket.u_before;
  fold.lambda = closer(n);
  fold.y = closer.head(n);
  fold.tangent_lambda =
      lambda_scale * (after_closer ? bracket.tangent_lambda_after : bracket.tangent_lambda_before);
  fold.lambda_accuracy = std::abs(bracket.u_after(n) - bracket.u_before(n));

  const Eigen::VectorXd direction = scaling.FromScaled(bracket.tangent_before);
  double a = 0.0, fa = bracket.tangent_lambda_before;
  double b = bracket.step, fb = bracket.tangent_lambda_after;
  int side = 0;  // which end was replaced last (Illinois halves the other end's value)
  double last_s = b, last_f = fb, last_lambda = bracket.u_after(n);
  // τ_λ at the bracket's ends as computed (fa and fb carry Illinois's halvings).
  double tau_a = fa, tau_b = fb;
  double lambda_a = bracket.u_before(n), lambda_b = bracket.u_after(n);
  const double level_a = kCornerFraction * std::abs(bracket.tangent_lambda_before);
  const double level_b = kCornerFraction * std::abs(bracket.tangent_lambda_after);
  bool bisect = false;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    const double s = bisect ? 0.5 * (a + b) : (a * fb - b * fa) / (fb - fa);
    if (!(s > a && s < b)) break;  // bracket collapsed to rounding
    CorrectorResult corrected = CorrectOnArclength(
        evaluator, scaling, settings, bracket.u_before + s * direction, bracket.tangent_before);
    result.newton_iterations += corrected.iterations;
    Eigen::VectorXd tangent;
    if (!corrected.converged ||
        !NextTangent(corrected.linearization, scaling, settings.residual_scale,
                     bracket.tangent_before, &tangent)) {
      break;
    }
    const double fs = tangent(n);
    const double lambda = corrected.u(n);
    fold.iterations = iteration;
    fold.lambda = lambda;
    fold.y = corrected.u.head(n);
    fold.tangent_lambda = fs * lambda_scale;
    // λ is stationary at the fold, so iterates on either side can share a λ while both
    // are off: the quadratic model λ_fold − λ ≈ ½ s_λ τ_λ²/|dτ_λ/ds| bounds the error too.
    const double slope = std::abs((fs - last_f) / (s - last_s));
    const double model_error = fs == 0.0 ? 0.0 : 0.5 * lambda_scale * fs * fs / slope;
    fold.lambda_accuracy = std::max(std::abs(lambda - last_lambda), model_error);
    if (!std::isfinite(fold.lambda_accuracy)) {
      fold.lambda_accuracy = std::numeric_limits<double>::infinity();
    }
    last_s = s;
    last_f = fs;
    last_lambda = lambda;
    const double reference = std::max(std::abs(lambda), kLambdaNearZero * lambda_scale);
    if (fold.lambda_accuracy <= tolerance * reference) {
      fold.converged = true;
      break;
    }
    if ((fs > 0.0) == (fb > 0.0)) {
      b = s;
      fb = fs;
      tau_b = fs;
      lambda_b = lambda;
      if (side == -1) fa *= 0.5;
      side = -1;
      bisect = std::abs(fs) >= level_b;
    } else {
      a = s;
      fa = fs;
      tau_a = fs;
      lambda_a = lambda;
      if (side == 1) fb *= 0.5;
      side = 1;
      bisect = std::abs(fs) >= level_a;
    }
    if (b - a <= bracket.step / kCornerShrink && std::abs(tau_a) >= level_a &&
        std::abs(tau_b) >= level_b) {
      // The corner's λ lies past both ends' by at most their slope across the bracket.
      fold.corner = true;
      fold.converged = true;
      fold.lambda_accuracy = std::abs(lambda_a - lambda_b) +
                             lambda_scale * std::max(std::abs(tau_a), std::abs(tau_b)) * (b - a);
      break;
    }
  }
  return result;
}

}  // namespace nfrc
