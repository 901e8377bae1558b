#include "nonlinearities/coulomb_friction.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "core/errors.h"
#include "nonlinearities/jacobian_check.h"

namespace nfrc {
namespace {

// Away from switching instants every law is smooth on each sample, so central differences
// with relative step 1e-7 are accurate to ~1e-7 (round-off 1e-16/1e-7 over O(1) entries).
constexpr double kFdTolerance = 1e-6;
constexpr double kFdStep = 1e-7;
// A sample whose switching functions are this far from zero cannot change branch under a
// perturbation of size kFdStep·|y| (the basis functions are bounded by 1, ω·k by ~10).
constexpr double kSwitchMargin = 1e-3;

// Distance of the sample (v, r) from the law's switching surfaces (∞ for smooth laws).
double SwitchDistance(const FrictionParameters& p, double v, double r) {
  switch (p.equality) {
    case FrictionEquality::kMinMax:
      return std::min(std::abs(p.rho * (r + p.limit) - v), std::abs(p.rho * (r - p.limit) - v));
    case FrictionEquality::kHueber:
      return std::min(std::abs(std::abs(r - p.rho * v) - p.limit), std::abs(r - p.rho * v));
    case FrictionEquality::kPiecewiseLinear:
      return std::min(std::abs(v - p.delta), std::abs(v + p.delta));
    case FrictionEquality::kSign:
      return std::abs(v);
    default:
      return INFINITY;
  }
}

struct Setup {
  HarmonicSet set{7, true, 32};
  FourierTransform fourier{set};
  NonlinearityContext ctx;
  Setup(bool relative) {
    ctx.fourier = &fourier;
    ctx.local_dofs = relative ? std::vector<int>{0, 1} : std::vector<int>{1};
    ctx.own_offset = 2 * set.NumCoefficients();
  }
};

// A random state (two displacement signals, one force signal) with every sample at least
// kSwitchMargin from a switch; counts how many samples are on each active branch.
Eigen::VectorXd StateAwayFromSwitches(const CoulombFriction& law, const Setup& s, double omega,
                                      std::mt19937& rng) {
  const int nc = s.set.NumCoefficients();
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int attempt = 0; attempt < 10000; ++attempt) {
    Eigen::VectorXd y(3 * nc);
    for (int i = 0; i < y.size(); ++i) y(i) = normal(rng) / (1 + i % nc);
    y.tail(nc) *= 1.5 * law.parameters().limit;
    const Eigen::VectorXd v = s.fourier.ToTime(law.VelocityCoefficients(s.ctx, y, omega));
    const Eigen::VectorXd r = s.fourier.ToTime(y.tail(nc));
    double distance = INFINITY;
    for (int j = 0; j < v.size(); ++j) {
      distance = std::min(distance, SwitchDistance(law.parameters(), v(j), r(j)));
    }
    if (distance > kSwitchMargin) return y;
  }
  FAIL("no state away from switches found");
  return {};
}

// Calls check(law, setup, relative) for every friction equality, against ground and between
// two DOFs, with parameters that put samples on every branch of each law.
template <typename Check>
void ForEachFrictionLaw(const Check& check) {
  const FrictionEquality laws[] = {
      FrictionEquality::kMinMax, FrictionEquality::kHueber,          FrictionEquality::kTanh,
      FrictionEquality::kArctan, FrictionEquality::kPiecewiseLinear, FrictionEquality::kSign};
  for (FrictionEquality equality : laws) {
    for (bool relative : {false, true}) {
      CAPTURE(ToString(equality));
      CAPTURE(relative);
      FrictionParameters p;
      p.equality = equality;
      p.limit = 9.0;
      p.rho = 0.7;
      p.alpha = 3.0;
      p.delta = 0.5;
      const CoulombFriction law(relative ? 0 : 1, relative ? 1 : -1, p);
      const Setup setup(relative);
      check(law, setup, relative);
    }
  }
}

TEST_CASE("every friction law: Jacobian and ω-derivative match finite differences") {
  std::mt19937 rng(20261122);
  ForEachFrictionLaw([&](const CoulombFriction& law, const Setup& setup, bool /*relative*/) {
    const double omega = 0.8;
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::VectorXd y = StateAwayFromSwitches(law, setup, omega, rng);
      const JacobianCheckResult result =
          CheckNonlinearityJacobian(law, setup.ctx, nullptr, y, omega, kFdStep, 1.0);
      CHECK(result.y_error < kFdTolerance);
      CHECK(result.residual_error <= kSameResidual);
      CHECK(result.omega_error < kFdTolerance);
    }
  });
}

// Hill's Δ1 block: the law depends on the displacements only through v = ωDx, so the
// displacement columns of its Jacobian are J_v·ωD. Central differences of the residual in x
// (at fixed force coefficients) give them; on an odd-only set D is invertible, so this checks
// every entry of the velocity Jacobian J_v.
TEST_CASE(
    "every friction law: the velocity Jacobian for Hill's method matches finite differences") {
  std::mt19937 rng(20261124);
  ForEachFrictionLaw([&](const CoulombFriction& law, const Setup& setup, bool relative) {
    const double omega = 0.8;
    const int nc = setup.set.NumCoefficients();
    const Eigen::VectorXd y = StateAwayFromSwitches(law, setup, omega, rng);
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(y.size(), y.size());
    Eigen::MatrixXd velocity = Eigen::MatrixXd::Zero(y.size(), y.size());
    law.LinearizeForStability(setup.ctx, y, omega, &jacobian, &velocity);
    const int dof = setup.ctx.DofOffset(0), own = setup.ctx.own_offset;
    Eigen::MatrixXd fd(nc, nc);
    for (int j = 0; j < nc; ++j) {
      const double h = kFdStep * std::max(1.0, std::abs(y(dof + j)));
      Eigen::VectorXd plus = y, minus = y;
      plus(dof + j) += h;
      minus(dof + j) -= h;
      Eigen::VectorXd r_plus = Eigen::VectorXd::Zero(y.size()), r_minus = r_plus;
      law.Evaluate(setup.ctx, plus, omega, r_plus, nullptr, nullptr);
      law.Evaluate(setup.ctx, minus, omega, r_minus, nullptr, nullptr);
      fd.col(j) = (r_plus - r_minus).segment(own, nc) / (2 * h);
    }
    const Eigen::MatrixXd block = velocity.block(own, dof, nc, nc);
    const Eigen::MatrixXd expected = fd * (omega * setup.fourier.DerivativeMatrix()).inverse();
    CHECK((block - expected).norm() <= kFdTolerance * std::max(1.0, expected.norm()));
    if (relative) {
      CHECK((velocity.block(own, setup.ctx.DofOffset(1), nc, nc) + block).norm() == 0.0);
    }
  });
}

// ∂Ψ/∂(μN), which contact with friction uses for its varying limit.
TEST_CASE("every friction law: the derivative in the limit matches finite differences") {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  ForEachFrictionLaw([&](const CoulombFriction& law, const Setup& /*setup*/, bool /*relative*/) {
    int checked = 0;
    while (checked < 50) {
      FrictionParameters p = law.parameters();
      const double v = uniform(rng), r = 4.0 * uniform(rng);
      p.limit = 3.0 + uniform(rng);
      if (SwitchDistance(p, v, r) < kSwitchMargin) continue;
      const double h = kFdStep * p.limit;
      FrictionParameters plus = p, minus = p;
      plus.limit += h;
      minus.limit -= h;
      const double fd = (EvaluateFrictionEquality(plus, v, r).value -
                         EvaluateFrictionEquality(minus, v, r).value) /
                        (2 * h);
      CHECK(EvaluateFrictionEquality(p, v, r).d_limit ==
            doctest::Approx(fd).epsilon(kFdTolerance).scale(1.0));
      ++checked;
    }
  });
}

TEST_CASE("the exact laws' zero set is Coulomb's law, sliding force r = -muN sign(v)") {
  FrictionParameters p;
  p.limit = 2.0;
  for (FrictionEquality equality : {FrictionEquality::kMinMax, FrictionEquality::kHueber}) {
    p.equality = equality;
    CAPTURE(ToString(equality));
    CHECK(EvaluateFrictionEquality(p, 1.5, -2.0).value == doctest::Approx(0.0));  // slip +
    CHECK(EvaluateFrictionEquality(p, -1.5, 2.0).value == doctest::Approx(0.0));  // slip −
    CHECK(EvaluateFrictionEquality(p, 0.0, 0.7).value == doctest::Approx(0.0));   // stick
    CHECK(EvaluateFrictionEquality(p, 1.5, 2.0).value != doctest::Approx(0.0));   // wrong sign
    CHECK(EvaluateFrictionEquality(p, 0.1, 0.7).value != doctest::Approx(0.0));   // not stuck
    CHECK(EvaluateFrictionEquality(p, 0.0, 2.5).value != doctest::Approx(0.0));   // |r| > μN
  }
}

}  // namespace
}  // namespace nfrc
