#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>

#include "core/linear_model.h"
#include "core/errors.h"

namespace nfrc::testing {

// Two unit DOFs named "a" and "b": a model for laws that only resolve DOFs.
inline LinearModel TwoDofModel() {
  LinearModel model;
  model.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.stiffness = Eigen::MatrixXd::Identity(2, 2).sparseView();
  model.damping = Eigen::MatrixXd::Zero(2, 2).sparseView();
  model.dof_names = {"a", "b"};
  return model;
}

// A damped four-DOF chain (N/m, kg), clamped at DOF 0's left: the contact laws' test model
// (contact at DOF 3, where the tests force it).
inline LinearModel ChainModel() {
  const int n = 4;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) += 2.0e9;
    if (i + 1 < n) k(i, i + 1) = k(i + 1, i) = -1.0e9;
  }
  k(n - 1, n - 1) = 1.0e9;
  LinearModel model;
  model.stiffness = k.sparseView();
  model.mass = (0.5 * Eigen::MatrixXd::Identity(n, n)).sparseView();
  model.damping = (2e-6 * k).sparseView();
  return model;
}

}  // namespace nfrc::testing
