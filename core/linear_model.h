#pragma once

#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace nfrc {

// The linear part M ẍ + C ẋ + K x = f(t) of a structure, in any consistent units.
// Matrices are square, of equal size, and need not be symmetric.
struct LinearModel {
  Eigen::SparseMatrix<double> mass;
  Eigen::SparseMatrix<double> damping;
  Eigen::SparseMatrix<double> stiffness;
  // Optional DOF names (empty, or one per DOF) so case files can say "dof": "end".
  std::vector<std::string> dof_names;

  int num_dofs() const { return static_cast<int>(stiffness.rows()); }

  // Index of a DOF named `name`, or −1 if there is none.
  int FindDof(const std::string& name) const;

  // Throws std::invalid_argument naming the matrix ("mass", ...) if the sizes disagree, a
  // matrix is not square, an entry is not finite, or dof_names has the wrong length.
  void Validate() const;
};

// One harmonic component of the external force: f_dof(t) += cos·cos(kωt) + sin·sin(kωt).
struct ForcingTerm {
  int dof = 0;
  int harmonic = 1;
  double cos = 0.0;
  double sin = 0.0;
};

// A linear model with its external forcing: what a case's "model" describes, built once by
// a reader (matrices loaded) and copied by value wherever a system is built from it.
struct ModelDefinition {
  LinearModel model;
  std::vector<ForcingTerm> forcing;
};

}  // namespace nfrc
