#pragma once

// Shared pieces of the _nfrc extension: the Python-side case, the observer that lets Ctrl-C
// stop an analysis running without the GIL, and the typed results as Python sees them.

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "analysis/case.h"
#include "analysis/trace.h"
#include "core/errors.h"

namespace nfrc::python {

namespace py = pybind11;

void BindLaws(py::module_& m);
void BindCase(py::module_& m);
void BindResults(py::module_& m);  // Summary, Fold, Solution
void BindTrace(py::module_& m);
void BindSolveAt(py::module_& m);
void BindValidate(py::module_& m);
void BindStability(py::module_& m);  // Floquet, Bifurcation
void BindFoldCurve(py::module_& m);

// A Case as Python holds it. Every setter validates the whole case and restores the old value
// on error, unless changes are batched by `with case.edit():` (then validated once at the end,
// so that e.g. the model and its laws can change size together).
struct PyCase {
  explicit PyCase(Case the_case) : value(std::move(the_case)) {}
  Case value;
  int editing = 0;            // depth of nested edit() blocks
  std::optional<Case> saved;  // the case before the outermost edit() block
};

// Case::Validate with the continuation fields named as in the case file (the engine calls
// ω "lambda" and the first step "initial_step").
void ValidateCase(const Case& the_case);

// Applies `change` to the case and validates; on any error the case is left as it was.
// Inside `with case.edit():` validation waits for the end of the block.
template <typename Change>
void Modify(PyCase& c, Change change) {
  if (c.editing > 0) {
    change(c.value);
    return;
  }
  Case before = c.value;
  try {
    change(c.value);
    ValidateCase(c.value);
  } catch (...) {
    c.value = std::move(before);
    throw;
  }
}

// value.cast<T>() with an InputError naming `field` instead of pybind11's cast_error.
template <typename T>
T Cast(const py::handle& value, const std::string& field, const char* expected) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw InputError(field + ": expected " + expected + ", got " +
                     py::str(value).cast<std::string>());
  }
}

// A model DOF given by name or index (InputError naming `field` for an unknown name).
int DofIndex(const Case& the_case, const py::handle& dof, const std::string& field);

// Binds the model's parts (M, C, K, DOF names, forcing, set_model) onto the Case class.
void BindModel(py::module_& m, py::class_<PyCase>& cls);

// How the outputs of a case are named: a measure's `dof` argument is an index among the
// outputs, the name the case gave it, or the model's name of that DOF.
struct OutputNaming {
  std::vector<std::string> names;      // Case::output_names
  std::vector<std::string> dof_names;  // model DOF name of each output ("" if unnamed)
  // ω = omega_factor·λ: Case::period_multiple (a period-m branch follows λ = ω/m), as the
  // writers report it.
  double omega_factor = 1.0;
  explicit OutputNaming(const Case& the_case);
  int Find(const py::handle& dof) const;  // throws InputError naming "dof"
};

// One measure of a solution by name: max_abs, min, max, h1 (per output), energy, min_gap,
// min_force (contact cases) or law<i>_<diagnostic>. Throws InputError for an unknown name.
double MeasureOf(const SolutionMeasures& measures, const std::string& name, int output);

// The same for records that keep only the response measures (folds, bifurcations: `where`
// names them in the error for a law's or a contact's measure).
double ResponseMeasure(const PointMeasures& measures, const std::string& name, int output,
                       const std::string& where);

// A case's stability options under their case-file names, and one of them set (InputError
// naming "stability.<key>" for an unknown key or a value of the wrong type).
py::dict GetStability(const StabilityOptions& options);
void SetStabilityOption(StabilityOptions& options, const std::string& key, const py::handle& value);

// Per point: True/False, or None where stability was not analysed.
py::list StableFlags(const std::vector<TracePoint>& points);

// Stops an analysis running without the GIL when Python has a pending signal: after every
// point it takes the GIL (main thread only: other threads never run signal handlers) and
// calls PyErr_CheckSignals. A KeyboardInterrupt stops the analysis, which keeps its points;
// any other exception a handler raises is re-raised by Finish().
class InterruptWatch : public TraceObserver {
 public:
  InterruptWatch();  // with the GIL held
  bool OnPoint(const TracePoint& point) override;
  // Checks Python's signals (taking the GIL) from the main thread; false once interrupted.
  bool Poll();
  const std::atomic<bool>* stop() const { return &stop_; }
  // With the GIL held, after the analysis: re-raises a pending non-interrupt error; returns
  // whether a KeyboardInterrupt stopped the analysis.
  bool Finish();

 private:
  bool main_thread_;
  std::atomic<bool> stop_{false};
  bool interrupted_ = false;
  py::object error_type_, error_value_, error_trace_;
};

// A solution at one ω (a signals_at crossing of a trace, or solve_at).
struct SolutionView {
  SolutionSignals signals;
  std::string label;
  std::optional<Eigen::MatrixXd> coefficients;  // every DOF × coefficient; solve_at only
  std::vector<std::tuple<std::string, int, double>> phases;  // solve_at: (name, count, fraction)
  std::shared_ptr<const OutputNaming> naming;
};

// A fold keeps the branch's output naming for measure(name, dof).
struct FoldView {
  TraceFold record;
  std::shared_ptr<const OutputNaming> naming;
};

// A bifurcation keeps the branch's output naming for measure(name, dof).
struct BifurcationView {
  Bifurcation record;
  std::shared_ptr<const OutputNaming> naming;
};

// A traced branch; `interrupted` makes nfrc.trace raise nfrc.Interrupted carrying it.
struct BranchView {
  TraceResult result;
  std::shared_ptr<const OutputNaming> naming;
  bool interrupted = false;
};

}  // namespace nfrc::python
