#include "analysis/solve_at.h"

#include <algorithm>
#include <memory>

#include "continuation/fixed_lambda.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// Each law's distinguished phase per period (stick, contact), from its typed summary.
std::vector<PhaseSummary> Phases(HarmonicSystem& system, const FourierTransform& fine,
                                 const Eigen::VectorXd& y, double omega) {
  std::vector<PhaseSummary> phases;
  for (size_t i = 0; i < system.laws().size(); ++i) {
    const LawSummary summary =
        system.laws()[i]->Summarize(system.context(static_cast<int>(i)), y, omega, fine);
    if (summary.phase) {
      phases.push_back({summary.phase->name, summary.phase->count, summary.phase->fraction});
    }
  }
  return phases;
}

// The label of the solution of rank `rank` (0: lowest energy) among `count`.
std::string EnergyLabel(size_t rank, size_t count) {
  static const char* kNames3[] = {"lower", "middle", "upper"};
  if (count == 1) return "only";
  if (count == 2) return rank == 0 ? "lower" : "upper";
  if (count == 3) return kNames3[rank];
  return "solution " + std::to_string(rank + 1) + " of " + std::to_string(count) + " by energy";
}

}  // namespace

std::vector<CrossingSolution> SolveCrossings(const Case& the_case, HarmonicSystem& system,
                                             const Branch& branch, double omega) {
  SolutionReporter reporter(system, the_case.output_dofs, the_case.output_names);
  std::vector<CrossingSolution> solutions;
  std::vector<int> converged;  // indices into `solutions`
  for (size_t i = 0; i < branch.points.size(); ++i) {
    const BranchPoint* previous = i > 0 ? &branch.points[i - 1] : nullptr;
    const auto solved =
        SolveAtCrossing(system, previous, branch.points[i], omega, the_case.continuation);
    if (!solved) continue;
    CrossingSolution& s = solutions.emplace_back();
    s.omega = omega;
    s.after_point = static_cast<int>(i);
    s.converged = solved->converged;
    s.message = solved->message;
    s.y = solved->y;
    if (!s.converged) {
      s.label = "not converged";
      continue;
    }
    s.coefficients = system.AllDofCoefficients(s.y, omega);
    s.signals = reporter.Signals(s.y, omega);
    s.signals.after_point = s.after_point;
    s.signals.converged = true;
    s.signals.note = s.message;
    s.phases = Phases(system, reporter.analyzer().fine(), s.y, omega);
    converged.push_back(static_cast<int>(solutions.size() - 1));
  }
  std::vector<int> order = converged;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return solutions[a].signals.measures.response.energy <
           solutions[b].signals.measures.response.energy;
  });
  for (size_t rank = 0; rank < order.size(); ++rank) {
    solutions[order[rank]].label = EnergyLabel(rank, order.size());
  }
  return solutions;
}

SolveAtResult SolveAt(const Case& the_case, double omega, const TraceOptions& options) {
  the_case.Validate();
  if (the_case.method != Method::kArclength) {
    throw InputError(
        "continuation.method: solving at one omega needs the arclength branch (Newton solves "
        "between its points), not \"" +
        std::string(ToString(the_case.method)) + "\"");
  }
  const ContinuationOptions& range = the_case.continuation;
  if (!(omega >= range.LowerBound() && omega <= range.UpperBound())) {
    throw InputError("omega: " + std::to_string(omega) + " is outside the case's range [" +
                     std::to_string(range.LowerBound()) + ", " +
                     std::to_string(range.UpperBound()) + "]");
  }
  SolveAtResult result;
  result.trace = TraceCase(the_case, options);
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  result.solutions = SolveCrossings(the_case, *system, result.trace.branch, omega);
  return result;
}

}  // namespace nfrc
