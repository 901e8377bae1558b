#include "nonlinearities/jenkins.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "nonlinearities/jacobian_check.h"

namespace nfrc {
namespace {

constexpr double kPi = std::numbers::pi;
// The residual's return mapping (switches resolved between the samples) is C¹ in y away from
// the birth of a stick or slip phase, so central differences agree to O(δ²) and round-off
// (1e-16 / 1e-7 relative over O(1) entries).
constexpr double kFdTolerance = 1e-6;
constexpr double kFdStep = 1e-7;
// A sampled trial force this far (relative to μN) from the slip limit: the test's play
// operator and the law's sampled Sweep then agree sample by sample.
constexpr double kSwitchMargin = 1e-3;

struct Setup {
  HarmonicSet set;
  FourierTransform fourier;
  NonlinearityContext ctx;
  Setup(bool relative, int max_harmonic, bool odd_only, int samples)
      : set(max_harmonic, odd_only, samples), fourier(set) {
    ctx.fourier = &fourier;
    ctx.local_dofs = relative ? std::vector<int>{0, 1} : std::vector<int>{1};
    ctx.own_offset = 2 * set.NumCoefficients();
  }
};

// The return mapping written out independently of Jenkins::Sweep: the slider w follows the
// play operator w_j = clamp(w_{j−1}, u_j − μN/k_t, u_j + μN/k_t) from w = 0, two passes.
// Returns the second pass's force and the smallest distance ||k_t(u_j − w_{j−1})| − μN| / μN
// over both passes (how near a sample is to switching).
std::pair<Eigen::VectorXd, double> PlayOperator(const Eigen::VectorXd& u, double k, double limit) {
  const double r = limit / k;
  double w = 0.0, margin = INFINITY;
  Eigen::VectorXd force(u.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (Eigen::Index j = 0; j < u.size(); ++j) {
      margin = std::min(margin, std::abs(std::abs(k * (u(j) - w)) - limit) / limit);
      w = std::clamp(w, u(j) - r, u(j) + r);
      if (pass == 1) force(j) = k * (u(j) - w);
    }
  }
  return {force, margin};
}

TEST_CASE("jenkins: Jacobian and omega-derivative match finite differences") {
  std::mt19937 rng(20261125);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (bool relative : {false, true}) {
    for (bool odd_only : {true, false}) {
      CAPTURE(relative);
      CAPTURE(odd_only);
      const Setup s(relative, 5, odd_only, 64);
      const int nc = s.set.NumCoefficients();
      const double k = 3.0, limit = 2.0;
      const Jenkins law(relative ? 0 : 1, relative ? 1 : -1, k, limit);
      int checked = 0, with_slip = 0;
      for (int attempt = 0; attempt < 2000 && checked < 6; ++attempt) {
        Eigen::VectorXd y(2 * nc);
        for (int i = 0; i < y.size(); ++i) y(i) = normal(rng) / (1 + i % nc);
        // Amplitudes from below the slip limit (stick throughout) to well above it.
        y *= (checked % 3 == 0 ? 0.2 : 1.5);
        Eigen::VectorXd u_coefficients = y.segment(s.ctx.DofOffset(0), nc);
        if (relative) u_coefficients -= y.segment(s.ctx.DofOffset(1), nc);
        const Eigen::VectorXd u = s.fourier.ToTime(u_coefficients).col(0);
        const auto [force, margin] = PlayOperator(u, k, limit);
        if (margin < kSwitchMargin) continue;
        const SlipHistory history = law.Sweep(u);
        CHECK((history.force - force).cwiseAbs().maxCoeff() < 1e-12 * limit);
        with_slip += history.Slips();
        const JacobianCheckResult result =
            CheckNonlinearityJacobian(law, s.ctx, nullptr, y, 0.7, kFdStep, 1.0);
        CHECK(result.y_error < kFdTolerance);
        CHECK(result.residual_error <= kSameResidual);
        CHECK(result.omega_error < kFdTolerance);
        ++checked;
      }
      CHECK(checked == 6);
      CHECK(with_slip >= 2);
      CHECK(with_slip < checked);
    }
  }
}

// Below the slip limit the slider never moves: the element is the linear spring k_t, so the
// residual is k_t ũ and the Jacobian k_t I exactly (up to the transform's round-off).
TEST_CASE("jenkins: below the slip limit it is the linear spring k_t") {
  const Setup s(false, 7, false, 32);
  const int nc = s.set.NumCoefficients();
  const double k = 5.0;
  const Jenkins law(1, -1, k, 1e6);
  Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(2 * nc, -1.0, 2.0);
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(y.size());
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(y.size(), y.size());
  law.Evaluate(s.ctx, y, 1.0, residual, &jacobian, nullptr);
  const int row = s.ctx.DofOffset(0);
  CHECK((residual.segment(row, nc) - k * y.segment(row, nc)).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((jacobian.block(row, row, nc, nc) - k * Eigen::MatrixXd::Identity(nc, nc))
            .cwiseAbs()
            .maxCoeff() < 1e-12);
}

// For u = U cos θ with U > μN/k_t the force traces Masing's loop, whose area (the energy
// dissipated per cycle) is 4μN(U − μN/k_t). The harmonic force gives it as ∮ f du = −πU·b_1
// (b_1 the sin coefficient of f). The residual integrates the loop exactly (the sampled
// mapping's trapezoidal rule erred by O(1/N_t²) ≈ 1e-5 at N_t = 512).
TEST_CASE("jenkins: energy per cycle is the area of Masing's loop") {
  constexpr double kLoopTolerance = 1e-12;
  const Setup s(false, 1, true, 512);
  const int nc = s.set.NumCoefficients();
  const double k = 4.0, limit = 3.0;
  const Jenkins law(1, -1, k, limit);
  for (double amplitude : {1.0, 2.5, 10.0}) {
    CAPTURE(amplitude);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * nc);
    y(s.ctx.DofOffset(0) + s.set.CosIndex(0)) = amplitude;
    Eigen::VectorXd residual = Eigen::VectorXd::Zero(y.size());
    law.Evaluate(s.ctx, y, 1.0, residual, nullptr, nullptr);
    const double b1 = residual(s.ctx.DofOffset(0) + s.set.SinIndex(0));
    const double dissipated = -kPi * amplitude * b1;
    const double loop = 4.0 * limit * (amplitude - limit / k);
    CHECK(std::abs(dissipated - loop) < kLoopTolerance * loop);
  }
}

TEST_CASE("jenkins: bad parameters are refused naming the field") {
  CHECK_THROWS_WITH_AS(Jenkins(0, -1, 0.0, 1.0), doctest::Contains("stiffness"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(Jenkins(0, -1, 1.0, -1.0), doctest::Contains("mu*normal_load"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(Jenkins(0, 0, 1.0, 1.0), doctest::Contains("other"), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
