#pragma once

#include <Eigen/Sparse>

namespace nfrc {

// Rayleigh damping C = α M + β K (α in 1/s, β in s).
Eigen::SparseMatrix<double> RayleighDamping(const Eigen::SparseMatrix<double>& mass,
                                            const Eigen::SparseMatrix<double>& stiffness,
                                            double alpha, double beta);

// Largest modal damping ratio a case may give: ten times critical damping is already a
// structure whose modes no longer oscillate; far beyond, 2ζω overflows.
inline constexpr double kMaxModalRatio = 10.0;

// Modal damping with ratio ζ in every mode: C = M Φ diag(2ζω_i) Φᵀ M with mass-normalised
// modes Φ of the symmetric pencil (K, M). Dense (all modes), so limited to kMaxModalDofs;
// throws InputError("model.damping.modal_ratio: ...") above it or if M is not positive
// definite. The limit bounds the reading of a case: the dense eigenproblem grows as n³ and
// runs before the trace reports anything.
inline constexpr int kMaxModalDofs = 1000;
Eigen::SparseMatrix<double> ModalDamping(const Eigen::SparseMatrix<double>& mass,
                                         const Eigen::SparseMatrix<double>& stiffness,
                                         double ratio);

}  // namespace nfrc
