#pragma once

#include <Eigen/Dense>

namespace nfrc {

// Two-body relative-coordinate condensation for one harmonic. Retained DOF i may face a
// massless obstacle of compliance d_i = 1/k_obs (m/N; 0 = rigid obstacle or none), which
// is a second body with Z² = k_obs in every harmonic. With x_r = x − x_obs the condensed
// equations Z x + f_nl = F become Z_r x_r + f_nl = F_r with
//   Z_r = (Z⁻¹ + D)⁻¹ = (I + Z D)⁻¹ Z,   F_r = (I + Z D)⁻¹ F,
// written without Z⁻¹ so a statically free structure (Z_0 singular) still condenses.
struct RelativeBlock {
  Eigen::MatrixXcd z, dz;  // Z_r and dZ_r/dω
  Eigen::VectorXcd f, df;  // F_r and dF_r/dω
};

// Z, dZ/dω, F, dF/dω of the structure in absolute coordinates → the same in relative
// coordinates. Throws std::runtime_error if I + Z D is singular.
RelativeBlock ToRelativeCoordinates(const Eigen::VectorXd& compliance, const Eigen::MatrixXcd& z,
                                    const Eigen::MatrixXcd& dz, const Eigen::VectorXcd& f,
                                    const Eigen::VectorXcd& df);

// Absolute displacement amplitudes x = x_r + D f_nl, where f_nl = F_r − Z_r x_r is the
// interface force the condensed equations imply (exact at a solution).
Eigen::VectorXcd AbsoluteFromRelative(const Eigen::VectorXd& compliance, const RelativeBlock& block,
                                      const Eigen::VectorXcd& x_relative);

}  // namespace nfrc
