#include "validation/steady_state.h"

#include <algorithm>

namespace nfrc {

SteadyStateMonitor::SteadyStateMonitor(const TransientOptions& options) : options_(options) {}

void SteadyStateMonitor::Start(const Eigen::VectorXd& z) {
  boundaries_.assign(1, z);
  scales_.clear();
  periods_ = 0;
  consecutive_ = 0;
}

double SteadyStateMonitor::EndPeriod(const Eigen::VectorXd& z, double scale) {
  boundaries_.push_back(z);
  scales_.push_back(scale);
  ++periods_;
  // Enough history for the kT search: k + steady_periods − 1 periods back from the last.
  const size_t history = options_.max_period_multiple + options_.steady_periods;
  while (scales_.size() > history) {
    boundaries_.pop_front();
    scales_.pop_front();
  }
  const double difference = Difference(static_cast<int>(boundaries_.size()) - 1, 1);
  consecutive_ = difference < options_.steady_tolerance ? consecutive_ + 1 : 0;
  return difference;
}

bool SteadyStateMonitor::Steady() const {
  return periods_ >= options_.min_periods && consecutive_ >= options_.steady_periods;
}

int SteadyStateMonitor::PeriodMultiple() const {
  const int last = static_cast<int>(boundaries_.size()) - 1;
  for (int k = 2; k <= options_.max_period_multiple; ++k) {
    if (last - options_.steady_periods + 1 - k < 0) break;  // too few boundaries kept
    bool periodic = true;
    for (int b = last - options_.steady_periods + 1; b <= last && periodic; ++b) {
      periodic = Difference(b, k) < options_.steady_tolerance;
    }
    if (periodic) return k;
  }
  return 0;
}

double SteadyStateMonitor::Difference(int b, int k) const {
  const double scale = *std::max_element(scales_.begin() + (b - k), scales_.begin() + b);
  const Eigen::VectorXd delta = boundaries_[b] - boundaries_[b - k];
  const double change = delta.size() > 0 ? delta.cwiseAbs().maxCoeff() : 0.0;
  // A zero scale means z vanished over those periods, boundaries included: no change.
  return scale > 0.0 ? change / scale : 0.0;
}

}  // namespace nfrc
