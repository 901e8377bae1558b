#pragma once

#include <Eigen/Dense>
#include <cstdlib>

#include "analysis/case.h"
#include "analysis/hill.h"

namespace nfrc::testing {

// Hill's pencil of a case at ω on its linear initial guess perturbed by `perturbation` times a
// seeded random vector: a fixed state with some samples on each side of the law's switch.
inline HillPencil PencilOf(const Case& c, double omega, double perturbation, unsigned seed) {
  auto system = BuildSystem(c);
  Eigen::VectorXd y = system->InitialGuess(omega);
  std::srand(seed);
  y += perturbation * Eigen::VectorXd::Random(y.size());
  return AssembleHillPencil(*system, y, omega);
}

}  // namespace nfrc::testing
