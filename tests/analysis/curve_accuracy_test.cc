// CurveDeviation against distances worked out by hand, and the step weights' effect on a
// traced curve against a reference traced with a tenth of the step.
#include "analysis/curve_accuracy.h"

#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

namespace nfrc {
namespace {

// Exact geometry in double precision: the distances below are sums of a few roundings.
constexpr double kExact = 1e-12;

PlottedCurve Tent(int points_per_side, double height) {
  PlottedCurve curve;
  curve.measures.resize(1);
  for (int i = 0; i <= 2 * points_per_side; ++i) {
    const double x = static_cast<double>(i) / (2 * points_per_side);
    curve.omega.push_back(1.0 + x);  // ω from 1 to 2: span 1
    curve.measures[0].push_back(height * (1.0 - std::abs(2.0 * x - 1.0)));
  }
  return curve;
}

TEST_CASE("CurveDeviation: a tent against its base is the tent's normalised height") {
  const PlottedCurve reference = Tent(50, 0.1);
  PlottedCurve base;
  base.omega = {1.0, 2.0};
  base.measures = {{0.0, 0.0}};
  // The apex (0.5, 1) in plot proportions lies 1 above the base segment.
  CHECK(std::abs(CurveDeviation(reference, base) - 1.0) < kExact);
  // The same tent sampled coarser but through its apex is the same polyline.
  CHECK(CurveDeviation(reference, Tent(1, 0.1)) < kExact);
}

TEST_CASE("CurveDeviation: on a log scale a uniform factor is its logarithm") {
  PlottedCurve reference = Tent(20, 1.0), scaled = Tent(20, 1.0);
  reference.log_scale = scaled.log_scale = true;
  for (size_t i = 0; i < reference.omega.size(); ++i) {
    reference.measures[0][i] += 1.0;
    scaled.measures[0][i] = 1.001 * reference.measures[0][i];
  }
  // ln(1.001 m) − ln m = ln 1.001 vertically; the polylines are parallel translates, so the
  // distance is that gap times the cosine of the slope, at most ln 1.001 and at least it
  // times cos(atan(slope)) on the steepest segment (slope ≤ ln 2 per 1/40 of the span).
  const double deviation = CurveDeviation(reference, scaled);
  CHECK(deviation <= std::log(1.001) + kExact);
  CHECK(deviation >= std::log(1.001) * std::cos(std::atan(40.0 * std::log(2.0))) - kExact);
}

TEST_CASE("CurveDeviation: bad curves are refused") {
  PlottedCurve one;
  one.omega = {1.0};
  one.measures = {{1.0}};
  CHECK_THROWS_AS(CurveDeviation(one, Tent(2, 1.0)), std::invalid_argument);
  PlottedCurve logged = Tent(2, 1.0);
  logged.log_scale = true;  // the tent's ends are 0
  CHECK_THROWS_AS(CurveDeviation(logged, logged), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
