#pragma once

#include <Eigen/Dense>
#include <complex>
#include <cstdint>
#include <memory>
#include <vector>

// Internal to core/: LU factorisations of the condensed block Z_ll used by Condensation.
namespace nfrc::internal {

// Square sparse pattern in compressed-column form with SuiteSparse's 64-bit indices.
struct CscPattern {
  int n = 0;
  std::vector<int64_t> col_start;  // n + 1 entries
  std::vector<int64_t> row_index;  // sorted within each column
};

class LuFactorization {
 public:
  virtual ~LuFactorization() = default;
  // Overwrites b (n × m) with Z⁻¹ b, or Z⁻ᵀ b (plain transpose, no conjugate) if `transposed`.
  virtual void Solve(Eigen::MatrixXcd& b, bool transposed) const = 0;

  // Refactorises in place a matrix of the same pattern with new `values`, reusing the pivot
  // order (cheap across nearby frequencies). Returns false, leaving this factorisation
  // unusable, if unsupported or if the old pivots are no longer stable for the new values.
  virtual bool Refactor(const std::vector<std::complex<double>>& /*values*/) { return false; }
};

// Dense partial-pivoting LU of z. Throws std::runtime_error naming `harmonic` and `omega`
// if z is numerically singular.
std::unique_ptr<LuFactorization> DenseLu(const Eigen::MatrixXcd& z, int harmonic, double omega);

// SuiteSparse back ends. KLU (left-looking, no frontal matrices) is several times faster
// when the factors stay very sparse (chains, beams, 2D meshes); UMFPACK (multifrontal,
// BLAS-3 fronts) pays off when fill is heavy. kAuto picks by KLU's flop estimate.
enum class SparseBackend { kAuto, kKlu, kUmfpack };

// Symbolic analysis of a pattern (which must outlive it), shared by the numeric
// factorisations of every matrix on that pattern: harmonics and frequencies alike.
class SparseAnalysis {
 public:
  explicit SparseAnalysis(const CscPattern& pattern, SparseBackend backend = SparseBackend::kAuto);
  ~SparseAnalysis();
  SparseAnalysis(const SparseAnalysis&) = delete;
  SparseAnalysis& operator=(const SparseAnalysis&) = delete;

  // kKlu or kUmfpack.
  SparseBackend backend() const { return backend_; }

  // Sparse LU of the matrix with `values` (aligned with pattern.row_index). Throws
  // std::runtime_error naming `harmonic` and `omega` if the matrix is numerically singular.
  // Factorisations must not outlive this analysis.
  std::unique_ptr<LuFactorization> Factorize(const std::vector<std::complex<double>>& values,
                                             int harmonic, double omega) const;

 private:
  struct State;
  const CscPattern& pattern_;
  SparseBackend backend_;
  std::unique_ptr<State> state_;
};

}  // namespace nfrc::internal
