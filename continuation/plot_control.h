#pragma once

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "continuation/problem.h"

namespace nfrc {

// Sizes steps by the curve the user plots rather than by the whole state: estimates how far
// the chord between two points departs from the curve, in each (λ, coordinate) plane, from
// the points' plot coordinates and their slopes along the branch (the cubic Hermite
// interpolant between them). On a nonsmooth branch the state's tangent jumps whenever a
// sample of a law switches, while the plotted curve stays smooth between its few corners.
class PlotChordControl {
 public:
  // A point's plot coordinates (logarithms on log axes), λ, and their derivatives per unit
  // scaled arclength along the branch.
  struct Sample {
    Eigen::VectorXd coordinates;
    Eigen::VectorXd slopes;
    double lambda = 0.0;
    double lambda_slope = 0.0;
  };

  // lambda_span (> 0): the λ extent the plot spans; tolerance (> 0): plot_tolerance.
  // Throws std::invalid_argument if `curve` has no coordinates.
  PlotChordControl(PlotCurve& curve, double lambda_span, double tolerance);

  // The sample at u = (y, λ) with the branch heading along `direction` (unscaled, of unit
  // scaled norm). Nothing when the curve gives no usable coordinates there (a non-finite
  // value, or one ≤ 0 on a log axis).
  std::optional<Sample> At(const Eigen::VectorXd& u, const Eigen::VectorXd& direction);

  // Largest distance (plot units: λ over its span, linear coordinates over their largest
  // |value| on the branch so far) of the chord from a to b, h apart in scaled arclength,
  // from the cubic interpolant through both. Across a `corner` (the state's tangent jumped:
  // a law switched branch) the curve may bend at one point rather than along the chord,
  // which the cubic's bulge underestimates up to twice: the apex of the triangle of the two
  // end tangents is taken instead, where they meet ahead of both ends.
  double ChordError(const Sample& a, const Sample& b, double h, bool corner) const;

  // Takes an accepted point's sample in: linear axes are scaled by the largest |value|.
  void Include(const Sample& sample);

  double tolerance() const { return tolerance_; }

 private:
  std::optional<Eigen::VectorXd> Coordinates(const Eigen::VectorXd& u);

  PlotCurve& curve_;
  std::vector<PlotScale> scales_;
  double lambda_span_;
  double tolerance_;
  Eigen::VectorXd largest_;  // largest |value| seen on each linear axis
};

}  // namespace nfrc
