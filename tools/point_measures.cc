#include "tools/point_measures.h"

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

PointAnalyzer::PointAnalyzer(HarmonicSystem& system, std::vector<int> output_dofs)
    : system_(system),
      output_dofs_(std::move(output_dofs)),
      fine_(FineSet(system.harmonic_set())) {}

PointMeasures PointAnalyzer::Measure(const Eigen::VectorXd& y, double omega) {
  const HarmonicSet& set = system_.harmonic_set();
  PointMeasures measures;
  for (int dof : output_dofs_) {
    const Eigen::VectorXd c = system_.DofCoefficients(y, omega, dof);
    measures.max_abs.push_back(fine_.ToTime(c).cwiseAbs().maxCoeff());
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
