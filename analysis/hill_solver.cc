#include "analysis/hill_solver.h"

#include <algorithm>
#include <cassert>
#include <map>
#include <memory>
#include <numeric>
#include <span>

#include "continuation/block_elimination.h"

namespace nfrc {
namespace {

// The representative of i's set (union-find, with path halving).
int Root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

// y ← (LU)⁻¹ y for the factors of a small block (unit L below the diagonal, U on and above),
// column by column: Eigen's general triangular solves cost more than the arithmetic on 4 × 4
// blocks, and these column updates still vectorise on the larger ones (40 × 40 on the rod).
void SolveWithFactors(const Eigen::MatrixXd& lu, double* y) {
  const Eigen::Index n = lu.rows();
  for (Eigen::Index j = 0; j + 1 < n; ++j) {
    Eigen::Map<Eigen::VectorXd>(y + j + 1, n - j - 1) -= y[j] * lu.col(j).tail(n - j - 1);
  }
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    y[j] /= lu(j, j);
    if (j > 0) Eigen::Map<Eigen::VectorXd>(y, j) -= y[j] * lu.col(j).head(j);
  }
}

}  // namespace

HillLinearSolver::HillLinearSolver(const Eigen::SparseMatrix<double>& matrix, int own_offset,
                                   const std::vector<int>& harmonics)
    : size_(static_cast<int>(matrix.rows())), own_offset_(own_offset) {
  ChooseSchur(matrix, harmonics);
  eliminating_ = schur_size() <= kMaxSchur && Eliminate(matrix);
  if (eliminating_) {
    ok_ = true;
    return;
  }
  blocks_.clear();
  sparse_lu_.analyzePattern(matrix);
  sparse_lu_.factorize(matrix);
  ok_ = sparse_lu_.info() == Eigen::Success;
}

void HillLinearSolver::ChooseSchur(const Eigen::SparseMatrix<double>& matrix,
                                   const std::vector<int>& harmonics) {
  using Iterator = Eigen::SparseMatrix<double>::InnerIterator;
  std::vector<bool> in_schur(static_cast<size_t>(size_), false);
  for (int i = own_offset_; i < size_; ++i) in_schur[static_cast<size_t>(i)] = true;
  if (!harmonics.empty()) {
    assert(static_cast<int>(harmonics.size()) == own_offset_);
    // Marking the rows is enough: what is left couples only unknowns of one harmonic.
    std::vector<bool> coupled(static_cast<size_t>(own_offset_), false);
    int num_coupled = 0;
    for (int j = 0; j < own_offset_; ++j) {
      for (Iterator it(matrix, j); it; ++it) {
        const int i = static_cast<int>(it.row());
        if (i < own_offset_ && it.value() != 0.0 && !coupled[static_cast<size_t>(i)] &&
            harmonics[static_cast<size_t>(i)] != harmonics[static_cast<size_t>(j)]) {
          coupled[static_cast<size_t>(i)] = true;
          ++num_coupled;
        }
      }
    }
    if (num_coupled <= kMaxCoupledRows) {
      for (int i = 0; i < own_offset_; ++i) {
        if (coupled[static_cast<size_t>(i)]) in_schur[static_cast<size_t>(i)] = true;
      }
    }
  }
  schur_position_.assign(static_cast<size_t>(size_), -1);
  for (int i = 0; i < size_; ++i) {
    if (!in_schur[static_cast<size_t>(i)]) continue;
    schur_position_[static_cast<size_t>(i)] = static_cast<int>(schur_unknowns_.size());
    schur_unknowns_.push_back(i);
  }
}

bool HillLinearSolver::Eliminate(const Eigen::SparseMatrix<double>& matrix) {
  using Iterator = Eigen::SparseMatrix<double>::InnerIterator;
  const int nr = schur_size();
  const auto in_schur = [&](int i) { return schur_position_[static_cast<size_t>(i)] >= 0; };
  // The other unknowns' blocks: connected components of H's pattern among them.
  std::vector<int> parent(static_cast<size_t>(size_));
  std::iota(parent.begin(), parent.end(), 0);
  for (int j = 0; j < size_; ++j) {
    if (in_schur(j)) continue;
    for (Iterator it(matrix, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      if (!in_schur(i) && it.value() != 0.0)
        parent[static_cast<size_t>(Root(parent, i))] = Root(parent, j);
    }
  }
  std::vector<int> block_of(static_cast<size_t>(size_), -1), position(static_cast<size_t>(size_));
  for (int i = 0; i < size_; ++i) {
    if (in_schur(i)) continue;
    const int root = Root(parent, i);
    if (block_of[static_cast<size_t>(root)] < 0) {
      block_of[static_cast<size_t>(root)] = static_cast<int>(blocks_.size());
      blocks_.emplace_back();
    }
    Block& block = blocks_[static_cast<size_t>(block_of[static_cast<size_t>(root)])];
    block_of[static_cast<size_t>(i)] = block_of[static_cast<size_t>(root)];
    position[static_cast<size_t>(i)] = static_cast<int>(block.unknowns.size());
    block.unknowns.push_back(i);
    if (static_cast<int>(block.unknowns.size()) > kMaxBlock) return false;
  }

  // One pass down the columns: each block's own matrix, its couplings with the Schur
  // unknowns (kept as entries until the block knows which rows and columns it touches) and
  // the Schur unknowns' own block, where the Schur complement starts.
  struct Coupling {
    int position;  // in the block
    int own;       // position in the Schur complement
    double value;
  };
  std::vector<Eigen::MatrixXd> block_matrices(blocks_.size());
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const int nb = static_cast<int>(blocks_[k].unknowns.size());
    block_matrices[k] = Eigen::MatrixXd::Zero(nb, nb);
  }
  // A block's couplings from the Schur rows, side by side in one array: each block has its
  // columns' lengths reserved (an upper bound), filled from from_start[k] to from_end[k].
  const auto column_length = [&](int j) {
    return matrix.isCompressed() ? matrix.outerIndexPtr()[j + 1] - matrix.outerIndexPtr()[j]
                                 : matrix.innerNonZeroPtr()[j];
  };
  std::vector<int> from_start(blocks_.size() + 1, 0);
  for (int j = 0; j < size_; ++j) {
    if (!in_schur(j))
      from_start[static_cast<size_t>(block_of[static_cast<size_t>(j)]) + 1] += column_length(j);
  }
  std::partial_sum(from_start.begin(), from_start.end(), from_start.begin());
  std::vector<int> from_end(from_start.begin(), from_start.end() - 1);
  const auto from_own =
      std::make_unique_for_overwrite<Coupling[]>(static_cast<size_t>(from_start.back()));
  std::vector<std::vector<Coupling>> to_own(blocks_.size());
  Eigen::MatrixXd schur = Eigen::MatrixXd::Zero(nr, nr);
  for (int j = 0; j < size_; ++j) {
    const int schur_j = schur_position_[static_cast<size_t>(j)];
    for (Iterator it(matrix, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      const int schur_i = schur_position_[static_cast<size_t>(i)];
      if (schur_j < 0) {
        const int k = block_of[static_cast<size_t>(j)];
        if (schur_i >= 0) {
          from_own[static_cast<size_t>(from_end[static_cast<size_t>(k)]++)] = {
              position[static_cast<size_t>(j)], schur_i, it.value()};
        } else if (block_of[static_cast<size_t>(i)] == k) {
          // A stored zero may sit between two blocks: only this block's own entries count.
          block_matrices[static_cast<size_t>(k)](position[static_cast<size_t>(i)],
                                                 position[static_cast<size_t>(j)]) = it.value();
        }
      } else if (schur_i < 0) {
        to_own[static_cast<size_t>(block_of[static_cast<size_t>(i)])].push_back(
            {position[static_cast<size_t>(i)], schur_j, it.value()});
      } else {
        schur(schur_i, schur_j) = it.value();
      }
    }
  }
  const auto from_own_of = [&](size_t k) {
    return std::span<const Coupling>(from_own.get() + from_start[k],
                                     static_cast<size_t>(from_end[k] - from_start[k]));
  };

  std::vector<int> slot(static_cast<size_t>(nr), -1);  // an own unknown's place in a block's list
  const auto release = [&](const std::vector<int>& owns) {
    for (const int own : owns) slot[static_cast<size_t>(own)] = -1;
  };
  std::map<std::vector<int>, int> group_of;  // own rows → group
  // Whether a block's position reaches an own row; cleared after each block.
  std::vector<char> reaches(static_cast<size_t>(kMaxBlock), 0);
  std::vector<int> own_rows;  // a block's, before it finds its group
  // The previous block's group: friction's blocks all share one, and one equality test of
  // their rows is cheaper than the map's two lexicographic comparisons (2–3 % of a Hill point
  // at N_φ = 160, nfrc_bench 8).
  int last_group = -1;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    const int nb = static_cast<int>(block.unknowns.size());
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(block_matrices[k]);
    if (!RegularForElimination(lu)) return false;
    block.lu = lu.matrixLU();
    block.gather.resize(static_cast<size_t>(nb));
    for (int i = 0; i < nb; ++i) {
      block.gather[static_cast<size_t>(lu.permutationP().indices()(i))] =
          block.unknowns[static_cast<size_t>(i)];
    }
    for (const Coupling& e : to_own[k]) {
      if (slot[static_cast<size_t>(e.own)] < 0) {
        slot[static_cast<size_t>(e.own)] = static_cast<int>(block.own_columns.size());
        block.own_columns.push_back(e.own);
      }
    }
    const int nc = static_cast<int>(block.own_columns.size());
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(nb, nc);
    for (const Coupling& e : to_own[k]) {
      coupling(e.position, slot[static_cast<size_t>(e.own)]) = e.value;
    }
    release(block.own_columns);
    // Zero-sized products are skipped: Eigen's kernels would bind references to null data.
    block.eliminated = nc > 0 ? Eigen::MatrixXd(lu.solve(coupling)) : coupling;
    block.solution.resize(nb);
    const std::span<const Coupling> from = from_own_of(k);
    if (from.empty()) continue;
    // One pass: the distinct own rows, and the positions that reach them, in order of
    // appearance.
    own_rows.clear();
    for (const Coupling& e : from) {
      if (slot[static_cast<size_t>(e.own)] < 0) {
        slot[static_cast<size_t>(e.own)] = 0;
        own_rows.push_back(e.own);
      }
      if (!reaches[static_cast<size_t>(e.position)]) {
        reaches[static_cast<size_t>(e.position)] = 1;
        block.row_positions.push_back(e.position);
      }
    }
    release(own_rows);
    for (const int position : block.row_positions) reaches[static_cast<size_t>(position)] = 0;
    if (!std::is_sorted(own_rows.begin(), own_rows.end()))
      std::sort(own_rows.begin(), own_rows.end());
    if (last_group >= 0 && groups_[static_cast<size_t>(last_group)].own_rows == own_rows) {
      block.group = last_group;
    } else {
      const auto [entry, added] = group_of.try_emplace(own_rows, static_cast<int>(groups_.size()));
      if (added) groups_.push_back(RowGroup{own_rows, {}, 0, {}, {}});
      block.group = entry->second;
    }
    last_group = block.group;
    RowGroup& group = groups_[static_cast<size_t>(block.group)];
    block.reach_offset = group.width;
    group.width += static_cast<int>(block.row_positions.size());
  }
  for (RowGroup& group : groups_) {
    group.rows =
        Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(group.own_rows.size()), group.width);
    group.reaching.resize(group.width);
    group.row_work.resize(static_cast<Eigen::Index>(group.own_rows.size()));
  }
  std::vector<int> column_of(static_cast<size_t>(kMaxBlock), -1);  // a position's reaching column
  Eigen::MatrixXd update;  // a block's H(own_rows, B) H(B, B)⁻¹ H(B, own_columns)
  int slotted_group = -1;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    if (block.group < 0) continue;
    RowGroup& group = groups_[static_cast<size_t>(block.group)];
    const int nreach = static_cast<int>(block.row_positions.size());
    for (int c = 0; c < nreach; ++c) {
      column_of[static_cast<size_t>(block.row_positions[static_cast<size_t>(c)])] =
          block.reach_offset + c;
    }
    // The slots hold the group's row places for as long as consecutive blocks share it.
    if (block.group != slotted_group) {
      if (slotted_group >= 0) release(groups_[static_cast<size_t>(slotted_group)].own_rows);
      for (size_t r = 0; r < group.own_rows.size(); ++r) {
        slot[static_cast<size_t>(group.own_rows[r])] = static_cast<int>(r);
      }
      slotted_group = block.group;
    }
    for (const Coupling& e : from_own_of(k)) {
      group.rows(slot[static_cast<size_t>(e.own)], column_of[static_cast<size_t>(e.position)]) =
          e.value;
    }
    // S −= H(own_rows, B) H(B, B)⁻¹ H(B, own_columns).
    if (!block.own_columns.empty()) {
      update.noalias() = group.rows.middleCols(block.reach_offset, nreach) *
                         block.eliminated(block.row_positions, Eigen::all);
      schur(group.own_rows, block.own_columns) -= update;
    }
  }
  if (nr > 0) schur_lu_.Compute(schur);
  schur_rhs_.resize(nr);
  own_solution_.resize(nr);
  return nr == 0 || RegularForElimination(schur_lu_);
}

void HillLinearSolver::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const {
  if (!eliminating_) {
    *x = sparse_lu_.solve(rhs);
    return;
  }
  x->resize(size_);
  schur_rhs_ = rhs(schur_unknowns_);
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    double* y = block.solution.data();
    for (int i = 0; i < nb; ++i) y[i] = rhs(block.gather[static_cast<size_t>(i)]);
    SolveWithFactors(block.lu, y);
    if (block.group < 0) continue;
    double* reaching =
        groups_[static_cast<size_t>(block.group)].reaching.data() + block.reach_offset;
    for (size_t c = 0; c < block.row_positions.size(); ++c) reaching[c] = y[block.row_positions[c]];
  }
  for (const RowGroup& group : groups_) {
    group.row_work.noalias() = group.rows * group.reaching;
    for (size_t r = 0; r < group.own_rows.size(); ++r) {
      schur_rhs_(group.own_rows[r]) -= group.row_work(static_cast<Eigen::Index>(r));
    }
  }
  if (!schur_unknowns_.empty()) schur_lu_.Solve(schur_rhs_, &own_solution_);
  (*x)(schur_unknowns_) = own_solution_;
  for (const Block& block : blocks_) {
    const int nb = static_cast<int>(block.unknowns.size());
    double* y = block.solution.data();
    for (size_t c = 0; c < block.own_columns.size(); ++c) {
      const double own = own_solution_(block.own_columns[c]);
      const double* column = block.eliminated.data() + static_cast<Eigen::Index>(c) * nb;
      for (int i = 0; i < nb; ++i) y[i] -= column[i] * own;
    }
    for (int i = 0; i < nb; ++i) (*x)(block.unknowns[static_cast<size_t>(i)]) = y[i];
  }
}

}  // namespace nfrc
