// The Case and its harmonic set as Python classes (the model's parts: model.cc). Cases come from
// the JSON reader (tools/case_file.h), so parsing has one implementation; fields are then read and
// changed here, each change validated (Case::Validate) and undone if it fails.
#include <cstring>
#include <nlohmann/json.hpp>
#include <variant>

#include "bindings.h"
#include "core/errors.h"
#include "tools/case_file.h"
#include "tools/case_manifest.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;

// The continuation options under their case-file names.
using OptionMember = std::variant<double ContinuationOptions::*, int ContinuationOptions::*,
                                  bool ContinuationOptions::*>;
const std::vector<std::pair<const char*, OptionMember>>& Options() {
  using O = ContinuationOptions;
  static const std::vector<std::pair<const char*, OptionMember>> options = {
      {"omega_start", &O::lambda_start},
      {"omega_end", &O::lambda_end},
      {"step", &O::initial_step},
      {"min_step", &O::min_step},
      {"max_step", &O::max_step},
      {"max_points", &O::max_points},
      {"max_newton_iterations", &O::max_newton_iterations},
      {"target_newton_iterations", &O::target_newton_iterations},
      {"newton_tolerance", &O::newton_tolerance},
      {"residual_tolerance", &O::residual_tolerance},
      {"max_tangent_angle", &O::max_tangent_angle},
      {"plot_tolerance", &O::plot_tolerance},
      {"max_plot_turn_angle", &O::max_plot_turn_angle},
      {"detect_folds", &O::detect_folds},
      {"fold_tolerance", &O::fold_tolerance},
      {"line_search", &O::line_search},
  };
  return options;
}

py::dict GetContinuation(const Case& c) {
  py::dict d;
  d["method"] = ToString(c.method);
  for (const auto& [name, member] : Options()) {
    std::visit([&, name = name](auto m) { d[name] = c.continuation.*m; }, member);
  }
  d["plot_measure"] = c.plot_measure == PlotMeasure::kEnergy ? "energy" : "max_abs";
  d["points"] = c.stepping.points;
  d["track_contact"] = c.stepping.track_contact;
  d["start_homotopy"] = c.start.homotopy;
  d["start_homotopy_factor"] = c.start.homotopy_factor;
  d["start_homotopy_rungs"] = c.start.homotopy_rungs;
  return d;
}

void SetOption(Case& c, const std::string& key, const py::handle& value) {
  const std::string field = "continuation." + key;
  if (key == "method") {
    const auto method = Cast<std::string>(value, field, "a string");
    if (method != "arclength" && method != "lemke_stepping") {
      throw InputError(field + ": must be \"arclength\" or \"lemke_stepping\", got \"" + method +
                       "\"");
    }
    c.method = method == "arclength" ? Method::kArclength : Method::kLemkeStepping;
    return;
  }
  if (key == "plot_measure") {
    const auto measure = Cast<std::string>(value, field, "a string");
    if (measure != "max_abs" && measure != "energy") {
      throw InputError(field + ": must be \"max_abs\" or \"energy\", got \"" + measure + "\"");
    }
    c.plot_measure = measure == "energy" ? PlotMeasure::kEnergy : PlotMeasure::kMaxAbs;
    return;
  }
  if (key == "points") {
    c.stepping.points = Cast<int>(value, field, "an integer");
    return;
  }
  if (key == "track_contact") {
    c.stepping.track_contact = Cast<bool>(value, field, "a bool");
    return;
  }
  if (key == "start_homotopy") {
    c.start.homotopy = Cast<bool>(value, field, "a bool");
    return;
  }
  if (key == "start_homotopy_factor") {
    c.start.homotopy_factor = Cast<double>(value, field, "a number");
    return;
  }
  if (key == "start_homotopy_rungs") {
    c.start.homotopy_rungs = Cast<int>(value, field, "an integer");
    return;
  }
  for (const auto& [name, member] : Options()) {
    if (key != name) continue;
    std::visit(
        [&](auto m) {
          using T = std::remove_reference_t<decltype(c.continuation.*m)>;
          c.continuation.*m = Cast<T>(value, field,
                                      std::is_same_v<T, double> ? "a number"
                                      : std::is_same_v<T, int>  ? "an integer"
                                                                : "a bool");
        },
        member);
    return;
  }
  std::string known =
      "method, points, track_contact, start_homotopy, start_homotopy_factor, start_homotopy_rungs";
  for (const auto& option : Options()) known += std::string(", ") + option.first;
  throw InputError(field + ": unknown option (known: " + known + ")");
}

std::string Repr(const Case& c) {
  std::string laws;
  for (const LawSpec& law : c.laws) laws += (laws.empty() ? "" : ", ") + std::string(LawType(law));
  const HarmonicSet& h = c.harmonics;
  return "<nfrc.Case" + (c.title.empty() ? "" : " '" + c.title + "'") + ": " +
         std::to_string(c.model.model.num_dofs()) + " DOFs, H=" + std::to_string(h.max_harmonic()) +
         (h.odd_only() ? " odd" : "") + ", N_t=" + std::to_string(h.num_samples()) + ", laws [" +
         laws + "], omega " +
         py::repr(py::float_(c.continuation.lambda_start)).cast<std::string>() + " -> " +
         py::repr(py::float_(c.continuation.lambda_end)).cast<std::string>() + ">";
}

HarmonicSet MakeHarmonics(int max, bool odd_only, int samples) {
  if (max < 1) throw InputError("harmonics.max: must be at least 1, got " + std::to_string(max));
  if (samples != 0 && samples < 2 * max + 1) {
    throw InputError("harmonics.samples: must be at least 2*max+1 = " +
                     std::to_string(2 * max + 1) + ", got " + std::to_string(samples));
  }
  ProblemDimensions dimensions;  // refuse what cannot fit before allocating
  dimensions.max_harmonic = max;
  dimensions.odd_only = odd_only;
  dimensions.samples = samples;
  CheckProblemSize(dimensions);
  try {
    return HarmonicSet(max, odd_only, samples);
  } catch (const std::invalid_argument& error) {
    throw InputError(std::string("harmonics.") + error.what());
  }
}

}  // namespace

void ValidateCase(const Case& the_case) {
  try {
    the_case.Validate();
  } catch (const InputError& error) {
    static const std::pair<const char*, const char*> kRenames[] = {
        {"continuation.lambda_start", "continuation.omega_start"},
        {"continuation.lambda_end", "continuation.omega_end"},
        {"continuation.initial_step", "continuation.step"},
    };
    std::string message = error.what();
    for (const auto& [engine, file] : kRenames) {
      if (message.rfind(engine, 0) == 0) message = file + message.substr(std::strlen(engine));
    }
    throw InputError(message);
  }
}

void BindCase(py::module_& m) {
  py::class_<HarmonicSet>(m, "HarmonicSet", "Harmonics 0..max (or odd ones) and N_t samples.")
      .def(py::init(&MakeHarmonics), "max"_a, "odd_only"_a = false, "samples"_a = 0)
      .def_property_readonly("max", &HarmonicSet::max_harmonic)
      .def_property_readonly("odd_only", &HarmonicSet::odd_only)
      .def_property_readonly("samples", &HarmonicSet::num_samples)
      .def_property_readonly("harmonics", &HarmonicSet::harmonics)
      .def_property_readonly("num_coefficients", &HarmonicSet::NumCoefficients)
      .def("__eq__",
           [](const HarmonicSet& a, const HarmonicSet& b) {
             return a.max_harmonic() == b.max_harmonic() && a.odd_only() == b.odd_only() &&
                    a.num_samples() == b.num_samples();
           })
      .def("__repr__", [](const HarmonicSet& h) {
        return "HarmonicSet(max=" + std::to_string(h.max_harmonic()) +
               ", odd_only=" + (h.odd_only() ? "True" : "False") +
               ", samples=" + std::to_string(h.num_samples()) + ")";
      });

  py::class_<PyCase> cls(m, "Case");
  cls.def_static("_from_json",
                 [](const std::string& text, const std::string& base_dir) {
                   nlohmann::json source;
                   try {
                     source = nlohmann::json::parse(text);
                   } catch (const nlohmann::json::parse_error& error) {
                     throw InputError(std::string("case: not valid JSON (") + error.what() + ")");
                   }
                   return PyCase{ParseCase(source, base_dir)};
                 })
      .def_static("_load", [](const std::string& path) { return PyCase{LoadCase(path)}; })
      .def_static("_manifest_members",
                  [](const std::string& path) {
                    std::vector<std::string> names;
                    for (const CaseVariant& variant : ReadManifest(path).variants) {
                      names.push_back(path + "#" + variant.name);
                    }
                    return names;
                  })
      .def("copy", [](const PyCase& c) { return PyCase{c.value}; })
      .def("__copy__", [](const PyCase& c) { return PyCase{c.value}; })
      .def("__deepcopy__", [](const PyCase& c, const py::object&) { return PyCase{c.value}; })
      .def("__repr__", [](const PyCase& c) { return Repr(c.value); })
      .def("validate", [](const PyCase& c) { ValidateCase(c.value); })
      .def("_begin_edit",
           [](PyCase& c) {
             if (c.editing++ == 0) c.saved = c.value;
           })
      .def("_end_edit",
           [](PyCase& c, bool keep) {
             if (--c.editing > 0) return;
             try {
               if (keep) ValidateCase(c.value);
             } catch (...) {
               keep = false;
               c.value = std::move(*c.saved);
               c.saved.reset();
               throw;
             }
             if (!keep) c.value = std::move(*c.saved);
             c.saved.reset();
           })
      .def_property(
          "title", [](const PyCase& c) { return c.value.title; },
          [](PyCase& c, std::string v) { c.value.title = std::move(v); })
      .def_property_readonly("path", [](const PyCase& c) { return c.value.path; })
      .def_property(
          "harmonics", [](const PyCase& c) { return c.value.harmonics; },
          [](PyCase& c, const HarmonicSet& h) { Modify(c, [&](Case& v) { v.harmonics = h; }); })
      .def("_continuation", [](const PyCase& c) { return GetContinuation(c.value); })
      .def("_set_continuation",
           [](PyCase& c, const py::dict& options) {
             Modify(c, [&](Case& v) {
               for (const auto& [key, value] : options) {
                 SetOption(v, key.cast<std::string>(), value);
               }
             });
           })
      .def("_stability", [](const PyCase& c) { return GetStability(c.value.stability); })
      .def("_set_stability",
           [](PyCase& c, const py::dict& options) {
             Modify(c, [&](Case& v) {
               for (const auto& [key, value] : options) {
                 SetStabilityOption(v.stability, key.cast<std::string>(), value);
               }
             });
           })
      .def_property(
          "output_dofs", [](const PyCase& c) { return c.value.output_dofs; },
          [](PyCase& c, const py::list& dofs) {
            Modify(c, [&](Case& v) {
              v.output_dofs.clear();
              v.output_names.clear();
              for (size_t i = 0; i < dofs.size(); ++i) {
                const std::string field = "output.dofs[" + std::to_string(i) + "]";
                v.output_dofs.push_back(DofIndex(v, dofs[i], field));
                v.output_names.push_back(py::isinstance<py::str>(dofs[i])
                                             ? dofs[i].cast<std::string>()
                                             : std::to_string(v.output_dofs.back()));
              }
            });
          })
      .def_property_readonly("output_names", [](const PyCase& c) { return c.value.output_names; })
      .def_property(
          "signals_at", [](const PyCase& c) { return c.value.signals_at; },
          [](PyCase& c, std::vector<double> omegas) {
            Modify(c, [&](Case& v) { v.signals_at = std::move(omegas); });
          })
      .def_property(
          "_laws", [](const PyCase& c) { return c.value.laws; },
          [](PyCase& c, std::vector<LawSpec> laws) {
            Modify(c, [&](Case& v) { v.laws = std::move(laws); });
          });
  BindModel(m, cls);
}

}  // namespace nfrc::python
