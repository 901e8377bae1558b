#include "core/fourier_transform.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nfrc {

namespace {

// FFTW's planner is not thread-safe (its execute is): plans are made and destroyed under this.
std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

// Unscaled half-spectrum real FFT by FFTW: Forward gives Y_m = Σ_j x_j e^{−2πi jm/N} for
// m ≤ N/2, Inverse takes Y_0..Y_{N/2} and returns x_j = Σ_{m=0}^{N−1} Y_m e^{2πi jm/N}
// (Hermitian extension). Plans are unaligned so that they run on any Eigen column.
struct FourierTransform::FftState {
  explicit FftState(int n) : n_t(n), spectrum(n / 2 + 1, 0.0) {
    std::vector<double> samples(n);
    auto* bins = reinterpret_cast<fftw_complex*>(spectrum.data());
    const unsigned flags = FFTW_ESTIMATE | FFTW_UNALIGNED;
    std::lock_guard<std::mutex> lock(PlannerMutex());
    forward = fftw_plan_dft_r2c_1d(n, samples.data(), bins, flags);
    // c2r overwrites its input: it always runs on `spectrum`, which callers refill.
    inverse = fftw_plan_dft_c2r_1d(n, bins, samples.data(), flags | FFTW_DESTROY_INPUT);
    if (forward == nullptr || inverse == nullptr) {
      throw std::runtime_error("FourierTransform: FFTW could not plan N_t = " + std::to_string(n));
    }
  }
  ~FftState() {
    std::lock_guard<std::mutex> lock(PlannerMutex());
    fftw_destroy_plan(forward);
    fftw_destroy_plan(inverse);
  }
  FftState(const FftState&) = delete;
  FftState& operator=(const FftState&) = delete;

  // spectrum ← FFT of x (N_t samples).
  void Forward(const double* x) {
    fftw_execute_dft_r2c(forward, const_cast<double*>(x),
                         reinterpret_cast<fftw_complex*>(spectrum.data()));
  }
  // x ← inverse FFT of spectrum (spectrum is overwritten).
  void Inverse(double* x) {
    fftw_execute_dft_c2r(inverse, reinterpret_cast<fftw_complex*>(spectrum.data()), x);
  }

  int n_t;
  std::vector<std::complex<double>> spectrum;
  // WeightedProduct's table of (C_m, S_m) pairs, kept between calls.
  std::vector<double> sums;
  // Each harmonic's row of a (HarmonicSet::CosIndex; b's follows it) for WeightedProduct.
  std::vector<int> cos_index;
  fftw_plan forward = nullptr;
  fftw_plan inverse = nullptr;
};

namespace {

void CheckShape(const char* name, Eigen::Index rows, Eigen::Index cols, Eigen::Index want_rows,
                Eigen::Index want_cols) {
  if (rows != want_rows || cols != want_cols) {
    throw std::invalid_argument(std::string(name) + ": must be " + std::to_string(want_rows) + "x" +
                                std::to_string(want_cols) + ", got " + std::to_string(rows) + "x" +
                                std::to_string(cols));
  }
}

// A 2 × 2 block's rows are adjacent in each column: its sums, differences and products are
// taken in pairs (two lanes, each entry's own operations: the bits of the entry-wise form).
using Pair = Eigen::Map<Eigen::Vector2d>;
using ConstPair = Eigen::Map<const Eigen::Vector2d>;

// The block's sine column (b_S − a_S, a_C − b_C): a_C − b_C is −(b_C − a_C) exactly.
Eigen::Vector2d SineColumn(const ConstPair& a, const ConstPair& b) {
  const Eigen::Vector2d difference = b - a;
  return {difference(1), -difference(0)};
}

}  // namespace

FourierTransform::FourierTransform(const HarmonicSet& set)
    : set_(set), fft_(std::make_unique<FftState>(set.num_samples())) {
  const int n_c = set_.NumCoefficients();
  derivative_matrix_.setZero(n_c, n_c);
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    fft_->cos_index.push_back(set_.CosIndex(p));
    const int k = set_.harmonics()[p];
    if (k == 0) continue;
    derivative_matrix_(set_.CosIndex(p), set_.SinIndex(p)) = k;
    derivative_matrix_(set_.SinIndex(p), set_.CosIndex(p)) = -k;
  }
}

const FourierTransform::DenseMatrices& FourierTransform::Dense() const {
  if (dense_) return *dense_;
  const int n_t = set_.num_samples();
  const int n_c = set_.NumCoefficients();
  // cos kθ_j and sin kθ_j take only N_t values, at the phase k·j mod N_t (reduced so that the
  // angle stays in [0, 2π) with full accuracy): tabulated once instead of N_t·n_c calls.
  std::vector<double> cosine(static_cast<size_t>(n_t)), sine(static_cast<size_t>(n_t));
  for (int phase = 0; phase < n_t; ++phase) {
    const double theta = 2.0 * std::numbers::pi * static_cast<double>(phase) / n_t;
    cosine[static_cast<size_t>(phase)] = std::cos(theta);
    sine[static_cast<size_t>(phase)] = std::sin(theta);
  }
  auto dense = std::make_unique<DenseMatrices>();
  Eigen::MatrixXd& sample = dense->sample;
  Eigen::MatrixXd& projection = dense->projection;
  sample.resize(n_t, n_c);
  projection.resize(n_c, n_t);
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int k = set_.harmonics()[p];
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    if (k == 0) {
      sample.col(ic).setOnes();
      projection.row(ic).setConstant(1.0 / n_t);
      continue;
    }
    for (int j = 0; j < n_t; ++j) {
      const auto phase = static_cast<size_t>((static_cast<long long>(k) * j) % n_t);
      sample(j, ic) = cosine[phase];
      sample(j, is) = sine[phase];
    }
    projection.row(ic) = (2.0 / n_t) * sample.col(ic).transpose();
    projection.row(is) = (2.0 / n_t) * sample.col(is).transpose();
  }
  dense_ = std::move(dense);
  return *dense_;
}

const Eigen::MatrixXd& FourierTransform::SampleMatrix() const { return Dense().sample; }
const Eigen::MatrixXd& FourierTransform::ProjectionMatrix() const { return Dense().projection; }

FourierTransform::~FourierTransform() = default;
FourierTransform::FourierTransform(FourierTransform&&) noexcept = default;
FourierTransform& FourierTransform::operator=(FourierTransform&&) noexcept = default;

void FourierTransform::ToTime(const Eigen::Ref<const Eigen::MatrixXd>& coefficients,
                              Eigen::Ref<Eigen::MatrixXd> samples) const {
  const int n_t = set_.num_samples();
  CheckShape("coefficients", coefficients.rows(), coefficients.cols(), set_.NumCoefficients(),
             coefficients.cols());
  CheckShape("samples", samples.rows(), samples.cols(), n_t, coefficients.cols());
  auto& spectrum = fft_->spectrum;
  for (Eigen::Index col = 0; col < coefficients.cols(); ++col) {
    std::fill(spectrum.begin(), spectrum.end(), std::complex<double>(0.0));
    for (int p = 0; p < set_.num_harmonics(); ++p) {
      const int k = set_.harmonics()[p];
      const double a = coefficients(set_.CosIndex(p), col);
      // a cos kθ + b sin kθ = 2 Re(Y_k e^{ikθ}) with Y_k = (a − ib)/2; Y_0 = a_0.
      spectrum[k] = k == 0 ? std::complex<double>(a, 0.0)
                           : 0.5 * std::complex<double>(a, -coefficients(set_.SinIndex(p), col));
    }
    fft_->Inverse(samples.col(col).data());
  }
}

Eigen::MatrixXd FourierTransform::ToTime(
    const Eigen::Ref<const Eigen::MatrixXd>& coefficients) const {
  Eigen::MatrixXd samples(set_.num_samples(), coefficients.cols());
  ToTime(coefficients, samples);
  return samples;
}

void FourierTransform::ToCoefficients(const Eigen::Ref<const Eigen::MatrixXd>& samples,
                                      Eigen::Ref<Eigen::MatrixXd> coefficients) const {
  const int n_t = set_.num_samples();
  CheckShape("samples", samples.rows(), samples.cols(), n_t, samples.cols());
  CheckShape("coefficients", coefficients.rows(), coefficients.cols(), set_.NumCoefficients(),
             samples.cols());
  auto& spectrum = fft_->spectrum;
  for (Eigen::Index col = 0; col < samples.cols(); ++col) {
    // Columns of a Ref are contiguous (unit inner stride), so the FFT reads them in place.
    fft_->Forward(samples.col(col).data());
    for (int p = 0; p < set_.num_harmonics(); ++p) {
      const int k = set_.harmonics()[p];
      if (k == 0) {
        coefficients(set_.CosIndex(p), col) = spectrum[0].real() / n_t;
      } else {
        coefficients(set_.CosIndex(p), col) = 2.0 * spectrum[k].real() / n_t;
        coefficients(set_.SinIndex(p), col) = -2.0 * spectrum[k].imag() / n_t;
      }
    }
  }
}

Eigen::MatrixXd FourierTransform::ToCoefficients(
    const Eigen::Ref<const Eigen::MatrixXd>& samples) const {
  Eigen::MatrixXd coefficients(set_.NumCoefficients(), samples.cols());
  ToCoefficients(samples, coefficients);
  return coefficients;
}

void FourierTransform::Differentiate(const Eigen::Ref<const Eigen::MatrixXd>& coefficients,
                                     Eigen::Ref<Eigen::MatrixXd> derivative) const {
  CheckShape("coefficients", coefficients.rows(), coefficients.cols(), set_.NumCoefficients(),
             coefficients.cols());
  CheckShape("derivative", derivative.rows(), derivative.cols(), set_.NumCoefficients(),
             coefficients.cols());
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int k = set_.harmonics()[p];
    const int ic = set_.CosIndex(p);
    if (k == 0) {
      derivative.row(ic).setZero();
      continue;
    }
    const int is = set_.SinIndex(p);
    // Row-wise copy through a temporary so in-place use (derivative aliasing coefficients) works.
    const Eigen::RowVectorXd a = coefficients.row(ic);
    derivative.row(ic) = k * coefficients.row(is);
    derivative.row(is) = -k * a;
  }
}

Eigen::MatrixXd FourierTransform::TimesDerivative(
    const Eigen::Ref<const Eigen::MatrixXd>& m) const {
  Eigen::MatrixXd product = Eigen::MatrixXd::Zero(m.rows(), m.cols());
  AddTimesDerivative(m, 1.0, product);  // 0 + 1·(±k·m) is ±k·m exactly
  return product;
}

void FourierTransform::AddTimesDerivative(const Eigen::Ref<const Eigen::MatrixXd>& m, double scale,
                                          Eigen::Ref<Eigen::MatrixXd> target) const {
  CheckShape("m", m.rows(), m.cols(), m.rows(), set_.NumCoefficients());
  CheckShape("target", target.rows(), target.cols(), m.rows(), m.cols());
  // D(cos k, sin k) = k and D(sin k, cos k) = −k: each column of m·D is a scaled column of
  // m (columns, not rows, of the column-major storage).
  for (int p = 0; p < set_.num_harmonics(); ++p) {
    const int k = set_.harmonics()[p];
    if (k == 0) continue;  // m·D's column of the constant is zero
    const int ic = set_.CosIndex(p);
    const int is = set_.SinIndex(p);
    // ±k·m first, as m·D has it, then scaled: scale·TimesDerivative(m) to the bit.
    target.col(ic) += scale * (-k * m.col(is));
    target.col(is) += scale * (k * m.col(ic));
  }
}

Eigen::MatrixXd FourierTransform::WeightedProduct(
    const Eigen::Ref<const Eigen::VectorXd>& weights) const {
  Eigen::MatrixXd product;
  WeightedProduct(weights, &product);
  return product;
}

void FourierTransform::TabulateSums(const Eigen::Ref<const Eigen::VectorXd>& weights) const {
  const int n_t = set_.num_samples();
  CheckShape("weights", weights.rows(), weights.cols(), n_t, 1);
  auto& spectrum = fft_->spectrum;
  fft_->Forward(weights.data());
  // C_m = (1/N) Σ w_j cos(mθ_j), S_m = (1/N) Σ w_j sin(mθ_j) for any integer m (periodic in
  // N; the half spectrum holds m ≤ N/2, the rest follows from Hermitian symmetry), tabulated
  // as pairs for −2H ≤ m ≤ 2H at 2(m + 2H): C_−m = C_m, S_−m = −S_m. Pairs, because each
  // 2 × 2 block of the product reads one pair at j − k and one at j + k.
  const int top = 2 * set_.max_harmonic();
  std::vector<double>& sums = fft_->sums;
  sums.resize(2 * (2 * static_cast<size_t>(top) + 1));
  for (int m = top; m >= 0; --m) {  // downwards: m = 0 is written last, as +S_0
    const int r = m % n_t;
    const double c = (r <= n_t / 2 ? spectrum[r].real() : spectrum[n_t - r].real()) / n_t;
    const double s = (r <= n_t / 2 ? -spectrum[r].imag() : spectrum[n_t - r].imag()) / n_t;
    sums[2 * static_cast<size_t>(top - m)] = c;
    sums[2 * static_cast<size_t>(top - m) + 1] = -s;
    sums[2 * static_cast<size_t>(top + m)] = c;
    sums[2 * static_cast<size_t>(top + m) + 1] = s;
  }
}

template <typename Put, typename PutBlock>
void FourierTransform::ForEachProductBlock(int q, Put put, PutBlock put_block) const {
  const double* pair = fft_->sums.data() + 2 * 2 * set_.max_harmonic();  // (C_m, S_m) at 2m
  const int n_h = set_.num_harmonics();
  const std::vector<int>& harmonics = set_.harmonics();
  const std::vector<int>& cos_index = fft_->cos_index;
  const int k = harmonics[static_cast<size_t>(q)];
  // A harmonic's sine index follows its cosine index (HarmonicSet's layout).
  if (k == 0) {
    put(0, 0, pair[0]);
    for (int p = 1; p < n_h; ++p) {
      const double* c = pair + 2 * harmonics[static_cast<size_t>(p)];
      const int rc = cos_index[static_cast<size_t>(p)];
      put(rc, 0, 2.0 * c[0]);
      put(rc + 1, 0, 2.0 * c[1]);
    }
    return;
  }
  const bool has_constant = harmonics.front() == 0;
  if (has_constant) {
    put(0, 0, pair[2 * k]);
    put(0, 1, pair[2 * k + 1]);
  }
  // Product-to-sum: 2 cos jθ cos kθ = cos(j−k)θ + cos(j+k)θ, and likewise.
  for (int p = has_constant ? 1 : 0; p < n_h; ++p) {
    const int j = harmonics[static_cast<size_t>(p)];
    put_block(cos_index[static_cast<size_t>(p)], pair + 2 * (j - k), pair + 2 * (j + k));
  }
}

void FourierTransform::WeightedProduct(const Eigen::Ref<const Eigen::VectorXd>& weights,
                                       Eigen::MatrixXd* product) const {
  TabulateSums(weights);
  const int n_c = set_.NumCoefficients();
  product->resize(n_c, n_c);
  // Column pair by column pair: the column-major storage is written in order.
  for (int q = 0; q < set_.num_harmonics(); ++q) {
    double* const cos_column = product->col(fft_->cos_index[static_cast<size_t>(q)]).data();
    double* const sin_column = cos_column + n_c;
    ForEachProductBlock(
        q,
        [&](int row, int column, double value) {
          (column == 0 ? cos_column : sin_column)[row] = value;
        },
        [&](int rc, const double* a, const double* b) {
          const ConstPair a_pair(a), b_pair(b);
          Pair(cos_column + rc) = a_pair + b_pair;
          Pair(sin_column + rc) = SineColumn(a_pair, b_pair);
        });
  }
}

void FourierTransform::AddWeightedProduct(const Eigen::Ref<const Eigen::VectorXd>& weights,
                                          double scale, bool times_derivative,
                                          Eigen::Ref<Eigen::MatrixXd> target) const {
  const int n_c = set_.NumCoefficients();
  CheckShape("target", target.rows(), target.cols(), n_c, n_c);
  TabulateSums(weights);
  // By blocks in pairs (the entry-wise form was 10 % of the N_φ = 160 friction curve's trace).
  for (int q = 0; q < set_.num_harmonics(); ++q) {
    const int k = set_.harmonics()[static_cast<size_t>(q)];
    double* const cos_target = target.col(fft_->cos_index[static_cast<size_t>(q)]).data();
    double* const sin_target = cos_target + target.outerStride();
    if (times_derivative) {
      if (k == 0) continue;  // m·D's column of the constant is zero
      // (m·D)(:, cos k) = −k·m(:, sin k) and (m·D)(:, sin k) = k·m(:, cos k): ±k·m first, as
      // AddTimesDerivative rounds it.
      const double plus_k = k;
      const double minus_k = -k;
      ForEachProductBlock(
          q,
          [&](int row, int column, double value) {
            if (column == 0) {
              sin_target[row] += scale * (k * value);
            } else {
              cos_target[row] += scale * (-k * value);
            }
          },
          [&](int rc, const double* a, const double* b) {
            const ConstPair a_pair(a), b_pair(b);
            Pair(sin_target + rc) += scale * (plus_k * (a_pair + b_pair));
            Pair(cos_target + rc) += scale * (minus_k * SineColumn(a_pair, b_pair));
          });
    } else {
      ForEachProductBlock(
          q,
          [&](int row, int column, double value) {
            (column == 0 ? cos_target : sin_target)[row] += scale * value;
          },
          [&](int rc, const double* a, const double* b) {
            const ConstPair a_pair(a), b_pair(b);
            Pair(cos_target + rc) += scale * (a_pair + b_pair);
            Pair(sin_target + rc) += scale * SineColumn(a_pair, b_pair);
          });
    }
  }
}

}  // namespace nfrc
