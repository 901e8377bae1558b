// Steps sized by the plotted curve (ContinuationOptions::plot_tolerance) on the one-harmonic
// Duffing branch, whose amplitude curve is known in closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::DuffingProblem;

// The engine's chord error comes from the cubic through the end points and slopes, exact to
// O(h³) against the chord's O(h²): at the steps a tolerance of 1e-3 allows the true distance
// stays within half the tolerance again.
constexpr double kEstimateSlack = 1.5;

// The Duffing branch plotted as its amplitude A = √(a² + b²) on a linear axis.
class DuffingAmplitude : public PlotCurve {
 public:
  std::vector<PlotScale> Scales() const override { return {PlotScale::kLinear}; }
  Eigen::VectorXd Coordinates(const Eigen::VectorXd& y, double) override {
    return Eigen::VectorXd::Constant(1, std::hypot(y(0), y(1)));
  }
};

struct Point2 {
  double x, y;
};

// Points of the exact curve in plot units (ω over span, A over a_max), for ω in [lo, hi]:
// for each A the amplitude equation [(1 − ω² + κA²)² + (cω)²]A² = F² is a quadratic in
// w = ω², w² − (2(1 + κA²) − c²) w + (1 + κA²)² − F²/A² = 0, whose roots give both sides.
std::vector<Point2> ExactCurve(double lo, double hi, double span, double a_max) {
  const double kappa = 0.75 * DuffingProblem::kCubic, c = DuffingProblem::kDamping;
  const double f = DuffingProblem::kForce;
  std::vector<Point2> curve;
  constexpr int kSamples = 200000;
  for (int k = 1; k <= kSamples; ++k) {
    const double a = 1.2 * a_max * k / kSamples;
    const double s = 1.0 + kappa * a * a;
    const double p = 2.0 * s - c * c, q = s * s - f * f / (a * a);
    const double disc = p * p - 4.0 * q;
    if (disc < 0.0) continue;
    for (const double w : {(p - std::sqrt(disc)) / 2.0, (p + std::sqrt(disc)) / 2.0}) {
      if (w <= 0.0) continue;
      const double omega = std::sqrt(w);
      if (omega >= lo && omega <= hi) curve.push_back({omega / span, a / a_max});
    }
  }
  return curve;
}

// Largest distance of the exact curve from the branch's polyline, in plot units.
double Deviation(const Branch& branch, double span) {
  std::vector<Point2> line;
  double a_max = 0.0;
  for (const BranchPoint& p : branch.points) a_max = std::max(a_max, std::hypot(p.y(0), p.y(1)));
  for (const BranchPoint& p : branch.points) {
    line.push_back({p.lambda / span, std::hypot(p.y(0), p.y(1)) / a_max});
  }
  double worst = 0.0;
  for (const Point2& q :
       ExactCurve(branch.points.front().lambda, branch.points.back().lambda, span, a_max)) {
    double nearest = INFINITY;
    for (size_t i = 0; i + 1 < line.size(); ++i) {
      const double dx = line[i + 1].x - line[i].x, dy = line[i + 1].y - line[i].y;
      const double l2 = dx * dx + dy * dy;
      const double t =
          l2 > 0.0 ? std::clamp(((q.x - line[i].x) * dx + (q.y - line[i].y) * dy) / l2, 0.0, 1.0)
                   : 0.0;
      nearest = std::min(nearest, std::hypot(q.x - line[i].x - t * dx, q.y - line[i].y - t * dy));
    }
    worst = std::max(worst, nearest);
  }
  return worst;
}

Branch TraceDuffing(double plot_tolerance) {
  DuffingProblem problem;
  DuffingAmplitude amplitude;
  ContinuationOptions options;
  options.lambda_start = 0.5;
  options.lambda_end = 1.6;
  options.max_step = 0.5;
  options.plot_tolerance = plot_tolerance;
  const double static_amplitude = DuffingProblem::kForce / (1.0 - 0.25);
  return Continue(problem, Eigen::Vector2d(static_amplitude, 0.0), options, nullptr, &amplitude);
}

TEST_CASE("plot steps: every chord of the Duffing curve stays within plot_tolerance") {
  constexpr double kSpan = 1.1;  // |lambda_end − lambda_start|
  for (const double tolerance : {1e-3, 2.5e-4}) {
    const Branch branch = TraceDuffing(tolerance);
    REQUIRE(branch.summary.reason == TerminationReason::kReachedLambdaBound);
    CHECK(branch.folds.size() == 2);
    const double deviation = Deviation(branch, kSpan);
    MESSAGE("tolerance " << tolerance << ": " << branch.points.size() << " points, deviation "
                         << deviation);
    CHECK(deviation <= kEstimateSlack * tolerance);
  }
}

TEST_CASE("plot steps: a quarter of the tolerance takes about twice the points") {
  // The chord error of a smooth curve grows as the step squared.
  const Branch coarse = TraceDuffing(1e-3), fine = TraceDuffing(2.5e-4);
  const double ratio = static_cast<double>(fine.points.size()) / coarse.points.size();
  MESSAGE(coarse.points.size() << " -> " << fine.points.size() << " points");
  CHECK(ratio > 1.5);
  CHECK(ratio < 2.7);
}

TEST_CASE("plot steps: off by default, and refused without a plotted curve") {
  DuffingProblem problem;
  ContinuationOptions options;
  options.lambda_start = 0.5;
  options.lambda_end = 1.6;
  options.plot_tolerance = 1e-3;
  CHECK_THROWS_AS(Continue(problem, Eigen::Vector2d(0.24, 0.0), options), std::invalid_argument);
  options.plot_tolerance = 0.0;
  CHECK(Continue(problem, Eigen::Vector2d(0.24, 0.0), options).summary.success());
}

}  // namespace
}  // namespace nfrc
