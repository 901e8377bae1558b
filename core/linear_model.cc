#include "core/linear_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace nfrc {
namespace {

void CheckMatrix(const Eigen::SparseMatrix<double>& matrix, const std::string& name,
                 Eigen::Index num_dofs) {
  if (matrix.rows() != matrix.cols()) {
    throw std::invalid_argument(name + ": must be square, got " + std::to_string(matrix.rows()) +
                                "x" + std::to_string(matrix.cols()));
  }
  if (matrix.rows() != num_dofs) {
    throw std::invalid_argument(name + ": must be " + std::to_string(num_dofs) + "x" +
                                std::to_string(num_dofs) + " like stiffness, got " +
                                std::to_string(matrix.rows()) + "x" +
                                std::to_string(matrix.cols()));
  }
  for (int col = 0; col < matrix.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, col); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw std::invalid_argument(name + ": entry (" + std::to_string(it.row()) + ", " +
                                    std::to_string(it.col()) + ") is not finite");
      }
    }
  }
}

}  // namespace

int LinearModel::FindDof(const std::string& name) const {
  for (size_t i = 0; i < dof_names.size(); ++i) {
    if (dof_names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

void LinearModel::Validate() const {
  if (stiffness.rows() == 0) {
    throw std::invalid_argument("stiffness: model has no DOFs");
  }
  CheckMatrix(stiffness, "stiffness", stiffness.rows());
  CheckMatrix(mass, "mass", stiffness.rows());
  CheckMatrix(damping, "damping", stiffness.rows());
  if (!dof_names.empty() && static_cast<int>(dof_names.size()) != num_dofs()) {
    throw std::invalid_argument("dof_names: must be empty or have " + std::to_string(num_dofs()) +
                                " entries, got " + std::to_string(dof_names.size()));
  }
}

}  // namespace nfrc
