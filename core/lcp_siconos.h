#pragma once

// Adapter to the LCP solvers of Siconos numerics (libsiconos-numerics-dev), the reference
// against which nfrc's Lemke (core/lemke.h) is compared in tests/core/lcp_siconos_test.cc and
// nfrc_bench section 6. Compiled only when CMake finds the package (option NFRC_SICONOS, then
// NFRC_HAVE_SICONOS is defined for nfrc_core and everything linking it).

#include <Eigen/Dense>
#include <string>

namespace nfrc {

enum class SiconosLcpSolver {
  kLexicoLemke,  // lcp_lexicolemke: Lemke with the lexicographic ratio test, dense tableau
  kPivotLemke,   // lcp_pivot with the Lemke rule (SICONOS_LCP_PIVOT_LEMKE)
  kEnum,         // lcp_enum: enumeration of the 2^n complementary bases (small n only)
};

// "lexicolemke", "pivot-lemke" or "enum".
std::string ToString(SiconosLcpSolver solver);

struct SiconosLcpResult {
  bool ok = false;  // Siconos reported convergence (info 0)
  int info = -1;    // the solver's termination code (0 = success)
  // Pivots or enumerated bases, as the solver counts them: the Lemke solvers leave out z0's
  // entry, which LemkeResult::pivots counts.
  int iterations = -1;
  double error = 0.0;  // Siconos's own error estimate (lcp_compute_error), relative
  Eigen::VectorXd z, w;
  // Residuals of the returned (z, w) recomputed from M, q, as in LemkeResult:
  double complementarity = 0.0;    // max_i |w_i z_i|
  double feasibility = 0.0;        // max(0, −min_i w_i, −min_i z_i)
  double equation_residual = 0.0;  // ‖w − M z − q‖∞
  std::string message;
};

// Solves w = M z + q, 0 ≤ w ⊥ z ≥ 0 (M dense, column-major copy handed to Siconos) with the
// chosen Siconos solver, in the units of M and q (no scaling: the caller scales if it wants
// relative tolerances). max_iterations 0 keeps Siconos's default. Throws
// std::invalid_argument for a non-square M or a size mismatch.
SiconosLcpResult SolveLcpSiconos(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                                 SiconosLcpSolver solver, int max_iterations = 0);

}  // namespace nfrc
