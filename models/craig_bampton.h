#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "core/linear_model.h"

namespace nfrc {

// Craig–Bampton reduction of a large sparse linear model onto its boundary DOFs (those the
// laws act on, the forced and the output DOFs), which stay physical so that the laws attach
// unchanged. With the DOFs split into boundary b and interior i,
//   x = T q,   T = [[I, 0], [Ψ, Φ]],   Ψ = −K_ii⁻¹ K_ib,   (K_ii − ω_j² M_ii) φ_j = 0,
// Ψ the static constraint modes and Φ the lowest mass-normalised fixed-interface modes.
// The reduced matrices are Tᵀ K T, Tᵀ M T and Tᵀ C T (dense, (n_b + m)²): a Rayleigh damping
// αM + βK maps exactly onto αM_r + βK_r. K_ii must be symmetric positive definite (the
// boundary and the clamps together remove every rigid-body motion of the interior); it is
// factorised once by CHOLMOD (supernodal Cholesky), and that factor serves the constraint
// modes and the shift-invert eigensolver (Spectra, σ = 0) alike. Memory and work are linear
// in the number of FE DOFs for a fixed reduced size: T is N × (n_b + m), nothing is N × N.

// Fixed-interface modes kept when the number comes from a frequency band: every mode below
// kBandFactor × max_frequency. Factor 2 is the usual rule for component mode synthesis: the
// modes a response below ω_max needs most are those below it; the ones up to 2ω_max carry
// the rest of the dynamic flexibility to within a few percent (and the static part of every
// higher one is exact through the constraint modes).
inline constexpr double kBandFactor = 2.0;
// Most fixed-interface modes kept (the reduced model is dense).
inline constexpr int kMaxReductionModes = 500;

// Eigenfrequencies compared by default between the full and the reduced model.
inline constexpr int kDefaultCheckFrequencies = 5;

struct CraigBamptonOptions {
  int modes = -1;              // fixed-interface modes kept; −1: from max_frequency
  double max_frequency = 0.0;  // rad/s; used when modes < 0
  // Eigenfrequencies compared between full and reduced (0: none; at most the reduced size);
  // −1: kDefaultCheckFrequencies, or the reduced size if smaller.
  int check_frequencies = -1;
  bool keep_recovery = false;  // keep T (N × (n_b + m)) for full-field recovery
};

// One eigenfrequency (rad/s) of the full model against the reduced model's.
struct EigenfrequencyCheck {
  double full = 0.0;
  double reduced = 0.0;
  double relative_error = 0.0;  // (reduced − full) / full; ≥ 0 up to round-off (Rayleigh–Ritz)
};

struct ReductionReport {
  int full_dofs = 0;
  int boundary_dofs = 0;
  int modes = 0;
  double time_s = 0.0;        // factorisation, constraint modes, eigenmodes, projection
  double factor_s = 0.0;      // of which: the K_ii split and its Cholesky factorisation
  double modes_s = 0.0;       //           the fixed-interface modes (Lanczos)
  double check_time_s = 0.0;  // the full model's eigenfrequencies for the check
  std::vector<double> fixed_interface_frequencies;  // rad/s, ascending
  std::vector<EigenfrequencyCheck> eigenfrequencies;
};

struct CraigBamptonModel {
  // Boundary DOFs first, in the order given (named as in the full model, or by their full
  // index), then the modal amplitudes ("cb_mode_1", ...).
  LinearModel model;
  // x_full = recovery · x_reduced (empty unless options.keep_recovery).
  Eigen::MatrixXd recovery;
  ReductionReport report;
};

// Throws std::invalid_argument naming the problem ("boundary", "modes", "max_frequency",
// "check_frequencies") for bad arguments (no interior DOF among them), and std::runtime_error
// if K_ii or M_ii is not positive definite or an eigensolve does not converge.
CraigBamptonModel ReduceCraigBampton(const LinearModel& full, const std::vector<int>& boundary,
                                     const CraigBamptonOptions& options);

// The `count` lowest eigenvalues ω² (ascending) of the symmetric pencil (K, M), M positive
// definite, by Spectra's shift-invert Lanczos about σ (K − σM must be positive definite:
// σ below the lowest eigenvalue), with the matching M-normalised eigenvectors if `vectors`.
// Throws std::runtime_error if the factorisation fails or Lanczos does not converge.
Eigen::VectorXd LowestEigenpairs(const Eigen::SparseMatrix<double>& stiffness,
                                 const Eigen::SparseMatrix<double>& mass, int count, double sigma,
                                 Eigen::MatrixXd* vectors = nullptr);

}  // namespace nfrc
