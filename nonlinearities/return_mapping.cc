#include "nonlinearities/return_mapping.h"

#include <cmath>

namespace nfrc {

bool SlipHistory::Slips() const {
  for (int a : anchor) {
    if (a == kSlip) return true;
  }
  return false;
}

SlipHistory ReturnMapping(const Eigen::VectorXd& input, double stiffness, double limit) {
  const int nt = static_cast<int>(input.size());
  SlipHistory history;
  history.force.resize(nt);
  history.anchor.assign(static_cast<size_t>(nt), SlipHistory::kOrigin);
  double slider = 0.0;
  int anchor = SlipHistory::kOrigin;
  for (int pass = 0; pass < 2; ++pass) {
    for (int j = 0; j < nt; ++j) {
      const double trial = stiffness * (input(j) - slider);
      double force = trial;
      int state = anchor;
      if (std::abs(trial) > limit) {
        force = std::copysign(limit, trial);
        slider = input(j) - force / stiffness;
        anchor = j;
        state = SlipHistory::kSlip;
      }
      if (pass == 1) {
        history.force(j) = force;
        history.anchor[static_cast<size_t>(j)] = state;
      }
    }
  }
  return history;
}

Eigen::MatrixXd ReturnMappingJacobian(const FourierTransform& fourier, const SlipHistory& history,
                                      double stiffness) {
  const Eigen::MatrixXd& sample = fourier.SampleMatrix();
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(sample.rows(), sample.cols());
  for (Eigen::Index j = 0; j < sample.rows(); ++j) {
    const int anchor = history.anchor[static_cast<size_t>(j)];
    if (anchor == SlipHistory::kSlip) continue;
    rows.row(j) = stiffness * sample.row(j);
    if (anchor != SlipHistory::kOrigin) rows.row(j) -= stiffness * sample.row(anchor);
  }
  return fourier.ProjectionMatrix() * rows;
}

PhaseCount StickPhases(const HarmonicSet& set, const SlipHistory& history) {
  std::vector<bool> stuck(history.anchor.size());
  for (size_t j = 0; j < stuck.size(); ++j) stuck[j] = history.Sticks(static_cast<int>(j));
  return CountPhases(stuck, 1.0 / set.max_harmonic());
}

}  // namespace nfrc
