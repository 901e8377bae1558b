#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <vector>

#include "continuation/dense_lu.h"

namespace nfrc {

// Solves with Hill's matrix H(σ) = Δ0 + σΔ1 + σ²Δ2, which shift-invert Arnoldi applies
// 30–100 times per point. The linear part couples no two harmonics; the laws couple them
// through their own unknowns (friction: the force enters the equations of motion only there)
// or through the displacement rows of their DOFs (contact, polynomial springs). With the
// harmonic of each displacement unknown given, the rows that reach another harmonic join
// the own unknowns in a Schur complement, and the rest splits into small independent
// blocks, one per harmonic, which are eliminated: only the Schur complement (the own
// unknowns and the contact DOFs' coefficients) is factorised densely. Where that fails (a
// block above kMaxBlock, a Schur complement above kMaxSchur, a singular pivot), one sparse
// LU of the whole matrix.
class HillLinearSolver {
 public:
  // Displacement blocks larger than this go to the sparse LU.
  static constexpr int kMaxBlock = 64;
  // The dense Schur complement is at most this many unknowns (an LU of 3000 is ~1 s).
  static constexpr int kMaxSchur = 3000;
  // At most this many displacement rows join it (its LU ~0.1 Gflop): with more (a chain with
  // a spring at every DOF) the sparse LU, which keeps the chain's band, is the cheaper one.
  static constexpr int kMaxCoupledRows = 512;

  // own_offset: the own unknowns are the indices from own_offset to the end. harmonics
  // (optional, own_offset entries): the harmonic of each displacement unknown; empty, only
  // the own unknowns form the Schur complement.
  HillLinearSolver(const Eigen::SparseMatrix<double>& matrix, int own_offset,
                   const std::vector<int>& harmonics = {});

  bool ok() const { return ok_; }
  // True when the blocks were eliminated (false: the sparse LU).
  bool eliminating() const { return eliminating_; }
  // Unknowns in the Schur complement when eliminating.
  int schur_size() const { return static_cast<int>(schur_unknowns_.size()); }
  // x = H⁻¹ rhs; x must not alias rhs. No allocation once x has the matrix's size.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;

 private:
  struct Block {
    std::vector<int> unknowns;                // indices in H
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of H(B, B)
    std::vector<int> own_columns;             // Schur positions p with H(B, p) ≠ 0
    std::vector<int> own_rows;                // Schur positions p with H(p, B) ≠ 0
    Eigen::MatrixXd eliminated;               // H(B, B)⁻¹ H(B, own_columns)
    // The block's positions whose columns reach own rows (friction: its DOF's, not the
    // others'), and H(own_rows, those columns): the zero columns are left out.
    std::vector<int> row_positions;
    Eigen::MatrixXd rows;
    // Work vectors of Solve (block, own_rows, own_columns and row_positions sized).
    mutable Eigen::VectorXd local, solution, row_work, column_work, reaching;
  };

  // The Schur complement's unknowns: the own ones and the displacement rows that reach
  // another harmonic.
  void ChooseSchur(const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& harmonics);
  // Builds the blocks and the Schur complement; false when the structure or the pivots
  // rule the elimination out.
  bool Eliminate(const Eigen::SparseMatrix<double>& matrix);

  int size_ = 0;
  int own_offset_ = 0;
  std::vector<int> schur_unknowns_;  // ascending
  std::vector<int> schur_position_;  // per unknown: its place in schur_unknowns_, or -1
  bool ok_ = false;
  bool eliminating_ = false;
  std::vector<Block> blocks_;
  DenseLu schur_lu_;
  mutable Eigen::VectorXd schur_rhs_, own_solution_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse_lu_;
};

}  // namespace nfrc
