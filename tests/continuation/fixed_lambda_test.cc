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

TEST_CASE("solve at crossing: exact point, crossing segment, and a segment that misses") {
  testing::CubicProblem problem;  // y³/3 − y − λ = 0
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  // Two upper-branch points around λ = 1 (y = 2 gives λ = 2/3, y = 2.2 gives λ ≈ 1.349).
  BranchPoint a;
  a.y = Eigen::VectorXd::Constant(1, 2.0);
  a.lambda = 2.0 / 3.0;
  BranchPoint b;
  b.y = Eigen::VectorXd::Constant(1, 2.2);
  b.lambda = 2.2 * 2.2 * 2.2 / 3.0 - 2.2;

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

}  // namespace
}  // namespace nfrc
