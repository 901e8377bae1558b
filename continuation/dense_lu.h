#pragma once

#include <Eigen/Dense>
#include <vector>

namespace nfrc {

// A dense LU with partial pivoting, P A = L U, that sends matrices of kLapackMinSize unknowns
// and more to LAPACK's dgetrf/dgetrs from OpenBLAS (blocked, with the host's vector kernels
// chosen at run time; one thread unless OPENBLAS_NUM_THREADS says otherwise) and smaller ones
// to Eigen's PartialPivLU, whose kernels are compiled for the baseline instruction set.
// `nfrc_bench 13` times both: level at 40 unknowns, LAPACK 1.2–1.4× faster at 80–160, 1.8×
// at 320 and 2.5–2.8× at 1 280–2 560.
class DenseLu {
 public:
  // From this size up (rows), LAPACK; below it, Eigen (see the class comment).
  static constexpr Eigen::Index kLapackMinSize = 100;

  DenseLu() = default;
  explicit DenseLu(const Eigen::MatrixXd& a) { Compute(a); }

  // Factorises a square matrix; a singular one still factorises (a zero pivot shows in
  // Pivots(), and solves then return non-finite values).
  void Compute(const Eigen::MatrixXd& a);
  // Forces the back end (tests compare the two): true for LAPACK at any size.
  void Compute(const Eigen::MatrixXd& a, bool lapack);

  Eigen::Index rows() const { return size_; }
  bool lapack() const { return lapack_; }
  // U's diagonal, in pivoting order.
  Eigen::VectorXd Pivots() const;
  // The sign of det A (the pivots' signs and the permutation's parity; the product itself
  // over- or underflows for large matrices); 0 if a pivot is zero.
  int DeterminantSign() const;

  // A⁻¹ b for one or several right-hand sides.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b) const;
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const;
  // x = A⁻¹ b without allocating once x has b's size; x must not alias b.
  void Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) const;

 private:
  // Solves in place, columns of `b` (rows() rows, leading dimension rows()).
  void SolveInPlace(double* b, int columns) const;

  Eigen::Index size_ = 0;
  bool lapack_ = false;
  Eigen::PartialPivLU<Eigen::MatrixXd> eigen_;  // below kLapackMinSize
  Eigen::MatrixXd factors_;                     // LAPACK's L\U
  std::vector<int> pivots_;                     // LAPACK's row interchanges, 1-based
};

// True when every pivot is above `ratio` times the largest in magnitude and that is finite;
// true when there is none. The second form reads U's diagonal.
bool PivotsAbove(const Eigen::VectorXd& pivots, double ratio);
bool PivotsAbove(const DenseLu& lu, double ratio);

// The sign of the determinant of a partial-pivoting LU's matrix: the pivots' signs and the
// permutation's parity (the product itself over- or underflows for large matrices).
int DeterminantSign(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu);

}  // namespace nfrc
