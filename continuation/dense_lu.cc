#include "continuation/dense_lu.h"

#include <cassert>
#include <cmath>
#include <cstdlib>

// LAPACK through OpenBLAS. With NFRC_BLAS, Eigen's lapacke.h already declares the Fortran
// symbols (with other const-ness), so the calls go through LAPACKE's column-major functions.
#ifdef EIGEN_USE_LAPACKE
namespace {
int Getrf(int n, double* a, int* ipiv) {
  return static_cast<int>(LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, n, n, a, n, ipiv));
}
int Getrs(char trans, int n, int columns, const double* a, const int* ipiv, double* b) {
  return static_cast<int>(
      LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, trans, n, columns, a, n, ipiv, b, n));
}
}  // namespace
extern "C" void openblas_set_num_threads(int num_threads);
#else
// Fortran calling convention; the trailing length of the character argument is passed as
// gfortran's interface expects, and ignored by OpenBLAS's C version.
extern "C" {
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, size_t trans_length);
void openblas_set_num_threads(int num_threads);
}
namespace {
int Getrf(int n, double* a, int* ipiv) {
  int info = 0;
  dgetrf_(&n, &n, a, &n, ipiv, &info);
  return info;
}
int Getrs(char trans, int n, int columns, const double* a, const int* ipiv, double* b) {
  int info = 0;
  dgetrs_(&trans, &n, &columns, a, &n, ipiv, b, &n, &info, 1);
  return info;
}
}  // namespace
#endif

namespace nfrc {
namespace {

// OpenBLAS otherwise runs a thread per core that spins between calls: at these sizes its
// second thread gained nothing on whole runs (point E's curve 7.0–7.1 s on one thread, 7.1–7.6
// on two) and it competes with a sweep's own threads and with other processes. Once, before
// the first LAPACK call, unless the user chose a number in OPENBLAS_NUM_THREADS.
void OneBlasThreadUnlessChosen() {
  static const bool chosen = [] {
    if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) openblas_set_num_threads(1);
    return true;
  }();
  (void)chosen;
}

// The permutation's sign times the pivots' signs (read in place from the factors' diagonal).
template <typename Diagonal>
int WithPivotSigns(int permutation_sign, const Diagonal& pivots) {
  int sign = permutation_sign;
  for (Eigen::Index i = 0; i < pivots.size(); ++i) {
    if (pivots(i) < 0.0) sign = -sign;
  }
  return sign;
}

// The sign of the permutation i ↦ indices(i), from its cycles (one of length L is L − 1
// swaps), each counted at its smallest index. No scratch: Eigen's determinant() allocates a
// mask, and every elimination asks this of each of its blocks.
int PermutationSign(const Eigen::VectorXi& indices) {
  int sign = 1;
  for (Eigen::Index i = 0; i < indices.size(); ++i) {
    Eigen::Index length = 1;
    bool smallest = true;
    for (Eigen::Index j = indices(i); j != i; j = indices(j), ++length) {
      if (j < i) {
        smallest = false;
        break;
      }
    }
    if (smallest && length % 2 == 0) sign = -sign;
  }
  return sign;
}

}  // namespace

void DenseLu::Compute(const Eigen::MatrixXd& a) { Compute(a, a.rows() >= kLapackMinSize); }

void DenseLu::Compute(const Eigen::MatrixXd& a, bool lapack) {
  assert(a.rows() == a.cols());
  size_ = a.rows();
  lapack_ = lapack && size_ > 0;
  if (!lapack_) {
    eigen_.compute(a);
    factors_.resize(0, 0);
    pivots_.clear();
    return;
  }
  OneBlasThreadUnlessChosen();
  eigen_ = Eigen::PartialPivLU<Eigen::MatrixXd>();
  factors_ = a;
  const int n = static_cast<int>(size_);
  pivots_.resize(static_cast<size_t>(n));
  [[maybe_unused]] const int info = Getrf(n, factors_.data(), pivots_.data());
  // info > 0 is an exact zero pivot (reported by Pivots()); < 0 would be a wrong argument.
  assert(info >= 0);
}

Eigen::VectorXd DenseLu::Pivots() const {
  return lapack_ ? Eigen::VectorXd(factors_.diagonal())
                 : Eigen::VectorXd(eigen_.matrixLU().diagonal());
}

int DenseLu::DeterminantSign() const {
  const auto pivots = lapack_ ? factors_.diagonal() : eigen_.matrixLU().diagonal();
  if ((pivots.array() == 0.0).any()) return 0;
  if (!lapack_) return size_ > 0 ? nfrc::DeterminantSign(eigen_) : 1;
  int interchanges = 1;  // the permutation's sign, from LAPACK's 1-based row swaps
  for (int i = 0; i < static_cast<int>(size_); ++i) {
    if (pivots_[static_cast<size_t>(i)] != i + 1) interchanges = -interchanges;
  }
  return WithPivotSigns(interchanges, pivots);
}

void DenseLu::SolveInPlace(double* b, int columns) const {
  const int n = static_cast<int>(size_);
  [[maybe_unused]] const int info = Getrs('N', n, columns, factors_.data(), pivots_.data(), b);
  assert(info == 0);
}

Eigen::MatrixXd DenseLu::Solve(const Eigen::MatrixXd& b) const {
  assert(b.rows() == size_);
  if (!lapack_) return eigen_.solve(b);
  Eigen::MatrixXd x = b;
  if (x.cols() > 0) SolveInPlace(x.data(), static_cast<int>(x.cols()));
  return x;
}

Eigen::VectorXd DenseLu::Solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd x(b.size());
  Solve(b, &x);
  return x;
}

void DenseLu::Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
  assert(b.size() == size_ && x != &b);
  if (!lapack_) {
    *x = eigen_.solve(b);
    return;
  }
  *x = b;
  SolveInPlace(x->data(), 1);
}

bool PivotsAbove(const Eigen::VectorXd& pivots, double ratio) {
  if (pivots.size() == 0) return true;
  const double largest = pivots.cwiseAbs().maxCoeff();
  return std::isfinite(largest) && pivots.cwiseAbs().minCoeff() > ratio * largest;
}

bool PivotsAbove(const DenseLu& lu, double ratio) { return PivotsAbove(lu.Pivots(), ratio); }

int DeterminantSign(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  return WithPivotSigns(PermutationSign(lu.permutationP().indices()), lu.matrixLU().diagonal());
}

}  // namespace nfrc
