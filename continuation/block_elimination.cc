#include "continuation/block_elimination.h"

#include <stdexcept>
#include <string>

namespace nfrc {

bool RegularForElimination(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
  return PivotsAbove(lu.matrixLU().diagonal(), kMinEliminationPivotRatio);
}

bool RegularForElimination(const DenseLu& lu) { return PivotsAbove(lu, kMinEliminationPivotRatio); }

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

std::optional<BlockElimination> BlockElimination::Factor(const Eigen::MatrixXd& a,
                                                         const EliminationBlocks& blocks) {
  BlockElimination result;
  const int size = static_cast<int>(a.rows());
  result.size_ = size;
  std::vector<int> block_of(static_cast<size_t>(size), -1);
  for (size_t k = 0; k < blocks.size(); ++k) {
    for (const int i : blocks[k]) block_of[static_cast<size_t>(i)] = static_cast<int>(k);
  }
  for (int i = 0; i < size; ++i) {
    if (block_of[static_cast<size_t>(i)] < 0) result.rest_.push_back(i);
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
  const std::vector<int>& rest = result.rest_;
  const int num_rest = static_cast<int>(rest.size());
  result.blocks_.resize(blocks.size());
  // Each block's coupled rest columns, found down the columns (the storage's order; along
  // the blocks' rows it was a strided read per entry), in increasing order.
  std::vector<int> block_rows;
  for (int row = 0; row < size; ++row) {
    if (block_of[static_cast<size_t>(row)] >= 0) block_rows.push_back(row);
  }
  for (int j = 0; j < num_rest; ++j) {
    const int column = rest[static_cast<size_t>(j)];
    for (const int row : block_rows) {
      if (a(row, column) == 0.0) continue;
      std::vector<int>& coupled =
          result.blocks_[static_cast<size_t>(block_of[static_cast<size_t>(row)])].coupled;
      if (coupled.empty() || coupled.back() != j) coupled.push_back(j);
    }
  }
  for (size_t k = 0; k < blocks.size(); ++k) {
    Block& block = result.blocks_[k];
    block.unknowns = blocks[k];
    const int nb = static_cast<int>(block.unknowns.size());
    block.matrix.resize(nb, nb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < nb; ++i) block.matrix(i, j) = a(block.unknowns[i], block.unknowns[j]);
    }
    block.lu.compute(block.matrix);
    if (!RegularForElimination(block.lu)) return std::nullopt;
    result.sign_ *= DeterminantSign(block.lu);
    const int nc = static_cast<int>(block.coupled.size());
    block.coupling.resize(nb, nc);
    for (int c = 0; c < nc; ++c) {
      for (int i = 0; i < nb; ++i) {
        block.coupling(i, c) = a(block.unknowns[i], rest[static_cast<size_t>(block.coupled[c])]);
      }
    }
    // Solved with a last column for b_B, zero here (BlockSolutions solves with it): a
    // solve's rounding depends on the shape of its right-hand side, and this one's keeps
    // the solutions bit for bit those of the joint solve [A_B,coupled b_B] that it replaced.
    Eigen::MatrixXd right = Eigen::MatrixXd::Zero(nb, nc + 1);
    right.leftCols(nc) = block.coupling;
    block.eliminated = block.lu.solve(right).leftCols(nc);
  }
  return result;
}

bool BlockElimination::SameBlockRows(const Eigen::MatrixXd& a) const {
  if (a.rows() != size_) return false;
  const int num_rest = static_cast<int>(rest_.size());
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < nb; ++i) {
        if (a(block.unknowns[i], block.unknowns[j]) != block.matrix(i, j)) return false;
      }
    }
    size_t next = 0;  // the next coupled column
    for (int j = 0; j < num_rest; ++j) {
      const int column = rest_[static_cast<size_t>(j)];
      const bool coupled = next < block.coupled.size() && block.coupled[next] == j;
      for (int i = 0; i < nb; ++i) {
        const double expected = coupled ? block.coupling(i, static_cast<Eigen::Index>(next)) : 0.0;
        if (a(block.unknowns[i], column) != expected) return false;
      }
      if (coupled) ++next;
    }
  }
  return true;
}

Eigen::VectorXd BlockElimination::BlockSolutions(const Eigen::VectorXd& b) const {
  Eigen::VectorXd solutions(size_ - static_cast<int>(rest_.size()));
  Eigen::Index offset = 0;
  Eigen::MatrixXd right;
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    const int nc = static_cast<int>(block.coupled.size());
    right.setZero(nb, nc + 1);  // the shape of Factor's solve (see there)
    for (int i = 0; i < nb; ++i) right(i, nc) = b(block.unknowns[i]);
    solutions.segment(offset, nb) = block.lu.solve(right).col(nc);
    offset += nb;
  }
  return solutions;
}

void BlockElimination::Reduce(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                              const Eigen::VectorXd& block_solutions, Eigen::MatrixXd* schur,
                              Eigen::VectorXd* schur_rhs) const {
  const int num_rest = static_cast<int>(rest_.size());
  *schur = a(rest_, rest_);
  *schur_rhs = b(rest_);
  Eigen::Index offset = 0;
  // S −= A_rest,B A_BB⁻¹ A_B,coupled and the right-hand side alike. Small blocks (a
  // harmonic's two coefficients) are many: plain loops avoid Eigen's per-call overhead.
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    const int nc = static_cast<int>(block.coupled.size());
    for (int i = 0; i < nb; ++i) {
      const int unknown = block.unknowns[static_cast<size_t>(i)];
      const double solution = block_solutions(offset + i);
      for (int r = 0; r < num_rest; ++r) {
        const double left = a(rest_[static_cast<size_t>(r)], unknown);
        if (left == 0.0) continue;
        for (int c = 0; c < nc; ++c) (*schur)(r, block.coupled[c]) -= left * block.eliminated(i, c);
        (*schur_rhs)(r) -= left * solution;
      }
    }
    offset += nb;
  }
}

void BlockElimination::BackSubstitute(const Eigen::VectorXd& block_solutions,
                                      const Eigen::VectorXd& rest_solution,
                                      Eigen::VectorXd* x) const {
  x->resize(size_);
  (*x)(rest_) = rest_solution;
  Eigen::Index offset = 0;
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    const int nc = static_cast<int>(block.coupled.size());
    for (int i = 0; i < nb; ++i) {
      double value = block_solutions(offset + i);
      for (int c = 0; c < nc; ++c)
        value -= block.eliminated(i, c) * rest_solution(block.coupled[c]);
      (*x)(block.unknowns[static_cast<size_t>(i)]) = value;
    }
    offset += nb;
  }
}

bool SolveEliminating(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                      const EliminationBlocks& blocks, Eigen::VectorXd* x, int* determinant_sign) {
  const std::optional<BlockElimination> elimination = BlockElimination::Factor(a, blocks);
  if (!elimination) return false;
  Eigen::MatrixXd schur;
  Eigen::VectorXd schur_rhs;
  const Eigen::VectorXd block_solutions = elimination->BlockSolutions(b);
  elimination->Reduce(a, b, block_solutions, &schur, &schur_rhs);
  const DenseLu schur_lu(schur);
  if (!RegularForElimination(schur_lu)) return false;
  elimination->BackSubstitute(block_solutions, schur_lu.Solve(schur_rhs), x);
  if (!x->allFinite()) return false;
  if (determinant_sign != nullptr) {
    *determinant_sign = elimination->determinant_sign() * schur_lu.DeterminantSign();
  }
  return true;
}

}  // namespace nfrc
