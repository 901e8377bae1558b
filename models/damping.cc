#include "models/damping.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/errors.h"

namespace nfrc {

Eigen::SparseMatrix<double> RayleighDamping(const Eigen::SparseMatrix<double>& mass,
                                            const Eigen::SparseMatrix<double>& stiffness,
                                            double alpha, double beta) {
  return alpha * mass + beta * stiffness;
}

Eigen::SparseMatrix<double> ModalDamping(const Eigen::SparseMatrix<double>& mass,
                                         const Eigen::SparseMatrix<double>& stiffness,
                                         double ratio) {
  const std::string field = "model.damping.modal_ratio";
  if (mass.rows() > kMaxModalDofs) {
    throw InputError(field + ": modal damping needs every mode of the model (a dense " +
                     "eigenproblem); above " + std::to_string(kMaxModalDofs) +
                     " DOFs (this one has " + std::to_string(mass.rows()) +
                     ") use Rayleigh damping, or model.reduction, " +
                     "whose modal_ratio damps the reduced model's modes");
  }
  const Eigen::MatrixXd m = Eigen::MatrixXd(mass);
  const Eigen::MatrixXd k = Eigen::MatrixXd(stiffness);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m);
  if (solver.info() != Eigen::Success) {
    throw InputError(field + ": the mass matrix must be symmetric positive definite");
  }
  const Eigen::VectorXd omegas = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd m_phi = m * solver.eigenvectors();  // Φ is mass-normalised
  const Eigen::MatrixXd c = m_phi * (2.0 * ratio * omegas).asDiagonal() * m_phi.transpose();
  // Entries at round-off level are dropped; modal damping is otherwise a full matrix.
  const double tiny = 1e-14 * c.cwiseAbs().maxCoeff();
  return c.sparseView(1.0, tiny);
}

}  // namespace nfrc
