#include "core/harmonic_set.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace nfrc {
namespace {

void CheckMaxHarmonic(int max_harmonic) {
  if (max_harmonic < 1) {
    throw std::invalid_argument("max_harmonic: must be at least 1, got " +
                                std::to_string(max_harmonic));
  }
}

}  // namespace

HarmonicSet::HarmonicSet(int max_harmonic, bool odd_only, int num_samples)
    : max_harmonic_(max_harmonic), odd_only_(odd_only), num_samples_(num_samples) {
  CheckMaxHarmonic(max_harmonic);
  // Guard 2H + 1 and 4H + 1 below against int overflow for absurd inputs.
  if (max_harmonic > (1 << 28)) {
    throw std::invalid_argument("max_harmonic: must be at most 2^28, got " +
                                std::to_string(max_harmonic));
  }
  if (num_samples_ == 0) num_samples_ = DefaultNumSamples(max_harmonic);
  const int min_samples = 2 * max_harmonic + 1;
  if (num_samples_ < min_samples) {
    throw std::invalid_argument(
        "num_samples: must be at least 2*max_harmonic+1 = " + std::to_string(min_samples) +
        ", got " + std::to_string(num_samples));
  }
  for (int k = odd_only ? 1 : 0; k <= max_harmonic; k += odd_only ? 2 : 1) {
    harmonics_.push_back(k);
  }
  num_coefficients_ = 2 * num_harmonics() - (odd_only ? 0 : 1);
}

int HarmonicSet::DefaultNumSamples(int max_harmonic) {
  CheckMaxHarmonic(max_harmonic);
  if (max_harmonic > (1 << 28)) {
    throw std::invalid_argument("max_harmonic: must be at most 2^28, got " +
                                std::to_string(max_harmonic));
  }
  const int target = std::max(4 * max_harmonic + 1, 16);
  int n = 1;
  while (n < target) n *= 2;
  return n;
}

int HarmonicSet::CosIndex(int position) const {
  if (position < 0 || position >= num_harmonics()) {
    throw std::invalid_argument("position: must be in [0, " + std::to_string(num_harmonics()) +
                                "), got " + std::to_string(position));
  }
  // Full sets: a_0 at 0, then (a_k, b_k) pairs from 1; odd sets: pairs from 0.
  return odd_only_ ? 2 * position : std::max(2 * position - 1, 0);
}

int HarmonicSet::SinIndex(int position) const {
  const int cos_index = CosIndex(position);
  return harmonics_[position] == 0 ? cos_index : cos_index + 1;
}

void HarmonicSet::Basis(double theta, Eigen::Ref<Eigen::VectorXd> basis) const {
  const double c1 = std::cos(theta), s1 = std::sin(theta);
  double c = 1.0, s = 0.0;  // cos kθ, sin kθ for k = 0, 1, ...
  int k = 0;
  for (int p = 0; p < num_harmonics(); ++p) {
    for (const int harmonic = harmonics_[static_cast<size_t>(p)]; k < harmonic; ++k) {
      const double rotated = c * c1 - s * s1;
      s = s * c1 + c * s1;
      c = rotated;
    }
    basis(CosIndex(p)) = c;
    if (k > 0) basis(SinIndex(p)) = s;
  }
}

Eigen::VectorXd HarmonicSet::Basis(double theta) const {
  Eigen::VectorXd basis(num_coefficients_);
  Basis(theta, basis);
  return basis;
}

Eigen::VectorXd ChangeHarmonicSet(const Eigen::VectorXd& coefficients, const HarmonicSet& from,
                                  const HarmonicSet& to) {
  const int nf = from.NumCoefficients();
  const int nt = to.NumCoefficients();
  if (coefficients.size() % nf != 0) {
    throw std::invalid_argument("coefficients: size " + std::to_string(coefficients.size()) +
                                " is not a multiple of " + std::to_string(nf));
  }
  const int blocks = static_cast<int>(coefficients.size()) / nf;
  Eigen::VectorXd result = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(blocks) * nt);
  for (int q = 0; q < to.num_harmonics(); ++q) {
    const auto& list = from.harmonics();
    const auto found = std::find(list.begin(), list.end(), to.harmonics()[q]);
    if (found == list.end()) continue;
    const int p = static_cast<int>(found - list.begin());
    for (int b = 0; b < blocks; ++b) {
      result(b * nt + to.CosIndex(q)) = coefficients(b * nf + from.CosIndex(p));
      if (to.harmonics()[q] != 0) {
        result(b * nt + to.SinIndex(q)) = coefficients(b * nf + from.SinIndex(p));
      }
    }
  }
  return result;
}

}  // namespace nfrc
