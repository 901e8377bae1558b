#pragma once

#include <functional>
#include <string>
#include <vector>

namespace nfrc::bench {

// What BenchAcceptance runs and how.
struct AcceptanceOptions {
  // Each curve's accuracy against a reference traced with a tenth of the maximum step (see
  // CurveDeviation), in the first round or, with `perturb`, in every round. Default off.
  bool accuracy = false;
  // Rounds of every case in turn (> 1: then each case's fastest and median time, in ms and in
  // its own child's LU(320), and its fewest / median / most points where they differ).
  int runs = 1;
  // Round r traces a copy whose first forcing term is scaled by 1 + r·4.4e-16, so that the
  // summary spans the step sequences a curve takes under rounding-level changes instead of
  // one draw. Default off.
  bool perturb = false;
  // TraceOptions::threads: Hill's analyses beside the trace (0 in turn, -1 one per hardware
  // thread, the default).
  int threads = -1;
  // > 0: every case (and its accuracy reference) traced with that
  // continuation.target_newton_iterations instead of its own, a study of the step pacing.
  int newton_target = 0;
  // Hill's analyses at every point, as the budgets count them (the default); false
  // (`nostability`) times the trace alone: the floor that no cheaper stability analysis can
  // go below.
  bool stability = true;
  // Only the cases whose name (e.g. "friction/point_e.json", "friction point at N_phi = 640")
  // contains one of these; empty (the default): every case. A word that names no case is an
  // error, so that a typo does not run nothing in silence.
  std::vector<std::string> only;
};

// The names of the cases BenchAcceptance can run, in its order.
std::vector<std::string> AcceptanceCaseNames();
// Throws std::invalid_argument for an entry of AcceptanceOptions::only that names no case.
void CheckAcceptanceSelection(const std::vector<std::string>& only);

// The acceptance cases of the speed issue, each a whole TraceCase with stability on (off with
// AcceptanceOptions::stability false), in a child process so that its peak memory (ru_maxrss)
// is its own: wall time in ms and in LU(320) units (`lu_unit()` s, timed again in each child just
// before its case, so that a load that comes and goes on a shared machine shows in both), the
// issue's budget, points, Newton iterations, bifurcations and, with `accuracy`, the curve's
// accuracy. Also one friction point at N_φ = 640. Checks `only` first (CheckAcceptanceSelection).
void BenchAcceptance(const std::function<double()>& lu_unit, const AcceptanceOptions& options);

// Points, Newton iterations, time and ln E accuracy of the Fig. 7 curve (N = 10) for the
// friction force's step weights 1, 0.3 (the default), 0.1 and 0 (HarmonicSystem::
// set_own_step_weight), against the curve traced with a tenth of the step.
void BenchStepWeights(double lu_unit);

}  // namespace nfrc::bench
