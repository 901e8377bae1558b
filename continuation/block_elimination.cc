#include "continuation/block_elimination.h"

#include <stdexcept>
#include <string>

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

int DeterminantSign(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  int sign = static_cast<int>(lu.permutationP().determinant());
  const auto pivots = lu.matrixLU().diagonal();
  for (Eigen::Index i = 0; i < pivots.size(); ++i) {
    if (pivots(i) < 0.0) sign = -sign;
  }
  return sign;
}

bool SolveEliminating(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                      const EliminationBlocks& blocks, Eigen::VectorXd* x, int* determinant_sign) {
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
      if (a(row, col) == 0.0) continue;  // most entries of a block's column: tested first
      const int block = block_of[static_cast<size_t>(row)];
      if (block >= 0 && other != block) {
        throw std::logic_error("SolveEliminating: blocks " + std::to_string(block) + " and " +
                               std::to_string(other) + " are coupled");
      }
    }
  }

  const int num_rest = static_cast<int>(rest.size());
  Eigen::MatrixXd schur = a(rest, rest);
  Eigen::VectorXd schur_rhs = b(rest);
  // Per block: the rest positions it couples to (A_B,rest ≠ 0) and A_BB⁻¹ [A_B,coupled  b_B].
  // Small blocks (a harmonic's two coefficients) are many: the loops below avoid Eigen's
  // per-call overhead and allocate only these two per block.
  std::vector<std::vector<int>> coupled_columns(blocks.size());
  std::vector<Eigen::MatrixXd> eliminated(blocks.size());
  Eigen::MatrixXd block_matrix, right;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  int sign = 1;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const std::vector<int>& block = blocks[k];
    const int nb = static_cast<int>(block.size());
    block_matrix.resize(nb, nb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < nb; ++i) block_matrix(i, j) = a(block[i], block[j]);
    }
    lu.compute(block_matrix);
    if (!RegularForElimination(lu)) return false;
    sign *= DeterminantSign(lu);
    std::vector<int>& positions = coupled_columns[k];
    for (int j = 0; j < num_rest; ++j) {
      const int column = rest[static_cast<size_t>(j)];
      for (const int i : block) {
        if (a(i, column) != 0.0) {
          positions.push_back(j);
          break;
        }
      }
    }
    const int nc = static_cast<int>(positions.size());
    right.resize(nb, nc + 1);
    for (int c = 0; c < nc; ++c) {
      for (int i = 0; i < nb; ++i)
        right(i, c) = a(block[i], rest[static_cast<size_t>(positions[c])]);
    }
    for (int i = 0; i < nb; ++i) right(i, nc) = b(block[i]);
    eliminated[k] = lu.solve(right);
    // S −= A_rest,B A_BB⁻¹ A_B,coupled and the right-hand side alike.
    const Eigen::MatrixXd& e = eliminated[k];
    for (int i = 0; i < nb; ++i) {
      for (int r = 0; r < num_rest; ++r) {
        const double left = a(rest[static_cast<size_t>(r)], block[i]);
        if (left == 0.0) continue;
        for (int c = 0; c < nc; ++c) schur(r, positions[c]) -= left * e(i, c);
        schur_rhs(r) -= left * e(i, nc);
      }
    }
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> schur_lu(schur);
  if (!RegularForElimination(schur_lu)) return false;
  sign *= DeterminantSign(schur_lu);
  const Eigen::VectorXd rest_solution = schur_lu.solve(schur_rhs);

  x->resize(size);
  (*x)(rest) = rest_solution;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const Eigen::MatrixXd& e = eliminated[k];
    const std::vector<int>& positions = coupled_columns[k];
    const int nc = static_cast<int>(positions.size());
    for (int i = 0; i < static_cast<int>(blocks[k].size()); ++i) {
      double value = e(i, nc);
      for (int c = 0; c < nc; ++c) value -= e(i, c) * rest_solution(positions[c]);
      (*x)(blocks[k][i]) = value;
    }
  }
  if (!x->allFinite()) return false;
  if (determinant_sign != nullptr) *determinant_sign = sign;
  return true;
}

}  // namespace nfrc
