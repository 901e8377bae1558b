// nfrc.solve_at: every solution of a case's branch at one ω (all crossings, across folds).
#include "analysis/solve_at.h"

#include <pybind11/eigen.h>

#include <algorithm>
#include <iostream>

#include "bindings.h"
#include "core/errors.h"

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
          // As for a trace's signals_at crossings: the branch point the solution follows
          // (CrossingSolution counts the point that ends the crossed segment).
          view.signals.after_point = std::max(0, s.after_point - 1);
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
