#include "nonlinearities/polynomial_spring.h"

#include <doctest/doctest.h>

#include <cmath>

#include "core/errors.h"
#include "nonlinearities/jacobian_check.h"
#include "nonlinearities/law_test_support.h"

namespace nfrc {
namespace {

using testing::TwoDofModel;

// Central differences with relative step 1e-6 on a cubic have truncation error ~h² ≈ 1e-12
// and round-off ~1e-16/1e-6 = 1e-10 relative; 1e-7 leaves margin without hiding a wrong entry.
constexpr double kFdTolerance = 1e-7;
constexpr double kFdStep = 1e-6;

NonlinearityContext Context(const FourierTransform& fourier, std::vector<int> local_dofs) {
  NonlinearityContext ctx;
  ctx.fourier = &fourier;
  ctx.local_dofs = std::move(local_dofs);
  return ctx;
}

TEST_CASE("cubic spring to ground: AFT force equals the exact harmonic projection") {
  // x = A cos θ gives k A³ cos³θ = k A³ (3/4 cos θ + 1/4 cos 3θ): exact reference.
  const HarmonicSet set(5, true);
  const FourierTransform fourier(set);
  PolynomialSpring spring("cubic_spring", 0, -1, {{3, 0.7}});
  Eigen::VectorXd y = Eigen::VectorXd::Zero(set.NumCoefficients());
  const double amplitude = 1.3;
  y(set.CosIndex(0)) = amplitude;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(y.size());
  spring.Evaluate(Context(fourier, {0}), y, 1.0, r, nullptr, nullptr);
  const double cube = 0.7 * std::pow(amplitude, 3);
  CHECK(r(set.CosIndex(0)) == doctest::Approx(0.75 * cube).epsilon(1e-13));
  CHECK(r(set.CosIndex(1)) == doctest::Approx(0.25 * cube).epsilon(1e-13));
  CHECK(std::abs(r(set.SinIndex(0))) < 1e-13);
  CHECK(std::abs(r(set.CosIndex(2))) < 1e-13);
}

TEST_CASE("polynomial spring Jacobians match finite differences, grounded and between DOFs") {
  for (bool odd_only : {true, false}) {
    const HarmonicSet set(7, odd_only);
    const FourierTransform fourier(set);
    const int nc = set.NumCoefficients();
    Eigen::VectorXd y = Eigen::VectorXd::Random(2 * nc);

    PolynomialSpring grounded("polynomial_spring", 1, -1, {{2, 0.3}, {3, 1.1}, {5, -0.2}});
    auto result =
        CheckNonlinearityJacobian(grounded, Context(fourier, {1}), nullptr, y, 0.9, kFdStep, 1.0);
    CHECK(result.y_error < kFdTolerance);
    CHECK(result.residual_error <= kSameResidual);

    PolynomialSpring between("cubic_spring", 0, 1, {{3, 2.0}});
    result =
        CheckNonlinearityJacobian(between, Context(fourier, {0, 1}), nullptr, y, 0.9, kFdStep, 1.0);
    CHECK(result.y_error < kFdTolerance);
    CHECK(result.residual_error <= kSameResidual);
    // A displacement law: the ω column is exactly zero, analytically and by differences.
    CHECK(result.omega_error == 0.0);
  }
}

TEST_CASE("spring between two DOFs acts equal and opposite") {
  const HarmonicSet set(3, false);
  const FourierTransform fourier(set);
  const int nc = set.NumCoefficients();
  PolynomialSpring spring("cubic_spring", 0, 1, {{3, 1.0}});
  const Eigen::VectorXd y = Eigen::VectorXd::Random(2 * nc);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * nc);
  spring.Evaluate(Context(fourier, {0, 1}), y, 1.0, r, nullptr, nullptr);
  CHECK((r.head(nc) + r.tail(nc)).norm() < 1e-14 * r.norm());
  CHECK(r.norm() > 0.0);
}

}  // namespace
}  // namespace nfrc
