#pragma once

#include <Eigen/Dense>
#include <memory>

#include "core/harmonic_set.h"

namespace nfrc {

// Moves periodic signals between real Fourier coefficients (HarmonicSet layout) and
// samples at θ_j = 2πj/N_t, j = 0..N_t−1, by real FFT. Signals are columns: coefficient
// matrices are NumCoefficients() × m, sample matrices are N_t × m.
// Not thread-safe (the FFT back end caches plans); use one instance per thread.
class FourierTransform {
 public:
  explicit FourierTransform(const HarmonicSet& set);
  ~FourierTransform();
  FourierTransform(FourierTransform&&) noexcept;
  FourierTransform& operator=(FourierTransform&&) noexcept;

  const HarmonicSet& harmonic_set() const { return set_; }

  // samples.col(i) = x_i(θ_j) for the signal with coefficients coefficients.col(i).
  void ToTime(const Eigen::Ref<const Eigen::MatrixXd>& coefficients,
              Eigen::Ref<Eigen::MatrixXd> samples) const;
  Eigen::MatrixXd ToTime(const Eigen::Ref<const Eigen::MatrixXd>& coefficients) const;

  // Galerkin projection of sampled signals onto the set (trapezoidal quadrature on the
  // samples): a_0 = (1/N_t) Σ x_j, a_k = (2/N_t) Σ x_j cos kθ_j, b_k = (2/N_t) Σ x_j sin kθ_j.
  // ToCoefficients(ToTime(c)) == c for every c since N_t ≥ 2H + 1.
  void ToCoefficients(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                      Eigen::Ref<Eigen::MatrixXd> coefficients) const;
  Eigen::MatrixXd ToCoefficients(const Eigen::Ref<const Eigen::MatrixXd>& samples) const;

  // d/dθ on coefficients: (a_k, b_k) -> (k·b_k, −k·a_k); the time derivative is ω·D.
  void Differentiate(const Eigen::Ref<const Eigen::MatrixXd>& coefficients,
                     Eigen::Ref<Eigen::MatrixXd> derivative) const;
  // The same operator as a dense NumCoefficients()² matrix D.
  const Eigen::MatrixXd& DerivativeMatrix() const { return derivative_matrix_; }
  // m·D by column operations, O(rows · n_c) where the dense product costs O(rows · n_c²).
  Eigen::MatrixXd TimesDerivative(const Eigen::Ref<const Eigen::MatrixXd>& m) const;
  // target += scale·(m·D), rounded entry for entry as scale·TimesDerivative(m) added would be,
  // without the two temporaries (a law's Jacobian block is assembled in place).
  void AddTimesDerivative(const Eigen::Ref<const Eigen::MatrixXd>& m, double scale,
                          Eigen::Ref<Eigen::MatrixXd> target) const;

  // Dense equivalents for assembling Jacobians: samples = E·c (N_t × n_c) and
  // c = P·samples (n_c × N_t), with P·E = I. A nonlinearity f(x) sampled in time has
  // ∂(P f(E c))/∂c = P·diag(f'(E c))·E. Built at the first call (only the LCP laws use them:
  // at N_φ = 640 with 8 192 samples they are 2 × 84 MB, a quarter of the point's time to fill).
  const Eigen::MatrixXd& SampleMatrix() const;
  const Eigen::MatrixXd& ProjectionMatrix() const;

  // P·diag(weights)·E for samples `weights` (size N_t): the Jacobian block of a sampled law
  // with pointwise derivative `weights`. Assembled from the discrete Fourier coefficients of
  // the weights by product-to-sum identities, O(N_t log N_t + n_c²) instead of O(N_t n_c²).
  Eigen::MatrixXd WeightedProduct(const Eigen::Ref<const Eigen::VectorXd>& weights) const;
  // The same into `product`, whose storage is kept when it already has the size.
  void WeightedProduct(const Eigen::Ref<const Eigen::VectorXd>& weights,
                       Eigen::MatrixXd* product) const;
  // target += scale·P·diag(weights)·E (times_derivative: ·D), column pair by column pair
  // without the product's n_c² temporary; each entry rounded as adding scale times
  // WeightedProduct (or AddTimesDerivative of it) would round it.
  void AddWeightedProduct(const Eigen::Ref<const Eigen::VectorXd>& weights, double scale,
                          bool times_derivative, Eigen::Ref<Eigen::MatrixXd> target) const;

 private:
  // The table of (C_m, S_m) of the weights that ForEachProductBlock reads.
  void TabulateSums(const Eigen::Ref<const Eigen::VectorXd>& weights) const;
  // The column pair cos k, sin k (harmonic position q) of P·diag(w)·E, from the table, each
  // entry once (a caller writes or accumulates it where it belongs): the constant's entries
  // by put(row, column 0 or 1, value) (the constant has no sine column), and each 2 × 2
  // block of rows cos j, sin j (j, k ≠ 0) by put_block(row of cos j, a, b), with a and b
  // the table's pairs (C, S) at j − k and j + k: [a_C + b_C, b_S − a_S; a_S + b_S, a_C − b_C].
  template <typename Put, typename PutBlock>
  void ForEachProductBlock(int q, Put put, PutBlock put_block) const;

  struct FftState;
  HarmonicSet set_;
  std::unique_ptr<FftState> fft_;
  Eigen::MatrixXd derivative_matrix_;
  struct DenseMatrices {
    Eigen::MatrixXd sample, projection;
  };
  // E and P once asked for (mutable: filled by the const accessors; the class is per thread).
  mutable std::unique_ptr<DenseMatrices> dense_;
  const DenseMatrices& Dense() const;
};

}  // namespace nfrc
