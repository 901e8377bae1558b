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
  const int n = scaling.num_unknowns();
  const Eigen::VectorXd& scales = scaling.scales();
  a->resize(n + 1, n + 1);
  a->topLeftCorner(n, n).noalias() =
      linearization.jacobian_y * scales.head(n).asDiagonal() / residual_scale;
  a->topRightCorner(n, 1) = linearization.jacobian_lambda * (scales(n) / residual_scale);
  a->bottomRows(1) = last_row.transpose();
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
  if (elimination != nullptr && !elimination->empty() &&
      SolveEliminating(a, b, *elimination, x, determinant_sign)) {
    return true;
  }
  if (SolveRegular(a, b, x, determinant_sign)) return true;
  if (determinant_sign != nullptr) *determinant_sign = 0;
  Eigen::FullPivLU<Eigen::MatrixXd> full(a);
  *x = full.solve(b);
  return x->allFinite();
}

}  // namespace nfrc
