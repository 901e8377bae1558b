#pragma once

#include <Eigen/Dense>
#include <string>

#include "validation/time_law.h"

namespace nfrc {

// Finite-difference check of a TimeLaw's Jacobian in its current mode, the time-domain twin of
// nonlinearities/jacobian_check.h: compares ∂F/∂y + cj ∂F/∂ẏ from Jacobian() with central
// differences of Residual() in y and ẏ at (t, y, ẏ). `y` and `yp` are whole DAE vectors
// [x | v | own of this law] with the law's own unknowns at layout.own_offset.
struct TimeLawCheck {
  double max_abs_error = 0.0;  // largest |analytic − finite difference| over the entries
  double scale = 0.0;          // largest |finite-difference entry|
  std::string worst;           // "row r, column c: analytic a, finite difference d"
  bool Passed(double relative_tolerance) const {
    return max_abs_error <= relative_tolerance * std::max(scale, 1.0);
  }
};

TimeLawCheck CheckTimeLawJacobian(const TimeLaw& law, const TimeLawLayout& layout, double t,
                                  double phase, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                                  double cj, double step = 1e-7);

// A DaeView over whole vectors y, ẏ for `law` (x, v, ẋ, a and the law's own block).
DaeView MakeDaeView(const TimeLaw& law, const TimeLawLayout& layout, double t, double phase,
                    const Eigen::VectorXd& y, const Eigen::VectorXd& yp);

}  // namespace nfrc
