#include "continuation/fixed_lambda.h"

#include <doctest/doctest.h>

#include <cmath>

#include "test_problems.h"

namespace nfrc {
namespace {

TEST_CASE("fixed-lambda Newton finds the branch point at the requested lambda") {
  testing::CubicProblem problem;  // y³/3 − y − λ = 0
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  const Eigen::VectorXd guess = Eigen::VectorXd::Constant(1, 2.0);
  const FixedLambdaSolution solution = SolveAtFixedLambda(problem, guess, 1.0, guess, options);
  REQUIRE(solution.converged);
  const double y = solution.y(0);
  CHECK(std::abs(y * y * y / 3.0 - y - 1.0) < 1e-12);  // the upper branch root at λ = 1
  CHECK(y > 1.0);
  CHECK(solution.message.empty());
}

TEST_CASE("fixed-lambda Newton reports failure where there is no solution") {
  testing::CircleProblem problem;  // y² + λ² = 1 has no real y at λ = 2
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 1.0;
  const Eigen::VectorXd guess = Eigen::VectorXd::Constant(1, 0.5);
  const FixedLambdaSolution solution = SolveAtFixedLambda(problem, guess, 2.0, guess, options);
  CHECK_FALSE(solution.converged);
  CHECK_FALSE(solution.message.empty());
}

// Options for the cubic y³/3 − y − λ = 0 over λ in [−2, 2], and two of its upper-branch
// points around λ = 1 (y = 2 gives λ = 2/3, y = 2.2 gives λ ≈ 1.349).
ContinuationOptions CubicOptions() {
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  return options;
}

BranchPoint CubicPoint(double y) {
  BranchPoint point;
  point.y = Eigen::VectorXd::Constant(1, y);
  point.lambda = y * y * y / 3.0 - y;
  return point;
}

TEST_CASE("solve at crossing: exact point, crossing segment, and a segment that misses") {
  testing::CubicProblem problem;  // y³/3 − y − λ = 0
  const ContinuationOptions options = CubicOptions();
  const BranchPoint a = CubicPoint(2.0);
  const BranchPoint b = CubicPoint(2.2);

  const auto crossing = SolveAtCrossing(problem, &a, b, 1.0, options);
  REQUIRE(crossing.has_value());
  REQUIRE(crossing->converged);
  const double y = crossing->y(0);
  CHECK(std::abs(y * y * y / 3.0 - y - 1.0) < 1e-12);
  CHECK(y > 2.0);
  CHECK(y < 2.2);

  const auto exact = SolveAtCrossing(problem, &a, b, b.lambda, options);
  REQUIRE(exact.has_value());
  CHECK(exact->y(0) == b.y(0));  // the point itself, no solve

  CHECK_FALSE(SolveAtCrossing(problem, &a, b, 1.5, options).has_value());
  CHECK_FALSE(SolveAtCrossing(problem, nullptr, b, 1.0, options).has_value());
}

// The cubic with a wrong slope at one λ: there ∂R/∂y comes with its sign flipped (as a law's
// one-sided derivative at a kink can point the wrong way), so that no fraction of a Newton
// step at that λ decreases |R|. An arclength correction leaves that λ after its first step.
class WrongSlopeAtLambda : public testing::CubicProblem {
 public:
  explicit WrongSlopeAtLambda(double target) : target_(target) {}
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    if (!CubicProblem::Evaluate(y, lambda, residual, jacobian_y, jacobian_lambda)) return false;
    if (lambda == target_ && jacobian_y != nullptr) *jacobian_y = -*jacobian_y;
    return true;
  }

 private:
  double target_;
};

TEST_CASE("solve at crossing: where Newton at fixed lambda fails, along the branch") {
  WrongSlopeAtLambda problem(1.0);
  const ContinuationOptions options = CubicOptions();
  const BranchPoint a = CubicPoint(2.0);
  const BranchPoint b = CubicPoint(2.2);
  const Eigen::VectorXd chord = Eigen::VectorXd::Constant(1, 2.1);
  CHECK_FALSE(SolveAtFixedLambda(problem, chord, 1.0, chord, options).converged);

  const auto crossing = SolveAtCrossing(problem, &a, b, 1.0, options);
  REQUIRE(crossing.has_value());
  INFO(crossing->message);
  REQUIRE(crossing->converged);
  const double y = crossing->y(0);
  // The root of y³/3 − y = 1 on the upper branch, to the rounding of λ* − λ (1e-13).
  CHECK(std::abs(y * y * y / 3.0 - y - 1.0) < 1e-12);
  CHECK(y > 2.0);
  CHECK(y < 2.2);
}

}  // namespace
}  // namespace nfrc
