// nfrc.fold_curve, nfrc.peak_curve and nfrc.sweep: studies in further parameters of a case.
#include "analysis/fold_curve.h"

#include <algorithm>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/case_parameter.h"
#include "analysis/event_curve.h"
#include "bindings.h"
#include "tools/sweep.h"

namespace nfrc::python {

using namespace pybind11::literals;

namespace {

py::dict CurveDict(const FoldCurve& curve, const std::vector<std::string>& output_names) {
  py::list parameter, omega, energy, max_abs, turns;
  for (const FoldCurvePoint& point : curve.points) {
    parameter.append(point.parameter);
    omega.append(point.omega);
    energy.append(point.energy);
    py::dict per_output;
    for (size_t i = 0; i < point.max_abs.size() && i < output_names.size(); ++i) {
      per_output[py::str(output_names[i])] = point.max_abs[i];
    }
    max_abs.append(per_output);
  }
  for (const FoldCurveTurn& turn : curve.turns) {
    turns.append(py::dict("parameter"_a = turn.parameter, "omega"_a = turn.omega,
                          "after_point"_a = turn.after_point, "cusp"_a = turn.cusp));
  }
  return py::dict("start_fold"_a = curve.start_fold, "start_omega"_a = curve.start_omega,
                  "termination"_a = ToString(curve.summary.reason),
                  "message"_a = curve.summary.message, "parameter"_a = parameter, "omega"_a = omega,
                  "energy"_a = energy, "max_abs"_a = max_abs, "turns"_a = turns);
}

// nfrc.sweep's loop: one branch per grid point, each case made by case_at(k, point); a value
// the case refuses fails that run only, Ctrl-C stops the running branch and leaves the rest
// pending.
py::list SweepRuns(const SweepGrid& grid,
                   const std::function<Case(size_t, const std::vector<double>&)>& case_at,
                   bool progress) {
  CheckGrid(grid);
  py::list runs;
  bool interrupted = false;
  for (size_t k = 0; k < GridSize(grid); ++k) {
    const std::vector<double> point = GridPoint(grid, k);
    py::dict values;
    for (size_t i = 0; i < grid.size(); ++i) values[py::str(grid[i].path)] = point[i];
    py::dict run("values"_a = values);
    if (interrupted) {
      run["status"] = "pending";
      runs.append(run);
      continue;
    }
    // A value the case refuses is the run's status, not the end of the sweep.
    std::optional<Case> at_point;
    try {
      at_point = case_at(k, point);
    } catch (const InputError& error) {
      run["status"] = "failed";
      run["message"] = error.what();
      runs.append(run);
      continue;
    }
    InterruptWatch watch;
    TraceOptions options;
    options.progress = progress ? &std::cerr : nullptr;
    options.stop = watch.stop();
    options.observer = &watch;
    BranchView branch{{}, std::make_shared<OutputNaming>(*at_point), false};
    {
      py::gil_scoped_release release;
      branch.result = TraceCase(*at_point, options);
    }
    branch.interrupted = watch.Finish();
    interrupted = branch.interrupted;
    const ContinuationSummary& summary = branch.result.branch.summary;
    const bool complete = summary.success() || summary.reason == TerminationReason::kMaxPoints;
    run["status"] = interrupted ? "interrupted" : complete ? "complete" : "failed";
    run["message"] = summary.message;
    run["branch"] = std::move(branch);
    runs.append(run);
  }
  return runs;
}

}  // namespace

void BindFoldCurve(py::module_& m) {
  m.def(
      "_fold_curve",
      [](const PyCase& c, const std::string& path, double to, double max_step, bool progress) {
        const Case the_case = c.value;
        const CaseParameter parameter(path, the_case);
        FoldCurveOptions options;
        options.to = to;
        options.SetMaxStep(max_step);
        options.progress = progress ? &std::cerr : nullptr;
        InterruptWatch watch;
        options.poll = [&watch] { return watch.Poll(); };
        FoldCurveResult result;
        {
          py::gil_scoped_release release;
          result = TraceFoldCurves(the_case, parameter, options);
        }
        const bool interrupted = watch.Finish();
        py::list curves;
        for (const FoldCurve& curve : result.curves) {
          curves.append(CurveDict(curve, the_case.output_names));
        }
        return py::dict("parameter"_a = result.parameter, "from"_a = result.from,
                        "to"_a = result.to, "branch_folds"_a = result.branch_folds,
                        "notes"_a = result.notes, "curves"_a = curves,
                        "interrupted"_a = interrupted);
      },
      "case"_a, "parameter"_a, "to"_a, "max_step"_a = 0.1, "progress"_a = false);

  m.def(
      "_event_curve",
      [](const PyCase& c, const std::string& kind, const std::string& path, double to,
         const std::string& measure, double near, const std::vector<double>& at, double max_step,
         bool progress) {
        const Case the_case = c.value;
        const CaseParameter parameter(path, the_case);
        EventCurveOptions options;
        options.to = to;
        options.measure = ParsePeakMeasure(measure, the_case);
        options.near = near;
        options.stations = at;
        options.SetMaxStep(max_step);
        options.progress = progress ? &std::cerr : nullptr;
        InterruptWatch watch;
        options.poll = [&watch] { return watch.Poll(); };
        EventCurveResult result;
        {
          py::gil_scoped_release release;
          result = kind == "peak" ? TracePeakCurves(the_case, parameter, options)
                                  : TraceNeimarkSackerCurves(the_case, parameter, options);
        }
        const bool interrupted = watch.Finish();
        py::list curves;
        for (const EventCurve& curve : result.curves) {
          py::list parameter_values, omega, values;
          for (const EventCurvePoint& point : curve.points) {
            parameter_values.append(point.parameter);
            omega.append(point.omega);
            values.append(point.measure);
          }
          curves.append(py::dict("start_omega"_a = curve.start_omega,
                                 "termination"_a = ToString(curve.end), "message"_a = curve.message,
                                 "parameter"_a = parameter_values, "omega"_a = omega,
                                 "measure"_a = values, "solves"_a = curve.solves));
        }
        return py::dict("parameter"_a = result.parameter, "from"_a = result.from,
                        "to"_a = result.to, "measure"_a = result.measure,
                        "branch_events"_a = result.branch_events, "notes"_a = result.notes,
                        "curves"_a = curves, "interrupted"_a = interrupted);
      },
      "case"_a, "kind"_a, "parameter"_a, "to"_a, "measure"_a = "energy",
      "near"_a = std::numeric_limits<double>::quiet_NaN(), "at"_a = std::vector<double>{},
      "max_step"_a = 0.1, "progress"_a = false);

  m.def(
      "_sweep",
      [](const PyCase& c, const std::vector<std::pair<std::string, std::vector<double>>>& axes,
         bool progress) {
        const Case the_case = c.value;
        SweepGrid grid;
        for (const auto& [path, values] : axes)
          grid.push_back({CaseParameter(path, the_case), values});
        return SweepRuns(
            grid,
            [&](size_t, const std::vector<double>& point) {
              return CaseAtGridPoint(the_case, grid, point);
            },
            progress);
      },
      "case"_a, "axes"_a, "progress"_a = false);
  // A case file (or a manifest's member): any numeric field of its JSON, as `nfrc sweep`.
  m.def(
      "_sweep_file",
      [](const std::string& path,
         const std::vector<std::pair<std::string, std::vector<double>>>& axes, bool progress) {
        const CaseFile file = ReadCaseFile(path);
        SweepGrid grid;
        for (const auto& [field, values] : axes) grid.emplace_back(field, values);
        CheckGridPaths(file, grid);
        const SweepPlan plan(grid);
        return SweepRuns(
            grid,
            [&](size_t k, const std::vector<double>&) {
              return CaseForRun(file, plan, k).the_case;
            },
            progress);
      },
      "path"_a, "axes"_a, "progress"_a = false);
}

}  // namespace nfrc::python
