#pragma once

#include <Eigen/Dense>

#include "analysis/case.h"

namespace nfrc::testing {

// A chain of n unit masses (kg) and unit springs (N/m), held at both ends (k_ii = 2,
// k_i,i±1 = −1), with damping 0.02·K: the small damped model of the system-level tests. No
// forcing, laws or outputs yet.
inline Case ChainCase(int n) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) = 2.0;
    if (i + 1 < n) k(i, i + 1) = k(i + 1, i) = -1.0;
  }
  Case c;
  c.model.model.stiffness = k.sparseView();
  c.model.model.mass = Eigen::MatrixXd::Identity(n, n).sparseView();
  c.model.model.damping = (0.02 * k).sparseView();
  return c;
}

// Exact Coulomb friction at `dof` (against `other`, −1: ground) with coefficient mu and
// normal load (N), the other fields at their defaults.
inline CoulombFrictionSpec Friction(int dof, double mu, double normal_load, int other = -1) {
  CoulombFrictionSpec friction;
  friction.dof = dof;
  friction.other = other;
  friction.mu = mu;
  friction.normal_load = normal_load;
  return friction;
}

// The chain of four forced at its last DOF (0.3 N cos), which meets a rigid obstacle through
// DLFT contact at gap 0.05 m, with output DOF 0.
inline Case ChainAgainstRigidObstacle(const HarmonicSet& harmonics) {
  Case c = ChainCase(4);
  c.model.forcing = {ForcingTerm{3, 1, 0.3, 0.0}};
  c.harmonics = harmonics;
  ContactGeometry geometry;
  geometry.dof = 3;
  geometry.gap = 0.05;
  c.laws.push_back(DlftContactSpec{{geometry, 0.0, 0.0}});
  c.output_dofs = {0};
  c.output_names = {"0"};
  return c;
}

}  // namespace nfrc::testing
