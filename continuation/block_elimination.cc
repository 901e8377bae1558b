#include "continuation/block_elimination.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace nfrc {

bool RegularForElimination(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  const Eigen::VectorXd pivots = lu.matrixLU().diagonal().cwiseAbs();
  return pivots.size() == 0 || pivots.minCoeff() > kMinEliminationPivotRatio * pivots.maxCoeff();
}

void ValidateEliminationBlocks(const EliminationBlocks& blocks, int n) {
  std::vector<bool> seen(static_cast<size_t>(n), false);
  for (const std::vector<int>& block : blocks) {
    for (const int i : block) {
      if (i < 0 || i >= n || seen[static_cast<size_t>(i)]) {
        throw std::invalid_argument("EliminationBlocks: index " + std::to_string(i) +
                                    " outside [0, " + std::to_string(n) + ") or repeated");
      }
      seen[static_cast<size_t>(i)] = true;
    }
  }
}

bool SolveEliminating(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                      const EliminationBlocks& blocks, Eigen::VectorXd* x) {
  const int size = static_cast<int>(a.rows());
  std::vector<int> block_of(static_cast<size_t>(size), -1);
  for (size_t k = 0; k < blocks.size(); ++k) {
    for (const int i : blocks[k]) block_of[static_cast<size_t>(i)] = static_cast<int>(k);
  }
  std::vector<int> rest;  // the unknowns kept, ascending: the Schur complement's order
  for (int i = 0; i < size; ++i) {
    if (block_of[static_cast<size_t>(i)] < 0) rest.push_back(i);
  }
  for (int col = 0; col < size; ++col) {  // column-major: down each column
    const int other = block_of[static_cast<size_t>(col)];
    if (other < 0) continue;
    for (int row = 0; row < size; ++row) {
      const int block = block_of[static_cast<size_t>(row)];
      if (block >= 0 && other != block && a(row, col) != 0.0) {
        throw std::logic_error("SolveEliminating: blocks " + std::to_string(block) + " and " +
                               std::to_string(other) + " are coupled");
      }
    }
  }

  const int num_rest = static_cast<int>(rest.size());
  Eigen::MatrixXd schur = a(rest, rest);
  Eigen::VectorXd schur_rhs = b(rest);
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXd>> factors;
  std::vector<Eigen::VectorXd> block_solutions;       // A_BB⁻¹ b_B
  std::vector<std::vector<int>> coupled_columns;      // rest positions with A_B,rest ≠ 0
  std::vector<Eigen::MatrixXd> block_times_coupling;  // A_BB⁻¹ A_B,coupled
  factors.reserve(blocks.size());
  for (const std::vector<int>& block : blocks) {
    factors.emplace_back(Eigen::MatrixXd(a(block, block)));
    if (!RegularForElimination(factors.back())) return false;
    std::vector<int> columns, positions;
    for (int j = 0; j < num_rest; ++j) {
      bool nonzero = false;
      for (const int i : block) nonzero = nonzero || a(i, rest[static_cast<size_t>(j)]) != 0.0;
      if (nonzero) {
        columns.push_back(rest[static_cast<size_t>(j)]);
        positions.push_back(j);
      }
    }
    Eigen::MatrixXd coupling = factors.back().solve(Eigen::MatrixXd(a(block, columns)));
    Eigen::VectorXd solution = factors.back().solve(Eigen::VectorXd(b(block)));
    // S −= A_rest,B A_BB⁻¹ A_B,rest and the right-hand side alike.
    const Eigen::MatrixXd left = a(rest, block);
    schur(Eigen::all, positions) -= left * coupling;
    schur_rhs -= left * solution;
    block_solutions.push_back(std::move(solution));
    coupled_columns.push_back(std::move(positions));
    block_times_coupling.push_back(std::move(coupling));
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> schur_lu(schur);
  if (!RegularForElimination(schur_lu)) return false;
  const Eigen::VectorXd rest_solution = schur_lu.solve(schur_rhs);

  x->resize(size);
  (*x)(rest) = rest_solution;
  for (size_t k = 0; k < blocks.size(); ++k) {
    (*x)(blocks[k]) =
        block_solutions[k] - block_times_coupling[k] * rest_solution(coupled_columns[k]);
  }
  return x->allFinite();
}

}  // namespace nfrc
