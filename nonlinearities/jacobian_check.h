#pragma once

#include <Eigen/Dense>
#include <functional>

#include "core/condensation.h"
#include "core/nonlinearity.h"

namespace nfrc {

// A law's residual evaluated alone and with its derivatives is the same arithmetic: equal
// bit for bit (the corrector's line search judges steps by the residual alone).
inline constexpr double kSameResidual = 0.0;

// Outcome of comparing an analytic Jacobian with central finite differences. Errors are
// relative to the largest entry of the analytic matrix (or vector), floored at `floor`.
struct JacobianCheckResult {
  double y_error = 0.0;  // max |J − J_fd| / max(|J|_max, floor)
  int worst_row = -1;
  int worst_col = -1;
  double omega_error = 0.0;  // max |dω − dω_fd| / max(|dω|_max, floor)
  int worst_omega_row = -1;
  // max |r − r₀| / max(|r|_max, floor), r₀ evaluated without derivatives (as the corrector's
  // line search does): the two must be the same residual.
  double residual_error = 0.0;
};

// Evaluates r(y, ω) and, when non-null, ∂r/∂y and ∂r/∂ω.
using ResidualFunction =
    std::function<void(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* r,
                       Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega)>;

// Central differences with steps h_i = relative_step·max(|y_i|, typical_y) and
// h_ω = relative_step·|ω|; every column of ∂r/∂y and the ω column are checked, and the
// residual evaluated alone against the one evaluated with its derivatives.
JacobianCheckResult CheckJacobian(const ResidualFunction& function, const Eigen::VectorXd& y,
                                  double omega, double relative_step, double typical_y,
                                  double floor = 1e-12);

// The same for one law; `condensation` (may be null) is moved to each ω the differences
// visit, so laws that use the condensed operator are checked in ω too.
JacobianCheckResult CheckNonlinearityJacobian(const Nonlinearity& law,
                                              const NonlinearityContext& ctx,
                                              Condensation* condensation, const Eigen::VectorXd& y,
                                              double omega, double relative_step, double typical_y);

}  // namespace nfrc
