// nfrc.trace: TraceCase without the GIL (Ctrl-C stops it, keeping its points) and the
// Branch it returns: ω, measures per point as numpy arrays, folds, summary, solutions.
#include <pybind11/eigen.h>
#include <pythread.h>

#include <iostream>

#include "analysis/branch_switching.h"
#include "bindings.h"

namespace nfrc::python {

using namespace pybind11::literals;

InterruptWatch::InterruptWatch() {
  main_thread_ =
      PyThread_get_thread_ident() ==
      py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
}

bool InterruptWatch::OnPoint(const TracePoint& /*point*/) { return Poll(); }

bool InterruptWatch::Poll() {
  if (stop_.load()) return false;
  if (!main_thread_) return true;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() == 0) return true;
  if (PyErr_ExceptionMatches(PyExc_KeyboardInterrupt)) {
    PyErr_Clear();
    interrupted_ = true;
  } else {
    PyObject *type, *value, *trace;
    PyErr_Fetch(&type, &value, &trace);
    error_type_ = py::reinterpret_steal<py::object>(type);
    error_value_ = py::reinterpret_steal<py::object>(value);
    error_trace_ = py::reinterpret_steal<py::object>(trace);
  }
  stop_.store(true);
  return false;
}

bool InterruptWatch::Finish() {
  if (error_type_) {
    PyErr_Restore(error_type_.release().ptr(), error_value_.release().ptr(),
                  error_trace_.release().ptr());
    throw py::error_already_set();
  }
  return interrupted_;
}

void BindTrace(py::module_& m) {
  py::class_<BranchView>(m, "Branch", "A traced branch: points, measures, folds, summary.")
      .def_property_readonly("points", [](const BranchView& b) { return b.result.points.size(); })
      .def("__len__", [](const BranchView& b) { return b.result.points.size(); })
      .def_property_readonly("omega",
                             [](const BranchView& b) {
                               Eigen::VectorXd omega(b.result.points.size());
                               for (size_t i = 0; i < b.result.points.size(); ++i) {
                                 omega(i) =
                                     b.naming->omega_factor * b.result.points[i].point.lambda;
                               }
                               return omega;
                             })
      .def_property_readonly("y",
                             [](const BranchView& b) {
                               Eigen::MatrixXd y(b.result.points.size(), b.result.num_unknowns);
                               for (size_t i = 0; i < b.result.points.size(); ++i) {
                                 y.row(i) = b.result.points[i].point.y.transpose();
                               }
                               return y;
                             })
      .def(
          "measure",
          [](const BranchView& b, const std::string& name, const py::object& dof) {
            const int output = b.naming->Find(dof);
            Eigen::VectorXd values(b.result.points.size());
            for (size_t i = 0; i < b.result.points.size(); ++i) {
              values(i) = MeasureOf(b.result.points[i].measures, name, output);
            }
            return values;
          },
          "name"_a, "dof"_a = 0)
      .def_property_readonly("folds",
                             [](const BranchView& b) {
                               std::vector<FoldView> folds;
                               for (const auto& f : b.result.folds) folds.push_back({f, b.naming});
                               return folds;
                             })
      .def_property_readonly("stable",
                             [](const BranchView& b) { return StableFlags(b.result.points); })
      .def_property_readonly("floquet",
                             [](const BranchView& b) {
                               std::vector<FloquetResult> floquet;
                               for (const auto& p : b.result.points) floquet.push_back(p.floquet);
                               return floquet;
                             })
      .def_property_readonly("bifurcations",
                             [](const BranchView& b) {
                               std::vector<BifurcationView> found;
                               for (const auto& f : b.result.bifurcations) {
                                 found.push_back({f, b.naming});
                               }
                               return found;
                             })
      .def_property_readonly(
          "quasi_periodic_windows",
          [](const BranchView& b) {
            py::list windows;
            const double f = b.naming->omega_factor;
            for (const QuasiPeriodicWindow& w : b.result.quasi_periodic_windows) {
              windows.append(py::dict("omega_from"_a = f * w.omega_from,
                                      "omega_to"_a = f * w.omega_to,
                                      "first_point"_a = w.first_point,
                                      "last_point"_a = w.last_point, "closed"_a = w.closed));
            }
            return windows;
          })
      .def_property_readonly(
          "period_multiple",
          [](const BranchView& b) { return static_cast<int>(b.naming->omega_factor); })
      .def_property_readonly("solutions",
                             [](const BranchView& b) {
                               std::vector<SolutionView> solutions;
                               for (const auto& s : b.result.signals) {
                                 solutions.push_back({s, "signals_at", std::nullopt, {}, b.naming});
                               }
                               return solutions;
                             })
      .def_property_readonly("summary", [](const BranchView& b) { return b.result.branch.summary; })
      .def_property_readonly("num_unknowns",
                             [](const BranchView& b) { return b.result.num_unknowns; })
      .def_property_readonly("output_names", [](const BranchView& b) { return b.naming->names; })
      .def_readonly("interrupted", &BranchView::interrupted)
      .def("__repr__", [](const BranchView& b) {
        return "<nfrc.Branch " + std::to_string(b.result.points.size()) + " points, " +
               std::to_string(b.result.folds.size()) + " folds, " +
               ToString(b.result.branch.summary.reason) + ">";
      });

  m.def(
      "_trace",
      [](const PyCase& c, bool progress, int threads) {
        // The analysis gets its own copy: other Python threads may change `c` meanwhile.
        Case the_case = c.value;
        InterruptWatch watch;
        TraceOptions options;
        options.threads = threads;  // TraceCase validates it
        options.progress = progress ? &std::cerr : nullptr;
        options.stop = watch.stop();
        options.observer = &watch;
        BranchView branch{{}, std::make_shared<OutputNaming>(the_case), false};
        {
          py::gil_scoped_release release;
          branch.result = TraceCase(the_case, options);
        }
        branch.interrupted = watch.Finish();
        return branch;
      },
      "case"_a, "progress"_a = false, "threads"_a = -1);

  m.def(
      "_switch_branch",
      [](const PyCase& c, const BifurcationView& bifurcation, bool progress, int threads) {
        const Case the_case = c.value;
        InterruptWatch watch;
        TraceOptions options;
        options.threads = threads;  // TraceCase validates it
        options.progress = progress ? &std::cerr : nullptr;
        options.stop = watch.stop();
        options.observer = &watch;
        SwitchedBranch switched;
        {
          py::gil_scoped_release release;
          switched = FollowBifurcation(the_case, bifurcation.record, options);
        }
        BranchView branch{std::move(switched.trace),
                          std::make_shared<OutputNaming>(switched.the_case), false};
        branch.interrupted = watch.Finish();
        return branch;
      },
      "case"_a, "bifurcation"_a, "progress"_a = false, "threads"_a = -1);
}

}  // namespace nfrc::python
