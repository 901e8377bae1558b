#pragma once

#include <Eigen/Sparse>
#include <complex>

#include "core/linear_model.h"

namespace nfrc {

// Complex dynamic stiffness of harmonic k: Z_k(ω) = K − (kω)² M + i·kω·C.
// Convention: x(t) = Re(X e^{ikωt}) with X = a_k − i·b_k; Z_k X = F for a forcing with
// complex amplitude F = f_cos − i·f_sin. In real coefficients (a_k, b_k) the block is
// [[Re Z, Im Z], [−Im Z, Re Z]], i.e. [[K − (kω)²M, kωC], [−kωC, K − (kω)²M]].
using SparseComplex = Eigen::SparseMatrix<std::complex<double>>;

SparseComplex DynamicStiffness(const LinearModel& model, int harmonic, double omega);

// dZ_k/dω = −2k²ω M + i·k·C.
SparseComplex DynamicStiffnessDerivative(const LinearModel& model, int harmonic, double omega);

}  // namespace nfrc
