#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <string>
#include <vector>

namespace nfrc {

// Settings of SolveLcp. The solver works on the problem scaled to unit max-norm of M and of q
// (z, w and z0 are rescaled on return), so the tolerances are relative, never in SI units.
struct LemkeOptions {
  // Covering vector d > 0 of the artificial variable z0 (w = Mz + q + d·z0); empty = all ones.
  // Only its direction matters. Unused by a warm start, which covers with d̄ = 1 (see SolveLcp).
  Eigen::VectorXd covering;
  // Complementary basis to start from: indices i whose z_i is basic (all other w_j basic), e.g.
  // LemkeResult::basic_z of a nearby problem. Empty = the cold start at w = q. A warm basis is
  // used even when q ≥ 0, so that a non-trivial solution coexisting with z = 0 can be found.
  std::vector<int> warm_basis;
  // 0 = automatic: 50·n + 1000. Every basis change counts, the entry of z0 included.
  int max_pivots = 0;
  // An entry of the entering column B⁻¹a counts as positive only above this times the 1-norm
  // of its row of B⁻¹ (the size rounding errors in it scale with).
  double pivot_tolerance = 1e-11;
  // What counts as ≥ 0 for q / the basic variables, relative to ‖q‖∞; also the width of the
  // ties in the ratio test, which the lexicographic rule then breaks.
  double feasibility_tolerance = 1e-10;
  // Raised (a signal handler's flag): Lemke ends before its next pivot (kInterrupted).
  const std::atomic<bool>* stop = nullptr;

  // Throws std::invalid_argument naming the field ("covering", "warm_basis", "max_pivots",
  // "pivot_tolerance", "feasibility_tolerance") for a wrong size, a non-positive or non-finite
  // covering entry, an out-of-range or repeated index, a negative count or tolerance.
  void Validate(int n) const;
};

enum class LemkeStatus {
  kSolution,        // complementary solution found (possibly the trivial z = 0 when q ≥ 0)
  kRayTermination,  // secondary ray: the entering column has no positive entry; LCP may have no
                    // solution (none exists if M is positive semidefinite or copositive-plus)
  kPivotLimit,      // max_pivots reached
  kSingularBasis,   // the final basis could not be refactorised; numerical failure
  kInterrupted,     // LemkeOptions::stop was raised
};

// "solution", "ray termination", "pivot limit", "singular basis" or "interrupted".
std::string ToString(LemkeStatus status);

struct LemkeResult {
  LemkeStatus status = LemkeStatus::kPivotLimit;
  std::string message;  // human-readable reason, e.g. which variable blocked
  // At a solution; the last basic point otherwise (there w = Mz + q + d·z0).
  Eigen::VectorXd z, w;
  bool trivial = false;  // solution with no pivot because q ≥ 0 (z = 0)
  // The warm basis was used: false if none was given or if it was singular (then the cold
  // start ran and `message` says so).
  bool warm_started = false;
  int pivots = 0;
  // Artificial variable at termination (0 at a solution), in units of q for the covering
  // scaled to unit max-norm.
  double z0 = 0.0;
  std::vector<int> basic_z;  // ascending indices with z basic at termination: a warm_basis
  // Residuals of the returned (z, w), recomputed from them and M, q, not from the tableau:
  double complementarity = 0.0;    // max_i |w_i z_i|
  double feasibility = 0.0;        // max(0, −min_i w_i, −min_i z_i)
  double equation_residual = 0.0;  // ‖w − M z − q‖∞ (= ‖d·z0‖∞ short of a solution)
  bool ok() const { return status == LemkeStatus::kSolution; }
};

// Solves the linear complementarity problem w = M z + q, w ≥ 0, z ≥ 0, wᵀz = 0 (M dense, possibly
// singular and nonsymmetric) by Lemke's complementary pivoting on I·w − M·z − d·z0 = q, with the
// lexicographic ratio test (no cycling on degenerate problems) and an explicit basis inverse
// updated in O(n·k) per pivot, k ≤ n the number of basic z's and z0 (at most rank(M) + 1, so
// n/k times cheaper than O(n²) on low-rank Delassus operators). It terminates on any M and finds a
// solution whenever one exists for P-matrices and positive semidefinite M; the returned point is
// recomputed from an LU of the final basis.
//
// Warm start: with a nonsingular complementary basis B of options.warm_basis, q̄ = B⁻¹q ≥ 0
// means B is the solution (0 pivots); otherwise Lemke runs on the tableau transformed by B with
// covering d̄ = 1 there, i.e. d = B·1 (B of the scaled problem). This is Lemke's method on the
// principal pivot transform of M, which keeps the P-matrix and positive semidefinite classes.
//
// Throws std::invalid_argument (naming "M" or "q") for a non-square M, a size mismatch or
// non-finite entries, and whatever options.Validate throws.
LemkeResult SolveLcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                     const LemkeOptions& options = {});

}  // namespace nfrc
