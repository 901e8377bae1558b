#pragma once

#include <Eigen/Dense>
#include <optional>

#include "analysis/case.h"
#include "analysis/harmonic_system.h"
#include "analysis/solution_report.h"
#include "core/lemke.h"

namespace nfrc {

// The LCP-HBM limit of DLFT contact (Vadcard et al. 2022, Sec. 4.1): as ε grows, a DLFT
// solution tends to the solution of the same case as a complementarity problem on the same
// N_t samples, which Lemke solves directly (LcpHbm).

// The case DLFT's ε-refinement tends to: every dlft_contact turned into lcp_contact with the
// same contact fields (ε then only scales gaps to forces); nullopt unless every law is
// dlft_contact.
std::optional<Case> LcpLimitCase(const Case& the_case);

// The LCP-HBM solution of a case at one ω.
struct LcpReference {
  LemkeStatus status = LemkeStatus::kSolution;
  int pivots = 0;
  double complementarity_gap = 0.0;  // m, LcpHbm::Solution::complementarity_gap
  double min_gap = 0.0;              // m, smallest gap W λ + p on the samples
  Eigen::VectorXd force;             // N, λ on the N_t samples, stacked per contact
  Eigen::VectorXd gap;               // m, W λ + p on the same samples
  int num_unknowns = 0;              // of the LCP-HBM system: displacements, then λ samples
  // At ω; after_point −1, converged = Lemke found a solution, note "LCP-HBM (Lemke)".
  SolutionSignals signals;

  bool ok() const { return status == LemkeStatus::kSolution; }
};

// Lemke at ω on `lcp_case` (every law lcp_contact, e.g. LcpLimitCase). Throws InputError if a
// law is not lcp_contact, std::runtime_error if the condensed operator is singular at ω.
LcpReference SolveLcpReference(const Case& lcp_case, double omega);

// Relative distances (dimensionless) of a DLFT solution to the LCP-HBM reference on the same
// samples, each |a − b| / |b| (|a − b| when the reference is 0).
struct LcpDistance {
  double force_raw = 0.0;     // sampled forces before truncation, max norm
  double force = 0.0;         // truncated forces on the samples, 2-norm
  double gap = 0.0;           // sampled gaps, max norm
  double displacement = 0.0;  // condensed displacement coefficients, 2-norm
};

// The distance of solution y at ω of `system`, built from `dlft_case` (every law
// dlft_contact) and last evaluated at ω (as after a solve there), to `reference`, the
// solution of LcpLimitCase(dlft_case) at the same ω.
LcpDistance DistanceToLcp(const Case& dlft_case, const HarmonicSystem& system,
                          const Eigen::VectorXd& y, double omega, const LcpReference& reference);

}  // namespace nfrc
