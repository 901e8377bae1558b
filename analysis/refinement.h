#pragma once

#include <atomic>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/lcp_reference.h"
#include "analysis/solution_report.h"
#include "analysis/trace.h"

namespace nfrc {

// ε-refinement of DLFT contact at one frequency (Vadcard et al. 2022, Sec. 4.1): the case is
// solved at ω with each ε of a sequence in turn, every solve warm-started from the previous
// solution, so that very large ε (where a cold start fails) are reached.
struct RefinementOptions {
  double omega = 0.0;            // rad/s; must lie on the case's ω range
  std::vector<double> epsilons;  // N/m, in the order solved; every one > 0

  // Throws InputError naming "omega" or "epsilons", or "nonlinearities" if the case has no
  // dlft_contact law.
  void Validate(const Case& the_case) const;
};

// ε_i = ε_0·factor^i, i = 0..steps. Throws InputError naming "factor" or "steps".
std::vector<double> GeometricEpsilons(double epsilon0, double factor, int steps);

// One ε of the refinement: the Newton solve at ω warm-started from the previous step.
struct RefinementStep {
  double epsilon = 0.0;  // N/m, on every dlft_contact
  bool converged = false;
  int newton_iterations = 0;
  double residual_norm = 0.0;  // as SolveAtFixedLambda reports it
  std::string message;         // the solver's; empty on success
  // Measures and time signals at ω; after_point −1, note "epsilon=<ε>".
  SolutionSignals signals;
  std::optional<LcpDistance> distance_to_lcp;  // when the reference has a Lemke solution
};

struct RefinementResult {
  double omega = 0.0;  // rad/s
  // The branch from omega_start to its first point at or beyond ω (no signals_at solved).
  TraceResult branch;
  std::optional<LcpReference> lcp;  // every law dlft_contact and a solution at ω
  // In the order solved; steps after a failed one are not attempted.
  std::vector<RefinementStep> steps;
  // Why steps are missing: no solution at ω, or an interrupt; empty otherwise.
  std::string message;
  bool interrupted = false;  // the stop flag was raised

  // Every ε of `options` solved, the last converged, and not interrupted.
  bool Complete(const RefinementOptions& options) const;
};

// Receives a refinement's results as they are found (a writer). Called on the refining thread.
class RefinementObserver {
 public:
  virtual ~RefinementObserver() = default;
  // The branch up to ω has ended (its points and folds went to RefinementRunOptions::branch).
  virtual void OnBranchEnd(const ContinuationSummary& /*summary*/) {}
  virtual void OnLcpReference(const LcpReference& /*reference*/) {}
  virtual void OnStep(const RefinementStep& /*step*/) {}
};

struct RefinementRunOptions {
  std::ostream* progress = nullptr;  // progress lines; null = quiet
  // Polled after every branch point and before every step; null = never stops.
  const std::atomic<bool>* stop = nullptr;
  TraceObserver* branch = nullptr;         // the branch up to ω as it is traced
  RefinementObserver* observer = nullptr;  // the reference and the steps as they come
};

// Traces the case from omega_start until the branch first reaches ω, solves there, then solves
// at ω for each ε in turn. When every law is dlft_contact, the LCP-HBM limit is solved at ω
// and each step gets its distance to it. A raised stop flag ends the trace or the steps early
// (result.interrupted). Throws InputError for bad input (before anything is traced).
RefinementResult RefineEpsilon(const Case& the_case, const RefinementOptions& options,
                               const RefinementRunOptions& run = {});

}  // namespace nfrc
