#pragma once

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "continuation/bordered_view.h"
#include "continuation/dense_lu.h"

namespace nfrc {

// Groups of unknowns whose rows and columns of a matrix are block diagonal among themselves
// (ContinuationProblem::EliminationBlocks): each group couples with no other group's
// unknowns, only with itself and with the rest.
using EliminationBlocks = std::vector<std::vector<int>>;

// A pivot below this fraction of the largest one makes an elimination give way to the whole
// LU: a Schur complement formed with the blocks' inverses carries their conditioning (at
// 1e-8, up to eight digits of the sixteen).
constexpr double kMinEliminationPivotRatio = 1e-8;

// True when every pivot of the LU is above kMinEliminationPivotRatio times the largest.
bool RegularForElimination(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu);
bool RegularForElimination(const DenseLu& lu);

// Throws std::invalid_argument if an index is outside [0, n) or in two blocks.
void ValidateEliminationBlocks(const EliminationBlocks& blocks, int n);

// Solves a x = b by eliminating the blocks' unknowns: one small LU per block, then the Schur
// complement on the other unknowns (and the border row of an augmented matrix), which is all
// that is factorised densely. Only the columns of a block's coupling to the rest that are
// non-zero are solved for, so a block coupled to the rest through a few columns (a force
// entering its equations) costs O(rest · block²). False, leaving x unset, where a block or
// the Schur complement is numerically singular (the caller then factorises `a` whole).
// Throws std::logic_error if two blocks are coupled in `a` (the problem broke its promise).
// determinant_sign (optional): the sign of det a, as the product of the blocks' and the Schur
// complement's (a symmetric reordering leaves it unchanged), set when true is returned.
bool SolveEliminating(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                      const EliminationBlocks& blocks, Eigen::VectorXd* x,
                      int* determinant_sign = nullptr);

// The blocks' part of SolveEliminating, kept: their LUs and A_BB⁻¹ A_B,rest (only the
// columns where A_B,rest ≠ 0). It serves any matrix whose blocks' rows (A_BB, A_B,rest)
// are the same, whatever its other rows (ReusedFactorization: a Newton iteration at fixed λ,
// where only the laws' rows change).
class BlockElimination {
 public:
  // Nullopt where a block is numerically singular (kMinEliminationPivotRatio). Throws
  // std::logic_error if two blocks are coupled in `a` (the problem broke its promise).
  // Matrix: Eigen::MatrixXd or BorderedView (the bordered matrix read in place).
  template <typename Matrix>
  static std::optional<BlockElimination> Factor(const Matrix& a, const EliminationBlocks& blocks);
  // Factor into this object, reusing its storage (a Newton iteration's blocks have the sizes
  // of the last one's: no allocation then). False where Factor gives nullopt; this object
  // then matches no matrix (SameBlockRows) and must not be used until a Refactor succeeds.
  template <typename Matrix>
  bool Refactor(const Matrix& a, const EliminationBlocks& blocks);

  // The unknowns kept, ascending: the Schur complement's order.
  const std::vector<int>& rest() const { return rest_; }
  // The product of the blocks' determinant signs.
  int determinant_sign() const { return sign_; }
  // True when a's blocks' rows are those factorised (bitwise), so that Reduce applies.
  template <typename Matrix>
  bool SameBlockRows(const Matrix& a) const;
  // A_BB⁻¹ b_B of every block, one after the other (for Reduce and BackSubstitute).
  Eigen::VectorXd BlockSolutions(const Eigen::VectorXd& b) const;
  // S = A_rr − A_rB A_BB⁻¹ A_B,rest and its right-hand side b_r − A_rB A_BB⁻¹ b_B.
  // rest_columns (optional): A_rest,B, the blocks' columns in the rest's rows, one block after
  // the other, for ReduceRhs.
  template <typename Matrix>
  void Reduce(const Matrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd& block_solutions,
              Eigen::MatrixXd* schur, Eigen::VectorXd* schur_rhs,
              Eigen::MatrixXd* rest_columns = nullptr) const;
  // The right-hand side alone, b_r − A_rB A_BB⁻¹ b_B, for a further one with the same `a`,
  // from Reduce's rest_columns.
  Eigen::VectorXd ReduceRhs(const Eigen::MatrixXd& rest_columns, const Eigen::VectorXd& b,
                            const Eigen::VectorXd& block_solutions) const;
  // x from the rest's solution: x_r, and x_B = A_BB⁻¹ b_B − A_BB⁻¹ A_B,rest x_r.
  void BackSubstitute(const Eigen::VectorXd& block_solutions, const Eigen::VectorXd& rest_solution,
                      Eigen::VectorXd* x) const;

 private:
  struct Block {
    std::vector<int> unknowns;
    Eigen::MatrixXd matrix;                   // A_BB
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of A_BB
    std::vector<int> coupled;                 // rest positions with A_B,rest ≠ 0
    Eigen::MatrixXd coupling;                 // A_B,coupled
    Eigen::MatrixXd eliminated;               // A_BB⁻¹ A_B,coupled
  };
  // Column `unknown` of a in the rest's rows, into `column` (sized by the caller).
  template <typename Matrix>
  void RestColumn(const Matrix& a, int unknown, Eigen::Ref<Eigen::VectorXd> column) const;

  int size_ = 0;
  std::vector<int> rest_;
  // The rest is one run of unknowns (the harmonic problems': the displacements' blocks first,
  // then the laws' unknowns and λ): its rows and columns are read as blocks, not entry by
  // entry through the index list.
  bool rest_run_ = false;
  std::vector<Block> blocks_;
  int sign_ = 1;
  // Refactor's work: each unknown's block (−1: the rest's), the blocks' rows ascending, and
  // a block's coupling with a last zero column, and its solution.
  std::vector<int> block_of_;
  std::vector<int> block_rows_;
  Eigen::MatrixXd right_;
  Eigen::MatrixXd solved_;
};

}  // namespace nfrc
