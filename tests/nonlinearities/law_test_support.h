#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <nlohmann/json.hpp>
#include <string>

#include "core/input_fields.h"
#include "core/linear_model.h"
#include "nonlinearities/registry.h"

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

// The InputError message of MakeNonlinearity for the JSON `text` on TwoDofModel, or
// "no error".
inline std::string LawInputError(const std::string& text) {
  try {
    MakeNonlinearity(nlohmann::json::parse(text), "nonlinearities[0]", TwoDofModel());
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// True if `message` starts by naming `field` of the law ("nonlinearities[0].<field>: ").
inline bool NamesField(const std::string& message, const std::string& field) {
  return message.rfind("nonlinearities[0]." + field + ": ", 0) == 0;
}

}  // namespace nfrc::testing
