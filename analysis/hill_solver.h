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
  // Groups of blocks that reach the same own rows when eliminating.
  int num_row_groups() const { return static_cast<int>(groups_.size()); }
  // x = H⁻¹ rhs; x must not alias rhs. No allocation once x has the matrix's size.
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;

 private:
  struct Block {
    std::vector<int> unknowns;  // indices in H
    // The rows of H(B, B) in pivot order: the LU's right-hand side is rhs(gather).
    std::vector<int> gather;
    Eigen::MatrixXd lu;            // unit L below the diagonal and U of P H(B, B)
    std::vector<int> own_columns;  // Schur positions p with H(B, p) ≠ 0
    Eigen::MatrixXd eliminated;    // H(B, B)⁻¹ H(B, own_columns)
    // The block's positions whose columns reach own rows (friction: its DOF's, not the
    // others'): its columns of its group's rows, from reach_offset on.
    std::vector<int> row_positions;
    int group = -1;  // in groups_; -1: no own row depends on the block
    int reach_offset = 0;
    mutable Eigen::VectorXd solution;  // Solve's work vector
  };
  // The blocks that reach the same own rows (friction: every harmonic reaches all the force
  // rows), side by side: one product per group instead of one per block, and one scatter.
  struct RowGroup {
    std::vector<int> own_rows;  // Schur positions, ascending
    Eigen::MatrixXd rows;       // H(own_rows, its blocks' reaching columns)
    int width = 0;              // columns of rows
    // Work vectors of Solve: the blocks' reaching solutions and rows · reaching.
    mutable Eigen::VectorXd reaching, row_work;
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
  std::vector<RowGroup> groups_;
  DenseLu schur_lu_;
  mutable Eigen::VectorXd schur_rhs_, own_solution_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse_lu_;
};

}  // namespace nfrc
