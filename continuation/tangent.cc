#include "continuation/tangent.h"

#include <cmath>

#include "continuation/augmented_system.h"

namespace nfrc {

bool InitialTangent(const Linearization& linearization, const Scaling& scaling,
                    double residual_scale, double lambda_direction,
                    Eigen::VectorXd* tangent_scaled) {
  const int n = scaling.num_unknowns();
  const Eigen::MatrixXd jacobian =
      AugmentedMatrix(linearization, scaling, residual_scale, Eigen::VectorXd::Zero(n + 1))
          .topRows(n);
  // The last column of Q in Jᵀ = QR is orthogonal to the row space of J.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(jacobian.transpose());
  if (qr.rank() != n) return false;
  const Eigen::MatrixXd q = qr.householderQ();
  *tangent_scaled = q.col(n).normalized();
  if ((*tangent_scaled)(n)*lambda_direction < 0.0) *tangent_scaled = -*tangent_scaled;
  return tangent_scaled->allFinite();
}

bool NextTangent(const Linearization& linearization, const Scaling& scaling, double residual_scale,
                 const Eigen::VectorXd& previous_scaled, Eigen::VectorXd* tangent_scaled) {
  const int n = scaling.num_unknowns();
  Eigen::VectorXd solution;
  if (!SolveAugmented(AugmentedMatrix(linearization, scaling, residual_scale, previous_scaled),
                      Eigen::VectorXd::Unit(n + 1, n), &solution,
                      linearization.elimination.get())) {
    return false;
  }
  const double norm = solution.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  *tangent_scaled = solution / norm;
  // A full-pivoting fallback on a singular border may lose the orientation: refuse it.
  return tangent_scaled->dot(previous_scaled) > 0.0;
}

}  // namespace nfrc
