// The _nfrc extension: the compiled half of the Python package nfrc (python/nfrc/).
#include "bindings.h"
#include "core/errors.h"
#include "tools/version.h"

PYBIND11_MODULE(_nfrc, m) {
  namespace py = pybind11;
  m.doc() = "Compiled bindings of nfrc; use the package nfrc.";
  // Bad input keeps its message (naming the field); a ValueError so generic code catches it.
  // Other std::invalid_argument become ValueError and std::runtime_error RuntimeError
  // through pybind11's own translations.
  py::register_exception<nfrc::InputError>(m, "InputError", PyExc_ValueError);
  m.attr("__version__") = nfrc::kNfrcVersion;
  nfrc::python::BindLaws(m);
  nfrc::python::BindCase(m);
  nfrc::python::BindResults(m);
  nfrc::python::BindStability(m);
  nfrc::python::BindTrace(m);
  nfrc::python::BindSolveAt(m);
  nfrc::python::BindValidate(m);
  nfrc::python::BindFoldCurve(m);
}
