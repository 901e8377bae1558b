#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "analysis/harmonic_system.h"
#include "core/fourier_transform.h"

namespace nfrc {

// Response measures of one HBM solution, per output DOF.
struct PointMeasures {
  std::vector<double> max_abs;  // max_t |x(t)| over the period (finely resampled)
  std::vector<double> min;      // min_t x(t) and max_t x(t) (signed, same sampling): for a
  std::vector<double> max;      // rigid stop max x is g0 on the exact solution
  std::vector<double> h1;       // first-harmonic amplitude √(a_1² + b_1²)
  std::vector<std::vector<double>> amplitudes;  // √(a_k² + b_k²) per harmonic of the set
  // Period mean of the total energy ½ẋᵀMẋ + ½xᵀKx over all DOFs, exact from the
  // coefficients by Parseval (no sampling).
  double energy = 0.0;
};

// ½·mean over a period of xᵀ A x for coefficient rows X (DOF × coefficient) of `set`.
double MeanQuadraticForm(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixXd& x,
                         const HarmonicSet& set);

// PointMeasures::energy of solution y at ω: recovers every DOF, needs no time sampling.
double PeriodEnergy(HarmonicSystem& system, const Eigen::VectorXd& y, double omega);

// Computes PointMeasures; max |x| is taken on kOversampling × (2H + 1) samples (at least
// kMinSamples) so that the peak between the solver's samples is not missed.
class PointAnalyzer {
 public:
  static constexpr int kOversampling = 8;
  static constexpr int kMinSamples = 512;

  PointAnalyzer(HarmonicSystem& system, std::vector<int> output_dofs);
  PointMeasures Measure(const Eigen::VectorXd& y, double omega);
  // max_t |x(t)| of model DOF `dof` alone, on the fine sampling.
  double MaxAbs(const Eigen::VectorXd& y, double omega, int dof);
  // The fine sampling used for max |x|, for writing time signals.
  const FourierTransform& fine() const { return fine_; }
  const std::vector<int>& output_dofs() const { return output_dofs_; }

 private:
  HarmonicSystem& system_;
  std::vector<int> output_dofs_;
  FourierTransform fine_;
};

}  // namespace nfrc
