#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <vector>

namespace nfrc {

// Solves with Hill's matrix H(σ) = Δ0 + σΔ1 + σ²Δ2, which shift-invert Arnoldi applies
// 30–100 times per point. Where the laws' own unknowns are the only coupling between the
// displacement unknowns of different harmonics (friction laws: their force enters the
// equations of motion only through its own unknowns), the displacement part splits into
// small independent blocks, one per harmonic; these are eliminated and only the Schur
// complement on the own unknowns is factorised densely. Otherwise (a law that couples
// harmonics in the displacement rows, e.g. contact) one sparse LU of the whole matrix.
class HillLinearSolver {
 public:
  // Displacement blocks larger than this go to the sparse LU.
  static constexpr int kMaxBlock = 64;
  // The dense Schur complement is at most this many own unknowns (an LU of 3000 is ~1 s).
  static constexpr int kMaxSchur = 3000;

  // own_offset: the own unknowns are the indices from own_offset to the end.
  HillLinearSolver(const Eigen::SparseMatrix<double>& matrix, int own_offset);

  bool ok() const { return ok_; }
  // True when the blocks were eliminated (false: the sparse LU).
  bool eliminating() const { return eliminating_; }
  // x = H⁻¹ rhs; x must not alias rhs. No allocation once x has the matrix's size.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;

 private:
  struct Block {
    std::vector<int> unknowns;                // indices in H
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of H(B, B)
    std::vector<int> own_columns;             // own unknowns (offsets) with H(B, own) ≠ 0
    std::vector<int> own_rows;                // own unknowns (offsets) with H(own, B) ≠ 0
    Eigen::MatrixXd eliminated;               // H(B, B)⁻¹ H(B, own_columns)
    Eigen::MatrixXd rows;                     // H(own_rows, B)
    // Work vectors of Solve (block, own_rows and own_columns sized).
    mutable Eigen::VectorXd local, solution, row_work, column_work;
  };

  // Builds the blocks and the Schur complement; false when the structure or the pivots
  // rule the elimination out.
  bool Eliminate(const Eigen::SparseMatrix<double>& matrix);

  int size_ = 0;
  int own_offset_ = 0;
  bool ok_ = false;
  bool eliminating_ = false;
  std::vector<Block> blocks_;
  Eigen::PartialPivLU<Eigen::MatrixXd> schur_lu_;
  mutable Eigen::VectorXd schur_rhs_, own_solution_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse_lu_;
};

}  // namespace nfrc
