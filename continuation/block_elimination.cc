#include "continuation/block_elimination.h"

#include <algorithm>
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

namespace {

// Rows read at once where the blocks' rows are one run: most chunks of a block's column are
// zero, and a chunk's sum of magnitudes (zero exactly when every entry is; NaN when one is)
// tests them in vector instructions instead of one branch per entry.
constexpr int kScanChunk = 16;

// Rows [start, start + length) of column j of a, into `out` (size length).
void ReadColumn(const Eigen::MatrixXd& a, Eigen::Index j, Eigen::Index start, Eigen::Index length,
                Eigen::Ref<Eigen::VectorXd> out) {
  out = a.col(j).segment(start, length);
}
void ReadColumn(const BorderedView& a, Eigen::Index j, Eigen::Index start, Eigen::Index length,
                Eigen::Ref<Eigen::VectorXd> out) {
  a.ReadColumn(j, start, length, out);
}

// Column j's storage from row 0, where its zeros are read (the blocks' rows are above a
// bordered matrix's last row).
const double* ZeroPatternColumn(const Eigen::MatrixXd& a, Eigen::Index j) {
  return a.col(j).data();
}
const double* ZeroPatternColumn(const BorderedView& a, Eigen::Index j) {
  return a.UnscaledColumn(j);
}

// Calls visit(row) for each of block_rows (ascending) whose entry in `column` is not zero
// (NaN included), in increasing order.
template <typename Matrix, typename Visit>
void ForEachNonzeroBlockRow(const Matrix& a, int column, const std::vector<int>& block_rows,
                            Visit visit) {
  const int count = static_cast<int>(block_rows.size());
  if (count == 0) return;
  const int first = block_rows.front();
  const double* entries = ZeroPatternColumn(a, column);
  if (block_rows.back() - first + 1 != count) {
    for (const int row : block_rows) {
      if (entries[row] != 0.0) visit(row);
    }
    return;
  }
  for (int start = 0; start < count; start += kScanChunk) {
    const int length = std::min(kScanChunk, count - start);
    const Eigen::Map<const Eigen::VectorXd> chunk(entries + first + start, length);
    if (chunk.cwiseAbs().sum() == 0.0) continue;
    for (int k = 0; k < length; ++k) {
      if (chunk(k) != 0.0) visit(first + start + k);
    }
  }
}

}  // namespace

template <typename Matrix>
std::optional<BlockElimination> BlockElimination::Factor(const Matrix& a,
                                                         const EliminationBlocks& blocks) {
  BlockElimination result;
  if (!result.Refactor(a, blocks)) return std::nullopt;
  return result;
}

template <typename Matrix>
bool BlockElimination::Refactor(const Matrix& a, const EliminationBlocks& blocks) {
  const int size = static_cast<int>(a.rows());
  size_ = size;
  sign_ = 1;
  block_of_.assign(static_cast<size_t>(size), -1);
  for (size_t k = 0; k < blocks.size(); ++k) {
    for (const int i : blocks[k]) block_of_[static_cast<size_t>(i)] = static_cast<int>(k);
  }
  rest_.clear();
  block_rows_.clear();
  for (int i = 0; i < size; ++i) {
    (block_of_[static_cast<size_t>(i)] < 0 ? rest_ : block_rows_).push_back(i);
  }
  // Down each block's column (the storage's order), in the blocks' rows only: the rest's
  // rows of a block column (A_rest,B) may hold anything.
  for (int col = 0; col < size; ++col) {
    const int other = block_of_[static_cast<size_t>(col)];
    if (other < 0) continue;
    ForEachNonzeroBlockRow(a, col, block_rows_, [&](int row) {
      const int block = block_of_[static_cast<size_t>(row)];
      if (other != block) {
        throw std::logic_error("SolveEliminating: blocks " + std::to_string(block) + " and " +
                               std::to_string(other) + " are coupled");
      }
    });
  }
  const int num_rest = static_cast<int>(rest_.size());
  rest_run_ = num_rest > 0 && rest_.back() - rest_.front() + 1 == num_rest;
  blocks_.resize(blocks.size());
  for (Block& block : blocks_) block.coupled.clear();
  // Each block's coupled rest columns, found down the columns (the storage's order; along
  // the blocks' rows it was a strided read per entry), in increasing order.
  for (int j = 0; j < num_rest; ++j) {
    ForEachNonzeroBlockRow(a, rest_[static_cast<size_t>(j)], block_rows_, [&](int row) {
      std::vector<int>& coupled =
          blocks_[static_cast<size_t>(block_of_[static_cast<size_t>(row)])].coupled;
      if (coupled.empty() || coupled.back() != j) coupled.push_back(j);
    });
  }
  for (size_t k = 0; k < blocks.size(); ++k) {
    Block& block = blocks_[k];
    block.unknowns = blocks[k];
    const int nb = static_cast<int>(block.unknowns.size());
    block.matrix.resize(nb, nb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < nb; ++i) block.matrix(i, j) = a(block.unknowns[i], block.unknowns[j]);
    }
    block.lu.compute(block.matrix);
    if (!RegularForElimination(block.lu)) {
      size_ = 0;  // matches no matrix (SameBlockRows) until a Refactor succeeds
      return false;
    }
    sign_ *= DeterminantSign(block.lu);
    const int nc = static_cast<int>(block.coupled.size());
    block.coupling.resize(nb, nc);
    for (int c = 0; c < nc; ++c) {
      for (int i = 0; i < nb; ++i) {
        block.coupling(i, c) = a(block.unknowns[i], rest_[static_cast<size_t>(block.coupled[c])]);
      }
    }
    // Solved with a last column for b_B, zero here (BlockSolutions solves with it): a
    // solve's rounding depends on the shape of its right-hand side, and this one's keeps
    // the solutions bit for bit those of the joint solve [A_B,coupled b_B] that it replaced.
    right_.setZero(nb, nc + 1);
    right_.leftCols(nc) = block.coupling;
    solved_ = block.lu.solve(right_);  // into the kept storage: no temporary per block
    block.eliminated = solved_.leftCols(nc);
  }
  return true;
}

template <typename Matrix>
bool BlockElimination::SameBlockRows(const Matrix& a) const {
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

template <typename Matrix>
void BlockElimination::Reduce(const Matrix& a, const Eigen::VectorXd& b,
                              const Eigen::VectorXd& block_solutions, Eigen::MatrixXd* schur,
                              Eigen::VectorXd* schur_rhs, Eigen::MatrixXd* rest_columns) const {
  const int num_rest = static_cast<int>(rest_.size());
  schur->resize(num_rest, num_rest);
  for (int j = 0; j < num_rest; ++j) RestColumn(a, rest_[static_cast<size_t>(j)], schur->col(j));
  *schur_rhs = b(rest_);
  Eigen::MatrixXd own_columns;
  Eigen::MatrixXd& columns = rest_columns != nullptr ? *rest_columns : own_columns;
  columns.resize(num_rest, size_ - num_rest);
  Eigen::Index offset = 0;
  // S −= A_rest,B A_BB⁻¹ A_B,coupled and the right-hand side alike, one column of A_rest,B
  // at a time: an update of the few coupled columns of S.
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    const int nc = static_cast<int>(block.coupled.size());
    for (int i = 0; i < nb; ++i) {
      auto left = columns.col(offset + i);
      RestColumn(a, block.unknowns[static_cast<size_t>(i)], left);
      for (int c = 0; c < nc; ++c) schur->col(block.coupled[c]) -= block.eliminated(i, c) * left;
      *schur_rhs -= block_solutions(offset + i) * left;
    }
    offset += nb;
  }
}

Eigen::VectorXd BlockElimination::ReduceRhs(const Eigen::MatrixXd& rest_columns,
                                            const Eigen::VectorXd& b,
                                            const Eigen::VectorXd& block_solutions) const {
  Eigen::VectorXd rhs = b(rest_);
  for (Eigen::Index k = 0; k < rest_columns.cols(); ++k) {
    rhs -= block_solutions(k) * rest_columns.col(k);
  }
  return rhs;
}

template <typename Matrix>
void BlockElimination::RestColumn(const Matrix& a, int unknown,
                                  Eigen::Ref<Eigen::VectorXd> column) const {
  const Eigen::Index num_rest = static_cast<Eigen::Index>(rest_.size());
  if (rest_run_) {
    ReadColumn(a, unknown, rest_.front(), num_rest, column);
  } else {
    for (Eigen::Index k = 0; k < num_rest; ++k)
      column(k) = a(rest_[static_cast<size_t>(k)], unknown);
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

template std::optional<BlockElimination> BlockElimination::Factor(const Eigen::MatrixXd&,
                                                                  const EliminationBlocks&);
template std::optional<BlockElimination> BlockElimination::Factor(const BorderedView&,
                                                                  const EliminationBlocks&);
template bool BlockElimination::Refactor(const Eigen::MatrixXd&, const EliminationBlocks&);
template bool BlockElimination::Refactor(const BorderedView&, const EliminationBlocks&);
template void BlockElimination::Reduce(const Eigen::MatrixXd&, const Eigen::VectorXd&,
                                       const Eigen::VectorXd&, Eigen::MatrixXd*, Eigen::VectorXd*,
                                       Eigen::MatrixXd*) const;
template void BlockElimination::Reduce(const BorderedView&, const Eigen::VectorXd&,
                                       const Eigen::VectorXd&, Eigen::MatrixXd*, Eigen::VectorXd*,
                                       Eigen::MatrixXd*) const;
template bool BlockElimination::SameBlockRows(const Eigen::MatrixXd&) const;
template bool BlockElimination::SameBlockRows(const BorderedView&) const;

}  // namespace nfrc
