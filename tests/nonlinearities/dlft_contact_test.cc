#include "nonlinearities/dlft_contact.h"

#include <doctest/doctest.h>

#include <random>

#include "nonlinearities/jacobian_check.h"

namespace nfrc {
namespace {

// Away from switching samples DLFT is linear in y on each sample (the mask is frozen), so
// central differences are exact up to round-off: 1e-7 relative step, 1e-6 tolerance.
constexpr double kFdStep = 1e-7;
constexpr double kFdTolerance = 1e-6;
// A perturbation of relative size kFdStep moves a predicted force by far less than this
// share of its largest sample, so no sample switches between contact and separation.
constexpr double kSwitchMargin = 1e-4;

// A damped four-DOF chain, clamped at DOF 0's left, forced at DOF 3; contact at DOF 3.
LinearModel Chain() {
  const int n = 4;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) += 2.0e9;
    if (i + 1 < n) {
      k(i, i + 1) = k(i + 1, i) = -1.0e9;
    }
  }
  k(n - 1, n - 1) = 1.0e9;
  LinearModel model;
  model.stiffness = k.sparseView();
  model.mass = (0.5 * m).sparseView();
  model.damping = (2e-6 * k).sparseView();
  return model;
}

struct Setup {
  HarmonicSet set{5, false, 64};
  FourierTransform fourier{set};
  Condensation condensation;
  NonlinearityContext ctx;
  Setup(std::vector<int> retained, std::vector<int> local)
      : condensation(Chain(), std::move(retained), set, {ForcingTerm{3, 1, 1e5, 0.0}}) {
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = std::move(local);
  }
};

// Random displacements of amplitude ~1e-4 m about a mean that puts part of each period in
// contact, redrawn until no predicted-force sample lies within kSwitchMargin of zero.
Eigen::VectorXd StateAwayFromSwitches(const DlftContact& law, Setup& s, double omega,
                                      std::mt19937& rng, double* contact_fraction) {
  const int n = s.condensation.num_unknowns();
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) y(i) = 1e-4 * normal(rng) / (1 + i % s.set.NumCoefficients());
    const auto samples = law.RawSamples(s.ctx, y, omega);
    // force_raw is the corrected force; rebuild the predicted one from its zero pattern.
    const Eigen::VectorXd& force = samples[1].samples;
    const Eigen::VectorXd& gap = samples[0].samples;
    const double scale = force.cwiseAbs().maxCoeff();
    int in_contact = 0;
    double distance = INFINITY;
    for (Eigen::Index j = 0; j < force.size(); ++j) {
      in_contact += force(j) > 0.0;
      if (force(j) > 0.0) distance = std::min(distance, force(j));
      // A separated sample is safe when its gap is clearly open (the prediction is then
      // clearly negative, since ε·g dominates for these states).
      if (force(j) == 0.0) distance = std::min(distance, law.epsilon() * std::abs(gap(j)));
    }
    if (in_contact > 0 && in_contact < force.size() && distance > kSwitchMargin * scale) {
      *contact_fraction = static_cast<double>(in_contact) / force.size();
      return y;
    }
  }
  FAIL("no state away from switches");
  return {};
}

TEST_CASE("DLFT contact: Jacobian and ω-derivative match finite differences") {
  std::mt19937 rng(4);
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
    const DlftContact law(geometry, v.obstacle_stiffness, 5e9);
    for (int trial = 0; trial < 5; ++trial) {
      double fraction = 0.0;
      const Eigen::VectorXd y = StateAwayFromSwitches(law, s, omega, rng, &fraction);
      CAPTURE(fraction);
      const JacobianCheckResult r =
          CheckNonlinearityJacobian(law, s.ctx, &s.condensation, y, omega, kFdStep, 1e-5);
      CHECK(r.y_error < kFdTolerance);
      CHECK(r.omega_error < kFdTolerance);
    }
  }
}

}  // namespace
}  // namespace nfrc
