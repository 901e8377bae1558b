#include "nonlinearities/dlft_friction.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "nonlinearities/jacobian_check.h"
#include "nonlinearities/law_test_support.h"

namespace nfrc {
namespace {

// Away from switches DLFT friction is linear in y on every sample (the anchors are frozen), so
// central differences are exact up to round-off: 1e-7 relative step, 1e-6 tolerance.
constexpr double kFdStep = 1e-7;
constexpr double kFdTolerance = 1e-6;
// A trial force this far (relative to μN) from the slip limit cannot cross it under a
// perturbation of relative size kFdStep (ε·|z| is at most a few μN here).
constexpr double kSwitchMargin = 1e-4;

struct Setup {
  HarmonicSet set{5, false, 64};
  FourierTransform fourier{set};
  Condensation condensation;
  NonlinearityContext ctx;
  Setup(std::vector<int> retained, std::vector<int> local)
      : condensation(testing::ChainModel(), retained, set, {ForcingTerm{3, 1, 1e5, 0.0}}) {
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = std::move(local);
  }
};

// The smallest ||ε(z_j − w_{j−1})| − μN| / μN over both passes of the play operator, written
// out independently of ReturnMapping.
double SwitchMargin(const Eigen::VectorXd& z, double epsilon, double limit) {
  double w = 0.0, margin = INFINITY;
  for (int pass = 0; pass < 2; ++pass) {
    for (Eigen::Index j = 0; j < z.size(); ++j) {
      margin = std::min(margin, std::abs(std::abs(epsilon * (z(j) - w)) - limit) / limit);
      w = std::clamp(w, z(j) - limit / epsilon, z(j) + limit / epsilon);
    }
  }
  return margin;
}

TEST_CASE("dlft friction: Jacobian and omega-derivative match finite differences") {
  struct Variant {
    const char* name;
    std::vector<int> retained, local;
    int other;
  };
  const Variant variants[] = {{"against ground", {1, 3}, {1}, -1},
                              {"between two model DOFs", {3, 1}, {0, 1}, 1}};
  std::mt19937 rng(20261125);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double omega = 2.0e4, epsilon = 2.0e9, limit = 5.0e4;
  for (const Variant& v : variants) {
    CAPTURE(v.name);
    Setup s(v.retained, v.local);
    s.condensation.Update(omega);
    const DlftFriction law(3, v.other, limit, epsilon);
    const int n = s.condensation.num_unknowns();
    int checked = 0, with_slip = 0;
    for (int attempt = 0; attempt < 2000 && checked < 4; ++attempt) {
      Eigen::VectorXd y(n);
      for (int i = 0; i < n; ++i) y(i) = 1e-4 * normal(rng) / (1 + i % s.set.NumCoefficients());
      const Eigen::VectorXd z = law.Input(s.ctx, y, omega);
      if (SwitchMargin(z, epsilon, limit) < kSwitchMargin) continue;
      const JacobianCheckResult result =
          CheckNonlinearityJacobian(law, s.ctx, &s.condensation, y, omega, kFdStep, 1e-4);
      CHECK(result.y_error < kFdTolerance);
      CHECK(result.residual_error <= kSameResidual);
      CHECK(result.omega_error < kFdTolerance);
      with_slip += ReturnMapping(z, epsilon, limit).Slips();
      ++checked;
    }
    CHECK(checked == 4);
    CHECK(with_slip >= 1);
  }
}

// At a fixed point of DLFT (λ = λ_u on the samples) the force is Coulomb's: with the linear
// rows of a single grounded DOF the prediction is z = u + λ_u/ε, and a sliding sample's force
// is ±μN. Here: the law's force where every sample slips is the sign of z's increments.
TEST_CASE("dlft friction: sliding throughout gives the force +-muN with the sign of motion") {
  Setup s({3}, {0});
  const double omega = 2.0e4, epsilon = 1e9, limit = 10.0;
  s.condensation.Update(omega);
  const DlftFriction law(3, -1, limit, epsilon);
  const int nc = s.set.NumCoefficients();
  // A large harmonic-1 motion: the limit is reached within a sample of each reversal.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(nc);
  y(s.set.CosIndex(1)) = 1e-3;
  const Eigen::VectorXd z = law.Input(s.ctx, y, omega);
  const SlipHistory history = ReturnMapping(z, epsilon, limit);
  int sliding = 0;
  for (Eigen::Index j = 0; j < z.size(); ++j) {
    const double dz = z(j) - z((j + z.size() - 1) % z.size());
    if (!history.Sticks(static_cast<int>(j))) {
      ++sliding;
      CHECK(history.force(j) == doctest::Approx(std::copysign(limit, dz)));
    }
  }
  CHECK(sliding > z.size() / 2);
}

TEST_CASE("dlft friction: bad parameters are refused naming the field") {
  CHECK_THROWS_WITH_AS(DlftFriction(0, -1, 1.0, 0.0), doctest::Contains("epsilon"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(DlftFriction(0, -1, -1.0, 1.0), doctest::Contains("mu*normal_load"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(DlftFriction(1, 1, 1.0, 1.0), doctest::Contains("other"),
                       std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
