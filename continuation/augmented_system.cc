#include "continuation/augmented_system.h"

#include <limits>

#include "continuation/block_elimination.h"
#include "continuation/dense_lu.h"

namespace nfrc {
namespace {

// A pivot of the partial-pivoting LU below this fraction of the largest one is at rounding
// level: the rank-revealing full-pivoting LU is used instead. (A pivot ratio costs O(n),
// where Eigen's condition estimate costs about half of the factorisation itself.)
constexpr double kSingularPivotRatio = 1e2 * std::numeric_limits<double>::epsilon();

}  // namespace

Eigen::MatrixXd AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                                double residual_scale, const Eigen::VectorXd& last_row) {
  Eigen::MatrixXd a;
  AugmentedMatrix(linearization, scaling, residual_scale, last_row, &a);
  return a;
}

void AugmentedMatrix(const Linearization& linearization, const Scaling& scaling,
                     double residual_scale, const Eigen::VectorXd& last_row, Eigen::MatrixXd* a) {
  BorderedView(linearization.jacobian_y, linearization.jacobian_lambda, scaling.scales(),
               residual_scale, last_row)
      .Materialize(a);
}

bool SolveRegular(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                  int* determinant_sign) {
  const DenseLu lu(a);
  if (!PivotsAbove(lu, kSingularPivotRatio)) return false;
  *x = lu.Solve(b);
  if (!x->allFinite()) return false;
  if (determinant_sign != nullptr) *determinant_sign = lu.DeterminantSign();
  return true;
}

bool SolveAugmented(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                    const EliminationBlocks* elimination, int* determinant_sign) {
  AugmentedSolver solver;
  const bool solved = solver.Factorize(a, b, x, elimination);
  if (determinant_sign != nullptr) *determinant_sign = solved ? solver.determinant_sign() : 0;
  return solved;
}

bool AugmentedSolver::Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x,
                            const EliminationBlocks* elimination) {
  return Factorize(a_, b, x, elimination);
}

bool AugmentedSolver::Solve(const BorderedView& view, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                            const EliminationBlocks* elimination) {
  kind_ = Kind::kNone;
  sign_ = 0;
  last_row_ = view.last_row();
  if (elimination != nullptr && !elimination->empty() && Eliminate(view, b, x, *elimination)) {
    return true;
  }
  view.Materialize(&a_);
  return FactorizeWhole(a_, b, x);
}

bool AugmentedSolver::Factorize(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                Eigen::VectorXd* x, const EliminationBlocks* elimination) {
  kind_ = Kind::kNone;
  sign_ = 0;
  last_row_ = a.row(a.rows() - 1).transpose();
  if (elimination != nullptr && !elimination->empty() && Eliminate(a, b, x, *elimination)) {
    return true;
  }
  return FactorizeWhole(a, b, x);
}

template <typename Matrix>
bool AugmentedSolver::Eliminate(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd* x,
                                const EliminationBlocks& elimination) {
  // Refactored in place: within one correction the blocks keep their sizes, so the
  // iterations after the first allocate nothing here.
  if (!elimination_) elimination_.emplace();
  if (!elimination_->Refactor(a, elimination)) return false;
  const Eigen::VectorXd block_solutions = elimination_->BlockSolutions(b);
  elimination_->Reduce(a, b, block_solutions, &schur_, &schur_rhs_, &rest_columns_);
  lu_.Compute(schur_);
  if (!RegularForElimination(lu_)) return false;
  elimination_->BackSubstitute(block_solutions, lu_.Solve(schur_rhs_), x);
  if (!x->allFinite()) return false;
  kind_ = Kind::kEliminated;
  sign_ = elimination_->determinant_sign() * lu_.DeterminantSign();
  return true;
}

bool AugmentedSolver::FactorizeWhole(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                     Eigen::VectorXd* x) {
  lu_.Compute(a);
  if (PivotsAbove(lu_, kSingularPivotRatio)) {
    *x = lu_.Solve(b);
    if (x->allFinite()) {
      kind_ = Kind::kRegular;
      sign_ = lu_.DeterminantSign();
      return true;
    }
  }
  full_.compute(a);
  *x = full_.solve(b);
  if (!x->allFinite()) return false;
  kind_ = Kind::kFullPivoting;
  return true;
}

bool AugmentedSolver::SolveAgain(const Eigen::VectorXd& b, Eigen::VectorXd* x) const {
  switch (kind_) {
    case Kind::kNone:
      return false;
    case Kind::kEliminated: {
      const Eigen::VectorXd block_solutions = elimination_->BlockSolutions(b);
      elimination_->BackSubstitute(
          block_solutions, lu_.Solve(elimination_->ReduceRhs(rest_columns_, b, block_solutions)),
          x);
      break;
    }
    case Kind::kRegular:
      *x = lu_.Solve(b);
      break;
    case Kind::kFullPivoting:
      *x = full_.solve(b);
      break;
  }
  return x->allFinite();
}

}  // namespace nfrc
