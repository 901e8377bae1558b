#include "core/relative_coordinates.h"

#include <stdexcept>

namespace nfrc {

RelativeBlock ToRelativeCoordinates(const Eigen::VectorXd& compliance, const Eigen::MatrixXcd& z,
                                    const Eigen::MatrixXcd& dz, const Eigen::VectorXcd& f,
                                    const Eigen::VectorXcd& df) {
  const Eigen::Index n = z.rows();
  const Eigen::VectorXcd d = compliance.cast<std::complex<double>>();
  // B = I + Z D; dB/dω = dZ D.
  const Eigen::MatrixXcd b = Eigen::MatrixXcd::Identity(n, n) + z * d.asDiagonal();
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(b);
  const double pivot = lu.matrixLU().diagonal().cwiseAbs().minCoeff();
  if (!(pivot > 1e-14 * std::max(1.0, b.cwiseAbs().maxCoeff()))) {
    throw std::runtime_error("relative coordinates: I + Z·D is singular");
  }
  RelativeBlock block;
  block.z = lu.solve(z);
  block.f = lu.solve(f);
  // dZ_r = B⁻¹ dZ (I − D Z_r), dF_r = B⁻¹ (dF − dZ D F_r).
  block.dz = lu.solve(dz * (Eigen::MatrixXcd::Identity(n, n) - d.asDiagonal() * block.z));
  block.df = lu.solve(df - dz * (d.asDiagonal() * block.f));
  return block;
}

Eigen::VectorXcd AbsoluteFromRelative(const Eigen::VectorXd& compliance, const RelativeBlock& block,
                                      const Eigen::VectorXcd& x_relative) {
  const Eigen::VectorXcd force = block.f - block.z * x_relative;
  return x_relative + compliance.cast<std::complex<double>>().cwiseProduct(force);
}

}  // namespace nfrc
