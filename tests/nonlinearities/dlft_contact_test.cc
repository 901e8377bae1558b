#include "nonlinearities/dlft_contact.h"

#include <doctest/doctest.h>

#include <complex>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "nonlinearities/jacobian_check.h"
#include "nonlinearities/law_test_support.h"

namespace nfrc {
namespace {

using testing::TwoDofModel;

// Away from switching samples DLFT is linear in y on each sample (the mask is frozen), so
// central differences are exact up to round-off: 1e-7 relative step, 1e-6 tolerance.
constexpr double kFdStep = 1e-7;
constexpr double kFdTolerance = 1e-6;
// A perturbation of relative size kFdStep moves a predicted force by far less than this
// share of its largest sample, so no sample switches between contact and separation.
constexpr double kSwitchMargin = 1e-4;

struct Setup {
  HarmonicSet set{5, false, 64};
  FourierTransform fourier{set};
  Condensation condensation;
  NonlinearityContext ctx;
  // A flexible obstacle (N/m, 0: none) behind the law's first DOF.
  Setup(std::vector<int> retained, std::vector<int> local, double obstacle_stiffness = 0.0)
      : condensation(testing::ChainModel(), retained, set, {ForcingTerm{3, 1, 1e5, 0.0}}) {
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = std::move(local);
    if (obstacle_stiffness > 0.0) {
      std::vector<double> compliance(retained.size(), 0.0);
      compliance[ctx.local_dofs[0]] = 1.0 / obstacle_stiffness;
      condensation.SetObstacleCompliance(compliance);
    }
  }
};

// Where the law sits: the retained DOFs, the law's positions among them, its other DOF (−1:
// ground) and the obstacle behind it.
struct Variant {
  const char* name;
  std::vector<int> retained;
  std::vector<int> local;
  int other;
  double obstacle_stiffness;
};
const Variant kVariants[] = {{"rigid, contact DOF alone", {3}, {0}, -1, 0.0},
                             {"rigid, with another retained DOF", {1, 3}, {1}, -1, 0.0},
                             {"flexible obstacle", {1, 3}, {1}, -1, 4e9},
                             {"between two model DOFs", {3, 1}, {0, 1}, 1, 0.0}};

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
  for (const Variant& v : kVariants) {
    CAPTURE(v.name);
    Setup s(v.retained, v.local, v.obstacle_stiffness);
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
      CHECK(r.residual_error <= kSameResidual);
      CHECK(r.omega_error < kFdTolerance);
    }
  }
}

// Hill's method splits DLFT's Jacobian into the ε part (LinearizeForStability) and the part
// through the condensed linear rows (LinearResidualPart, rows taken from the full model
// there). With the condensed rows A put back, the two must give Evaluate's Jacobian (checked
// against finite differences above), for each variant.
TEST_CASE("DLFT contact: the stability split recomposes the Jacobian") {
  std::mt19937 rng(5);
  const double omega = 3.0e4;
  for (const Variant& v : kVariants) {
    CAPTURE(v.name);
    Setup s(v.retained, v.local, v.obstacle_stiffness);
    s.condensation.Update(omega);
    ContactGeometry geometry;
    geometry.dof = 3;
    geometry.other = v.other;
    geometry.gap = 2e-5;
    const DlftContact law(geometry, v.obstacle_stiffness, 5e9);
    double fraction = 0.0;
    const Eigen::VectorXd y = StateAwayFromSwitches(law, s, omega, rng, &fraction);
    const int n = static_cast<int>(y.size()), nc = s.set.NumCoefficients();
    Eigen::MatrixXd evaluated = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd residual = Eigen::VectorXd::Zero(n);
    law.Evaluate(s.ctx, y, omega, residual, &evaluated, nullptr);
    Eigen::MatrixXd split = Eigen::MatrixXd::Zero(n, n);
    law.LinearizeForStability(s.ctx, y, omega, &split, nullptr);
    const auto dependence = law.LinearResidualPart(s.ctx, y, omega);
    REQUIRE(dependence);
    const Eigen::MatrixXd a = s.condensation.RealOperator();
    for (const auto& [row_index, row_sign] : dependence->rows) {
      for (const auto& [term_index, coefficient] : dependence->terms) {
        split.middleRows(s.ctx.DofOffset(row_index), nc) +=
            row_sign * coefficient * dependence->weights *
            a.middleRows(s.ctx.DofOffset(term_index), nc);
      }
    }
    CHECK((split - evaluated).norm() <= 1e-12 * evaluated.norm());
  }
}

// ---------------------------------------------------------------------------------------
// Solutions at fixed ω of NLvib's two-DOF oscillator against a rigid obstacle.

// M = I, K = [[1, −1], [−1, 2]], C = 0.03 K, f_1 = 0.1 cos ωt; contact at DOF 0.
LinearModel NlvibTwoDof() {
  Eigen::MatrixXd k(2, 2);
  k << 1.0, -1.0, -1.0, 2.0;
  LinearModel model;
  model.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.stiffness = k.sparseView();
  model.damping = (0.03 * k).sparseView();
  return model;
}

struct NewtonResult {
  Eigen::VectorXd y;
  Eigen::VectorXd residual;
  bool converged = false;
  int iterations = 0;
};

// Semi-smooth Newton with backtracking on ‖R‖ for R(y) = A y − b + law(y), A and b the real
// condensed operator and forcing at the condensation's ω, from `guess`.
NewtonResult SolveAtOmega(const Nonlinearity& law, const NonlinearityContext& ctx,
                          const Condensation& condensation, const Eigen::VectorXd& guess,
                          double tolerance) {
  const double omega = condensation.omega();
  const Eigen::MatrixXd a = condensation.RealOperator();
  const Eigen::VectorXd b = condensation.RealForcing();
  auto residual_of = [&](const Eigen::VectorXd& y, Eigen::MatrixXd* jacobian) {
    Eigen::VectorXd r = a * y - b;
    if (jacobian != nullptr) *jacobian = a;
    law.Evaluate(ctx, y, omega, r, jacobian, nullptr);
    return r;
  };
  NewtonResult result;
  result.y = guess;
  for (; result.iterations < 50; ++result.iterations) {
    Eigen::MatrixXd jacobian;
    result.residual = residual_of(result.y, &jacobian);
    const double norm = result.residual.norm();
    if (norm <= tolerance * b.norm()) {
      result.converged = true;
      return result;
    }
    const Eigen::VectorXd step = jacobian.partialPivLu().solve(-result.residual);
    double t = 1.0;
    for (int halving = 0; halving < 30; ++halving, t *= 0.5) {
      if (residual_of(result.y + t * step, nullptr).norm() < (1.0 - 1e-4 * t) * norm) break;
    }
    result.y += t * step;
  }
  result.residual = residual_of(result.y, nullptr);
  return result;
}

// Newton stops at ‖R‖ ≤ 1e-12 ‖F‖: far below the contact-law and truncation effects
// measured here (≥ 1e-6), while reachable in double precision for these O(10) systems.
constexpr double kNewtonTolerance = 1e-12;

// The solution at `omega` reached by natural continuation from ω = 0.5, where the linear
// response (|x_0| ≈ 0.34) is clear of the obstacle, in steps of 0.01: NLvib's curve has no
// fold on its upper branch between 0.5 and its peak at ω ≈ 0.75, and a cold Newton start
// from the linear response at `omega` (|x_0| ≈ 2 ≫ the gap) does not converge.
NewtonResult SolveByContinuation(const Nonlinearity& law, const NonlinearityContext& ctx,
                                 Condensation& condensation, double omega) {
  constexpr double kStart = 0.5;
  condensation.Update(kStart);
  NewtonResult result;
  result.y = condensation.RealOperator().partialPivLu().solve(condensation.RealForcing());
  const int steps = static_cast<int>(std::lround((omega - kStart) / 0.01));
  for (int i = 0; i <= steps; ++i) {
    condensation.Update(i == steps ? omega : kStart + 0.01 * i);
    result = SolveAtOmega(law, ctx, condensation, result.y, kNewtonTolerance);
    if (!result.converged) break;
  }
  return result;
}

TEST_CASE("DLFT contact: at a solution gap and force satisfy the contact law up to truncation/ε") {
  // At a solution the residual rows R of the contact DOF satisfy L + n·T(λ) = R, with L the
  // linear rows and T(λ) the truncated corrected force, so the prediction on sample j is
  //   λ̃_j = T(λ)_j − n R_j − ε g_j.
  // Contact samples (λ_j = λ̃_j > 0) thus have ε g_j = T(λ)_j − λ_j − n R_j, and separated
  // ones (λ̃_j ≤ 0) have ε g_j ≥ T(λ)_j − n R_j. With τ = max_j |T(λ)_j − λ_j| (the force's
  // truncation error, measured) and ρ = Σ|R coefficients| ≥ |R_j|, the contact law holds as
  //   λ ≥ 0,   g ≥ −(τ + ρ)/ε,   |g| ≤ (τ + ρ)/ε where λ > 0,
  // i.e. DLFT penetrates by at most the truncation error over ε (Vadcard et al. 2022, §2.4).
  const LinearModel model = NlvibTwoDof();
  const double omega = 0.6;  // the linear response (|x_0| ≈ 2) would cross the gap of 1
  for (const std::pair<int, double>& setting :
       std::vector<std::pair<int, double>>{{10, 10.0}, {21, 10.0}, {21, 1000.0}}) {
    // Named copies: CAPTURE takes them by reference (clang 14 cannot, structured bindings).
    const int max_harmonic = setting.first;
    const double epsilon = setting.second;
    CAPTURE(max_harmonic);
    CAPTURE(epsilon);
    const HarmonicSet set(max_harmonic, false);
    const FourierTransform fourier(set);
    Condensation condensation(model, {0, 1}, set, {ForcingTerm{1, 1, 0.1, 0.0}});
    ContactGeometry geometry;
    geometry.dof = 0;
    geometry.gap = 1.0;
    const DlftContact law(geometry, 0.0, epsilon);
    NonlinearityContext ctx;
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = {0};
    const NewtonResult solved = SolveByContinuation(law, ctx, condensation, omega);
    REQUIRE(solved.converged);
    CAPTURE(solved.iterations);

    const std::vector<LawSignal> raw = law.RawSamples(ctx, solved.y, omega);
    const Eigen::VectorXd& gap = raw[0].samples;
    const Eigen::VectorXd& force = raw[1].samples;
    const Eigen::VectorXd& truncated = raw[2].samples;
    const int nc = set.NumCoefficients();
    const double tau = (truncated - force).cwiseAbs().maxCoeff();
    const double rho = solved.residual.head(nc).cwiseAbs().sum();
    // Rounding in forming g and λ̃ (‖λ̃‖ ~ ε·1 m): 1e-12 m for these magnitudes.
    const double bound = (tau + rho) / epsilon + 1e-12;
    int in_contact = 0;
    double penetration = 0.0;
    double complementarity = 0.0;
    for (Eigen::Index j = 0; j < gap.size(); ++j) {
      CHECK(force(j) >= 0.0);
      penetration = std::max(penetration, -gap(j));
      if (force(j) > 0.0) {
        ++in_contact;
        CHECK(std::abs(gap(j)) <= bound);
        complementarity = std::max(complementarity, std::abs(force(j) * gap(j)));
      } else {
        CHECK(gap(j) >= -bound);
      }
    }
    MESSAGE("N_h = " << max_harmonic << ", eps = " << epsilon << ": contact on " << in_contact
                     << "/" << gap.size() << " samples, truncation tau = " << tau
                     << " N, bound (tau + rho)/eps = " << bound << " m, max penetration "
                     << penetration << " m, max |lambda g| " << complementarity << ", newton "
                     << solved.iterations);
    // A genuinely nonsmooth state: both contact and separation within the period.
    CHECK(in_contact > 0);
    CHECK(in_contact < gap.size());
    // The bound is a small fraction of the 1 m gap, so the check above has teeth.
    CHECK(bound < 0.05);
  }
}

TEST_CASE(
    "DLFT contact: a time-varying gap equals the constant-gap problem in shifted coordinates") {
  // With g0(θ) = g + s(θ), s = a cos θ + b sin θ, the gap is g − (x_0 − s): x solves the
  // problem with g0(θ) iff x' = x − s e_0 solves the constant-gap problem with forcing
  // F − Z s e_0 (harmonic 1, every DOF). The DLFT prediction −n(Z x − F) − ε g is the same
  // expression in both, so the two solves must agree to the Newton tolerance; a wrong sign
  // or phase of the gap's harmonic would shift the response by O(s) = O(0.1 m).
  const LinearModel model = NlvibTwoDof();
  const HarmonicSet set(15, false);
  const FourierTransform fourier(set);
  const double omega = 0.6;
  const double s_cos = 0.2, s_sin = -0.15;
  // Z_k(ω) s e_0 for k = 1, complex amplitude S = a − i b.
  const std::complex<double> s(s_cos, -s_sin);
  const Eigen::MatrixXd k = Eigen::MatrixXd(model.stiffness);
  const Eigen::MatrixXd c = Eigen::MatrixXd(model.damping);
  std::vector<ForcingTerm> shifted_forcing = {ForcingTerm{1, 1, 0.1, 0.0}};
  for (int dof = 0; dof < 2; ++dof) {
    const std::complex<double> z(k(dof, 0) - omega * omega * (dof == 0 ? 1.0 : 0.0),
                                 omega * c(dof, 0));
    const std::complex<double> minus_zs = -z * s;
    // F = f_cos − i f_sin.
    shifted_forcing.push_back(ForcingTerm{dof, 1, minus_zs.real(), -minus_zs.imag()});
  }
  struct Problem {
    std::vector<ForcingTerm> forcing;
    bool varying;
  };
  Eigen::VectorXd solutions[2];
  const Problem problems[2] = {{{ForcingTerm{1, 1, 0.1, 0.0}}, true}, {shifted_forcing, false}};
  for (int i = 0; i < 2; ++i) {
    Condensation condensation(model, {0, 1}, set, problems[i].forcing);
    ContactGeometry geometry;
    geometry.dof = 0;
    geometry.gap = 1.0;
    if (problems[i].varying) geometry.gap_harmonics = {{1, s_cos, s_sin}};
    const DlftContact law(geometry, 0.0, 50.0);
    NonlinearityContext ctx;
    ctx.fourier = &fourier;
    ctx.condensation = &condensation;
    ctx.local_dofs = {0};
    const NewtonResult solved = SolveByContinuation(law, ctx, condensation, omega);
    REQUIRE(solved.converged);
    solutions[i] = solved.y;
    // The contact is active, so the comparison involves the law and not only the linear part.
    const std::vector<LawSignal> raw = law.RawSamples(ctx, solved.y, omega);
    CHECK(raw[1].samples.maxCoeff() > 0.01);
  }
  Eigen::VectorXd expected = solutions[1];
  expected(set.CosIndex(1)) += s_cos;
  expected(set.SinIndex(1)) += s_sin;
  // Both are Newton solutions to ‖R‖ ≤ 1e-12‖F‖ of equations whose Jacobian has O(100)
  // condition here (ε = 50 against unit stiffness): agreement to 1e-9 of the 1 m scale.
  constexpr double kShiftTolerance = 1e-9;
  const double difference = (solutions[0] - expected).cwiseAbs().maxCoeff();
  MESSAGE("time-varying vs shifted constant gap: max coefficient difference " << difference);
  CHECK(difference < kShiftTolerance);
  // And the shift matters: the unshifted constant-gap solution is far off.
  CHECK((solutions[0] - solutions[1]).cwiseAbs().maxCoeff() > 0.1);
}

}  // namespace
}  // namespace nfrc
