// The typed results as Python sees them: Summary, Fold, Solution, and measures by name.
#include <pybind11/eigen.h>

#include "bindings.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;

const char kMeasureNames[] =
    "max_abs, min, max, h1, energy, min_gap, min_force (contact laws), law<i>_<diagnostic>";

py::dict Table(const SignalTable& table) {
  py::dict d;
  for (size_t i = 0; i < table.names.size(); ++i) d[py::str(table.names[i])] = table.columns[i];
  return d;
}

bool IsDigits(const std::string& text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

double ResponseMeasure(const PointMeasures& measures, const std::string& name, int output,
                       const std::string& where) {
  if (name == "min_gap" || name == "min_force" || name.rfind("law", 0) == 0) {
    throw InputError("measure: \"" + name + "\" is not recorded at " + where +
                     " (max_abs, min, max, h1, energy are)");
  }
  return MeasureOf(SolutionMeasures{measures, {}, {}, {}}, name, output);
}

OutputNaming::OutputNaming(const Case& c) : names(c.output_names), omega_factor(c.period_multiple) {
  for (int dof : c.output_dofs) {
    const auto& all = c.model.model.dof_names;
    dof_names.push_back(dof < static_cast<int>(all.size()) ? all[dof] : std::string());
  }
}

int OutputNaming::Find(const py::handle& dof) const {
  const int n = static_cast<int>(names.size());
  if (py::isinstance<py::str>(dof)) {
    const std::string name = dof.cast<std::string>();
    for (int i = 0; i < n; ++i) {
      if (names[i] == name || (!dof_names[i].empty() && dof_names[i] == name)) return i;
    }
    std::string known;
    for (const auto& s : names) known += (known.empty() ? "" : ", ") + s;
    throw InputError("dof: \"" + name + "\" is not an output DOF (outputs: " + known + ")");
  }
  const int index = dof.cast<int>();
  if (index < 0 || index >= n) {
    throw InputError("dof: output index " + std::to_string(index) + " out of range (the case has " +
                     std::to_string(n) + " output DOFs)");
  }
  return index;
}

double MeasureOf(const SolutionMeasures& m, const std::string& name, int output) {
  const PointMeasures& r = m.response;
  if (name == "max_abs") return r.max_abs.at(output);
  if (name == "min") return r.min.at(output);
  if (name == "max") return r.max.at(output);
  if (name == "h1") return r.h1.at(output);
  if (name == "energy") return r.energy;
  if (name == "min_gap" || name == "min_force") {
    const std::optional<double>& value = name == "min_gap" ? m.min_gap : m.min_force;
    if (!value) throw InputError("measure: \"" + name + "\" needs a contact law");
    return *value;
  }
  // law<i>_<diagnostic>, as the signal columns name the laws.
  size_t end = 0;
  if (name.rfind("law", 0) == 0 && (end = name.find('_')) != std::string::npos &&
      IsDigits(name.substr(3, end - 3))) {
    const int law = std::stoi(name.substr(3, end - 3));
    const std::string key = name.substr(end + 1);
    if (law >= 0 && law < static_cast<int>(m.laws.size())) {
      if (const auto it = m.laws[law].find(key); it != m.laws[law].end()) return it->second;
    }
  }
  throw InputError("measure: unknown \"" + name + "\" (known: " + kMeasureNames + ")");
}

void BindResults(py::module_& m) {
  py::class_<StepRecord>(m, "Step", "One continuation step, accepted or rejected.")
      .def_readonly("step", &StepRecord::step)
      .def_readonly("newton_iterations", &StepRecord::newton_iterations)
      .def_readonly("accepted", &StepRecord::accepted)
      .def_readonly("fixed_lambda", &StepRecord::fixed_lambda)
      .def_readonly("note", &StepRecord::note)
      .def("__repr__", [](const StepRecord& s) {
        return std::string("<nfrc.Step ") + (s.accepted ? "accepted" : "rejected") +
               " step=" + py::repr(py::float_(s.step)).cast<std::string>() + ", " +
               std::to_string(s.newton_iterations) + " iterations>";
      });

  py::class_<ContinuationSummary>(m, "Summary", "How a trace ended, with its counts.")
      .def_property_readonly("termination",
                             [](const ContinuationSummary& s) { return ToString(s.reason); })
      .def_property_readonly("success", &ContinuationSummary::success)
      .def_readonly("message", &ContinuationSummary::message)
      .def_readonly("points", &ContinuationSummary::num_points)
      .def_readonly("folds", &ContinuationSummary::num_folds)
      .def_readonly("accepted_steps", &ContinuationSummary::num_accepted_steps)
      .def_readonly("rejected_steps", &ContinuationSummary::num_rejected_steps)
      .def_readonly("newton_iterations", &ContinuationSummary::total_newton_iterations)
      .def_readonly("evaluations", &ContinuationSummary::num_evaluations)
      .def_readonly("wall_time", &ContinuationSummary::wall_time_seconds)
      .def_readonly("notes", &ContinuationSummary::notes)
      .def_readonly("history", &ContinuationSummary::history)
      .def("__repr__", [](const ContinuationSummary& s) {
        return "<nfrc.Summary " + std::string(ToString(s.reason)) + ": " +
               std::to_string(s.num_points) + " points, " + std::to_string(s.num_folds) + " folds>";
      });

  py::class_<FoldView>(m, "Fold", "A turning point in omega.")
      .def_property_readonly(
          "omega", [](const FoldView& f) { return f.naming->omega_factor * f.record.fold.lambda; })
      .def_property_readonly("after_point",
                             [](const FoldView& f) { return f.record.fold.after_point; })
      .def_property_readonly(
          "omega_accuracy",
          [](const FoldView& f) { return f.naming->omega_factor * f.record.fold.lambda_accuracy; })
      .def_property_readonly("converged", [](const FoldView& f) { return f.record.fold.converged; })
      .def_property_readonly("corner", [](const FoldView& f) { return f.record.fold.corner; })
      .def_property_readonly("y", [](const FoldView& f) { return f.record.fold.y; })
      .def(
          "measure",
          [](const FoldView& f, const std::string& name, const py::object& dof) {
            return ResponseMeasure(f.record.measures, name, f.naming->Find(dof), "folds");
          },
          "name"_a, "dof"_a = 0)
      .def("__repr__", [](const FoldView& f) {
        return "<nfrc.Fold omega=" +
               py::repr(py::float_(f.record.fold.lambda)).cast<std::string>() + ">";
      });

  py::class_<SolutionView>(m, "Solution", "One periodic solution at a given omega.")
      .def_property_readonly(
          "omega", [](const SolutionView& s) { return s.naming->omega_factor * s.signals.omega; })
      .def_property_readonly("after_point",
                             [](const SolutionView& s) { return s.signals.after_point; })
      .def_readonly("label", &SolutionView::label)
      .def_property_readonly("converged", [](const SolutionView& s) { return s.signals.converged; })
      .def_property_readonly("message", [](const SolutionView& s) { return s.signals.note; })
      .def_property_readonly("y", [](const SolutionView& s) { return s.signals.y; })
      .def_property_readonly("coefficients", [](const SolutionView& s) { return s.coefficients; })
      .def_property_readonly("signals", [](const SolutionView& s) { return Table(s.signals.fine); })
      .def_property_readonly("samples",
                             [](const SolutionView& s) { return Table(s.signals.samples); })
      .def_property_readonly(
          "phases",
          [](const SolutionView& s) {
            py::list phases;
            for (const auto& [name, count, fraction] : s.phases) {
              phases.append(py::dict("name"_a = name, "count"_a = count, "fraction"_a = fraction));
            }
            return phases;
          })
      .def_property_readonly("laws", [](const SolutionView& s) { return s.signals.measures.laws; })
      .def(
          "measure",
          [](const SolutionView& s, const std::string& name, const py::object& dof) {
            return MeasureOf(s.signals.measures, name, s.naming->Find(dof));
          },
          "name"_a, "dof"_a = 0)
      .def("__repr__", [](const SolutionView& s) {
        return "<nfrc.Solution " + s.label +
               " omega=" + py::repr(py::float_(s.signals.omega)).cast<std::string>() +
               (s.signals.converged ? "" : " (not converged)") + ">";
      });
}

}  // namespace nfrc::python
