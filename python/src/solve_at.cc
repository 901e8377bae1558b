// nfrc.solve_at: every solution of a case's branch at one ω (all crossings, across folds).
#include <pybind11/eigen.h>

#include <algorithm>
#include <iostream>

#include "bindings.h"
#include "core/errors.h"

#if __has_include("analysis/solve_at.h")
#include "analysis/solve_at.h"
#else
// Until analysis/solve_at.h (being written) lands: the same declarations, computed from
// TraceCase's signals_at crossings (the case traced with signals_at = {ω}) with every DOF
// recovered from each solution. Phase summaries are left empty.
namespace nfrc {
namespace {

struct PhaseSummary {
  std::string name;
  int count = 0;
  double fraction = 0.0;
};

struct CrossingSolution {
  double omega = 0.0;
  int after_point = 0;
  std::string label;  // by energy: "only", "lower"/"upper", "lower"/"middle"/"upper", ...
  bool converged = false;
  std::string message;
  Eigen::VectorXd y;
  Eigen::MatrixXd coefficients;  // every model DOF × coefficient
  SolutionSignals signals;
  std::vector<PhaseSummary> phases;
};

struct SolveAtResult {
  TraceResult trace;
  std::vector<CrossingSolution> solutions;
};

void LabelByEnergy(std::vector<CrossingSolution>& solutions) {
  std::vector<CrossingSolution*> converged;
  for (CrossingSolution& s : solutions) {
    if (s.converged) {
      converged.push_back(&s);
    } else {
      s.label = "not converged";
    }
  }
  std::sort(converged.begin(), converged.end(), [](const auto* a, const auto* b) {
    return a->signals.measures.response.energy < b->signals.measures.response.energy;
  });
  const size_t n = converged.size();
  for (size_t i = 0; i < n; ++i) {
    static const char* const kTwo[] = {"lower", "upper"};
    static const char* const kThree[] = {"lower", "middle", "upper"};
    converged[i]->label =
        n == 1   ? std::string("only")
        : n == 2 ? std::string(kTwo[i])
        : n == 3 ? std::string(kThree[i])
                 : "solution " + std::to_string(i + 1) + " of " + std::to_string(n) + " by energy";
  }
}

SolveAtResult SolveAt(const Case& the_case, double omega, const TraceOptions& options = {}) {
  if (the_case.method != Method::kArclength) {
    throw InputError("continuation.method: solve_at needs the arclength method");
  }
  const ContinuationOptions& range = the_case.continuation;
  if (!(omega >= range.LowerBound() && omega <= range.UpperBound())) {
    throw InputError("omega: " + std::to_string(omega) + " is outside the case's range [" +
                     std::to_string(range.LowerBound()) + ", " +
                     std::to_string(range.UpperBound()) + "]");
  }
  Case crossing = the_case;
  crossing.signals_at = {omega};
  TraceOptions trace_options = options;
  trace_options.solve_signals = true;
  SolveAtResult result;
  result.trace = TraceCase(crossing, trace_options);
  std::unique_ptr<HarmonicSystem> system = BuildSystem(crossing);
  for (const SolutionSignals& s : result.trace.signals) {
    CrossingSolution& solution = result.solutions.emplace_back();
    solution.omega = s.omega;
    solution.after_point = s.after_point;
    solution.converged = s.converged;
    solution.message = s.note;
    solution.y = s.y;
    solution.coefficients = system->AllDofCoefficients(s.y, s.omega);
    solution.signals = s;
  }
  LabelByEnergy(result.solutions);
  return result;
}

}  // namespace
}  // namespace nfrc
#endif

namespace nfrc::python {

void BindSolveAt(py::module_& m) {
  using namespace pybind11::literals;
  // Returns (solutions, branch); nfrc.solve_at raises nfrc.Interrupted with the branch when
  // Ctrl-C stopped the trace.
  m.def(
      "_solve_at",
      [](const PyCase& c, double omega, bool progress) {
        Case the_case = c.value;  // other Python threads may change `c` meanwhile
        InterruptWatch watch;
        TraceOptions options;
        options.progress = progress ? &std::cerr : nullptr;
        options.stop = watch.stop();
        options.observer = &watch;
        auto naming = std::make_shared<OutputNaming>(the_case);
        SolveAtResult result;
        {
          py::gil_scoped_release release;
          result = SolveAt(the_case, omega, options);
        }
        const bool interrupted = watch.Finish();
        std::vector<SolutionView> solutions;
        for (CrossingSolution& s : result.solutions) {
          SolutionView& view = solutions.emplace_back();
          view.signals = std::move(s.signals);
          view.signals.omega = s.omega;
          view.signals.after_point = s.after_point;
          view.signals.converged = s.converged;
          view.signals.note = s.message;
          view.signals.y = std::move(s.y);
          view.label = s.label;
          view.coefficients = std::move(s.coefficients);
          for (const PhaseSummary& phase : s.phases) {
            view.phases.push_back({phase.name, phase.count, phase.fraction});
          }
          view.naming = naming;
        }
        BranchView branch{std::move(result.trace), naming, interrupted};
        return py::make_tuple(std::move(solutions), std::move(branch));
      },
      "case"_a, "omega"_a, "progress"_a = false);
}

}  // namespace nfrc::python
