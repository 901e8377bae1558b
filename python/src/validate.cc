// nfrc.validate: the HBM branch checked against transient integration at chosen ω.
#include "analysis/validate.h"

#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include <iostream>

#include "bindings.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;

// Lets Ctrl-C stop a validation: the trace's points and every transient poll the watch.
class ValidationWatch : public ValidationObserver {
 public:
  explicit ValidationWatch(InterruptWatch& watch) : watch_(watch) {}
  TraceObserver* OnTraceStart() override { return &watch_; }
  void OnTransient(const ValidationPoint& /*point*/) override { watch_.OnPoint(TracePoint{}); }

 private:
  InterruptWatch& watch_;
};

py::dict TransientDict(const ValidationPoint& point, const TransientRun& run) {
  py::dict d;
  d["start"] = run.start;
  d["status"] = std::string(ToString(run.result.status));
  d["message"] = run.result.message;
  d["method"] = run.result.method;
  d["periods"] = run.result.periods;
  d["period_multiple"] = run.result.period_multiple;
  d["wall_time"] = run.result.wall_seconds;
  d["steps"] = run.result.steps;
  d["events"] = run.result.events;
  if (run.recorded) {
    d["max_abs"] = run.measures.max_abs;
    d["h1"] = run.measures.h1;
    d["energy"] = run.measures.energy;
    d["energy_balance_defect"] = run.measures.energy_balance_defect;
  }
  if (run.comparison) {
    const TransientComparison& c = *run.comparison;
    d["matched"] = point.solutions[c.solution].label;
    d["stayed"] = c.stayed;
    d["difference"] = py::dict("h1"_a = c.h1, "max_abs"_a = c.max_abs, "energy"_a = c.energy,
                               "rms"_a = c.rms, "same_phase_counts"_a = c.same_phase_counts);
  }
  return d;
}

py::dict PointDict(const ValidationPoint& point) {
  py::list solutions;
  for (size_t i = 0; i < point.solutions.size(); ++i) {
    const CrossingSolution& s = point.solutions[i];
    const PointMeasures& m = s.signals.measures.response;
    py::dict solution("label"_a = s.label, "max_abs"_a = m.max_abs, "h1"_a = m.h1,
                      "energy"_a = m.energy);
    if (i < point.stability.size()) {
      const SolutionStability& stability = point.stability[i];
      // Hill's multipliers (a Floquet) and the transient monodromy's, as validation.json has
      // them; None when not computed.
      solution["hill"] = stability.hill.computed ? py::cast(stability.hill) : py::none();
      if (stability.monodromy) {
        const MonodromyResult& mono = *stability.monodromy;
        solution["monodromy"] = py::dict(
            "ok"_a = mono.ok, "message"_a = mono.message, "multipliers"_a = mono.multipliers,
            "max_modulus"_a = mono.max_modulus(), "closure"_a = mono.closure,
            "state_own"_a = mono.state_own, "integrations"_a = mono.integrations);
      } else {
        solution["monodromy"] = py::none();
      }
      solution["difference_to_monodromy"] =
          stability.multiplier_difference ? py::cast(*stability.multiplier_difference) : py::none();
    }
    solutions.append(std::move(solution));
  }
  py::list transients;
  for (const TransientRun& run : point.transients) transients.append(TransientDict(point, run));
  return py::dict("omega"_a = point.omega, "solutions"_a = solutions, "transients"_a = transients,
                  "primary"_a = point.primary);
}

}  // namespace

void BindValidate(py::module_& m) {
  using namespace pybind11::literals;
  // Returns (result dict, branch); nfrc.validate raises nfrc.Interrupted with the branch when
  // Ctrl-C stopped it.
  m.def(
      "_validate",
      [](const PyCase& c, const std::vector<double>& omegas, const std::string& start, bool chirp,
         bool progress) {
        Case the_case = c.value;  // other Python threads may change `c` meanwhile
        ValidationSettings settings = the_case.validation;
        if (!omegas.empty()) settings.omegas = omegas;
        if (start == "rest") {
          settings.start = ValidationSettings::Start::kRest;
        } else if (start == "hbm") {
          settings.start = ValidationSettings::Start::kHbm;
        } else {
          throw InputError("start: expected \"hbm\" or \"rest\", got \"" + start + "\"");
        }
        if (!chirp) settings.chirp.enabled = false;
        if (settings.omegas.empty() && !settings.chirp.enabled) {
          throw InputError(
              "omegas: no frequencies to validate (give omegas or the case's "
              "validation.omega)");
        }
        InterruptWatch watch;
        ValidationWatch observer(watch);
        ValidationOptions options;
        options.progress = progress ? &std::cerr : nullptr;
        options.stop = watch.stop();
        options.observer = &observer;
        auto naming = std::make_shared<OutputNaming>(the_case);
        ValidationResult result;
        {
          py::gil_scoped_release release;
          result = nfrc::ValidateCase(the_case, settings, options);
        }
        const bool interrupted = watch.Finish();
        py::list points;
        for (const ValidationPoint& point : result.points) points.append(PointDict(point));
        py::list chirps;
        for (const ChirpRun& run : result.chirps) {
          py::list omega, energy;
          for (const ChirpCycle& cycle : run.result.cycles) {
            omega.append(cycle.omega);
            energy.append(cycle.mean_energy);
          }
          chirps.append(py::dict("direction"_a = run.direction,
                                 "status"_a = ChirpStatusName(run.result.status), "omega"_a = omega,
                                 "energy"_a = energy));
        }
        py::dict out("complete"_a = result.complete, "points"_a = points, "chirps"_a = chirps);
        BranchView branch{std::move(result.trace), naming, interrupted};
        return py::make_tuple(out, std::move(branch));
      },
      "case"_a, "omegas"_a, "start"_a = "hbm", "chirp"_a = false, "progress"_a = false);
}

}  // namespace nfrc::python
