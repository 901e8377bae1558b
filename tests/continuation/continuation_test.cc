#include "continuation/continuation.h"

#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <sstream>
#include <string>

#include "continuation/corrector.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::CircleProblem;
using testing::CubicProblem;
using testing::DuffingFoldFrequency;
using testing::DuffingProblem;

// Folds are localised to fold_tolerance (1e-8) relative in λ by the engine; comparing
// with the analytic λ at 1e-8 relative is the requirement itself (the localisation stops
// on the difference of successive iterates, which bounds the error of the last one).
constexpr double kFoldLambdaTolerance = 1e-8;

double MaxResidual(ContinuationProblem& problem, const Branch& branch) {
  double worst = 0.0;
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(problem.NumUnknowns());
  for (const BranchPoint& point : branch.points) {
    problem.Evaluate(point.y, point.lambda, &residual, nullptr, nullptr);
    worst = std::max(worst, residual.norm());
  }
  return worst;
}

int TangentLambdaSignChanges(const Branch& branch) {
  int changes = 0;
  for (size_t i = 1; i < branch.points.size(); ++i) {
    if (branch.points[i].tangent_lambda * branch.points[i - 1].tangent_lambda < 0) ++changes;
  }
  return changes;
}

TEST_CASE("cubic: passes both folds and lands exactly on the far bound") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options);

  REQUIRE(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.summary.success());
  REQUIRE(branch.folds.size() == 2);
  // Lower branch rises to the fold at (y, λ) = (−1, 2/3), the middle one falls to (1, −2/3).
  CHECK(branch.folds[0].lambda == doctest::Approx(2.0 / 3.0).epsilon(kFoldLambdaTolerance));
  CHECK(branch.folds[1].lambda == doctest::Approx(-2.0 / 3.0).epsilon(kFoldLambdaTolerance));
  for (const Fold& fold : branch.folds) {
    CHECK(fold.converged);
    CHECK_FALSE(fold.corner);  // a smooth fold: τ_λ passes through zero
    CHECK(fold.lambda_accuracy <= options.fold_tolerance * std::abs(fold.lambda));
    // λ is quadratic in the arclength at a fold, y linear: y is known to about
    // sqrt(λ accuracy / curvature); 1e-4 is well above sqrt(1e-8).
    CHECK(std::abs(fold.y(0)) == doctest::Approx(1.0).epsilon(1e-4));
    CHECK(fold.y(0) * fold.lambda < 0.0);
  }
  // The reported accuracy is an honest error estimate: the quadratic model behind it is
  // exact to leading order, so twice it bounds the true error.
  CHECK(std::abs(branch.folds[0].lambda - 2.0 / 3.0) <= 2.0 * branch.folds[0].lambda_accuracy);
  CHECK(std::abs(branch.folds[1].lambda + 2.0 / 3.0) <= 2.0 * branch.folds[1].lambda_accuracy);
  CHECK(branch.folds[0].after_point < branch.folds[1].after_point);
  CHECK(TangentLambdaSignChanges(branch) == 2);

  // The last point is on the upper branch (y > 1) exactly at λ = 2.
  CHECK(branch.points.back().lambda == 2.0);
  CHECK(branch.points.back().y(0) > 1.0);
  CHECK(branch.points.front().lambda == -2.0);
  // Every point solves R = 0 to residual_tolerance·r, r = |R(0, −2)| = 2.
  CHECK(MaxResidual(problem, branch) <= options.residual_tolerance * 2.0);
  for (const BranchPoint& point : branch.points) {
    CHECK(point.lambda >= -2.0);
    CHECK(point.lambda <= 2.0);
  }
  const ContinuationSummary& summary = branch.summary;
  CHECK(summary.num_points == static_cast<int>(branch.points.size()));
  CHECK(summary.num_folds == 2);
  CHECK(summary.num_accepted_steps == summary.num_points - 1);
  CHECK(summary.num_accepted_steps + summary.num_rejected_steps ==
        static_cast<int>(summary.history.size()));
  CHECK(summary.total_newton_iterations > summary.num_accepted_steps);
  CHECK(summary.num_evaluations > summary.total_newton_iterations);
  CHECK(summary.wall_time_seconds >= 0.0);
}

TEST_CASE("cubic: followed downwards, the first tangent points towards lambda_end") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = 2.0;
  options.lambda_end = -2.0;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 2.0), options);

  REQUIRE(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.points.front().tangent_lambda < 0.0);
  REQUIRE(branch.folds.size() == 2);
  CHECK(branch.folds[0].lambda == doctest::Approx(-2.0 / 3.0).epsilon(kFoldLambdaTolerance));
  CHECK(branch.folds[1].lambda == doctest::Approx(2.0 / 3.0).epsilon(kFoldLambdaTolerance));
  CHECK(branch.points.back().lambda == -2.0);
  CHECK(branch.points.back().y(0) < -1.0);
}

TEST_CASE("cubic: fold detection can be switched off") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  options.detect_folds = false;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options);
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.folds.empty());
  CHECK(TangentLambdaSignChanges(branch) == 2);
}

TEST_CASE("circle: a closed curve stops after one turn with two folds") {
  CircleProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 2.0;
  // The range [−2, 2] contains the whole circle, so only closure can end the run.
  options.lambda_min = -2.0;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 0.8), options);

  REQUIRE(branch.summary.reason == TerminationReason::kClosedCurve);
  REQUIRE(branch.folds.size() == 2);
  // Heading towards λ_end = 2 from (1, 0): the fold at λ = 1 comes first.
  CHECK(branch.folds[0].lambda == doctest::Approx(1.0).epsilon(kFoldLambdaTolerance));
  CHECK(branch.folds[1].lambda == doctest::Approx(-1.0).epsilon(kFoldLambdaTolerance));
  // The circle's circumference in the scaled norm (s_y = 1, s_λ = 2) is about 4.84; with
  // max_step 0.1 that is ≥ 49 points, and the tangent-angle rule keeps it well below 1000.
  CHECK(branch.points.size() >= 49);
  CHECK(branch.points.size() < 1000);
  // The run stopped within a step of the first point, past it in y.
  const BranchPoint& last = branch.points.back();
  CHECK(std::hypot(last.y(0) - 1.0, last.lambda / 2.0) <= options.max_step);
  CHECK(last.tangent_lambda > 0.0);
  CHECK(MaxResidual(problem, branch) <= options.residual_tolerance);
}

TEST_CASE("duffing: folds where R_y is singular, passed by the bordered LU") {
  DuffingProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.5;
  options.lambda_end = 1.6;
  options.lambda_name = "omega";
  const double static_amplitude = DuffingProblem::kForce / (1.0 - 0.25);
  const Branch branch = Continue(problem, Eigen::Vector2d(static_amplitude, 0.0), options);

  REQUIRE(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(branch.folds.size() == 2);
  const double upper_fold = DuffingFoldFrequency(1.05, 1.6, true);   // ≈ 1.2675370
  const double lower_fold = DuffingFoldFrequency(1.05, 1.6, false);  // ≈ 1.1155859
  CHECK(upper_fold == doctest::Approx(1.267537).epsilon(1e-6));
  CHECK(lower_fold == doctest::Approx(1.115586).epsilon(1e-6));
  CHECK(branch.folds[0].lambda == doctest::Approx(upper_fold).epsilon(kFoldLambdaTolerance));
  CHECK(branch.folds[1].lambda == doctest::Approx(lower_fold).epsilon(kFoldLambdaTolerance));
  // At a fold in ω the 2×2 R_y is singular: det R_y vanishes up to the localisation error
  // (O(sqrt(fold_tolerance)) in y) times |∇det| ≈ O(1) here.
  for (const Fold& fold : branch.folds) {
    Eigen::VectorXd residual = Eigen::VectorXd::Zero(2), jacobian_lambda = residual;
    Eigen::MatrixXd jacobian_y = Eigen::MatrixXd::Zero(2, 2);
    problem.Evaluate(fold.y, fold.lambda, &residual, &jacobian_y, &jacobian_lambda);
    CHECK(std::abs(jacobian_y.determinant()) < 1e-3);
    CHECK(residual.norm() <= options.residual_tolerance * DuffingProblem::kForce);
  }
  CHECK(branch.points.back().lambda == 1.6);
  CHECK(MaxResidual(problem, branch) <= options.residual_tolerance * DuffingProblem::kForce);
}

TEST_CASE("a branch starting at y = 0 takes its y scale from dy/dlambda") {
  // R = y − 3λ from (0, 0): no |y| to scale by yet. Left at the tiny absolute floor, the
  // scaled tangent would be all y and λ would not move in max_points steps.
  class LineProblem : public ContinuationProblem {
   public:
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
      (*residual)(0) = y(0) - 3.0 * lambda;
      if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
      if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -3.0;
      return true;
    }
  } problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 1.0;
  options.max_points = 1000;
  const Branch branch = Continue(problem, Eigen::VectorXd::Zero(1), options);
  REQUIRE(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.points.back().lambda == 1.0);
  // The line is exact: y = 3λ to rounding (residual scale 1, so residual_tolerance applies).
  CHECK(std::abs(branch.points.back().y(0) - 3.0) <= options.residual_tolerance);
  // Scaled length of the line with s_y = 3, s_λ = 1 is √2; max_step 0.1 gives ≥ 15 points.
  CHECK(branch.points.size() >= 15);
  CHECK(branch.points.size() < 100);
}

TEST_CASE("stall: an Evaluate that fails beyond a lambda ends the run as stalled") {
  class EndingProblem : public ContinuationProblem {
   public:
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
      if (lambda > 0.5) return false;
      (*residual)(0) = y(0) - lambda - 1.0;
      if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
      if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -1.0;
      return true;
    }
  } problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 1.0;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 1.0), options);

  REQUIRE(branch.summary.reason == TerminationReason::kStalled);
  CHECK_FALSE(branch.summary.success());
  CHECK(branch.summary.message.find("stalled at lambda=") != std::string::npos);
  CHECK(branch.summary.message.find("step=") != std::string::npos);
  // The last step tried was below min_step in the scaled norm, s_λ = 1, so the branch got
  // to within a few min_step of the edge; 10·min_step leaves room for the tangent's slope.
  CHECK(branch.points.back().lambda <= 0.5);
  CHECK(branch.points.back().lambda >= 0.5 - 10.0 * options.min_step);
  // Each halving of the gap to the edge costs a few attempts; about log2(0.5/1e-7) ≈ 22
  // halvings, so a few hundred attempts is a generous bound for "finite".
  CHECK(branch.summary.history.size() < 400);
  CHECK(branch.summary.num_rejected_steps > 0);
  CHECK_FALSE(branch.summary.history.back().accepted);
  CHECK_FALSE(branch.summary.history.back().note.empty());
}

TEST_CASE("start failure: no solution at lambda_start") {
  class NoRootProblem : public ContinuationProblem {
   public:
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
      (*residual)(0) = y(0) * y(0) + 1.0 + lambda * lambda;
      if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 2.0 * y(0);
      if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = 2.0 * lambda;
      return true;
    }
  } problem;
  ContinuationOptions options;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 0.3), options);
  CHECK(branch.summary.reason == TerminationReason::kStartFailed);
  CHECK(branch.points.empty());
  CHECK(branch.summary.message.find("lambda=0") != std::string::npos);
}

TEST_CASE("max_points ends the run with that many points") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  options.max_points = 5;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options);
  CHECK(branch.summary.reason == TerminationReason::kMaxPoints);
  CHECK(branch.points.size() == 5);
  CHECK(branch.summary.num_accepted_steps == 4);
}

class RecordingObserver : public ContinuationObserver {
 public:
  explicit RecordingObserver(int stop_after) : stop_after_(stop_after) {}
  bool OnPoint(const BranchPoint& point, int index) override {
    CHECK(index == num_points_);
    ++num_points_;
    last_lambda_ = point.lambda;
    return stop_after_ < 0 || index < stop_after_;
  }
  void OnFold(const Fold& fold) override {
    CHECK(fold.after_point == num_points_ - 1);
    ++num_folds_;
  }
  int num_points_ = 0;
  int num_folds_ = 0;
  double last_lambda_ = 0.0;

 private:
  int stop_after_;
};

TEST_CASE("observer: sees every point and fold, and can stop the run") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  RecordingObserver all(-1);
  const Branch full = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options, &all);
  CHECK(all.num_points_ == static_cast<int>(full.points.size()));
  CHECK(all.num_folds_ == 2);
  CHECK(all.last_lambda_ == 2.0);

  RecordingObserver stopper(3);
  const Branch stopped = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options, &stopper);
  CHECK(stopped.summary.reason == TerminationReason::kStoppedByObserver);
  CHECK(stopped.points.size() == 4);
  CHECK(stopper.num_points_ == 4);
}

TEST_CASE("progress: one line per point and fold, and a summary line") {
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  options.lambda_name = "omega";
  std::ostringstream out;
  options.progress = &out;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options);

  std::istringstream lines(out.str());
  std::string line;
  int point_lines = 0, fold_lines = 0, other_lines = 0;
  std::string last;
  while (std::getline(lines, line)) {
    if (line.rfind("point ", 0) == 0) {
      ++point_lines;
    } else if (line.rfind("fold ", 0) == 0) {
      ++fold_lines;
    } else {
      ++other_lines;
    }
    last = line;
  }
  CHECK(point_lines == static_cast<int>(branch.points.size()));
  CHECK(fold_lines == 2);
  CHECK(other_lines == 1);
  CHECK(out.str().rfind("point 0  omega=-2  step=0  newton=", 0) == 0);
  CHECK(out.str().find("fold 1  omega=0.66666667  after point ") != std::string::npos);
  CHECK(last.rfind("finished: reached_lambda_bound", 0) == 0);
  CHECK(ToString(TerminationReason::kClosedCurve) == std::string("closed_curve"));
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

// R = y − λ − 20·max(0, λ − 1/2): a piecewise-smooth branch whose slope jumps from 1 to 21
// at λ = 1/2, turning the tangent by more than max_tangent_angle however short the step, as
// semismooth HBM branches do where a sample of a nonsmooth law switches branch. (A turn of
// more than 90° cannot be passed by pseudo-arclength: no hyperplane beyond the kink meets
// the branch: see the V-shaped problem below.)
class KinkProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const bool beyond = lambda > 0.5;
    (*residual)(0) = y(0) - lambda - (beyond ? kSlopeJump * (lambda - 0.5) : 0.0);
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -1.0 - (beyond ? kSlopeJump : 0.0);
    return true;
  }
  static constexpr double kSlopeJump = 20.0;
};

TEST_CASE("kink: a nonsmooth branch is passed, not stalled on, and stays on the curve") {
  KinkProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 1.0;
  options.initial_step = 0.05;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 0.0), options);
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  int kinks = 0;
  for (const StepRecord& record : branch.summary.history) {
    if (record.accepted && record.note.rfind("kink", 0) == 0) ++kinks;
  }
  CHECK(kinks == 1);
  for (const BranchPoint& point : branch.points) {
    const double exact =
        point.lambda + (point.lambda > 0.5 ? KinkProblem::kSlopeJump * (point.lambda - 0.5) : 0);
    CHECK(std::abs(point.y(0) - exact) < 1e-9 * (1 + std::abs(exact)));  // R = 0 at points
  }
}

// R = y − |λ − 1/2|: at λ = 1/2 the branch turns by more than 90° in the scaled norm, so no
// arclength hyperplane beyond the kink meets it; the natural-parameter fallback must pass it.
class VeeProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = y(0) - std::abs(lambda - 0.5);
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = lambda > 0.5 ? -1.0 : 1.0;
    return true;
  }
};

TEST_CASE("kink over 90 degrees: passed by a natural-parameter step, orientation kept") {
  VeeProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 1.0;
  options.initial_step = 0.05;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, 0.5), options);
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.points.back().lambda == doctest::Approx(1.0));
  int natural = 0;
  for (const StepRecord& record : branch.summary.history) {
    if (record.accepted && record.note.rfind("natural", 0) == 0) ++natural;
    CHECK(record.fixed_lambda == (record.accepted && record.note.rfind("natural", 0) == 0));
  }
  CHECK(natural >= 1);
  for (size_t i = 1; i < branch.points.size(); ++i) {
    CHECK(branch.points[i].lambda > branch.points[i - 1].lambda);  // never turned back
    CHECK(std::abs(branch.points[i].y(0) - std::abs(branch.points[i].lambda - 0.5)) < 1e-9);
  }
  CHECK(branch.folds.empty());
}

// R = λ − 1 + |y|/2: λ rises with y to 1 at y = 0, where it turns at a corner (τ_λ jumps
// from +1/√5 to −1/√5 without passing zero), as folds of sampled nonsmooth laws do.
class CornerProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = lambda - 1.0 + 0.5 * std::abs(y(0));
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = y(0) >= 0.0 ? 0.5 : -0.5;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = 1.0;
    return true;
  }
};

TEST_CASE("corner fold: located to its bracket, flagged, and the exact turn inside it") {
  CornerProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.0;
  options.lambda_end = 2.0;
  options.initial_step = 0.05;
  std::ostringstream progress;
  options.progress = &progress;
  const Branch branch = Continue(problem, Eigen::VectorXd::Constant(1, -2.0), options);
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(branch.folds.size() == 1);
  CHECK(progress.str().find("  (corner)\n") != std::string::npos);
  const Fold& fold = branch.folds[0];
  MESSAGE("corner fold at " << fold.lambda << " +- " << fold.lambda_accuracy << " after "
                            << fold.iterations << " iterations");
  CHECK(fold.corner);
  CHECK(fold.converged);
  CHECK(std::abs(fold.lambda - 1.0) <= fold.lambda_accuracy);
  // The bracket shrank 64-fold from a step of at most max_step: λ within a few 1e-3.
  CHECK(fold.lambda_accuracy <= options.max_step / 64.0);
  // Bisection from the step down to 1e-8 would take ~20 iterations; the corner stops at ~6.
  CHECK(fold.iterations <= 10);
  // The branch comes back down on the other side of the corner.
  CHECK(branch.points.back().y(0) > 0.0);
}

// The Duffing balance, raising `stop` at its `raise_at`-th evaluation: a signal arriving in
// the middle of a Newton correction.
class StoppingDuffing : public DuffingProblem {
 public:
  StoppingDuffing(std::atomic<bool>* stop, int raise_at) : stop_(stop), raise_at_(raise_at) {}
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    if (++evaluations_ == raise_at_) stop_->store(true);
    return DuffingProblem::Evaluate(y, lambda, residual, jacobian_y, jacobian_lambda);
  }
  int evaluations() const { return evaluations_; }

 private:
  std::atomic<bool>* stop_;
  int raise_at_;
  int evaluations_ = 0;
};

TEST_CASE("stop: a raised flag ends the run within the Newton correction it interrupts") {
  ContinuationOptions options;
  options.lambda_start = 0.5;
  options.lambda_end = 1.6;
  const Eigen::VectorXd guess = Eigen::Vector2d(DuffingProblem::kForce / 0.75, 0.0);
  // The whole branch, untouched, for the count of points and evaluations.
  std::atomic<bool> never{false};
  StoppingDuffing whole(&never, -1);
  const Branch full = Continue(whole, guess, options);
  REQUIRE(full.summary.success());

  for (const int raise_at : {2, 40, 200}) {
    CAPTURE(raise_at);
    std::atomic<bool> stop{false};
    StoppingDuffing problem(&stop, raise_at);
    ContinuationOptions stopping = options;
    stopping.stop = &stop;
    const Branch branch = Continue(problem, guess, stopping);
    CHECK(branch.summary.reason == TerminationReason::kStoppedByObserver);
    CHECK(branch.summary.message.find("interrupted") != std::string::npos);
    CHECK(branch.points.size() < full.points.size());
    // Once raised, at most the rest of the iteration under way evaluates (its line search:
    // the full step, 12 halvings, the Jacobian of the one taken and a watchdog step) and the
    // first linearisation of the fallback correction, which stops before iterating: no further
    // step. Without the flag inside Newton the run went on to its next point or to the end.
    constexpr int kRestOfIteration = 16;
    CHECK(problem.evaluations() <= raise_at + kRestOfIteration + 1);
  }
}

TEST_CASE("stop: a correction ends at once, failing with kInterrupted") {
  DuffingProblem problem;
  Evaluator evaluator(problem);
  const Scaling scaling(problem.ScaleGroups(), 1.0, 1e-6);
  std::atomic<bool> stop{true};
  NewtonSettings settings;
  settings.stop = &stop;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3);
  u(2) = 1.0;
  const CorrectorResult result = CorrectAtFixedLambda(evaluator, scaling, settings, u);
  CHECK_FALSE(result.converged);
  CHECK(result.failure == kInterrupted);
  CHECK(result.iterations == 0);
}

}  // namespace
}  // namespace nfrc
