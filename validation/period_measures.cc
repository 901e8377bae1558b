#include "validation/period_measures.h"

#include <cmath>
#include <numbers>

namespace nfrc {

Eigen::Vector2d FirstHarmonic(const Eigen::VectorXd& samples) {
  const int n = static_cast<int>(samples.size());
  Eigen::Vector2d ab = Eigen::Vector2d::Zero();
  for (int i = 0; i < n; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / n;
    ab(0) += samples(i) * std::cos(theta);
    ab(1) += samples(i) * std::sin(theta);
  }
  return ab * (2.0 / n);
}

PeriodMeasures MeasurePeriod(const PeriodRecord& record, const std::vector<int>& dofs) {
  PeriodMeasures out;
  for (int dof : dofs) {
    const Eigen::VectorXd samples = record.x.row(dof).transpose();
    out.max_abs.push_back(samples.cwiseAbs().maxCoeff());
    out.h1.push_back(FirstHarmonic(samples).norm());
  }
  out.energy = record.mean_energy;
  for (const LawPhaseLog& log : record.phases) {
    if (log.phase_name.empty()) continue;
    out.phase_names.push_back(log.phase_name);
    out.phase_counts.push_back(log.CountPhases(record.t0, record.period));
    out.phase_fractions.push_back(log.PhaseFraction(record.t0, record.period));
  }
  if (record.work_input != 0.0) {
    out.energy_balance_defect = std::abs(record.work_input - record.work_damping -
                                         record.work_laws - record.energy_change) /
                                std::abs(record.work_input);
  }
  return out;
}

}  // namespace nfrc
