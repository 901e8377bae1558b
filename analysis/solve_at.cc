#include "analysis/solve_at.h"

#include <algorithm>
#include <map>
#include <memory>

#include "continuation/fixed_lambda.h"
#include "core/errors.h"
#include "nonlinearities/phase_count.h"

namespace nfrc {
namespace {

// Stick phases from a law's diagnostics (`measures.laws`), contact phases from its raw force
// samples (the force before truncation is exactly zero while open, so every run of positive
// samples counts).
std::vector<PhaseSummary> Phases(HarmonicSystem& system, const SolutionMeasures& measures,
                                 const Eigen::VectorXd& y, double omega) {
  std::vector<PhaseSummary> phases;
  for (size_t i = 0; i < system.laws().size(); ++i) {
    const auto& law = *system.laws()[i];
    const NonlinearityContext& ctx = system.context(static_cast<int>(i));
    const std::map<std::string, double>& diagnostics = measures.laws[i];
    if (const auto it = diagnostics.find("stick_phases"); it != diagnostics.end()) {
      phases.push_back({"stick", static_cast<int>(it->second), diagnostics.at("stick_fraction")});
      continue;
    }
    for (const LawSignal& signal : law.RawSamples(ctx, y, omega)) {
      if (signal.name != "force_raw") continue;
      std::vector<bool> flags(signal.samples.size());
      for (Eigen::Index j = 0; j < signal.samples.size(); ++j) flags[j] = signal.samples(j) > 0;
      const PhaseCount count = CountPhases(flags, 0.0);
      phases.push_back({"contact", count.count, count.fraction});
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
    s.phases = Phases(system, s.signals.measures, s.y, omega);
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
