#include "continuation/tangent.h"

#include <doctest/doctest.h>

#include <cmath>

#include "test_problems.h"

namespace nfrc {
namespace {

using testing::CubicProblem;
using testing::DuffingProblem;

// Closed-form quantities computed in a handful of flops agree to rounding.
constexpr double kRoundoff = 1e-13;

doctest::Approx Near(double value) { return doctest::Approx(value).epsilon(kRoundoff); }

TEST_CASE("tangent: the first one points towards lambda_end, even from a fold") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  Scaling scaling({0}, 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Constant(1, 2.0));
  Linearization regular;
  // y = 2: R_y = 3, R_λ = −1, so dy/dλ = 1/3 and the scaled tangent ∝ (1/3 / 2, 1).
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(2.0, 2.0 / 3.0), &regular));
  Eigen::VectorXd up, down;
  REQUIRE(InitialTangent(regular, scaling, 1.0, 1.0, &up));
  REQUIRE(InitialTangent(regular, scaling, 1.0, -1.0, &down));
  CHECK(up(1) > 0.0);
  CHECK(down(1) < 0.0);
  CHECK(up.norm() == Near(1.0));
  CHECK(up(0) / up(1) == Near(1.0 / 6.0));

  Linearization fold;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(-1.0, 2.0 / 3.0), &fold));
  Eigen::VectorXd at_fold;
  REQUIRE(InitialTangent(fold, scaling, 1.0, 1.0, &at_fold));
  CHECK(std::abs(at_fold(0)) == Near(1.0));
  CHECK(at_fold(1) == Near(0.0));
}

TEST_CASE("tangent: the first one is the null vector of the scaled [R_y, R_lambda]") {
  DuffingProblem problem(/*with_energy=*/true);
  Evaluator evaluator(problem);
  Scaling scaling({0, 0, 1}, 0.5, 1e-6);
  scaling.Include(Eigen::Vector3d(1.0, 2.0, 5.0));
  Linearization at;
  // Any (y, ω): the tangent of [R_y, R_λ] is defined off the branch too.
  REQUIRE(evaluator.Linearize(Eigen::Vector4d(0.7, -0.4, 0.3, 1.1), &at));
  Eigen::VectorXd tangent;
  REQUIRE(InitialTangent(at, scaling, 2.0, -1.0, &tangent));
  // Closed form: Δy = −R_y⁻¹R_λ Δλ, scaled by the unknowns' scales; λ decreasing.
  const Eigen::Vector3d dy = -at.jacobian_y.lu().solve(at.jacobian_lambda);
  Eigen::Vector4d expected;
  expected << dy.cwiseQuotient(scaling.scales().head(3)), 1.0 / scaling.scales()(3);
  expected = -expected.normalized();
  for (int i = 0; i < 4; ++i) CHECK(tangent(i) == Near(expected(i)));
}

TEST_CASE("tangent: the bordered tangent keeps the orientation of the previous one") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  Scaling scaling({0}, 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Constant(1, 1.0));
  Linearization fold;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(-1.0, 2.0 / 3.0), &fold));
  for (double sign : {1.0, -1.0}) {
    const Eigen::Vector2d previous = sign * Eigen::Vector2d(1.0, 0.1).normalized();
    Eigen::VectorXd tangent;
    REQUIRE(NextTangent(fold, scaling, 1.0, previous, &tangent));
    CHECK(tangent.dot(previous) > 0.0);
    CHECK(tangent(0) == Near(sign));
    CHECK(tangent(1) == Near(0.0));
  }
}

}  // namespace
}  // namespace nfrc
