#include "core/lu_factorization.h"

#include <klu.h>
#include <umfpack.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace nfrc::internal {
namespace {

using Complex = std::complex<double>;
static_assert(std::is_same_v<SuiteSparse_long, int64_t>, "SuiteSparse index type must be int64_t");

// Below this pivot ratio or reciprocal condition estimate Z_ll is numerically singular: a
// solve would keep no correct digit.
constexpr double kSingularRcond = std::numeric_limits<double>::epsilon();

// A refactorisation with the previous pivot order is kept if its reciprocal pivot growth is
// at least this fraction of the one obtained with fresh pivoting (at most 10× more growth).
constexpr double kRefactorGrowthRatio = 0.1;

// KLU is chosen below this many estimated flops per DOF. With Debian's reference BLAS a
// 10^5-DOF chain (3 flops/DOF) factorises 5× faster with KLU and a 300×300 grid (10^4) 1.4×;
// beyond, UMFPACK's dense fronts gain most from an optimised BLAS.
constexpr double kKluMaxFlopsPerDof = 1e4;

// A ratio for a message: "%.3g", and "not a number" where the matrix held overflowed entries
// (printf's "-nan" says nothing to a user).
std::string Ratio(double value) {
  if (std::isnan(value)) return "not a number: the matrix has overflowed entries";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

[[noreturn]] void ThrowSingular(int harmonic, double omega, const std::string& detail) {
  char omega_text[32];
  std::snprintf(omega_text, sizeof(omega_text), "%.17g", omega);
  throw std::runtime_error("Condensation: Z_ll is singular at harmonic " +
                           std::to_string(harmonic) + ", omega = " + omega_text + " (" + detail +
                           ")");
}

// std::complex<double> is layout-compatible with double[2], SuiteSparse's packed complex.
double* Packed(Complex* values) { return reinterpret_cast<double*>(values); }
const double* Packed(const Complex* values) { return reinterpret_cast<const double*>(values); }

class DenseFactorization final : public LuFactorization {
 public:
  DenseFactorization(const Eigen::MatrixXcd& z, int harmonic, double omega) : lu_(z) {
    // Eigen's rcond estimate misses exactly zero pivots, so check the pivot ratio as well.
    const Eigen::VectorXd pivots = lu_.matrixLU().diagonal().cwiseAbs();
    const double pivot_ratio = pivots.minCoeff() / pivots.maxCoeff();
    if (!(pivot_ratio >= kSingularRcond)) {
      ThrowSingular(harmonic, omega, "pivot ratio " + Ratio(pivot_ratio));
    }
    const double rcond = lu_.rcond();
    if (!(rcond >= kSingularRcond)) {
      ThrowSingular(harmonic, omega, "rcond estimate " + Ratio(rcond));
    }
  }

  void Solve(Eigen::MatrixXcd& b, bool transposed) const override {
    Eigen::MatrixXcd x =
        transposed ? Eigen::MatrixXcd(lu_.transpose().solve(b)) : Eigen::MatrixXcd(lu_.solve(b));
    b = std::move(x);
  }

 private:
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu_;
};

class KluFactorization final : public LuFactorization {
 public:
  KluFactorization(const CscPattern& pattern, klu_l_symbolic* symbolic, const klu_l_common& common,
                   const std::vector<Complex>& values, int harmonic, double omega)
      : pattern_(pattern), symbolic_(symbolic), common_(common) {
    numeric_ = klu_zl_factor(ColStart(), RowIndex(), Values(values), symbolic_, &common_);
    if (numeric_ == nullptr) {
      if (common_.status == KLU_SINGULAR) ThrowSingular(harmonic, omega, "zero pivot");
      throw std::runtime_error("Condensation: klu_zl_factor failed with status " +
                               std::to_string(common_.status));
    }
    // The estimate is the ratio of the smallest to the largest pivot magnitude.
    klu_zl_rcond(symbolic_, numeric_, &common_);
    if (!(common_.rcond >= kSingularRcond)) {
      const double rcond = common_.rcond;
      klu_zl_free_numeric(&numeric_, &common_);
      ThrowSingular(harmonic, omega, "pivot ratio " + Ratio(rcond));
    }
    klu_zl_rgrowth(ColStart(), RowIndex(), Values(values), symbolic_, numeric_, &common_);
    fresh_rgrowth_ = common_.rgrowth;
  }

  bool Refactor(const std::vector<Complex>& values) override {
    if (!klu_zl_refactor(ColStart(), RowIndex(), Values(values), symbolic_, numeric_, &common_)) {
      return false;  // e.g. a zero pivot in the old order
    }
    klu_zl_rgrowth(ColStart(), RowIndex(), Values(values), symbolic_, numeric_, &common_);
    if (!(common_.rgrowth >= kRefactorGrowthRatio * fresh_rgrowth_)) return false;
    klu_zl_rcond(symbolic_, numeric_, &common_);
    return common_.rcond >= kSingularRcond;
  }

  ~KluFactorization() override { klu_zl_free_numeric(&numeric_, &common_); }
  KluFactorization(const KluFactorization&) = delete;
  KluFactorization& operator=(const KluFactorization&) = delete;

  void Solve(Eigen::MatrixXcd& b, bool transposed) const override {
    const int n = pattern_.n;
    if (b.cols() == 0 || n == 0) return;
    klu_l_common common = common_;  // status is written even by solves
    // Columns of b are contiguous, so the leading dimension is n.
    const auto ok = transposed
                        ? klu_zl_tsolve(symbolic_, numeric_, n, b.cols(), Packed(b.data()),
                                        /*conj_solve=*/0, &common)
                        : klu_zl_solve(symbolic_, numeric_, n, b.cols(), Packed(b.data()), &common);
    if (!ok) {
      throw std::runtime_error("Condensation: KLU solve failed with status " +
                               std::to_string(common.status));
    }
  }

 private:
  // KLU does not modify these inputs despite its non-const signature.
  int64_t* ColStart() const { return const_cast<int64_t*>(pattern_.col_start.data()); }
  int64_t* RowIndex() const { return const_cast<int64_t*>(pattern_.row_index.data()); }
  static double* Values(const std::vector<Complex>& values) {
    return const_cast<double*>(Packed(values.data()));
  }

  const CscPattern& pattern_;
  klu_l_symbolic* symbolic_;
  klu_l_common common_;
  klu_l_numeric* numeric_ = nullptr;
  double fresh_rgrowth_ = 0.0;  // reciprocal pivot growth with the pivots chosen for it
};

class UmfpackFactorization final : public LuFactorization {
 public:
  UmfpackFactorization(const CscPattern& pattern, void* symbolic, const double* control,
                       const std::vector<Complex>& values, int harmonic, double omega)
      : pattern_(pattern), control_(control), values_(values) {
    double info[UMFPACK_INFO];
    const auto status =
        umfpack_zl_numeric(pattern_.col_start.data(), pattern_.row_index.data(),
                           Packed(values_.data()), nullptr, symbolic, &numeric_, control_, info);
    // The estimate is the ratio of the smallest to the largest pivot magnitude.
    const double pivot_ratio = info[UMFPACK_RCOND];
    if (status == UMFPACK_OK && pivot_ratio >= kSingularRcond) return;
    // The destructor does not run when the constructor throws: free the factors here.
    if (numeric_ != nullptr) umfpack_zl_free_numeric(&numeric_);
    if (status == UMFPACK_WARNING_singular_matrix) ThrowSingular(harmonic, omega, "zero pivot");
    if (status != UMFPACK_OK) {
      throw std::runtime_error("Condensation: umfpack_zl_numeric failed with status " +
                               std::to_string(status));
    }
    ThrowSingular(harmonic, omega, "pivot ratio " + Ratio(pivot_ratio));
  }

  ~UmfpackFactorization() override {
    if (numeric_ != nullptr) umfpack_zl_free_numeric(&numeric_);
  }
  UmfpackFactorization(const UmfpackFactorization&) = delete;
  UmfpackFactorization& operator=(const UmfpackFactorization&) = delete;

  void Solve(Eigen::MatrixXcd& b, bool transposed) const override {
    const int n = pattern_.n;
    Eigen::MatrixXcd x(n, b.cols());
    // Workspace of umfpack_zl_wsolve with iterative refinement: n indices and 10n doubles.
    std::vector<SuiteSparse_long> wi(n);
    std::vector<double> w(10 * static_cast<size_t>(n));
    double info[UMFPACK_INFO];
    for (Eigen::Index c = 0; c < b.cols(); ++c) {
      const auto status = umfpack_zl_wsolve(
          transposed ? UMFPACK_Aat : UMFPACK_A, pattern_.col_start.data(),
          pattern_.row_index.data(), Packed(values_.data()), nullptr, Packed(x.col(c).data()),
          nullptr, Packed(b.col(c).data()), nullptr, numeric_, control_, info, wi.data(), w.data());
      if (status != UMFPACK_OK) {
        throw std::runtime_error("Condensation: umfpack_zl_wsolve failed with status " +
                                 std::to_string(status));
      }
    }
    b = std::move(x);
  }

 private:
  const CscPattern& pattern_;
  const double* control_;
  std::vector<Complex> values_;  // iterative refinement in wsolve reads the matrix
  void* numeric_ = nullptr;
};

}  // namespace

struct SparseAnalysis::State {
  klu_l_common klu_common;
  klu_l_symbolic* klu_symbolic = nullptr;
  std::vector<double> umfpack_control = std::vector<double>(UMFPACK_CONTROL);
  void* umfpack_symbolic = nullptr;

  ~State() {
    if (klu_symbolic != nullptr) klu_l_free_symbolic(&klu_symbolic, &klu_common);
    if (umfpack_symbolic != nullptr) umfpack_zl_free_symbolic(&umfpack_symbolic);
  }
};

std::unique_ptr<LuFactorization> DenseLu(const Eigen::MatrixXcd& z, int harmonic, double omega) {
  return std::make_unique<DenseFactorization>(z, harmonic, omega);
}

SparseAnalysis::SparseAnalysis(const CscPattern& pattern, SparseBackend backend)
    : pattern_(pattern), backend_(backend), state_(std::make_unique<State>()) {
  State& s = *state_;
  klu_l_defaults(&s.klu_common);
  umfpack_zl_defaults(s.umfpack_control.data());
  // The analyses see the pattern only, so they stay valid for every harmonic and frequency.
  if (backend_ != SparseBackend::kUmfpack) {
    s.klu_symbolic = klu_l_analyze(pattern_.n, const_cast<int64_t*>(pattern_.col_start.data()),
                                   const_cast<int64_t*>(pattern_.row_index.data()), &s.klu_common);
    if (s.klu_symbolic == nullptr) {
      throw std::runtime_error("Condensation: klu_l_analyze failed with status " +
                               std::to_string(s.klu_common.status));
    }
    if (backend_ == SparseBackend::kAuto) {
      backend_ = s.klu_symbolic->est_flops <= kKluMaxFlopsPerDof * pattern_.n
                     ? SparseBackend::kKlu
                     : SparseBackend::kUmfpack;
    }
    if (backend_ == SparseBackend::kUmfpack) {
      klu_l_free_symbolic(&s.klu_symbolic, &s.klu_common);
    }
  }
  if (backend_ == SparseBackend::kUmfpack) {
    double info[UMFPACK_INFO];
    const auto status = umfpack_zl_symbolic(pattern_.n, pattern_.n, pattern_.col_start.data(),
                                            pattern_.row_index.data(), nullptr, nullptr,
                                            &s.umfpack_symbolic, s.umfpack_control.data(), info);
    if (status != UMFPACK_OK) {
      throw std::runtime_error("Condensation: umfpack_zl_symbolic failed with status " +
                               std::to_string(status));
    }
  }
}

SparseAnalysis::~SparseAnalysis() = default;

std::unique_ptr<LuFactorization> SparseAnalysis::Factorize(const std::vector<Complex>& values,
                                                           int harmonic, double omega) const {
  if (backend_ == SparseBackend::kKlu) {
    return std::make_unique<KluFactorization>(pattern_, state_->klu_symbolic, state_->klu_common,
                                              values, harmonic, omega);
  }
  return std::make_unique<UmfpackFactorization>(
      pattern_, state_->umfpack_symbolic, state_->umfpack_control.data(), values, harmonic, omega);
}

}  // namespace nfrc::internal
