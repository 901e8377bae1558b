#pragma once

#include <Eigen/Dense>
#include <vector>

namespace nfrc {

// Which harmonics of the fundamental a periodic signal keeps, and how many samples a period
// is sampled at. A signal x(θ), θ = ωt, is stored as real coefficients in this layout:
//   [a_0] (only if harmonic 0 is in the set), then for each harmonic k > 0 ascending: a_k, b_k
// with x(θ) = a_0 + Σ_k (a_k cos kθ + b_k sin kθ).
class HarmonicSet {
 public:
  // All harmonics 0..max_harmonic, or odd ones 1, 3, ..., ≤ max_harmonic. num_samples = 0
  // picks DefaultNumSamples(max_harmonic). Throws std::invalid_argument (naming
  // "max_harmonic" or "num_samples") if max_harmonic < 1 or num_samples < 2·max_harmonic + 1.
  HarmonicSet(int max_harmonic, bool odd_only, int num_samples = 0);

  // Oversampled default: the smallest power of two ≥ max(4·H + 1, 16), so that products of
  // up to three signals of the set are projected without aliasing (cubic AFT is exact).
  static int DefaultNumSamples(int max_harmonic);

  int max_harmonic() const { return max_harmonic_; }
  bool odd_only() const { return odd_only_; }
  int num_samples() const { return num_samples_; }

  // Harmonic numbers in ascending order; starts with 0 for full sets.
  const std::vector<int>& harmonics() const { return harmonics_; }
  int num_harmonics() const { return static_cast<int>(harmonics_.size()); }
  bool has_constant() const { return !odd_only_; }

  // Number of real coefficients of one signal: 2·(number of harmonics > 0) + (1 if constant).
  int NumCoefficients() const { return num_coefficients_; }

  // Index of a_k (cos) and b_k (sin) of the harmonic at `position` in harmonics(); for k = 0
  // both return the index of a_0 (there is no b_0).
  int CosIndex(int position) const;
  int SinIndex(int position) const;

  // The basis functions at θ in this layout (1, then cos kθ and sin kθ), by rotating e^{iθ}:
  // one sine and cosine in all, rounding ~k·eps. `basis` has NumCoefficients() entries.
  void Basis(double theta, Eigen::Ref<Eigen::VectorXd> basis) const;
  Eigen::VectorXd Basis(double theta) const;

 private:
  int max_harmonic_;
  bool odd_only_;
  int num_samples_;
  std::vector<int> harmonics_;
  int num_coefficients_;
};

// Re-expresses stacked signals (consecutive blocks of from.NumCoefficients() entries) in the
// layout of `to`: harmonics of both sets are copied, harmonics only in `to` are zero.
// Throws std::invalid_argument if the size is not a multiple of the block size.
Eigen::VectorXd ChangeHarmonicSet(const Eigen::VectorXd& coefficients, const HarmonicSet& from,
                                  const HarmonicSet& to);

}  // namespace nfrc
