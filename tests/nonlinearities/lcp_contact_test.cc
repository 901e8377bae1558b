#include "nonlinearities/lcp_contact.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "nonlinearities/jacobian_check.h"
#include "nonlinearities/law_test_support.h"

namespace nfrc {
namespace {

// Away from ties of the min the law is linear in y on each sample, so central differences
// are exact up to round-off: 1e-7 relative step, 1e-6 tolerance.
constexpr double kFdStep = 1e-7;
constexpr double kFdTolerance = 1e-6;
// No sample has |ε g − λ| below this share of the largest force, so a step of relative
// size kFdStep switches no branch of the min.
constexpr double kTieMargin = 1e-3;

// H = 5 on the square grid N_t = 11 (the law's continuation form).
struct Setup {
  HarmonicSet set{5, false, 11};
  FourierTransform fourier{set};
  Condensation condensation;
  NonlinearityContext ctx;
  Setup(std::vector<int> retained, std::vector<int> local)
      : condensation(testing::ChainModel(), std::move(retained), set,
                     {ForcingTerm{3, 1, 1e5, 0.0}}) {
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = std::move(local);
    ctx.own_offset = condensation.num_unknowns();
  }
};

// Displacements ~1e-4 m and forces ~1e4 N (own unknowns λ/ε), half the samples at zero
// force, redrawn until no sample is within kTieMargin of the corner ε g = λ = 0 of the
// Fischer–Burmeister function.
Eigen::VectorXd StateAwayFromTies(const LcpContact& law, Setup& s, std::mt19937& rng) {
  const int nx = s.condensation.num_unknowns();
  const int nt = s.set.num_samples();
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    Eigen::VectorXd y(nx + nt);
    for (int i = 0; i < nx; ++i) y(i) = 1e-4 * normal(rng) / (1 + i % s.set.NumCoefficients());
    const double epsilon = law.EpsilonFor(s.ctx);
    for (int j = 0; j < nt; ++j) {
      y(nx + j) = j % 2 == 0 ? 0.0 : 1e4 * std::abs(normal(rng)) / epsilon;
    }
    const Eigen::VectorXd gap = law.RawSamples(s.ctx, y, 0.0)[0].samples;
    const Eigen::VectorXd force = epsilon * y.tail(nt);
    double corner = INFINITY;
    int penetrated = 0;
    for (int j = 0; j < nt; ++j) {
      corner = std::min(corner, std::hypot(epsilon * gap(j), force(j)));
      penetrated += gap(j) < 0.0;
    }
    if (penetrated > 0 && penetrated < nt && corner > kTieMargin * force.maxCoeff()) return y;
  }
  FAIL("no state away from ties");
  return {};
}

TEST_CASE("LCP contact: semismooth Jacobian and ω-derivative match finite differences") {
  std::mt19937 rng(11);
  const double omega = 3.0e4;
  struct Variant {
    const char* name;
    std::vector<int> retained;
    std::vector<int> local;
    int other;
    double obstacle_stiffness;
  };
  const Variant variants[] = {{"rigid, contact DOF alone", {3}, {0}, -1, 0.0},
                              {"rigid, with another retained DOF", {1, 3}, {1}, -1, 0.0},
                              {"flexible obstacle", {1, 3}, {1}, -1, 4e9},
                              {"between two model DOFs", {3, 1}, {0, 1}, 1, 0.0}};
  for (const Variant& v : variants) {
    CAPTURE(v.name);
    Setup s(v.retained, v.local);
    if (v.obstacle_stiffness > 0.0) {
      std::vector<double> compliance(v.retained.size(), 0.0);
      compliance[v.local[0]] = 1.0 / v.obstacle_stiffness;
      s.condensation.SetObstacleCompliance(compliance);
    }
    s.condensation.Update(omega);
    ContactGeometry geometry;
    geometry.dof = 3;
    geometry.other = v.other;
    geometry.gap = 2e-5;
    geometry.gap_harmonics = {{1, 1e-6, -2e-6}};
    const LcpContact law(geometry, v.obstacle_stiffness, 0.0);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd y = StateAwayFromTies(law, s, rng);
      const JacobianCheckResult r =
          CheckNonlinearityJacobian(law, s.ctx, &s.condensation, y, omega, kFdStep, 1e-5);
      CHECK(r.y_error < kFdTolerance);
      CHECK(r.residual_error <= kSameResidual);
      CHECK(r.omega_error < kFdTolerance);
    }
  }
}

TEST_CASE("LCP contact: the residual vanishes exactly on complementary samples") {
  // Independent of the Jacobian: the rows are φ(ε g_j, λ_j) = ε g + λ − √((ε g)² + λ²),
  // zero iff the pair is complementary and non-negative, and the force rows carry n·P·λ.
  Setup s({3}, {0});
  s.condensation.Update(2e4);
  ContactGeometry geometry;
  geometry.dof = 3;
  geometry.gap = 1e-5;
  const double epsilon = 1e9;
  const LcpContact law(geometry, 0.0, epsilon);
  const int nx = s.condensation.num_unknowns();
  const int nt = s.set.num_samples();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(nx + nt);
  y(0) = 1e-5;  // x = 1e-5 m constant: g = 0 on every sample, so any λ ≥ 0 is complementary
  for (int j = 0; j < nt; ++j) y(nx + j) = j / epsilon;  // λ_j = j N
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(nx + nt);
  law.Evaluate(s.ctx, y, 2e4, residual, nullptr, nullptr);
  CHECK(residual.tail(nt).cwiseAbs().maxCoeff() < 1e-9);
  // Mean of λ = 0..10 N is 5 N on harmonic 0 (n = +1).
  CHECK(residual(0) == doctest::Approx(5.0));
  y(0) = 2e-5;  // penetration 1e-5 m: ε g = −1e4 N on every sample
  residual.setZero();
  law.Evaluate(s.ctx, y, 2e4, residual, nullptr, nullptr);
  for (int j = 0; j < nt; ++j) {
    const double a = -1e4;
    const double b = j;
    CHECK(residual(nx + j) == doctest::Approx(a + b - std::sqrt(a * a + b * b)));
  }
}

TEST_CASE("LCP contact: continuation needs square Fourier matrices and the full set") {
  ContactGeometry geometry;
  geometry.dof = 0;
  const LcpContact law(geometry, 0.0, 0.0);
  CHECK_NOTHROW(law.CheckForContinuation(HarmonicSet(5, false, 11)));
  try {
    law.CheckForContinuation(HarmonicSet(5, false, 64));
    FAIL("oversampled set accepted");
  } catch (const std::invalid_argument& error) {
    CHECK(std::string(error.what()).rfind("harmonics.samples: ", 0) == 0);
  }
  CHECK_THROWS_AS(law.CheckForContinuation(HarmonicSet(5, true, 11)), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
