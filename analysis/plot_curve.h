#pragma once

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "analysis/harmonic_system.h"
#include "analysis/point_measures.h"
#include "continuation/problem.h"

namespace nfrc {

// The measure a curve is plotted in, which the step control by the plot follows
// (continuation.plot_tolerance): max_t |x(t)| of each output DOF (linear axes), or the
// period-mean energy (a log axis, as the friction papers draw it).
enum class PlotMeasure { kMaxAbs, kEnergy };

// What a trace's step control by the plot follows: the measure and the output DOFs of max |x|
// (none: nothing is plotted).
struct PlotSpec {
  PlotMeasure measure = PlotMeasure::kMaxAbs;
  std::vector<int> dofs;
};

// The plotted curve of a HarmonicSystem's branch in the measure of a PlotSpec, for the
// engine's step control by the plot.
class MeasureCurve : public PlotCurve {
 public:
  MeasureCurve(HarmonicSystem& system, PlotSpec plot);

  std::vector<PlotScale> Scales() const override;
  Eigen::VectorXd Coordinates(const Eigen::VectorXd& y, double omega) override;

 private:
  HarmonicSystem& system_;
  PlotMeasure measure_;
  std::vector<int> output_dofs_;
  // Only for max |x|: its fine sampling (8(2H + 1) samples) is large at high H.
  std::optional<PointAnalyzer> analyzer_;
};

}  // namespace nfrc
