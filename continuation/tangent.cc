#include "continuation/tangent.h"

#include <cassert>
#include <cmath>
#include <limits>

#include "continuation/augmented_system.h"
#include "continuation/block_elimination.h"
#include "continuation/dense_lu.h"

namespace nfrc {
namespace {

// ‖J t‖ relative to ‖J‖_F‖t‖ for a null vector t: a backward-stable LU leaves ~1e-14; a
// bordered system that is singular in R_y (a start at a fold) leaves O(1).
constexpr double kNullResidual = 1e-8;
// The tangent from a factorisation of the bordered matrix one Newton update away is refined
// against the point's own at most this many times, and accepted once a correction is below
// kRefinedTangent of the solution (the tangent of the point's Jacobian to ~1e-10; within one
// update of quadratic Newton one refinement usually gets there, across a kink it does not).
constexpr int kMaxTangentRefinements = 2;
constexpr double kRefinedTangent = 1e-10;
// A pivot this far below the largest leaves the sign of a determinant to rounding.
constexpr double kSingularPivotRatio = 1e2 * std::numeric_limits<double>::epsilon();

}  // namespace

bool InitialTangent(const Linearization& linearization, const Scaling& scaling,
                    double residual_scale, double lambda_direction, Eigen::VectorXd* tangent_scaled,
                    int* orientation) {
  const int n = scaling.num_unknowns();
  const Eigen::MatrixXd bordered =
      AugmentedMatrix(linearization, scaling, residual_scale, Eigen::VectorXd::Unit(n + 1, n));
  // Away from a fold the border Δλ = 1 gives the tangent by one (eliminating) LU; the QR
  // below costs several LUs and forming Q.
  Eigen::VectorXd solution;
  int sign = 0;
  if (SolveAugmented(bordered, Eigen::VectorXd::Unit(n + 1, n), &solution,
                     linearization.elimination.get(), &sign)) {
    const double scale = bordered.topRows(n).norm() * solution.norm();
    if (scale > 0.0 && (bordered.topRows(n) * solution).norm() <= kNullResidual * scale) {
      const double direction = lambda_direction < 0.0 ? -1.0 : 1.0;
      *tangent_scaled = solution.normalized() * direction;
      if (tangent_scaled->allFinite()) {
        // The border eₙ replaced by τ = ±s/‖s‖ (NextTangent): det scales by ±‖s‖.
        if (orientation != nullptr) *orientation = direction < 0.0 ? -sign : sign;
        return true;
      }
    }
  }
  if (orientation != nullptr) *orientation = 0;
  // The last column of Q in Jᵀ = QR is orthogonal to the row space of J.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(bordered.topRows(n).transpose());
  if (qr.rank() != n) return false;
  *tangent_scaled = (qr.householderQ() * Eigen::VectorXd::Unit(n + 1, n)).normalized();
  if ((*tangent_scaled)(n)*lambda_direction < 0.0) *tangent_scaled = -*tangent_scaled;
  return tangent_scaled->allFinite();
}

namespace {

// The tangent from the bordered system's solution s for [0; 1]: s/‖s‖, refused where it does
// not keep the orientation (a full-pivoting fallback on a singular border may lose it).
bool TangentFromSolution(const Eigen::VectorXd& solution, const Eigen::VectorXd& previous_scaled,
                         Eigen::VectorXd* tangent_scaled) {
  const double norm = solution.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  *tangent_scaled = solution / norm;
  return tangent_scaled->dot(previous_scaled) > 0.0;
}

}  // namespace

bool NextTangent(const Linearization& linearization, const Scaling& scaling, double residual_scale,
                 const Eigen::VectorXd& previous_scaled, Eigen::VectorXd* tangent_scaled,
                 int* orientation) {
  const int n = scaling.num_unknowns();
  Eigen::VectorXd solution;
  int sign = 0;
  if (!SolveAugmented(AugmentedMatrix(linearization, scaling, residual_scale, previous_scaled),
                      Eigen::VectorXd::Unit(n + 1, n), &solution, linearization.elimination.get(),
                      &sign)) {
    return false;
  }
  if (orientation != nullptr) *orientation = sign;
  return TangentFromSolution(solution, previous_scaled, tangent_scaled);
}

bool NextTangent(const AugmentedSolver& last_step, const Linearization& linearization,
                 const Scaling& scaling, double residual_scale,
                 const Eigen::VectorXd& previous_scaled, Eigen::VectorXd* tangent_scaled,
                 int* orientation) {
  const int n = scaling.num_unknowns();
  assert(last_step.last_row().size() == n + 1 && last_step.last_row() == previous_scaled);
  const Eigen::VectorXd& scales = scaling.scales();
  const Eigen::VectorXd unit = Eigen::VectorXd::Unit(n + 1, n);
  Eigen::VectorXd solution, correction, residual(n + 1);
  if (!last_step.SolveAgain(unit, &solution)) return false;
  // Refined against the point's own bordered matrix A, whose last row is the factorised one's:
  // s ← s + A₀⁻¹ (e − A s), converging by the factor ‖A₀⁻¹ (A − A₀)‖ (the Jacobians' change
  // over one Newton update) a step; until the correction is at rounding level or refused.
  for (int refinement = 0; refinement < kMaxTangentRefinements; ++refinement) {
    residual.head(n).noalias() =
        linearization.jacobian_y * solution.head(n).cwiseProduct(scales.head(n));
    residual.head(n) += linearization.jacobian_lambda * (scales(n) * solution(n));
    residual.head(n) /= -residual_scale;
    residual(n) = 1.0 - previous_scaled.dot(solution);
    if (!last_step.SolveAgain(residual, &correction)) return false;
    solution += correction;
    if (correction.norm() <= kRefinedTangent * solution.norm()) {
      if (orientation != nullptr) *orientation = last_step.determinant_sign();
      return TangentFromSolution(solution, previous_scaled, tangent_scaled);
    }
  }
  return false;
}

int OrientationIndex(const Linearization& linearization, const Scaling& scaling,
                     double residual_scale, const Eigen::VectorXd& tangent_scaled) {
  const Eigen::MatrixXd bordered =
      AugmentedMatrix(linearization, scaling, residual_scale, tangent_scaled);
  // Through the problem's elimination where it applies (its pivots are then well above
  // rounding): an LU of the Schur complement instead of the whole matrix.
  if (linearization.elimination != nullptr && !linearization.elimination->empty()) {
    Eigen::VectorXd unused;
    int sign = 0;
    if (SolveEliminating(bordered, Eigen::VectorXd::Zero(bordered.rows()),
                         *linearization.elimination, &unused, &sign)) {
      return sign;
    }
  }
  const DenseLu lu(bordered);
  if (!PivotsAbove(lu, kSingularPivotRatio)) return 0;
  return lu.DeterminantSign();
}

}  // namespace nfrc
