#pragma once

#include <Eigen/Dense>
#include <deque>

#include "validation/transient.h"

namespace nfrc {

// The steady-state rule of every transient run (TransientOptions documents it): fed the
// state z = (x, v/ω) at each period boundary and the largest |z| over each period, it gives
// the period differences, says when the run is T-periodic and, at the end, which kT-periodic
// orbit it is on. Keeps the last max_period_multiple + steady_periods boundaries.
class SteadyStateMonitor {
 public:
  explicit SteadyStateMonitor(const TransientOptions& options);

  // The state at t = 0.
  void Start(const Eigen::VectorXd& z);
  // Closes the next period: z at its end and max_i |z_i| over it (samples and end). Returns
  // its relative difference d_p (TransientOptions).
  double EndPeriod(const Eigen::VectorXd& z, double scale);

  int periods() const { return periods_; }
  // Whether the periods closed so far make a T-periodic steady state.
  bool Steady() const;
  // The smallest k in 2..max_period_multiple for which the last steady_periods boundaries are
  // kT-periodic, 0 if none (or too few periods for it).
  int PeriodMultiple() const;

 private:
  // max_i |z_i(b) − z_i(b − k)| / the largest scale of the periods between them; b indexes
  // boundaries_ (scales_[b − 1] is that of the period ending at boundary b).
  double Difference(int b, int k) const;

  TransientOptions options_;
  std::deque<Eigen::VectorXd> boundaries_;
  std::deque<double> scales_;  // one per period, aligned with boundaries_[1..]
  int periods_ = 0;
  int consecutive_ = 0;  // latest periods whose difference counted
};

}  // namespace nfrc
