#include "nonlinearities/penalty_contact.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/errors.h"
#include "nonlinearities/jacobian_check.h"
#include "nonlinearities/law_test_support.h"

namespace nfrc {
namespace {

using testing::TwoDofModel;

constexpr double kPi = std::numbers::pi;

// The law is piecewise linear in y on each sample; away from the switch g = 0 the contact
// pattern is frozen under a perturbation, so central differences are exact up to round-off
// (1e-16 × |r| / 1e-7 ≈ 1e-9 relative): step 1e-7, tolerance 1e-6.
constexpr double kFdStep = 1e-7;
constexpr double kFdTolerance = 1e-6;
// No sample's gap closer to 0 than this (m): a perturbation of 1e-7 in each of the 2·11
// coefficients moves a sample's gap by ≤ 2.2e-6, far less, so no sample switches.
constexpr double kSwitchMargin = 1e-3;
// The forces on the samples and their projections, computed here by direct sums, agree
// with nfrc's FFT-based values to round-off: O(N_t) sums of O(100) terms, ~1e-14 relative.
constexpr double kAftTolerance = 1e-12;

constexpr double kStiffness = 250.0;

// x(θ) = a_0 + Σ_k a_k cos kθ + b_k sin kθ, summed directly (not through nfrc's FFT).
double EvaluateSeries(const HarmonicSet& set, const Eigen::VectorXd& c, double theta) {
  double x = 0.0;
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    x += c(set.CosIndex(p)) * std::cos(k * theta);
    if (k != 0) x += c(set.SinIndex(p)) * std::sin(k * theta);
  }
  return x;
}

// Galerkin projection of samples at θ_j = 2πj/N by direct sums.
Eigen::VectorXd Project(const HarmonicSet& set, const Eigen::VectorXd& samples) {
  const int n = static_cast<int>(samples.size());
  Eigen::VectorXd c = Eigen::VectorXd::Zero(set.NumCoefficients());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    for (int j = 0; j < n; ++j) {
      const double theta = 2 * kPi * j / n;
      if (k == 0) {
        c(set.CosIndex(p)) += samples(j) / n;
      } else {
        c(set.CosIndex(p)) += 2.0 * samples(j) * std::cos(k * theta) / n;
        c(set.SinIndex(p)) += 2.0 * samples(j) * std::sin(k * theta) / n;
      }
    }
  }
  return c;
}

struct Variant {
  const char* name;
  int other;  // −1: grounded
  double direction;
  bool varying_gap;  // g0(θ) = 1 + 0.1 cos 2θ − 0.05 sin 2θ instead of 1
};

const Variant kVariants[] = {{"grounded", -1, 1.0, false},
                             {"grounded, obstacle on the negative side", -1, -1.0, false},
                             {"grounded, time-varying gap", -1, 1.0, true},
                             {"between two DOFs", 1, 1.0, false},
                             {"between two DOFs, direction -1", 1, -1.0, true}};

ContactGeometry Geometry(const Variant& v) {
  ContactGeometry geometry;
  geometry.dof = 0;
  geometry.other = v.other;
  geometry.direction = v.direction;
  geometry.gap = 1.0;
  if (v.varying_gap) geometry.gap_harmonics = {{2, 0.1, -0.05}};
  return geometry;
}

double GapReference(const Variant& v, double theta) {
  return 1.0 + (v.varying_gap ? 0.1 * std::cos(2 * theta) - 0.05 * std::sin(2 * theta) : 0.0);
}

// A state whose relative displacement n·(x_0 − x_1) = 0.6 + 0.8 cos θ + 0.3 sin θ + random
// higher harmonics crosses the gap ≈ 1 twice per period, redrawn until no sample's gap is
// within kSwitchMargin of 0. y holds the two DOFs' coefficients (DOF 0 first). Returns the
// share of samples in contact.
double DrawState(const Variant& v, const HarmonicSet& set, std::mt19937& rng, Eigen::VectorXd* y) {
  const int nc = set.NumCoefficients();
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int attempt = 0; attempt < 100; ++attempt) {
    *y = Eigen::VectorXd::Zero(2 * nc);
    for (int i = 0; i < 2 * nc; ++i) (*y)(i) = 0.05 * normal(rng);
    // DOF 0 carries the bulk; the other DOF only moves in the pair variants.
    (*y)(set.CosIndex(0)) += v.direction * 0.6;
    (*y)(set.CosIndex(1)) += v.direction * 0.8;
    (*y)(set.SinIndex(1)) += v.direction * 0.3;
    if (v.other < 0) y->tail(nc).setZero();
    int in_contact = 0;
    double closest = INFINITY;
    for (int j = 0; j < set.num_samples(); ++j) {
      const double theta = 2 * kPi * j / set.num_samples();
      const double relative = EvaluateSeries(set, y->head(nc), theta) -
                              (v.other >= 0 ? EvaluateSeries(set, y->tail(nc), theta) : 0.0);
      const double gap = GapReference(v, theta) - v.direction * relative;
      in_contact += gap < 0.0;
      closest = std::min(closest, std::abs(gap));
    }
    if (closest > kSwitchMargin && in_contact > 0 && in_contact < set.num_samples()) {
      return static_cast<double>(in_contact) / set.num_samples();
    }
  }
  FAIL("no state away from the switch");
  return 0.0;
}

NonlinearityContext Context(const FourierTransform& fourier, const Variant& v) {
  NonlinearityContext ctx;
  ctx.fourier = &fourier;
  ctx.local_dofs = v.other >= 0 ? std::vector<int>{0, 1} : std::vector<int>{0};
  return ctx;
}

TEST_CASE("penalty contact: Jacobian matches finite differences, in contact and separated") {
  const HarmonicSet set(5, false, 64);
  const FourierTransform fourier(set);
  std::mt19937 rng(3);
  for (const Variant& v : kVariants) {
    INFO(v.name);
    const PenaltyContact law(Geometry(v), kStiffness);
    const NonlinearityContext ctx = Context(fourier, v);
    for (int trial = 0; trial < 4; ++trial) {
      Eigen::VectorXd y;
      const double fraction = DrawState(v, set, rng, &y);
      CAPTURE(fraction);
      const JacobianCheckResult r =
          CheckNonlinearityJacobian(law, ctx, nullptr, y, 1.3, kFdStep, 1.0);
      CHECK(r.y_error < kFdTolerance);
      CHECK(r.residual_error <= kSameResidual);
      // A displacement law: no ω dependence, analytically or by differences.
      CHECK(r.omega_error == 0.0);
    }
  }
}

TEST_CASE("penalty contact: sampled force is k·max(0, n·(x − x_other) − g0) and is projected") {
  const HarmonicSet set(5, false, 64);
  const FourierTransform fourier(set);
  const int nc = set.NumCoefficients();
  const int n_t = set.num_samples();
  std::mt19937 rng(5);
  for (const Variant& v : kVariants) {
    INFO(v.name);
    const PenaltyContact law(Geometry(v), kStiffness);
    const NonlinearityContext ctx = Context(fourier, v);
    Eigen::VectorXd y;
    DrawState(v, set, rng, &y);

    // Independent reference on the samples θ_j = 2πj/N_t.
    Eigen::VectorXd gap(n_t), force(n_t);
    for (int j = 0; j < n_t; ++j) {
      const double theta = 2 * kPi * j / n_t;
      const double relative = EvaluateSeries(set, y.head(nc), theta) -
                              (v.other >= 0 ? EvaluateSeries(set, y.tail(nc), theta) : 0.0);
      gap(j) = GapReference(v, theta) - v.direction * relative;
      force(j) = kStiffness * std::max(0.0, v.direction * relative - GapReference(v, theta));
    }
    const double scale = force.maxCoeff();
    REQUIRE(scale > 0.0);

    const std::vector<LawSignal> raw = law.RawSamples(ctx, y, 1.3);
    REQUIRE(raw.size() >= 2);
    CHECK(raw[0].name == "gap");
    CHECK(raw[1].name == "force_raw");
    CHECK((raw[0].samples - gap).cwiseAbs().maxCoeff() < kAftTolerance * gap.cwiseAbs().maxCoeff());
    CHECK((raw[1].samples - force).cwiseAbs().maxCoeff() < kAftTolerance * scale);

    // The residual gets +n·P λ on DOF 0's rows and −n·P λ on the other's (zero if grounded).
    Eigen::VectorXd residual = Eigen::VectorXd::Zero(2 * nc);
    law.Evaluate(ctx, y, 1.3, residual, nullptr, nullptr);
    const Eigen::VectorXd projected = Project(set, force);
    CHECK((residual.head(nc) - v.direction * projected).cwiseAbs().maxCoeff() <
          kAftTolerance * scale);
    const Eigen::VectorXd other_rows =
        v.other >= 0 ? Eigen::VectorXd(-v.direction * projected) : Eigen::VectorXd::Zero(nc);
    CHECK((residual.tail(nc) - other_rows).cwiseAbs().maxCoeff() < kAftTolerance * scale);
    // The obstacle pushes the DOF away from it: the mean force on the structure, −residual,
    // points against n (the spring is only ever compressed).
    CHECK(v.direction * residual(set.CosIndex(0)) > 0.0);
  }
}

TEST_CASE("penalty contact: a separated state carries no force and no stiffness") {
  const HarmonicSet set(3, false);
  const FourierTransform fourier(set);
  const int nc = set.NumCoefficients();
  const Variant v{"grounded", -1, 1.0, false};
  const PenaltyContact law(Geometry(v), kStiffness);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * nc);
  y(set.CosIndex(1)) = 0.99;  // |x| ≤ 0.99 < g0 = 1 on every sample
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(2 * nc);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  law.Evaluate(Context(fourier, v), y, 1.0, residual, &jacobian, nullptr);
  CHECK(residual.cwiseAbs().maxCoeff() == 0.0);
  CHECK(jacobian.cwiseAbs().maxCoeff() == 0.0);
  // Permanently in contact (x ≥ 1.01): the law is the linear spring k·(x − g0), exactly.
  y(set.CosIndex(0)) = 2.0;
  residual.setZero();
  law.Evaluate(Context(fourier, v), y, 1.0, residual, &jacobian, nullptr);
  CHECK(residual(set.CosIndex(0)) == doctest::Approx(kStiffness * (2.0 - 1.0)).epsilon(1e-13));
  CHECK(residual(set.CosIndex(1)) == doctest::Approx(kStiffness * 0.99).epsilon(1e-13));
  CHECK((jacobian.topLeftCorner(nc, nc) - kStiffness * Eigen::MatrixXd::Identity(nc, nc))
            .cwiseAbs()
            .maxCoeff() < 1e-10 * kStiffness);
}

TEST_CASE("penalty contact: the gap's harmonics must be in the set") {
  ContactGeometry geometry;
  geometry.dof = 0;
  geometry.gap = 1.0;
  geometry.gap_harmonics = {{4, 0.1, 0.0}};
  const PenaltyContact law(geometry, kStiffness);
  const HarmonicSet set(3, false);
  const FourierTransform fourier(set);
  NonlinearityContext ctx;
  ctx.fourier = &fourier;
  ctx.local_dofs = {0};
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(set.NumCoefficients());
  try {
    law.Evaluate(ctx, Eigen::VectorXd::Zero(set.NumCoefficients()), 1.0, residual, nullptr,
                 nullptr);
    FAIL("expected an error naming the gap");
  } catch (const std::invalid_argument& error) {
    CHECK(std::string(error.what()).rfind("gap:", 0) == 0);
  }
  // A constant gap needs harmonic 0.
  geometry.gap_harmonics.clear();
  const PenaltyContact constant(geometry, kStiffness);
  const HarmonicSet odd(3, true);
  const FourierTransform odd_fourier(odd);
  ctx.fourier = &odd_fourier;
  Eigen::VectorXd odd_residual = Eigen::VectorXd::Zero(odd.NumCoefficients());
  CHECK_THROWS_AS(constant.Evaluate(ctx, Eigen::VectorXd::Zero(odd.NumCoefficients()), 1.0,
                                    odd_residual, nullptr, nullptr),
                  std::invalid_argument);
  CHECK_THROWS_AS(PenaltyContact(geometry, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
