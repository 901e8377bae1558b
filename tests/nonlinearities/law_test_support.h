#pragma once

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
