// The model's parts of a Case: M, C and K as numpy arrays (set: validated, sparse inside),
// DOF names, forcing terms, and set_model for changing the model's size.
#include "bindings.h"

namespace nfrc::python {
namespace {

using namespace pybind11::literals;

// A matrix from a numpy array, a list of rows or (with scipy) a sparse matrix.
Eigen::SparseMatrix<double> ToSparse(const py::object& value, const std::string& field, int n) {
  Eigen::SparseMatrix<double> matrix;
  try {
    if (py::hasattr(value, "tocsc")) {
      matrix = value.attr("tocsc")().cast<Eigen::SparseMatrix<double>>();
    } else {
      matrix = value.cast<Eigen::MatrixXd>().sparseView();
    }
  } catch (const py::cast_error&) {
    throw InputError(field + ": expected a square matrix (numpy array or list of rows)");
  }
  if (matrix.rows() != matrix.cols() || (n >= 0 && matrix.rows() != n)) {
    throw InputError(
        field + ": expected " +
        (n >= 0 ? std::to_string(n) + "x" + std::to_string(n) : std::string("a square matrix")) +
        ", got " + std::to_string(matrix.rows()) + "x" + std::to_string(matrix.cols()) +
        " (set_model changes the size)");
  }
  for (int i = 0; i < matrix.rows(); ++i) {
    // Same rule as the reader: a negative diagonal entry is not a physical M, C or K.
    if (matrix.coeff(i, i) < 0.0) {
      throw InputError(field + ": negative diagonal entry at DOF " + std::to_string(i));
    }
  }
  return matrix;
}

// Dense copies are for inspecting small models; larger ones are read as triplets.
constexpr int kMaxDenseDofs = 5000;

Eigen::MatrixXd Dense(const Eigen::SparseMatrix<double>& matrix, const char* field) {
  if (matrix.rows() > kMaxDenseDofs) {
    throw InputError(std::string(field) + ": " + std::to_string(matrix.rows()) +
                     " DOFs are too many for a dense array; use Case.triplets()");
  }
  return Eigen::MatrixXd(matrix);
}

Eigen::SparseMatrix<double>& Matrix(Case& c, const std::string& name) {
  if (name == "M") return c.model.model.mass;
  if (name == "C") return c.model.model.damping;
  if (name == "K") return c.model.model.stiffness;
  throw InputError("matrix: expected \"M\", \"C\" or \"K\", got \"" + name + "\"");
}

void DefineMatrix(py::class_<PyCase>& cls, const char* name) {
  const std::string field = std::string("model.") + name;
  cls.def_property(
      name, [name, field](PyCase& c) { return Dense(Matrix(c.value, name), field.c_str()); },
      [name, field](PyCase& c, const py::object& value) {
        Eigen::SparseMatrix<double> matrix = ToSparse(value, field, c.value.model.model.num_dofs());
        Modify(c, [&](Case& v) { Matrix(v, name) = std::move(matrix); });
      });
}

}  // namespace

int DofIndex(const Case& c, const py::handle& dof, const std::string& field) {
  if (py::isinstance<py::str>(dof)) {
    const std::string name = dof.cast<std::string>();
    const int index = c.model.model.FindDof(name);
    if (index < 0) throw InputError(field + ": no DOF named \"" + name + "\" in the model");
    return index;
  }
  return Cast<int>(dof, field, "a DOF index or name");
}

void BindModel(py::module_& m, py::class_<PyCase>& cls) {
  py::class_<ForcingTerm> forcing(m, "Forcing", "f_dof(t) += cos*cos(k w t) + sin*sin(k w t)");
  forcing.attr("_fields") = py::make_tuple("dof", "cos", "sin", "harmonic");
  forcing
      .def(py::init([](int dof, double cos, double sin, int harmonic) {
             return ForcingTerm{dof, harmonic, cos, sin};
           }),
           "dof"_a, "cos"_a = 0.0, "sin"_a = 0.0, "harmonic"_a = 1)
      .def_readwrite("dof", &ForcingTerm::dof)
      .def_readwrite("cos", &ForcingTerm::cos)
      .def_readwrite("sin", &ForcingTerm::sin)
      .def_readwrite("harmonic", &ForcingTerm::harmonic);

  cls.def_property_readonly("num_dofs",
                            [](const PyCase& c) { return c.value.model.model.num_dofs(); })
      .def_property(
          "dof_names", [](const PyCase& c) { return c.value.model.model.dof_names; },
          [](PyCase& c, std::vector<std::string> names) {
            Modify(c, [&](Case& v) { v.model.model.dof_names = std::move(names); });
          })
      .def(
          "dof_index",
          [](const PyCase& c, const py::object& dof) { return DofIndex(c.value, dof, "dof"); },
          "dof"_a, "Model index of a DOF given by name (or index).")
      .def(
          "triplets",
          [](PyCase& c, const std::string& name) {
            const Eigen::SparseMatrix<double>& a = Matrix(c.value, name);
            std::vector<int> rows, cols;
            std::vector<double> values;
            for (int k = 0; k < a.outerSize(); ++k) {
              for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
                rows.push_back(static_cast<int>(it.row()));
                cols.push_back(static_cast<int>(it.col()));
                values.push_back(it.value());
              }
            }
            return py::make_tuple(rows, cols, values);
          },
          "matrix"_a, "(rows, cols, values) of \"M\", \"C\" or \"K\".")
      .def(
          "set_model",
          [](PyCase& c, const py::object& mass, const py::object& stiffness,
             const py::object& damping, std::optional<std::vector<std::string>> dof_names,
             std::optional<std::vector<ForcingTerm>> forcing) {
            LinearModel model;
            model.stiffness = ToSparse(stiffness, "model.K", -1);
            const int n = static_cast<int>(model.stiffness.rows());
            model.mass = ToSparse(mass, "model.M", n);
            model.damping = damping.is_none() ? Eigen::SparseMatrix<double>(n, n)
                                              : ToSparse(damping, "model.C", n);
            if (dof_names) {
              model.dof_names = std::move(*dof_names);
            } else if (n == c.value.model.model.num_dofs()) {
              model.dof_names = c.value.model.model.dof_names;
            }
            Modify(c, [&](Case& v) {
              v.model.model = std::move(model);
              if (forcing) v.model.forcing = std::move(*forcing);
            });
          },
          "M"_a, "K"_a, "C"_a = py::none(), "dof_names"_a = py::none(), "forcing"_a = py::none(),
          "Replaces the linear model (M, K, optional C); may change its size.")
      .def_property(
          "_forcing", [](const PyCase& c) { return c.value.model.forcing; },
          [](PyCase& c, std::vector<ForcingTerm> terms) {
            Modify(c, [&](Case& v) { v.model.forcing = std::move(terms); });
          });
  DefineMatrix(cls, "M");
  DefineMatrix(cls, "C");
  DefineMatrix(cls, "K");
}

}  // namespace nfrc::python
