#include "analysis/point_measures.h"

#include <algorithm>
#include <cmath>

namespace nfrc {
namespace {

HarmonicSet FineSet(const HarmonicSet& set) {
  const int samples = std::max(PointAnalyzer::kMinSamples,
                               PointAnalyzer::kOversampling * (2 * set.max_harmonic() + 1));
  return HarmonicSet(set.max_harmonic(), set.odd_only(), samples);
}

}  // namespace

double MeanQuadraticForm(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixXd& x,
                         const HarmonicSet& set) {
  // mean(x_i x_j) = a0_i a0_j + ½ Σ_k (a_ki a_kj + b_ki b_kj).
  Eigen::VectorXd weights = Eigen::VectorXd::Constant(set.NumCoefficients(), 0.5);
  if (set.has_constant()) weights(set.CosIndex(0)) = 1.0;
  const Eigen::MatrixXd ax = a * x;
  return 0.5 * (x.cwiseProduct(ax) * weights).sum();
}

PointAnalyzer::PointAnalyzer(HarmonicSystem& system, std::vector<int> output_dofs)
    : system_(system),
      output_dofs_(std::move(output_dofs)),
      fine_(FineSet(system.harmonic_set())) {}

double PeriodEnergy(HarmonicSystem& system, const Eigen::VectorXd& y, double omega) {
  const HarmonicSet& set = system.harmonic_set();
  const Eigen::MatrixXd x = system.AllDofCoefficients(y, omega);
  // v = ω x Dᵀ = −ω x D (D is antisymmetric), by column operations instead of a dense product.
  const Eigen::MatrixXd v = -omega * system.fourier().TimesDerivative(x);
  return MeanQuadraticForm(system.model().mass, v, set) +
         MeanQuadraticForm(system.model().stiffness, x, set);
}

double PointAnalyzer::MaxAbs(const Eigen::VectorXd& y, double omega, int dof) {
  return fine_.ToTime(system_.DofCoefficients(y, omega, dof)).col(0).cwiseAbs().maxCoeff();
}

PointMeasures PointAnalyzer::Measure(const Eigen::VectorXd& y, double omega) {
  const HarmonicSet& set = system_.harmonic_set();
  PointMeasures measures;
  measures.energy = PeriodEnergy(system_, y, omega);
  for (int dof : output_dofs_) {
    const Eigen::VectorXd c = system_.DofCoefficients(y, omega, dof);
    const Eigen::VectorXd samples = fine_.ToTime(c).col(0);
    measures.max_abs.push_back(samples.cwiseAbs().maxCoeff());
    measures.min.push_back(samples.minCoeff());
    measures.max.push_back(samples.maxCoeff());
    std::vector<double> amplitudes;
    double h1 = 0.0;
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const double a = c(set.CosIndex(p));
      const double b = set.harmonics()[p] == 0 ? 0.0 : c(set.SinIndex(p));
      const double amplitude = std::hypot(a, b);
      amplitudes.push_back(amplitude);
      if (set.harmonics()[p] == 1) h1 = amplitude;
    }
    measures.h1.push_back(h1);
    measures.amplitudes.push_back(std::move(amplitudes));
  }
  return measures;
}

}  // namespace nfrc
