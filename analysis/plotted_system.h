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

// A HarmonicSystem as the engine follows it with its plotted coordinates: forwards the
// equations unchanged and adds PlotScales/PlotCoordinates from the chosen measure.
class PlottedSystem : public ContinuationProblem {
 public:
  // plot.dofs: model DOFs whose max |x| is plotted (with kMaxAbs; none: no coordinates).
  PlottedSystem(HarmonicSystem& system, PlotSpec plot);

  int NumUnknowns() const override { return system_.NumUnknowns(); }
  bool Evaluate(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_omega) override {
    return system_.Evaluate(y, omega, residual, jacobian_y, jacobian_omega);
  }
  std::vector<int> ScaleGroups() const override { return system_.ScaleGroups(); }
  Eigen::VectorXd StepWeights() const override { return system_.StepWeights(); }
  std::vector<std::vector<int>> EliminationBlocks() const override {
    return system_.EliminationBlocks();
  }
  double ResidualNoise(const Eigen::VectorXd& y, double omega) override {
    return system_.ResidualNoise(y, omega);
  }
  std::vector<PlotScale> PlotScales() const override;
  Eigen::VectorXd PlotCoordinates(const Eigen::VectorXd& y, double omega) override;

 private:
  HarmonicSystem& system_;
  PlotMeasure measure_;
  std::vector<int> output_dofs_;
  // Only for max |x|: its fine sampling (8(2H + 1) samples) is large at high H.
  std::optional<PointAnalyzer> analyzer_;
};

}  // namespace nfrc
