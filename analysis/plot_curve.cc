#include "analysis/plot_curve.h"

#include <utility>

namespace nfrc {

MeasureCurve::MeasureCurve(HarmonicSystem& system, PlotSpec plot)
    : system_(system), measure_(plot.measure), output_dofs_(std::move(plot.dofs)) {
  if (measure_ == PlotMeasure::kMaxAbs) analyzer_.emplace(system, output_dofs_);
}

std::vector<PlotScale> MeasureCurve::Scales() const {
  if (measure_ == PlotMeasure::kEnergy) return {PlotScale::kLog};
  return std::vector<PlotScale>(output_dofs_.size(), PlotScale::kLinear);
}

Eigen::VectorXd MeasureCurve::Coordinates(const Eigen::VectorXd& y, double omega) {
  if (measure_ == PlotMeasure::kEnergy) {
    return Eigen::VectorXd::Constant(1, PeriodEnergy(system_, y, omega));
  }
  Eigen::VectorXd values(static_cast<Eigen::Index>(output_dofs_.size()));
  for (size_t j = 0; j < output_dofs_.size(); ++j) {
    values(static_cast<Eigen::Index>(j)) = analyzer_->MaxAbs(y, omega, output_dofs_[j]);
  }
  return values;
}

}  // namespace nfrc
