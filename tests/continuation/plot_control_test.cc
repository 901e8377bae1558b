#include "continuation/plot_control.h"

#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

namespace nfrc {
namespace {

// Rounding of a few dozen flops on O(1) plot coordinates.
constexpr double kRounding = 1e-12;
// ChordError samples the interpolant at τ = k/16; on a parabola whose extreme distance lies
// between two samples it reads low by at most the curvature over (1/32)² of the chord.
constexpr double kSamplingSlack = 2e-3;

// A curve whose one coordinate is the unknown y itself.
class PlotOnly : public PlotCurve {
 public:
  explicit PlotOnly(PlotScale scale) : scale_(scale) {}
  std::vector<PlotScale> Scales() const override { return {scale_}; }
  Eigen::VectorXd Coordinates(const Eigen::VectorXd& y, double) override { return y; }

 private:
  PlotScale scale_;
};

// A sample of the curve y = f(λ) at λ, the branch heading along (f'(λ), 1) scaled to unit
// length per unit arclength `h_unit`.
PlotChordControl::Sample Sample(double lambda, double value, double slope) {
  PlotChordControl::Sample s;
  s.lambda = lambda;
  s.lambda_slope = 1.0;
  s.coordinates = Eigen::VectorXd::Constant(1, value);
  s.slopes = Eigen::VectorXd::Constant(1, slope);
  return s;
}

// Largest distance of the curve (λ, f(λ)/unit), λ ∈ [l0, l1], from its chord segment,
// densely. A linear axis is drawn over the largest |value| so far: here the larger of the
// ends, `unit`, as in ChordError before any Include.
template <typename F>
double DenseChordDistance(F f, double l0, double l1, double unit) {
  const Eigen::Vector2d p0(l0, f(l0) / unit), p1(l1, f(l1) / unit), chord = p1 - p0;
  double worst = 0.0;
  for (int k = 0; k <= 100000; ++k) {
    const double l = l0 + (l1 - l0) * k / 100000.0;
    const Eigen::Vector2d p(l, f(l) / unit);
    const double t = std::clamp((p - p0).dot(chord) / chord.squaredNorm(), 0.0, 1.0);
    worst = std::max(worst, (p - p0 - t * chord).norm());
  }
  return worst;
}

TEST_CASE("plot control: the chord error of a parabola is its exact distance from the chord") {
  PlotOnly curve(PlotScale::kLinear);
  PlotChordControl control(curve, 1.0, 1e-3);
  // y = 0.8 λ², λ from 0.2 to 0.5 (h = Δλ with the λ slope 1); the cubic interpolant is the
  // parabola itself, so only the sampling in τ separates the two.
  auto f = [](double l) { return 0.8 * l * l; };
  const double l0 = 0.2, l1 = 0.5, h = l1 - l0;
  const double expected = DenseChordDistance(f, l0, l1, f(l1));
  const double error =
      control.ChordError(Sample(l0, f(l0), 1.6 * l0), Sample(l1, f(l1), 1.6 * l1), h, false);
  CHECK(error == doctest::Approx(expected).epsilon(kSamplingSlack));
  CHECK(error > 0.0);
}

TEST_CASE("plot control: a peak overshot just before the end of a chord counts") {
  // y = −(λ − 0.45)²: the peak lies inside the step but near its end, so the curve bulges
  // past the end point along the chord. The distance to the chord's line would miss most
  // of it; ChordError measures to the segment, as the accuracy of a drawn curve does.
  PlotOnly curve(PlotScale::kLinear);
  PlotChordControl control(curve, 1.0, 1e-3);
  auto f = [](double l) { return -(l - 0.45) * (l - 0.45); };
  auto df = [](double l) { return -2.0 * (l - 0.45); };
  const double l0 = 0.2, l1 = 0.5;
  const double expected = DenseChordDistance(f, l0, l1, std::abs(f(l0)));
  CHECK(control.ChordError(Sample(l0, f(l0), df(l0)), Sample(l1, f(l1), df(l1)), l1 - l0, false) ==
        doctest::Approx(expected).epsilon(kSamplingSlack));
}

TEST_CASE("plot control: across a corner the apex of the end tangents is taken") {
  // y = |λ − 0.3|·2 from 0.1 to 0.6: straight pieces meeting at λ = 0.3. The cubic's bulge
  // is half the corner's height; the apex of the end tangents is the corner itself.
  PlotOnly curve(PlotScale::kLinear);
  PlotChordControl control(curve, 1.0, 1e-3);
  auto f = [](double l) { return 2.0 * std::abs(l - 0.3); };
  const double l0 = 0.1, l1 = 0.6, h = l1 - l0;
  const double expected = DenseChordDistance(f, l0, l1, f(l1));
  const auto a = Sample(l0, f(l0), -2.0), b = Sample(l1, f(l1), 2.0);
  CHECK(control.ChordError(a, b, h, true) == doctest::Approx(expected).epsilon(kRounding));
  CHECK(control.ChordError(a, b, h, false) < 0.6 * expected);
}

TEST_CASE("plot control: linear axes are scaled by the largest value, lambda by its span") {
  PlotOnly curve(PlotScale::kLinear);
  PlotChordControl control(curve, 2.0, 1e-3);
  // y = 2λ², plotted as y over its largest value 2 (after Include) against x = λ/2 (span 2):
  // the curve 4x².
  auto f = [](double l) { return 10.0 * 0.8 * (l / 2.0) * (l / 2.0); };
  auto df = [](double l) { return 10.0 * 0.8 * l / 2.0; };
  const double l0 = 0.4, l1 = 1.0;
  control.Include(Sample(l1, f(l1), df(l1)));
  auto g = [](double x) { return 4.0 * x * x; };
  const double expected = DenseChordDistance(g, l0 / 2.0, l1 / 2.0, 1.0);
  CHECK(control.ChordError(Sample(l0, f(l0), df(l0)), Sample(l1, f(l1), df(l1)), l1 - l0, false) ==
        doctest::Approx(expected).epsilon(kSamplingSlack));
}

TEST_CASE("plot control: samples take logarithms on log axes and refuse values <= 0") {
  PlotOnly curve(PlotScale::kLog);
  PlotChordControl control(curve, 1.0, 1e-3);
  Eigen::VectorXd u(2), direction(2);
  u << 2.0, 0.3;
  direction << 0.5, 1.0;
  const auto sample = control.At(u, direction);
  REQUIRE(sample.has_value());
  CHECK(sample->coordinates(0) == doctest::Approx(std::log(2.0)).epsilon(kRounding));
  // d ln y / ds = (dy/ds) / y = 0.5 / 2, by a difference of step 1e-6: error ~1e-7.
  CHECK(sample->slopes(0) == doctest::Approx(0.25).epsilon(1e-6));
  CHECK(sample->lambda_slope == 1.0);
  u(0) = 0.0;
  CHECK_FALSE(control.At(u, direction).has_value());
}

TEST_CASE("plot control: a curve without coordinates is refused") {
  class Empty : public PlotCurve {
   public:
    std::vector<PlotScale> Scales() const override { return {}; }
    Eigen::VectorXd Coordinates(const Eigen::VectorXd&, double) override { return {}; }
  } curve;
  CHECK_THROWS_AS(PlotChordControl(curve, 1.0, 1e-3), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
