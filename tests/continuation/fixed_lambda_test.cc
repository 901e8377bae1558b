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
  const FixedLambdaSolution solution =
      SolveAtFixedLambda(problem, guess, 1.0, guess, options);
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
  const FixedLambdaSolution solution =
      SolveAtFixedLambda(problem, guess, 2.0, guess, options);
  CHECK_FALSE(solution.converged);
  CHECK_FALSE(solution.message.empty());
}

}  // namespace
}  // namespace nfrc
