#include "core/lu_factorization.h"

#include <doctest/doctest.h>

#include <Eigen/Sparse>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace nfrc::internal {
namespace {

using Complex = std::complex<double>;
using SparseComplex = Eigen::SparseMatrix<Complex>;

// Backward-stable LU on these well-conditioned (diagonally dominant) matrices gives ~1e-15
// relative residuals; 1e-11 allows for condition numbers up to ~1e4.
constexpr double kTol = 1e-11;

struct Matrix {
  CscPattern pattern;
  std::vector<Complex> values;
  Eigen::MatrixXcd dense;
};

Matrix FromSparse(SparseComplex a) {
  a.makeCompressed();
  Matrix m;
  m.pattern.n = static_cast<int>(a.rows());
  m.pattern.col_start.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.cols() + 1);
  m.pattern.row_index.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  m.values.assign(a.valuePtr(), a.valuePtr() + a.nonZeros());
  m.dense = Eigen::MatrixXcd(a);
  return m;
}

// Non-symmetric sparse complex matrix, a few entries per column plus a dominant diagonal.
Matrix RandomSparse(int n, unsigned seed) {
  std::srand(seed);
  std::vector<Eigen::Triplet<Complex>> t;
  for (int j = 0; j < n; ++j) {
    t.emplace_back(j, j, Complex(6.0, 1.0));
    for (int e = 0; e < 4; ++e) {
      const int i = std::rand() % n;
      t.emplace_back(i, j, Complex(std::rand() / double(RAND_MAX) - 0.5, 0.3));
    }
  }
  SparseComplex a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return FromSparse(a);
}

// Same pattern with other values: new diagonal, off-diagonal entries scaled.
std::vector<Complex> Perturbed(const Matrix& m, Complex scale) {
  std::vector<Complex> values = m.values;
  for (int j = 0; j < m.pattern.n; ++j) {
    for (auto e = m.pattern.col_start[j]; e < m.pattern.col_start[j + 1]; ++e) {
      values[e] *= m.pattern.row_index[e] == j ? Complex(1.0, 0.5) : scale;
    }
  }
  return values;
}

Eigen::MatrixXcd DenseOf(const CscPattern& pattern, const std::vector<Complex>& values) {
  Eigen::MatrixXcd dense = Eigen::MatrixXcd::Zero(pattern.n, pattern.n);
  for (int j = 0; j < pattern.n; ++j) {
    for (auto e = pattern.col_start[j]; e < pattern.col_start[j + 1]; ++e) {
      dense(pattern.row_index[e], j) += values[e];
    }
  }
  return dense;
}

// Residuals of A x = b and Aᵀ x = b (plain transpose) relative to |b|.
void CheckSolves(const LuFactorization& lu, const Eigen::MatrixXcd& a) {
  const Eigen::MatrixXcd b = Eigen::MatrixXcd::Random(a.rows(), 3);
  Eigen::MatrixXcd x = b;
  lu.Solve(x, false);
  CHECK((a * x - b).norm() / b.norm() < kTol);
  x = b;
  lu.Solve(x, true);
  CHECK((a.transpose() * x - b).norm() / b.norm() < kTol);
}

TEST_CASE("LU back ends solve plain and transposed systems") {
  const Matrix m = RandomSparse(80, 11);
  SUBCASE("dense") { CheckSolves(*DenseLu(m.dense, 1, 1.0), m.dense); }
  for (SparseBackend backend : {SparseBackend::kKlu, SparseBackend::kUmfpack}) {
    INFO("backend " << static_cast<int>(backend));
    const SparseAnalysis analysis(m.pattern, backend);
    CHECK(analysis.backend() == backend);
    const auto lu = analysis.Factorize(m.values, 1, 1.0);
    CheckSolves(*lu, m.dense);
    // The analysis serves other values on the same pattern.
    const std::vector<Complex> other = Perturbed(m, Complex(0.5, -0.2));
    CheckSolves(*analysis.Factorize(other, 2, 1.0), DenseOf(m.pattern, other));
  }
}

TEST_CASE("Sparse refactorisation reuses pivots only while stable") {
  const Matrix m = RandomSparse(50, 12);
  const SparseAnalysis klu(m.pattern, SparseBackend::kKlu);
  auto lu = klu.Factorize(m.values, 1, 1.0);
  const std::vector<Complex> nearby = Perturbed(m, Complex(1.1, 0.05));
  REQUIRE(lu->Refactor(nearby));
  CheckSolves(*lu, DenseOf(m.pattern, nearby));
  // Dense and UMFPACK factorisations always pivot afresh.
  CHECK_FALSE(DenseLu(m.dense, 1, 1.0)->Refactor(m.values));
  CHECK_FALSE(SparseAnalysis(m.pattern, SparseBackend::kUmfpack)
                  .Factorize(m.values, 1, 1.0)
                  ->Refactor(m.values));

  // 2×2 case: diagonal pivots chosen for [[1, .5], [.5, 1]] are unstable for
  // [[1e-6, 1], [1, 1]] (growth 1e6, though the pivot ratio 1e-12 looks regular) and
  // impossible for [[0, 1], [1, 1]].
  SparseComplex a(2, 2);
  a.insert(0, 0) = 1.0;
  a.insert(1, 0) = 0.5;
  a.insert(0, 1) = 0.5;
  a.insert(1, 1) = 1.0;
  const Matrix small = FromSparse(a);
  const SparseAnalysis small_klu(small.pattern, SparseBackend::kKlu);
  auto small_lu = small_klu.Factorize(small.values, 1, 1.0);
  const std::vector<Complex> tiny_pivot = {1e-6, 1.0, 1.0, 1.0};
  const std::vector<Complex> zero_pivot = {0.0, 1.0, 1.0, 1.0};
  CHECK_FALSE(small_lu->Refactor(tiny_pivot));
  small_lu = small_klu.Factorize(small.values, 1, 1.0);
  CHECK_FALSE(small_lu->Refactor(zero_pivot));
  // A fresh factorisation pivots off the diagonal and solves both.
  CheckSolves(*small_klu.Factorize(tiny_pivot, 1, 1.0), DenseOf(small.pattern, tiny_pivot));
  CheckSolves(*small_klu.Factorize(zero_pivot, 1, 1.0), DenseOf(small.pattern, zero_pivot));
}

TEST_CASE("Automatic sparse back end follows fill") {
  // A tridiagonal matrix factorises without fill (KLU); a 3D 7-point grid fills heavily.
  auto grid = [](int m, int dims) {
    const int n = dims == 1 ? m : m * m * m;
    std::vector<Eigen::Triplet<Complex>> t;
    const int strides[3] = {1, m, m * m};
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, Complex(7.0, 0.1));
      for (int d = 0; d < dims; ++d) {
        const int coordinate = (i / strides[d]) % m;
        if (coordinate + 1 < m) {
          t.emplace_back(i, i + strides[d], -1.0);
          t.emplace_back(i + strides[d], i, -1.0);
        }
      }
    }
    SparseComplex a(n, n);
    a.setFromTriplets(t.begin(), t.end());
    return FromSparse(a);
  };
  const Matrix chain = grid(2000, 1);
  CHECK(SparseAnalysis(chain.pattern).backend() == SparseBackend::kKlu);
  const Matrix cube = grid(16, 3);
  const SparseAnalysis cube_analysis(cube.pattern);
  CHECK(cube_analysis.backend() == SparseBackend::kUmfpack);
  const Eigen::VectorXcd b = Eigen::VectorXcd::Ones(cube.pattern.n);
  Eigen::MatrixXcd x = b;
  cube_analysis.Factorize(cube.values, 1, 1.0)->Solve(x, false);
  const SparseComplex a = cube.dense.sparseView();
  CHECK((a * x - b).norm() / b.norm() < kTol);
}

TEST_CASE("LU back ends report singular matrices with harmonic and frequency") {
  // Column 1 is zero: structurally singular for the sparse back ends once the values vanish.
  SparseComplex a(3, 3);
  a.insert(0, 0) = 2.0;
  a.insert(1, 1) = 0.0;
  a.insert(2, 2) = 1.0;
  a.insert(2, 0) = 1.0;
  const Matrix m = FromSparse(a);
  CHECK_THROWS_WITH_AS(DenseLu(m.dense, 3, 0.5), doctest::Contains("harmonic 3, omega = 0.5"),
                       std::runtime_error);
  for (SparseBackend backend : {SparseBackend::kKlu, SparseBackend::kUmfpack}) {
    const SparseAnalysis analysis(m.pattern, backend);
    CHECK_THROWS_WITH_AS(analysis.Factorize(m.values, 5, 2.25),
                         doctest::Contains("harmonic 5, omega = 2.25"), std::runtime_error);
  }
}

}  // namespace
}  // namespace nfrc::internal
