#include "nonlinearities/jacobian_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nfrc {

JacobianCheckResult CheckJacobian(const ResidualFunction& function, const Eigen::VectorXd& y,
                                  double omega, double relative_step, double typical_y,
                                  double floor) {
  const Eigen::Index n = y.size();
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd d_omega;
  function(y, omega, &r, &jacobian, &d_omega);
  const Eigen::Index m = r.size();
  Eigen::VectorXd r_alone;
  function(y, omega, &r_alone, nullptr, nullptr);

  Eigen::MatrixXd jacobian_fd(m, n);
  Eigen::VectorXd plus, minus;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double h = relative_step * std::max(std::abs(y(j)), typical_y);
    Eigen::VectorXd y_step = y;
    y_step(j) = y(j) + h;
    function(y_step, omega, &plus, nullptr, nullptr);
    y_step(j) = y(j) - h;
    function(y_step, omega, &minus, nullptr, nullptr);
    jacobian_fd.col(j) = (plus - minus) / (2.0 * h);
  }
  const double h_omega = relative_step * std::abs(omega);
  function(y, omega + h_omega, &plus, nullptr, nullptr);
  function(y, omega - h_omega, &minus, nullptr, nullptr);
  const Eigen::VectorXd d_omega_fd = (plus - minus) / (2.0 * h_omega);

  JacobianCheckResult result;
  const double y_scale = std::max(jacobian.cwiseAbs().maxCoeff(), floor);
  Eigen::Index row = 0, col = 0;
  result.y_error = (jacobian - jacobian_fd).cwiseAbs().maxCoeff(&row, &col) / y_scale;
  result.worst_row = static_cast<int>(row);
  result.worst_col = static_cast<int>(col);
  const double omega_scale = std::max(d_omega.cwiseAbs().maxCoeff(), floor);
  result.omega_error = (d_omega - d_omega_fd).cwiseAbs().maxCoeff(&row) / omega_scale;
  result.worst_omega_row = static_cast<int>(row);
  result.residual_error = r_alone.size() == m ? (r - r_alone).cwiseAbs().maxCoeff() /
                                                    std::max(r.cwiseAbs().maxCoeff(), floor)
                                              : std::numeric_limits<double>::infinity();
  return result;
}

JacobianCheckResult CheckNonlinearityJacobian(const Nonlinearity& law,
                                              const NonlinearityContext& ctx,
                                              Condensation* condensation, const Eigen::VectorXd& y,
                                              double omega, double relative_step,
                                              double typical_y) {
  const ResidualFunction function = [&](const Eigen::VectorXd& at, double at_omega,
                                        Eigen::VectorXd* r, Eigen::MatrixXd* jacobian,
                                        Eigen::VectorXd* d_omega) {
    if (condensation != nullptr) condensation->Update(at_omega);
    r->setZero(at.size());
    if (jacobian != nullptr) jacobian->setZero(at.size(), at.size());
    if (d_omega != nullptr) d_omega->setZero(at.size());
    law.Evaluate(ctx, at, at_omega, *r, jacobian, d_omega);
  };
  const JacobianCheckResult result = CheckJacobian(function, y, omega, relative_step, typical_y);
  if (condensation != nullptr) condensation->Update(omega);
  return result;
}

}  // namespace nfrc
