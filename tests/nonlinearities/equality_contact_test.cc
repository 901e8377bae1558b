#include "nonlinearities/equality_contact.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "nonlinearities/jacobian_check.h"

namespace nfrc {
namespace {

// Away from switches the law is linear on every sample, so central differences are exact up
// to round-off: 1e-16 / 1e-7 relative over O(1) entries.
constexpr double kFdTolerance = 1e-6;
constexpr double kFdStep = 1e-7;
// A sample with |λ − ρg| above this cannot switch branch under a perturbation of kFdStep·|y|
// (basis samples are bounded by 1, ρ·|y| ~ 10).
constexpr double kSwitchMargin = 1e-3;

struct Setup {
  HarmonicSet set{6, false, 32};
  FourierTransform fourier{set};
  NonlinearityContext ctx;
  explicit Setup(bool relative) {
    ctx.fourier = &fourier;
    ctx.local_dofs = relative ? std::vector<int>{0, 1} : std::vector<int>{1};
    ctx.own_offset = 2 * set.NumCoefficients();
  }
};

ContactGeometry Geometry(bool relative, double direction) {
  ContactGeometry g;
  g.dof = relative ? 0 : 1;
  g.other = relative ? 1 : -1;
  g.direction = direction;
  g.gap = 0.3;
  g.gap_harmonics = {{2, 0.1, -0.05}};
  return g;
}

TEST_CASE("equality contact: Jacobian and omega-derivative match finite differences") {
  std::mt19937 rng(20261125);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double rho = 2.5;
  for (bool relative : {false, true}) {
    for (double direction : {1.0, -1.0}) {
      CAPTURE(relative);
      CAPTURE(direction);
      const Setup s(relative);
      const int nc = s.set.NumCoefficients();
      const EqualityContact law(Geometry(relative, direction), 0.0, rho);
      int checked = 0;
      for (int attempt = 0; attempt < 1000 && checked < 4; ++attempt) {
        Eigen::VectorXd y(3 * nc);
        for (int i = 0; i < y.size(); ++i) y(i) = normal(rng) / (1 + i % nc);
        const ContactState state = law.State(s.ctx, y);
        const Eigen::VectorXd lambda = s.fourier.ToTime(y.tail(nc)).col(0);
        const double margin = (lambda - rho * state.gap).cwiseAbs().minCoeff();
        if (margin < kSwitchMargin) continue;
        // Both branches must be present for the check to cover them.
        const Eigen::Index contact = (lambda.array() > rho * state.gap.array()).count();
        if (contact == 0 || contact == lambda.size()) continue;
        const JacobianCheckResult result =
            CheckNonlinearityJacobian(law, s.ctx, nullptr, y, 0.9, kFdStep, 1.0);
        CHECK(result.y_error < kFdTolerance);
        CHECK(result.residual_error <= kSameResidual);
        CHECK(result.omega_error < kFdTolerance);
        ++checked;
      }
      CHECK(checked == 4);
    }
  }
}

// The zero set of min(λ, ρg) sample by sample is Signorini's: a force and gap that satisfy
// g ≥ 0, λ ≥ 0, gλ = 0 on every sample give a zero residual in the law's rows, whatever ρ;
// a penetrating sample or a tensile force does not.
TEST_CASE("equality contact: the law's rows vanish exactly on Signorini's conditions") {
  // Constant signals: g = 0.2 > 0 with λ = 0 (open) and g = 0 with
  // λ = 3 (closed) are both solutions; g = −0.1 (penetration) with λ = 0 and g = 0.2 with
  // λ = −1 (tension) are not.
  const HarmonicSet set(1, false, 4);
  const int nc = set.NumCoefficients();
  const FourierTransform fourier(set);
  NonlinearityContext ctx;
  ctx.fourier = &fourier;
  ctx.local_dofs = {0};
  ctx.own_offset = nc;
  struct Case {
    double gap, force;
    bool solution;
  };
  for (const Case c : {Case{0.2, 0.0, true}, Case{0.0, 3.0, true}, Case{-0.1, 0.0, false},
                       Case{0.2, -1.0, false}}) {
    CAPTURE(c.gap);
    CAPTURE(c.force);
    for (double rho : {0.1, 1.0, 40.0}) {
      ContactGeometry g;
      g.dof = 0;
      g.gap = c.gap;
      const EqualityContact law(g, 0.0, rho);
      Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * nc);
      y(nc + set.CosIndex(0)) = c.force;
      Eigen::VectorXd residual = Eigen::VectorXd::Zero(2 * nc);
      law.Evaluate(ctx, y, 1.0, residual, nullptr, nullptr);
      const double law_row = residual(nc + set.CosIndex(0));
      if (c.solution) {
        CHECK(law_row == 0.0);
      } else {
        CHECK(std::abs(law_row) > 0.0);
      }
    }
  }
}

TEST_CASE("equality contact: bad parameters are refused naming the field") {
  CHECK_THROWS_WITH_AS(EqualityContact(Geometry(false, 1.0), 0.0, -1.0), doctest::Contains("rho"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(EqualityContact(Geometry(true, 1.0), 1e6, 1.0),
                       doctest::Contains("obstacle_stiffness"), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
