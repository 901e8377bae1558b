// Stability as Python sees it: a case's stability options (case-file names), the Floquet
// result of a traced point and the bifurcations of a branch.
#include <pybind11/complex.h>

#include "bindings.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;

const char kStabilityOptions[] =
    "enabled, unstable_tolerance, bifurcation_tolerance, max_bifurcation_iterations, "
    "jump_tolerance, hill_modes";

py::dict ResponseMeasures(const PointMeasures& m) {
  return py::dict("energy"_a = m.energy, "max_abs"_a = m.max_abs, "min"_a = m.min, "max"_a = m.max,
                  "h1"_a = m.h1);
}

// None, not False, when not analysed: "unknown" must not read as "unstable".
py::object Stable(const FloquetResult& f) {
  return f.computed ? py::object(py::bool_(f.stable())) : py::object(py::none());
}

}  // namespace

py::dict GetStability(const StabilityOptions& s) {
  return py::dict("enabled"_a = s.enabled, "unstable_tolerance"_a = s.unstable_tolerance,
                  "bifurcation_tolerance"_a = s.bifurcation_tolerance,
                  "max_bifurcation_iterations"_a = s.max_bifurcation_iterations,
                  "jump_tolerance"_a = s.jump_tolerance, "hill_modes"_a = s.hill_modes);
}

void SetStabilityOption(StabilityOptions& s, const std::string& key, const py::handle& value) {
  const std::string field = "stability." + key;
  if (key == "enabled") {
    // pybind11 would convert numbers and None too, which the case file refuses; numpy's
    // bool still passes.
    const bool number = py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value);
    if (value.is_none() || (number && !py::isinstance<py::bool_>(value))) {
      throw InputError(field + ": expected a bool, got " + py::str(value).cast<std::string>());
    }
    s.enabled = Cast<bool>(value, field, "a bool");
  } else if (key == "unstable_tolerance") {
    s.unstable_tolerance = Cast<double>(value, field, "a number");
  } else if (key == "bifurcation_tolerance") {
    s.bifurcation_tolerance = Cast<double>(value, field, "a number");
  } else if (key == "max_bifurcation_iterations") {
    s.max_bifurcation_iterations = Cast<int>(value, field, "an integer");
  } else if (key == "jump_tolerance") {
    s.jump_tolerance = Cast<double>(value, field, "a number");
  } else if (key == "hill_modes") {
    s.hill_modes = Cast<int>(value, field, "an integer");
  } else {
    throw InputError(field + ": unknown option (known: " + kStabilityOptions + ")");
  }
}

py::list StableFlags(const std::vector<TracePoint>& points) {
  py::list flags;
  for (const TracePoint& point : points) flags.append(Stable(point.floquet));
  return flags;
}

void BindStability(py::module_& m) {
  py::class_<FloquetResult>(m, "Floquet", "Floquet exponents and multipliers of one solution.")
      .def_readonly("computed", &FloquetResult::computed)
      .def_readonly("message", &FloquetResult::message)
      .def_readonly("method", &FloquetResult::method)
      .def_readonly("exponents", &FloquetResult::exponents)
      .def_readonly("multipliers", &FloquetResult::multipliers)
      .def_readonly("max_modulus", &FloquetResult::max_modulus)
      .def_readonly("num_unstable", &FloquetResult::num_unstable)
      .def_readonly("seconds", &FloquetResult::seconds)
      .def_readonly("operator_applications", &FloquetResult::operator_applications)
      .def_property_readonly("stable", &Stable)
      .def("__repr__", [](const FloquetResult& f) {
        if (!f.computed) return std::string("<nfrc.Floquet not computed>");
        return "<nfrc.Floquet " + f.method +
               ": max |mu|=" + py::repr(py::float_(f.max_modulus)).cast<std::string>() + ", " +
               std::to_string(f.num_unstable) + " unstable>";
      });

  py::class_<BifurcationView>(m, "Bifurcation", "A change of stability along a branch.")
      .def_property_readonly("type",
                             [](const BifurcationView& b) { return ToString(b.record.type); })
      .def_property_readonly(
          "omega", [](const BifurcationView& b) { return b.naming->omega_factor * b.record.omega; })
      .def_property_readonly(
          "omega_accuracy",
          [](const BifurcationView& b) { return b.naming->omega_factor * b.record.omega_accuracy; })
      .def_property_readonly("converged",
                             [](const BifurcationView& b) { return b.record.converged; })
      .def_property_readonly("iterations",
                             [](const BifurcationView& b) { return b.record.iterations; })
      .def_property_readonly("after_point",
                             [](const BifurcationView& b) { return b.record.after_point; })
      .def_property_readonly("discontinuous",
                             [](const BifurcationView& b) { return b.record.discontinuous; })
      .def_property_readonly("crossing_multipliers",
                             [](const BifurcationView& b) { return b.record.crossing_multipliers; })
      .def_property_readonly("y", [](const BifurcationView& b) { return b.record.y; })
      .def_property_readonly(
          "measures", [](const BifurcationView& b) { return ResponseMeasures(b.record.measures); })
      .def(
          "measure",
          [](const BifurcationView& b, const std::string& name, const py::object& dof) {
            return ResponseMeasure(b.record.measures, name, b.naming->Find(dof), "bifurcations");
          },
          "name"_a, "dof"_a = 0)
      .def("__repr__", [](const BifurcationView& b) {
        return std::string("<nfrc.Bifurcation ") + ToString(b.record.type) +
               " omega=" + py::repr(py::float_(b.record.omega)).cast<std::string>() + ">";
      });
}

}  // namespace nfrc::python
