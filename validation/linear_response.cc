#include "validation/linear_response.h"

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <algorithm>
#include <complex>

#include "core/dynamic_stiffness.h"

namespace nfrc {
namespace {

// DOFs up to which Z is solved densely (full pivoting), sparse LU beyond.
constexpr int kDenseLimit = 300;

}  // namespace

double LinearAmplitude(const LinearModel& model, const std::vector<ForcingTerm>& terms,
                       double omega) {
  using Complex = std::complex<double>;
  const int n = model.num_dofs();
  if (n == 0) return 0.0;
  std::vector<int> harmonics;
  for (const auto& term : terms) {
    if (std::find(harmonics.begin(), harmonics.end(), term.harmonic) == harmonics.end()) {
      harmonics.push_back(term.harmonic);
    }
  }
  Eigen::VectorXd total = Eigen::VectorXd::Zero(n);
  for (int h : harmonics) {
    // F_h = f_cos − i f_sin (the convention of core/dynamic_stiffness.h).
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(n);
    for (const auto& term : terms) {
      if (term.harmonic == h) force(term.dof) += Complex(term.cos, -term.sin);
    }
    SparseComplex z = DynamicStiffness(model, h, omega);
    Eigen::VectorXcd response;
    if (n <= kDenseLimit) {
      response = Eigen::MatrixXcd(z).fullPivLu().solve(force);
    } else {
      z.makeCompressed();
      Eigen::SparseLU<SparseComplex> lu(z);
      if (lu.info() != Eigen::Success) return 0.0;
      response = lu.solve(force);
    }
    if (!response.allFinite()) return 0.0;
    total += response.cwiseAbs();
  }
  return total.maxCoeff();
}

}  // namespace nfrc
