#include "analysis/curve_accuracy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nfrc {
namespace {

struct Point2 {
  double x, y;
};

double SegmentDistance(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

// Largest distance of a point of `points` to the polyline `line`.
double OneSided(const std::vector<Point2>& points, const std::vector<Point2>& line) {
  double worst = 0.0;
  for (const Point2& p : points) {
    double nearest = INFINITY;
    for (size_t i = 0; i + 1 < line.size(); ++i) {
      nearest = std::min(nearest, SegmentDistance(p, line[i], line[i + 1]));
    }
    worst = std::max(worst, nearest);
  }
  return worst;
}

void Check(const PlottedCurve& curve, const char* name) {
  if (curve.omega.size() < 2) {
    throw std::invalid_argument(std::string(name) + ": needs at least two points");
  }
  for (const std::vector<double>& m : curve.measures) {
    if (m.size() != curve.omega.size()) {
      throw std::invalid_argument(std::string(name) + ": a measure's size differs from omega's");
    }
    if (curve.log_scale && std::any_of(m.begin(), m.end(), [](double v) { return !(v > 0.0); })) {
      throw std::invalid_argument(std::string(name) + ": non-positive value on a log scale");
    }
  }
}

}  // namespace

double CurveDeviation(const PlottedCurve& reference, const PlottedCurve& curve) {
  Check(reference, "reference");
  Check(curve, "curve");
  if (reference.measures.size() != curve.measures.size()) {
    throw std::invalid_argument("curve: number of measures differs from the reference's");
  }
  const auto [low, high] = std::minmax_element(reference.omega.begin(), reference.omega.end());
  const double span = *high > *low ? *high - *low : 1.0;
  const bool log_scale = reference.log_scale;
  double worst = 0.0;
  for (size_t j = 0; j < reference.measures.size(); ++j) {
    double size = 1.0;
    if (!log_scale) {
      size = 0.0;
      for (double v : reference.measures[j]) size = std::max(size, std::abs(v));
      if (size == 0.0) size = 1.0;
    }
    auto plotted = [&](const PlottedCurve& c) {
      std::vector<Point2> points(c.omega.size());
      for (size_t i = 0; i < points.size(); ++i) {
        const double m = c.measures[j][i];
        points[i] = {c.omega[i] / span, log_scale ? std::log(m) : m / size};
      }
      return points;
    };
    const std::vector<Point2> r = plotted(reference), c = plotted(curve);
    worst = std::max({worst, OneSided(r, c), OneSided(c, r)});
  }
  return worst;
}

}  // namespace nfrc
