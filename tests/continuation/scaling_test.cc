#include "continuation/scaling.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::DuffingFoldFrequency;
using testing::DuffingProblem;
using testing::UnitsProblem;

// Closed-form quantities computed in a handful of flops agree to rounding.
constexpr double kRoundoff = 1e-13;

doctest::Approx Near(double value) { return doctest::Approx(value).epsilon(kRoundoff); }

// Physical units of the twin run: displacements ~1e-4 m, ω ~ 1e4 rad/s, forces ~1e9 N.
constexpr double kLengthUnit = 1e-4;
constexpr double kFrequencyUnit = 1e4;
constexpr double kForceUnit = 1e9;
// Both runs see the same scaled problem up to the rounding of the unit conversions
// (a few ulps per evaluation); Newton and the LU amplify that by the conditioning, which
// is O(1) in scaled variables except near folds, so 1e-9 relative leaves ample room while
// any unit dependence of the engine (steps, tolerances, pivoting) would show at O(1).
constexpr double kTwinTolerance = 1e-9;

TEST_CASE("scaling: group scales are the running max of |y|, floored, and never shrink") {
  Scaling scaling({7, 7, 3}, 2.0, 1e-3);
  CHECK(scaling.num_unknowns() == 3);
  CHECK(scaling.lambda_scale() == 2.0);
  scaling.Include(Eigen::Vector3d(0.5, -4.0, 1e-9));
  CHECK(scaling.scales()(0) == 4.0);
  CHECK(scaling.scales()(1) == 4.0);
  // Group 3 is tiny: floored at scale_floor × the largest group scale.
  CHECK(scaling.scales()(2) == Near(4e-3));
  CHECK(scaling.scales()(3) == 2.0);
  scaling.Include(Eigen::Vector3d(0.1, 0.1, 0.1));
  CHECK(scaling.scales()(0) == 4.0);
  CHECK(scaling.scales()(2) == 0.1);
  CHECK(scaling.Norm(Eigen::Vector4d(4.0, 0.0, 0.0, 2.0)) == Near(std::sqrt(2.0)));
  CHECK(scaling.UnitScaled(Eigen::Vector4d(0.0, 0.0, 0.0, 5.0)) ==
        Eigen::Vector4d(0.0, 0.0, 0.0, 1.0));
}

TEST_CASE("scaling: an all-zero start is seeded from a sensitivity, never left at zero") {
  Scaling scaling({0, 1}, 1.0, 1e-6);
  scaling.Include(Eigen::Vector2d(0.0, 0.0));
  CHECK(scaling.HasZeroGroup());
  CHECK(scaling.scales()(0) > 0.0);
  scaling.SeedZeroGroups(Eigen::Vector2d(3.0, -5.0));
  CHECK_FALSE(scaling.HasZeroGroup());
  CHECK(scaling.scales()(0) == 3.0);
  CHECK(scaling.scales()(1) == 5.0);
  // Seeding does not override a group that has been seen.
  scaling.SeedZeroGroups(Eigen::Vector2d(30.0, 50.0));
  CHECK(scaling.scales()(0) == 3.0);
}

TEST_CASE("scaling: lambda scale from the options") {
  ContinuationOptions options;
  options.lambda_start = -3.0;
  options.lambda_end = 2.0;
  CHECK(LambdaScale(options) == 3.0);
  options.lambda_scale = 0.25;
  CHECK(LambdaScale(options) == 0.25);
}

void CheckTwins(ContinuationProblem& plain, const Eigen::VectorXd& plain_guess,
                const Eigen::VectorXd& y_unit) {
  ContinuationOptions options;
  options.lambda_start = 0.5;
  options.lambda_end = 1.6;
  const Branch reference = Continue(plain, plain_guess, options);

  UnitsProblem physical(plain, y_unit, kFrequencyUnit, kForceUnit);
  ContinuationOptions physical_options = options;  // same steps and tolerances
  physical_options.lambda_start = options.lambda_start * kFrequencyUnit;
  physical_options.lambda_end = options.lambda_end * kFrequencyUnit;
  const Branch twin = Continue(physical, plain_guess.cwiseProduct(y_unit), physical_options);

  REQUIRE(reference.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(twin.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(twin.points.size() == reference.points.size());
  REQUIRE(twin.summary.history.size() == reference.summary.history.size());
  CHECK(twin.summary.total_newton_iterations == reference.summary.total_newton_iterations);
  for (size_t i = 0; i < reference.points.size(); ++i) {
    const BranchPoint& expected = reference.points[i];
    const BranchPoint& actual = twin.points[i];
    CAPTURE(i);
    CHECK(actual.lambda / kFrequencyUnit ==
          doctest::Approx(expected.lambda).epsilon(kTwinTolerance));
    const double y_size = expected.y.cwiseAbs().maxCoeff();
    CHECK((actual.y.cwiseQuotient(y_unit) - expected.y).cwiseAbs().maxCoeff() <=
          kTwinTolerance * y_size);
    CHECK(actual.step == doctest::Approx(expected.step).epsilon(kTwinTolerance));
    CHECK(actual.newton_iterations == expected.newton_iterations);
  }
  REQUIRE(twin.folds.size() == 2);
  REQUIRE(reference.folds.size() == 2);
  for (size_t i = 0; i < 2; ++i) {
    CHECK(twin.folds[i].lambda / kFrequencyUnit ==
          doctest::Approx(reference.folds[i].lambda).epsilon(kTwinTolerance));
  }
  // Both are right, too: the folds of the amplitude relation (fold_tolerance 1e-8).
  CHECK(twin.folds[0].lambda / kFrequencyUnit ==
        doctest::Approx(DuffingFoldFrequency(1.05, 1.6, true)).epsilon(1e-8));
  CHECK(twin.folds[1].lambda / kFrequencyUnit ==
        doctest::Approx(DuffingFoldFrequency(1.05, 1.6, false)).epsilon(1e-8));
}

TEST_CASE("scaling: a Duffing problem in physical units takes the same steps") {
  DuffingProblem plain;
  const double static_amplitude = DuffingProblem::kForce / (1.0 - 0.25);
  CheckTwins(plain, Eigen::Vector2d(static_amplitude, 0.0), Eigen::Vector2d::Constant(kLengthUnit));
}

TEST_CASE("scaling: unknowns of two units in two scale groups take the same steps") {
  // z = A² is in m² while a, b are in m: each group gets its own scale.
  DuffingProblem plain(/*with_energy=*/true);
  const double static_amplitude = DuffingProblem::kForce / (1.0 - 0.25);
  CheckTwins(plain, Eigen::Vector3d(static_amplitude, 0.0, static_amplitude * static_amplitude),
             Eigen::Vector3d(kLengthUnit, kLengthUnit, kLengthUnit * kLengthUnit));
}

}  // namespace
}  // namespace nfrc
