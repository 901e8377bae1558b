#include "continuation/plot_control.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nfrc {
namespace {

// Scaled arclength of the finite difference giving a sample's slopes: far below any step
// (≥ 1e-7·…, typically 1e-3–1e-1) and far above the rounding of O(1) coordinates.
constexpr double kSlopeStep = 1e-6;

// Points along the chord at which the interpolant's distance is taken (τ = k/kChordSamples).
constexpr int kChordSamples = 16;

// Below this sine of the angle between the end tangents they are taken as parallel (no apex).
constexpr double kParallel = 1e-9;

// Distance of p from the segment [a, b]: a curve bulging past an end of its chord (a peak
// overshot by the step) counts as much as one bulging sideways.
double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d chord = b - a;
  const double length2 = chord.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(chord) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * chord)).norm();
}

}  // namespace

PlotChordControl::PlotChordControl(PlotCurve& curve, double lambda_span, double tolerance)
    : curve_(curve),
      scales_(curve.Scales()),
      lambda_span_(lambda_span),
      tolerance_(tolerance),
      largest_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(scales_.size()))) {
  if (scales_.empty()) {
    throw std::invalid_argument(
        "plot_tolerance: the plotted curve has no coordinates (PlotCurve::Scales() is empty)");
  }
  if (!(lambda_span > 0.0) || !(tolerance > 0.0)) {
    throw std::logic_error("PlotChordControl: lambda_span and tolerance must be positive");
  }
}

std::optional<Eigen::VectorXd> PlotChordControl::Coordinates(const Eigen::VectorXd& u) {
  const Eigen::Index n = u.size() - 1;
  Eigen::VectorXd values = curve_.Coordinates(u.head(n), u(n));
  if (values.size() != static_cast<Eigen::Index>(scales_.size())) {
    throw std::logic_error("PlotCurve: Coordinates() size != Scales() size");
  }
  for (Eigen::Index j = 0; j < values.size(); ++j) {
    if (scales_[j] == PlotScale::kLog) {
      if (!(values(j) > 0.0)) return std::nullopt;
      values(j) = std::log(values(j));
    }
    if (!std::isfinite(values(j))) return std::nullopt;
  }
  return values;
}

std::optional<PlotChordControl::Sample> PlotChordControl::At(const Eigen::VectorXd& u,
                                                             const Eigen::VectorXd& direction) {
  const std::optional<Eigen::VectorXd> here = Coordinates(u);
  if (!here) return std::nullopt;
  const std::optional<Eigen::VectorXd> ahead = Coordinates(u + kSlopeStep * direction);
  if (!ahead) return std::nullopt;
  Sample sample;
  sample.coordinates = *here;
  sample.slopes = (*ahead - *here) / kSlopeStep;
  sample.lambda = u(u.size() - 1);
  sample.lambda_slope = direction(direction.size() - 1);
  return sample;
}

double PlotChordControl::ChordError(const Sample& a, const Sample& b, double h, bool corner) const {
  double worst = 0.0;
  for (Eigen::Index j = 0; j < a.coordinates.size(); ++j) {
    double unit = 1.0;
    if (scales_[j] == PlotScale::kLinear) {
      unit = std::max({largest_(j), std::abs(a.coordinates(j)), std::abs(b.coordinates(j))});
      if (unit == 0.0) continue;  // the coordinate is zero so far: nothing to draw yet
    }
    const Eigen::Vector2d p0(a.lambda / lambda_span_, a.coordinates(j) / unit);
    const Eigen::Vector2d p1(b.lambda / lambda_span_, b.coordinates(j) / unit);
    const Eigen::Vector2d d0(h * a.lambda_slope / lambda_span_, h * a.slopes(j) / unit);
    const Eigen::Vector2d d1(h * b.lambda_slope / lambda_span_, h * b.slopes(j) / unit);
    // Hermite: H(τ) = (1−τ)p0 + τp1 + τ(1−τ)[(1−τ)(d0 − Δ) − τ(d1 − Δ)].
    const Eigen::Vector2d chord = p1 - p0;
    const Eigen::Vector2d start = d0 - chord, end = d1 - chord;
    if (corner) {
      // p0 + α d0 = p1 − β d1 with α, β > 0: the end tangents meet ahead of both ends.
      Eigen::Matrix2d lines;
      lines << d0, d1;
      if (std::abs(lines.determinant()) > kParallel * d0.norm() * d1.norm()) {
        const Eigen::Vector2d ab = lines.inverse() * chord;
        if (ab(0) > 0.0 && ab(1) > 0.0) {
          worst = std::max(worst, SegmentDistance(p0 + ab(0) * d0, p0, p1));
          continue;
        }
      }
    }
    for (int k = 1; k < kChordSamples; ++k) {
      const double t = static_cast<double>(k) / kChordSamples;
      const Eigen::Vector2d on_curve =
          (1.0 - t) * p0 + t * p1 + t * (1.0 - t) * ((1.0 - t) * start - t * end);
      worst = std::max(worst, SegmentDistance(on_curve, p0, p1));
    }
  }
  return worst;
}

void PlotChordControl::Include(const Sample& sample) {
  for (Eigen::Index j = 0; j < largest_.size(); ++j) {
    if (scales_[j] == PlotScale::kLinear) {
      largest_(j) = std::max(largest_(j), std::abs(sample.coordinates(j)));
    }
  }
}

}  // namespace nfrc
