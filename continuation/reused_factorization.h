#pragma once

#include <Eigen/Dense>
#include <optional>
#include <random>
#include <utility>

#include "continuation/block_elimination.h"
#include "continuation/dense_lu.h"

namespace nfrc {

// Solves the Newton systems of one correction at fixed λ, where from one iteration to the next
// only the laws' rows change, and for a piecewise law only through the few time samples that
// switched: the Schur complement S on the unknowns outside the elimination blocks then differs
// from the one last factorised by a low-rank ΔS (rank ≤ the samples that switched). Instead of
// a new LU (2/3 n³ flops), ΔS ≈ Q B is found by an adaptive randomised range finder (Halko,
// Martinsson & Tropp 2011, algorithm 4.2) and S⁻¹ applied by the Sherman–Morrison–Woodbury
// formula on the kept LU (~4 n² k flops). A new LU is taken instead where the blocks' rows
// changed, the rank exceeds kMaxRankFraction·n, or the solution's residual in S is above
// kMaxBackwardError (a nearly singular capacitance matrix).
class ReusedFactorization {
 public:
  // Ranks up to this fraction of S's size are updated (the break-even with a new LU is ~1/6).
  static constexpr double kMaxRankFraction = 1.0 / 12.0;
  // Columns of ΔS below this fraction of ‖S‖_F are rounding (ΔS of unchanged rows is 0).
  static constexpr double kRangeTolerance = 1e-12;
  // A solution is kept when ‖S x − r‖∞ ≤ this × (‖S‖∞‖x‖∞ + ‖r‖∞): a Newton step this
  // accurate converges as one from an exact solve.
  static constexpr double kMaxBackwardError = 1e-10;
  // Random probes per round of the range finder.
  static constexpr int kProbes = 8;

  struct Counts {
    int factorisations = 0;  // LUs of S
    int updates = 0;         // solves through a low-rank update of the kept LU
    int largest_rank = 0;    // of the updates
  };

  explicit ReusedFactorization(EliminationBlocks blocks) : blocks_(std::move(blocks)) {}

  // Solves a x = b; false where the elimination does not apply (a numerically singular block
  // or S: the caller then solves by SolveAugmented). Matrix: Eigen::MatrixXd or BorderedView
  // (the bordered matrix read in place).
  template <typename Matrix>
  bool Solve(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd* x);
  const Counts& counts() const { return counts_; }

 private:
  // Factorises S (with right-hand side `rhs`) as the new base and solves.
  bool Refactor(const Eigen::MatrixXd& schur, const Eigen::VectorXd& rhs,
                Eigen::VectorXd* rest_solution);
  // Solves with S through the base's LU and a low-rank update of S − base; false where the
  // rank is too high or the solution's residual fails (the caller then refactorises).
  bool Update(const Eigen::MatrixXd& schur, const Eigen::VectorXd& rhs,
              Eigen::VectorXd* rest_solution);
  // ΔS ≈ q b with q orthonormal, at most max_rank columns; false if the rank is larger.
  bool LowRank(const Eigen::MatrixXd& delta, int max_rank, Eigen::MatrixXd* q, Eigen::MatrixXd* b);

  EliminationBlocks blocks_;
  std::optional<BlockElimination> elimination_;
  Eigen::MatrixXd base_;    // the S factorised
  double base_norm_ = 0.0;  // its Frobenius norm
  DenseLu base_lu_;
  std::mt19937 random_{20240611u};  // fixed seed: runs repeat bit for bit
  Counts counts_;
};

}  // namespace nfrc
