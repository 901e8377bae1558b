#pragma once

#include <Eigen/Dense>
#include <optional>

#include "continuation/block_elimination.h"
#include "continuation/dense_lu.h"
#include "continuation/evaluator.h"
#include "continuation/scaling.h"

namespace nfrc {

// The scaled bordered matrix [[R_y D_y, R_λ s_λ] / r; cᵀ] acting on scaled increments
// (Δy/s_y, Δλ/s_λ): columns scaled by the unknowns' scales, rows of R by the residual
// scale r, so that its entries (and the LU's pivot choices) do not depend on units.
Eigen::MatrixXd AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                                double residual_scale, const Eigen::VectorXd& last_row);
// The same into `a`, whose storage is kept when it already has the size: a corrector's
// iterations then fill one buffer (at 2 561 unknowns a new one is 52 MB of fresh pages).
void AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                     double residual_scale, const Eigen::VectorXd& last_row, Eigen::MatrixXd* a);

// Solves a x = b by a partial-pivoting LU; false if a pivot is at rounding level against the
// largest (a numerically singular) or x is not finite. determinant_sign (optional): the sign
// of det a, set when true is returned.
bool SolveRegular(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                  int* determinant_sign = nullptr);

// Solves a x = b by one partial-pivoting LU of the whole matrix; falls back to a
// full-pivoting LU when that LU is (numerically) singular. False if x is not finite.
// With `elimination` (the Jacobian's blocks, whose indices are the same in the augmented
// matrix), SolveEliminating is tried first. determinant_sign (optional): the sign of det a
// from the factorisation that solved (0 after the full-pivoting fallback: a is singular to
// rounding, its sign undecided).
bool SolveAugmented(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                    const EliminationBlocks* elimination = nullptr,
                    int* determinant_sign = nullptr);

// SolveAugmented on a matrix it holds, keeping the factorisation that solved for further
// right-hand sides: the corrector's last Newton matrix then gives the next tangent.
class AugmentedSolver {
 public:
  // The matrix, filled by the caller before Solve (AugmentedMatrix into it keeps its storage).
  Eigen::MatrixXd& matrix() { return a_; }
  const Eigen::MatrixXd& matrix() const { return a_; }
  // Factorises matrix() and solves, exactly as SolveAugmented; false if x is not finite.
  bool Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, const EliminationBlocks* elimination);
  // The same for the matrix `view` reads, which is made only where the elimination gives way
  // (matrix() is then that copy; otherwise it is left as it was). Bit for bit Solve's solution.
  bool Solve(const BorderedView& view, const Eigen::VectorXd& b, Eigen::VectorXd* x,
             const EliminationBlocks* elimination);
  // Solves again with the factorisation of the last Solve that succeeded. False if x is not
  // finite or no Solve succeeded.
  bool SolveAgain(const Eigen::VectorXd& b, Eigen::VectorXd* x) const;
  // The sign of the factorised matrix's determinant (0 after the full-pivoting fallback).
  int determinant_sign() const { return sign_; }
  // The factorised matrix's last row (the constraint's).
  const Eigen::VectorXd& last_row() const { return last_row_; }

 private:
  friend bool SolveAugmented(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                             const EliminationBlocks* elimination, int* determinant_sign);
  // Solve on `a` (matrix() or the caller's, for SolveAugmented).
  bool Factorize(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                 const EliminationBlocks* elimination);
  // The elimination's part of Factorize; false where it gives way to the whole LU.
  template <typename Matrix>
  bool Eliminate(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                 const EliminationBlocks& elimination);
  // The whole matrix's LU, and the full-pivoting one where that is singular.
  bool FactorizeWhole(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x);

  enum class Kind { kNone, kEliminated, kRegular, kFullPivoting };
  Eigen::MatrixXd a_;
  Kind kind_ = Kind::kNone;
  std::optional<BlockElimination> elimination_;  // kEliminated: the blocks' part
  Eigen::MatrixXd rest_columns_;                 // kEliminated: A_rest,B (ReduceRhs)
  Eigen::MatrixXd schur_;                        // Eliminate's work: the Schur complement
  Eigen::VectorXd schur_rhs_;                    // and its right-hand side
  Eigen::VectorXd last_row_;
  DenseLu lu_;                              // of the Schur complement, or of a (kRegular)
  Eigen::FullPivLU<Eigen::MatrixXd> full_;  // kFullPivoting
  int sign_ = 0;
};

}  // namespace nfrc
