#pragma once

#include <vector>

namespace nfrc {

// A response curve as plotted: ω and one or more measures (e.g. max |x| of each output DOF,
// or the energy), each of the same length as ω, in branch order.
struct PlottedCurve {
  std::vector<double> omega;
  std::vector<std::vector<double>> measures;
  bool log_scale = false;  // drawn on a log axis: deviations of ln m count (relative)
};

// Largest distance between two traced versions of one curve, in the plot's own proportions:
// ω over the reference's ω span, each measure over its largest |value| on the reference (or
// ln m on a log scale, where a distance 1e-3 is a relative error of 0.1 %). Every point of
// each curve is measured against the other's polyline (linear interpolation), so a fold, a
// peak cut short or a detour counts. Throws std::invalid_argument for curves of fewer than
// two points, mismatched sizes, or non-positive values on a log scale.
double CurveDeviation(const PlottedCurve& reference, const PlottedCurve& curve);

}  // namespace nfrc
