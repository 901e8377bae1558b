#include "continuation/corrector.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "continuation/augmented_system.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::CubicProblem;

// Closed-form quantities computed in a handful of flops agree to rounding.
constexpr double kRoundoff = 1e-13;

doctest::Approx Near(double value) { return doctest::Approx(value).epsilon(kRoundoff); }

// R = atan(y) − λ: plain Newton from |y| ≳ 1.39 overshoots further each iteration, damped
// Newton converges (the classic line-search example).
class ArctanProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = std::atan(y(0)) - lambda;
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0 / (1.0 + y(0) * y(0));
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -1.0;
    return true;
  }
};

// Newton settings for the one-unknown problems below, whose residuals are O(1): residual
// scale 1 and the given cap on iterations.
NewtonSettings UnitSettings(int max_iterations) {
  NewtonSettings settings;
  settings.residual_scale = 1.0;
  settings.max_iterations = max_iterations;
  return settings;
}

Scaling UnitScaling(int n) {
  Scaling scaling(std::vector<int>(n, 0), 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Ones(n));
  return scaling;
}

TEST_CASE("augmented system: regular at a fold where R_y is singular") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling = UnitScaling(1);
  Linearization at_fold;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(-1.0, 2.0 / 3.0), &at_fold));
  CHECK(at_fold.jacobian_y(0, 0) == 0.0);
  // Border with the tangent at the fold, (Δy, Δλ) ∝ (1, 0): [[0, −1], [1, 0]] is orthogonal.
  const Eigen::MatrixXd a = AugmentedMatrix(at_fold, scaling, 1.0, Eigen::Vector2d(1.0, 0.0));
  CHECK(Eigen::PartialPivLU<Eigen::MatrixXd>(a).rcond() == Near(1.0));
  Eigen::VectorXd x;
  REQUIRE(SolveAugmented(a, Eigen::Vector2d(3.0, 5.0), &x));
  CHECK(x(0) == Near(5.0));
  CHECK(x(1) == Near(-3.0));
}

TEST_CASE("augmented system: a singular matrix falls back to the full-pivoting LU") {
  Eigen::Matrix2d a;
  a << 1.0, 1.0, 1.0, 1.0;
  Eigen::VectorXd x;
  REQUIRE(SolveAugmented(a, Eigen::Vector2d(2.0, 2.0), &x));
  // Consistent right-hand side: the fallback returns an exact solution (to rounding).
  CHECK((a * x - Eigen::Vector2d(2.0, 2.0)).norm() < kRoundoff);
}

// A friction-like system with elimination blocks: m blocks of two "harmonic" unknowns
// x_k, each driven by λ·f_k and by one "law" unknown z_k through its force column,
// A_k x_k + F_k z_k = λ f_k, and law rows z = clip(P x, −c, c) with a dense P (every law row
// depends on every x, as a friction force's samples do). Only the law rows change between
// Newton iterations, by one row of P per component that crosses ±c: the reused
// factorisation's case. ‖P‖ is small enough that z ↦ clip(P x(z), −c, c) is a contraction,
// so fixed-point iteration gives the solution independently of Newton.
class ClippedLawProblem : public ContinuationProblem {
 public:
  static constexpr int kBlocks = 60;
  static constexpr double kClip = 0.05;

  ClippedLawProblem() {
    std::srand(5);
    blocks_.resize(kBlocks);
    force_.resize(kBlocks);
    drive_.resize(kBlocks);
    for (int k = 0; k < kBlocks; ++k) {
      const double w = 0.3 + 0.1 * k;
      blocks_[k] << 1.0 - 0.2 * w * w, 0.1 * w, -0.1 * w, 1.0 - 0.2 * w * w;
      force_[k] = Eigen::Vector2d::Random();
      drive_[k] = Eigen::Vector2d::Random();
    }
    law_ = 0.08 * Eigen::MatrixXd::Random(kBlocks, 2 * kBlocks);
  }
  int NumUnknowns() const override { return 3 * kBlocks; }
  std::vector<std::vector<int>> EliminationBlocks() const override {
    std::vector<std::vector<int>> groups;
    for (int k = 0; k < kBlocks; ++k) groups.push_back({2 * k, 2 * k + 1});
    return groups;
  }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const Eigen::VectorXd x = y.head(2 * kBlocks), z = y.tail(kBlocks);
    if (jacobian_y != nullptr) jacobian_y->setZero();
    for (int k = 0; k < kBlocks; ++k) {
      residual->segment<2>(2 * k) =
          blocks_[k] * x.segment<2>(2 * k) + force_[k] * z(k) - lambda * drive_[k];
      if (jacobian_y != nullptr) {
        jacobian_y->block<2, 2>(2 * k, 2 * k) = blocks_[k];
        jacobian_y->block<2, 1>(2 * k, 2 * kBlocks + k) = force_[k];
      }
      if (jacobian_lambda != nullptr) jacobian_lambda->segment<2>(2 * k) = -drive_[k];
    }
    const Eigen::VectorXd g = law_ * x;
    for (int i = 0; i < kBlocks; ++i) {
      const bool inside = std::abs(g(i)) < kClip;
      (*residual)(2 * kBlocks + i) = z(i) - (inside ? g(i) : std::copysign(kClip, g(i)));
      if (jacobian_y != nullptr) {
        if (inside) jacobian_y->block(2 * kBlocks + i, 0, 1, 2 * kBlocks) = -law_.row(i);
        (*jacobian_y)(2 * kBlocks + i, 2 * kBlocks + i) = 1.0;
      }
    }
    if (jacobian_lambda != nullptr) jacobian_lambda->tail(kBlocks).setZero();
    return true;
  }
  // The solution at λ by fixed-point iteration on z.
  Eigen::VectorXd FixedPoint(double lambda) const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(kBlocks), x(2 * kBlocks);
    for (int iteration = 0; iteration < 500; ++iteration) {
      for (int k = 0; k < kBlocks; ++k) {
        x.segment<2>(2 * k) = blocks_[k].lu().solve(lambda * drive_[k] - force_[k] * z(k));
      }
      z = (law_ * x).cwiseMax(-kClip).cwiseMin(kClip);
    }
    Eigen::VectorXd y(3 * kBlocks);
    y << x, z;
    return y;
  }

 private:
  std::vector<Eigen::Matrix2d> blocks_;
  std::vector<Eigen::Vector2d> force_, drive_;
  Eigen::MatrixXd law_;
};

TEST_CASE("corrector: at fixed lambda, low-rank updates reach the independent solution") {
  ClippedLawProblem problem;
  Evaluator evaluator(problem);
  const int n = problem.NumUnknowns();
  const Scaling scaling = UnitScaling(n);
  NewtonSettings settings;
  settings.max_iterations = 40;
  // Far from the solution (z = 0, x = 0): several law rows switch at each iteration.
  const double lambda = 0.4;
  Eigen::VectorXd guess = Eigen::VectorXd::Zero(n + 1);
  guess(n) = lambda;
  const CorrectorResult result = CorrectAtFixedLambda(evaluator, scaling, settings, guess);
  REQUIRE(result.converged);
  const Eigen::VectorXd reference = problem.FixedPoint(lambda);
  // Both solve to rounding (Newton's update tolerance 1e-10, the contraction ~0.3 per
  // iteration for 500 iterations): they agree to the Newton tolerance.
  CHECK((result.u.head(n) - reference).norm() <= settings.update_tolerance * reference.norm());
  // Some law rows are clipped at the solution, others not: the case is nonsmooth.
  const Eigen::VectorXd z = reference.tail(ClippedLawProblem::kBlocks);
  CHECK((z.array().abs() >= ClippedLawProblem::kClip).count() > 0);
  CHECK((z.array().abs() < ClippedLawProblem::kClip).count() > 0);
  CHECK(result.low_rank_updates > 0);
}

TEST_CASE("corrector: converges quadratically through a fold") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling = UnitScaling(1);
  NewtonSettings settings;
  settings.residual_scale = 2.0;
  // Predicted 0.01 past the fold along its tangent; the arclength row pins y = −0.99.
  const CorrectorResult result = CorrectOnArclength(
      evaluator, scaling, settings, Eigen::Vector2d(-0.99, 2.0 / 3.0), Eigen::Vector2d(1.0, 0.0));
  REQUIRE(result.converged);
  CHECK(result.u(0) == Near(-0.99));
  const double expected_lambda = -0.99 * -0.99 * -0.99 / 3.0 + 0.99;
  CHECK(result.u(1) == Near(expected_lambda));
  // The first update is exact up to the O(1e-4) curvature term: Newton needs 2–3 solves.
  CHECK(result.iterations <= 3);
  CHECK(result.residual_norm <= settings.residual_tolerance * settings.residual_scale);
}

// R = y² − λ²: at λ = 0 the root is double and Newton halves y at every step (θ = 1/2),
// linear convergence that the contraction rule must not take for fast.
class SquareProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = y(0) * y(0) - lambda * lambda;
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 2.0 * y(0);
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -2.0 * lambda;
    return true;
  }
};

TEST_CASE("corrector: two fast-contracting steps accept without the confirming iteration") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling = UnitScaling(1);
  NewtonSettings settings;
  settings.residual_scale = 2.0;
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, scaling, settings, Eigen::Vector2d(3.0, 2.0));
  REQUIRE(result.converged);
  // The root of y³/3 − y − 2 by bisection on [2, 3] (R(2) < 0 < R(3)), independent of Newton.
  double low = 2.0, high = 3.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (mid * mid * mid / 3.0 - mid - 2.0 < 0.0 ? low : high) = mid;
  }
  const double root = 0.5 * (low + high);
  // Plain Newton from 3 until its update is below update_tolerance: the old stopping rule.
  int plain_iterations = 0;
  for (double y = 3.0;;) {
    const double update = -(y * y * y / 3.0 - y - 2.0) / (y * y - 1.0);
    y += update;
    ++plain_iterations;
    if (std::abs(update) <= settings.update_tolerance) break;
  }
  CHECK(result.error_estimate >= 0.0);
  CHECK(result.error_estimate <= settings.update_tolerance);
  CHECK(std::abs(result.u(0) - root) <= settings.update_tolerance);
  CHECK(result.iterations == plain_iterations - 1);
}

TEST_CASE("corrector: linear convergence takes the confirming iteration") {
  SquareProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling = UnitScaling(1);
  NewtonSettings settings;
  settings.max_iterations = 60;
  // At λ = 0 the root is double: Newton halves y, θ = 1/2 is above the rule's 1/4.
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, scaling, settings, Eigen::Vector2d(1.0, 0.0));
  REQUIRE(result.converged);
  CHECK(result.error_estimate < 0.0);
  // The last update y/2 ≤ update_tolerance leaves y ≤ update_tolerance.
  CHECK(std::abs(result.u(0)) <= settings.update_tolerance);
}

// R = y with a wrong derivative, as a sampled law's generalised derivative can be across a
// switch. Reported 121.6 times too small, each Newton step overshoots 121.6-fold, the line
// search takes 1/64 of it (1/32 would triple |R|) and |R| falls by only 10 % per iteration;
// reported 10 times too large, each full step is taken and |R| falls by 10 % too.
class MisledProblem : public ContinuationProblem {
 public:
  explicit MisledProblem(double derivative) : derivative_(derivative) {}
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double /*lambda*/, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = y(0);
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = derivative_;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = 0.0;
    return true;
  }

 private:
  double derivative_;
};

constexpr double kUnderstatement = 121.6;
// The iteration from which a crawl on the arclength is cut (kStagnationStart in corrector.cc):
// with the merit falling by 10 % per iteration, the sixth is not half of the third.
constexpr int kStagnationStart = 6;

TEST_CASE("corrector: a crawling arclength correction fails early, a fixed-lambda one goes on") {
  MisledProblem problem(1.0 / kUnderstatement);
  const NewtonSettings settings = UnitSettings(40);
  // The tangent along λ: the arclength row pins λ, as at fixed λ.
  Evaluator on_arclength(problem);
  const CorrectorResult cut = CorrectOnArclength(on_arclength, UnitScaling(1), settings,
                                                 Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0, 1));
  CHECK_FALSE(cut.converged);
  CHECK(cut.failure.rfind("stagnating", 0) == 0);
  CHECK(cut.iterations == kStagnationStart);
  CHECK(cut.u(0) == Near(std::pow(1.0 - kUnderstatement / 64.0, kStagnationStart)));

  // At fixed λ there is no fallback: the crawl goes on (0.9⁴⁰ ≈ 1.5e-2, not converged).
  Evaluator at_fixed_lambda(problem);
  const CorrectorResult crawled =
      CorrectAtFixedLambda(at_fixed_lambda, UnitScaling(1), settings, Eigen::Vector2d(1.0, 0.0));
  CHECK_FALSE(crawled.converged);
  CHECK(crawled.iterations == settings.max_iterations);
}

TEST_CASE("corrector: slow full steps on the arclength are not cut as a crawl") {
  MisledProblem problem(10.0);
  const NewtonSettings settings = UnitSettings(40);
  Evaluator evaluator(problem);
  const CorrectorResult result = CorrectOnArclength(
      evaluator, UnitScaling(1), settings, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0, 1));
  CHECK_FALSE(result.converged);
  CHECK(result.iterations == settings.max_iterations);
  CHECK(result.u(0) == Near(std::pow(0.9, settings.max_iterations)));
}

TEST_CASE("corrector: a slow but steady arclength correction is not cut") {
  SquareProblem problem;
  Evaluator evaluator(problem);
  const NewtonSettings settings = UnitSettings(60);
  // The row pins λ = 0, where the root is double: the merit y² falls by 4 per iteration, ~20
  // of them to the update tolerance.
  const CorrectorResult result = CorrectOnArclength(
      evaluator, UnitScaling(1), settings, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0, 1));
  REQUIRE(result.converged);
  CHECK(result.iterations > 2 * kStagnationStart);
  CHECK(std::abs(result.u(0)) <= settings.update_tolerance);
}

TEST_CASE("corrector: fixed lambda keeps lambda exactly") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling = UnitScaling(1);
  NewtonSettings settings;
  settings.residual_scale = 2.0;
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, scaling, settings, Eigen::Vector2d(3.0, 2.0));
  REQUIRE(result.converged);
  CHECK(result.u(1) == 2.0);
  const double y = result.u(0);
  CHECK(std::abs(y * y * y / 3.0 - y - 2.0) <= settings.residual_tolerance * 2.0);
}

TEST_CASE("corrector: the line search rescues Newton where the full step diverges") {
  ArctanProblem problem;
  const Scaling scaling = UnitScaling(1);
  NewtonSettings settings = UnitSettings(50);

  settings.line_search = false;
  Evaluator plain(problem);
  const CorrectorResult diverged =
      CorrectAtFixedLambda(plain, scaling, settings, Eigen::Vector2d(3.0, 0.0));
  CHECK_FALSE(diverged.converged);
  CHECK_FALSE(diverged.failure.empty());

  settings.line_search = true;
  Evaluator damped(problem);
  const CorrectorResult converged =
      CorrectAtFixedLambda(damped, scaling, settings, Eigen::Vector2d(3.0, 0.0));
  REQUIRE(converged.converged);
  // atan(y) = 0 at y = 0; Newton's last update (scale 1) is below the update tolerance.
  CHECK(std::abs(converged.u(0)) < settings.update_tolerance);
}

// Counts the calls with and without the Jacobian.
class CountingArctanProblem : public ArctanProblem {
 public:
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    ++(jacobian_y != nullptr ? with_jacobian : residual_only);
    return ArctanProblem::Evaluate(y, lambda, residual, jacobian_y, jacobian_lambda);
  }
  int with_jacobian = 0;
  int residual_only = 0;
};

// A halved step is judged by its residual alone: the Jacobian is evaluated at the start, at
// each full step and at each halved step taken, never at a refused halving.
TEST_CASE("corrector: refused halvings of a step cost no Jacobian") {
  CountingArctanProblem problem;
  Evaluator evaluator(problem);
  const NewtonSettings settings = UnitSettings(50);
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, UnitScaling(1), settings, Eigen::Vector2d(3.0, 0.0));
  REQUIRE(result.converged);
  CHECK(std::abs(result.u(0)) < settings.update_tolerance);
  CHECK(problem.residual_only > 0);
  CHECK(problem.with_jacobian <= 1 + 2 * result.iterations);
  CHECK(problem.with_jacobian + problem.residual_only == evaluator.num_evaluations());
}

// Piecewise-linear R(y) with its root at y = 1.5: slope 1 for y ≤ 0, −8/3 on (0, 0.75), 4
// from 0.75. At y = 0 the generalised derivative is the left branch's 1, so the Newton step
// +1 climbs the middle branch: no fraction of it decreases |R| (it is ≥ 1 on [0, 1]), yet the
// full step lands on the last branch, from which one Newton step is exact.
class KinkProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double /*lambda*/, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const double x = y(0);
    const double slope = x <= 0.0 ? 1.0 : (x < 0.75 ? -8.0 / 3.0 : 4.0);
    (*residual)(0) = x <= 0.0 ? x - 1.0 : (x < 0.75 ? -1.0 - 8.0 / 3.0 * x : 4.0 * x - 6.0);
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = slope;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = 0.0;
    return true;
  }
};

TEST_CASE("corrector: the watchdog takes a full step where no fraction of it decreases |R|") {
  KinkProblem problem;
  Evaluator evaluator(problem);
  NewtonSettings settings;
  settings.residual_scale = 1.0;
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, UnitScaling(1), settings, Eigen::Vector2d(0.0, 0.0));
  REQUIRE(result.converged);
  CHECK(result.u(0) == Near(1.5));
  // The watchdog step to y = 1, the exact step to 1.5, then a zero update that confirms it.
  CHECK(result.iterations <= 3);
}

TEST_CASE("corrector: a failing Evaluate is a failed correction, not a point") {
  class FailingProblem : public ContinuationProblem {
   public:
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd&, double, Eigen::VectorXd*, Eigen::MatrixXd*,
                  Eigen::VectorXd*) override {
      return false;
    }
  } problem;
  Evaluator evaluator(problem);
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, UnitScaling(1), NewtonSettings{}, Eigen::Vector2d(0, 0));
  CHECK_FALSE(result.converged);
  CHECK(result.failure.find("evaluation failed") != std::string::npos);
  CHECK(evaluator.num_evaluations() == 1);
}

// R = y − λ + η(λ): a line whose residual carries a deterministic noise η of amplitude
// kNoise that changes with every λ (a hash of λ's bits), as the rounding of a fine mesh's
// condensed operator does. `estimate` is what ResidualNoise reports.
class NoisyLineProblem : public ContinuationProblem {
 public:
  static constexpr double kNoise = 1e-6;
  explicit NoisyLineProblem(double estimate) : estimate_(estimate) {}
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    uint64_t bits = 0;
    std::memcpy(&bits, &lambda, sizeof bits);
    bits = (bits ^ (bits >> 31)) * 0x9E3779B97F4A7C15ull;
    const double eta = kNoise * (static_cast<double>(bits >> 11) * 0x1.0p-53 - 0.5);
    (*residual)(0) = y(0) - lambda + eta;
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -1.0;
    return true;
  }
  double ResidualNoise(const Eigen::VectorXd&, double) override { return estimate_; }

 private:
  double estimate_;
};

TEST_CASE("corrector: a residual that stalls at the problem's noise floor is converged there") {
  NewtonSettings settings;
  settings.residual_scale = 1.0;  // tolerance 1e-8, two decades below the noise
  // The arclength row moves λ at every iteration, so the noise re-rolls: without an
  // estimate the corrector cannot converge.
  const Eigen::Vector2d predicted(0.3, 0.2);
  const Eigen::Vector2d tangent = Eigen::Vector2d(1.0, 1.0).normalized();
  NoisyLineProblem unaware(0.0);
  Evaluator unaware_evaluator(unaware);
  const CorrectorResult failed =
      CorrectOnArclength(unaware_evaluator, UnitScaling(1), settings, predicted, tangent);
  CHECK_FALSE(failed.converged);

  NoisyLineProblem aware(NoisyLineProblem::kNoise);
  Evaluator aware_evaluator(aware);
  const CorrectorResult result =
      CorrectOnArclength(aware_evaluator, UnitScaling(1), settings, predicted, tangent);
  REQUIRE(result.converged);
  CHECK(result.at_noise_floor);
  CHECK(result.noise_floor == NoisyLineProblem::kNoise);
  CHECK(result.residual_norm <= kNoiseFactor * NoisyLineProblem::kNoise);
  // On the line y = λ to the noise (|η| ≤ kNoise / 2), and on the arclength hyperplane.
  CHECK(std::abs(result.u(0) - result.u(1)) <= NoisyLineProblem::kNoise);
  CHECK(std::abs(tangent.dot(result.u - predicted)) < kRoundoff);
  // Few iterations: the first step lands on the line, the next shows the stall.
  CHECK(result.iterations <= 3);
}

TEST_CASE("corrector: a noise estimate does not loosen a residual that still converges") {
  // R = atan(y) − λ has no noise: with a (wrong) estimate of 1e-3 the corrector still
  // converges to the tolerance, because its residual never stalls above it.
  ArctanProblem plain;
  class Claimed : public ContinuationProblem {
   public:
    explicit Claimed(ArctanProblem& inner) : inner_(inner) {}
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* r, Eigen::MatrixXd* jy,
                  Eigen::VectorXd* jl) override {
      return inner_.Evaluate(y, lambda, r, jy, jl);
    }
    double ResidualNoise(const Eigen::VectorXd&, double) override { return 1e-3; }

   private:
    ArctanProblem& inner_;
  } claimed(plain);
  Evaluator evaluator(claimed);
  NewtonSettings settings;
  const CorrectorResult result =
      CorrectAtFixedLambda(evaluator, UnitScaling(1), settings, Eigen::Vector2d(0.5, 0.2));
  REQUIRE(result.converged);
  CHECK_FALSE(result.at_noise_floor);
  CHECK(std::abs(std::atan(result.u(0)) - 0.2) <= settings.residual_tolerance);
}

}  // namespace
}  // namespace nfrc
