#pragma once

#include <Eigen/Dense>
#include <memory>
#include <optional>

#include "analysis/harmonic_system.h"
#include "analysis/hill.h"
#include "analysis/stability.h"
#include "continuation/branch.h"
#include "continuation/options.h"

namespace nfrc {

// Stability of the points of a traced branch (Hill's method) and the bifurcations between
// them: a change of the number of unstable multipliers between two consecutive points is
// classified by the multiplier that crossed (the least unstable one on the more unstable
// side) and localised in ω.
class StabilityMonitor {
 public:
  // Keeps references; `continuation` gives the fixed-ω Newton its tolerances.
  StabilityMonitor(HarmonicSystem& system, const StabilityOptions& options,
                   const ContinuationOptions& continuation);

  // Hill's multipliers at a solution; a failure is a result with computed = false. Arnoldi
  // starts from the previous analysis of this form.
  FloquetResult Analyze(const Eigen::VectorXd& y, double omega);
  // The same with Arnoldi's start in and out through `warm_start` (SolveHill's krylov_start:
  // empty starts cold), for callers that chain analyses of their own (StabilityPipeline).
  FloquetResult Analyze(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* warm_start);

  // The bifurcation between consecutive points a and b with their Floquet results, if their
  // unstable counts differ. `fold` is the fold the engine located between them, if any: a
  // real multiplier through +1 there is that fold (its ω and accuracy are the engine's).
  // Otherwise ω is monotone on the segment and the crossing is localised by the Illinois
  // method on log|μ| of the crossing multiplier, each trial solved by Newton at fixed ω from
  // the interpolated solution and its side decided by the unstable count; the accuracy is the
  // final bracket's width. Arnoldi starts cold at each localisation's first analysis, so the
  // result depends on a and b only.
  std::optional<Bifurcation> Between(const BranchPoint& a, const FloquetResult& floquet_a,
                                     const BranchPoint& b, const FloquetResult& floquet_b,
                                     const Fold* fold);

 private:
  HarmonicSystem& system_;
  std::unique_ptr<HillAssembler> hill_;  // made at the first analysis (it holds Δ's parts)
  // Arnoldi's start for the next analysis: the last one's Ritz vectors (SolveHill).
  Eigen::VectorXd krylov_start_;
  const StabilityOptions& options_;
  const ContinuationOptions& continuation_;
};

// The windows of a branch, from its Neimark–Sacker bifurcations in branch order: a window
// opens at one after which the unstable count is higher and closes at the next one after
// which it is lower again.
struct TracePoint;
std::vector<QuasiPeriodicWindow> QuasiPeriodicWindows(const std::vector<Bifurcation>& bifurcations,
                                                      const std::vector<TracePoint>& points);

}  // namespace nfrc
