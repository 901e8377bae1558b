#include "tools/model_reader.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>

#include "analysis/case.h"
#include "models/damping.h"
#include "models/matrix_market.h"
#include "models/rod.h"
#include "tools/input_fields.h"
#include "tools/reduction_reader.h"

namespace nfrc {
namespace {

// A matrix given inline as a list of rows, or as the path of a Matrix Market file.
Eigen::SparseMatrix<double> ReadMatrix(InputFields& fields, const std::string& key,
                                       const std::string& base_dir) {
  const nlohmann::json& value = fields.RequiredValue(key);
  const std::string where = fields.path() + "." + key;
  if (value.is_string()) {
    std::filesystem::path file(value.get<std::string>());
    if (file.is_relative()) file = std::filesystem::path(base_dir) / file;
    try {
      return ReadMatrixMarket(file.string());
    } catch (const InputError& error) {
      throw InputError(where + ": " + error.what());
    }
  }
  if (!value.is_array() || value.empty()) {
    throw InputError(where + ": expected a list of rows or a Matrix Market file name");
  }
  const auto rows = static_cast<Eigen::Index>(value.size());
  std::vector<Eigen::Triplet<double>> triplets;
  for (Eigen::Index i = 0; i < rows; ++i) {
    const nlohmann::json& row = value[static_cast<size_t>(i)];
    if (!row.is_array() || static_cast<Eigen::Index>(row.size()) != rows) {
      throw InputError(where + ": row " + std::to_string(i) + " must be a list of " +
                       std::to_string(rows) + " numbers (square matrix)");
    }
    for (Eigen::Index j = 0; j < rows; ++j) {
      const nlohmann::json& entry = row[static_cast<size_t>(j)];
      if (!entry.is_number()) {
        throw InputError(where + ": entry (" + std::to_string(i) + ", " + std::to_string(j) +
                         ") is not a number");
      }
      const double number = entry.get<double>();
      if (number != 0.0) triplets.emplace_back(static_cast<int>(i), static_cast<int>(j), number);
    }
  }
  Eigen::SparseMatrix<double> matrix(rows, rows);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

void CheckPhysical(const Eigen::SparseMatrix<double>& matrix, const std::string& where,
                   const std::string& what) {
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    if (matrix.coeff(i, i) < 0.0) {
      throw InputError(where + ": negative " + what + " on the diagonal at DOF " +
                       std::to_string(i) + " (" + std::to_string(matrix.coeff(i, i)) + ")");
    }
  }
}

std::vector<ForcingTerm> ReadForcing(InputFields& fields, const LinearModel& model) {
  std::vector<ForcingTerm> forcing;
  const nlohmann::json& list = fields.RequiredValue("forcing");
  if (!list.is_array()) fields.Fail("forcing", "expected a list of {dof, cos, sin, harmonic}");
  for (size_t i = 0; i < list.size(); ++i) {
    InputFields term(list[i], fields.path() + ".forcing[" + std::to_string(i) + "]");
    ForcingTerm f;
    f.dof = term.RequiredDof("dof", model);
    f.cos = term.OptionalNumber("cos", 0.0);
    f.sin = term.OptionalNumber("sin", 0.0);
    f.harmonic = term.OptionalInt("harmonic", 1);
    if (f.harmonic < 0) term.Fail("harmonic", "must be 0 or more");
    if (!term.Has("cos") && !term.Has("sin")) term.Fail("cos", "give cos and/or sin amplitudes");
    term.Finish();
    forcing.push_back(f);
  }
  return forcing;
}

// `deferred_modal` (non-null for a reduced model) receives a modal ratio instead of the
// full model's modal damping, which the reduction applies to the reduced model.
Eigen::SparseMatrix<double> ReadDamping(InputFields& fields, const LinearModel& model,
                                        double* deferred_modal) {
  InputFields damping(fields.RequiredObject("damping"), fields.path() + ".damping");
  Eigen::SparseMatrix<double> c(model.num_dofs(), model.num_dofs());
  if (damping.Has("rayleigh")) {
    InputFields rayleigh(damping.RequiredObject("rayleigh"), damping.path() + ".rayleigh");
    const double alpha = rayleigh.OptionalNumber("mass", 0.0);
    const double beta = rayleigh.OptionalNumber("stiffness", 0.0);
    if (alpha < 0.0) rayleigh.Fail("mass", "must be non-negative");
    if (beta < 0.0) rayleigh.Fail("stiffness", "must be non-negative");
    rayleigh.Finish();
    c += RayleighDamping(model.mass, model.stiffness, alpha, beta);
  }
  if (damping.Has("modal_ratio")) {
    const double ratio = damping.RequiredNumber("modal_ratio");
    if (ratio < 0.0 || ratio > kMaxModalRatio) {
      std::ostringstream text;
      text << "must lie in [0, " << kMaxModalRatio << "] (1 is critical damping), got " << ratio;
      damping.Fail("modal_ratio", text.str());
    }
    if (deferred_modal != nullptr) {
      *deferred_modal = ratio;
    } else {
      c += ModalDamping(model.mass, model.stiffness, ratio);
    }
  }
  damping.Finish();
  return c;
}

ModelDefinition BuildMatrixModel(InputFields& fields, const std::string& base_dir,
                                 double* deferred_modal) {
  ModelDefinition definition;
  LinearModel& model = definition.model;
  model.mass = ReadMatrix(fields, "M", base_dir);
  model.stiffness = ReadMatrix(fields, "K", base_dir);
  const Eigen::Index n = model.stiffness.rows();
  if (model.mass.rows() != n || model.mass.cols() != n) {
    fields.Fail("M", "size " + std::to_string(model.mass.rows()) + "x" +
                         std::to_string(model.mass.cols()) + " differs from K's " +
                         std::to_string(n) + "x" + std::to_string(n));
  }
  if (model.stiffness.cols() != n) fields.Fail("K", "must be square");
  model.damping =
      fields.Has("C") ? ReadMatrix(fields, "C", base_dir) : Eigen::SparseMatrix<double>(n, n);
  if (model.damping.rows() != n || model.damping.cols() != n) {
    fields.Fail("C", "size differs from K's " + std::to_string(n) + "x" + std::to_string(n));
  }
  CheckPhysical(model.mass, fields.path() + ".M", "mass");
  CheckPhysical(model.stiffness, fields.path() + ".K", "stiffness");
  CheckPhysical(model.damping, fields.path() + ".C", "damping");
  if (fields.Has("dof_names")) {
    const nlohmann::json& names = fields.RequiredValue("dof_names");
    if (!names.is_array() || static_cast<Eigen::Index>(names.size()) != n) {
      fields.Fail("dof_names", "expected a list of " + std::to_string(n) + " names");
    }
    for (const auto& name : names) {
      if (!name.is_string()) fields.Fail("dof_names", "names must be strings");
      const std::string text = name.get<std::string>();
      // A repeated name would make "dof": name ambiguous.
      if (std::find(model.dof_names.begin(), model.dof_names.end(), text) !=
          model.dof_names.end()) {
        fields.Fail("dof_names", "the name \"" + text + "\" appears more than once");
      }
      model.dof_names.push_back(text);
    }
  }
  if (fields.Has("damping")) model.damping += ReadDamping(fields, model, deferred_modal);
  definition.forcing = ReadForcing(fields, model);
  try {
    model.Validate();
  } catch (const std::invalid_argument& error) {
    throw InputError(fields.path() + ": " + error.what());
  }
  return definition;
}

ModelDefinition BuildRodModel(InputFields& fields, const std::string& /*base_dir*/,
                              double* deferred_modal) {
  RodParameters parameters;
  parameters.elements = fields.RequiredInt("elements");
  parameters.length = fields.RequiredNumber("length");
  parameters.area = fields.RequiredNumber("area");
  parameters.young = fields.RequiredNumber("young");
  parameters.density = fields.RequiredNumber("density");
  // A rod too large to trace even with one harmonic is refused before it is built.
  ProblemDimensions dimensions;
  dimensions.num_dofs = parameters.elements;
  try {
    CheckProblemSize(dimensions);
  } catch (const InputError& error) {
    throw InputError(fields.path() + ".elements: " + std::to_string(parameters.elements) +
                     " elements: " + error.what());
  }
  ModelDefinition definition;
  try {
    definition.model = BuildRod(parameters);
  } catch (const std::invalid_argument& error) {
    throw InputError(fields.path() + "." + error.what());
  }
  if (fields.Has("damping")) {
    definition.model.damping = ReadDamping(fields, definition.model, deferred_modal);
  }
  definition.forcing = ReadForcing(fields, definition.model);
  return definition;
}

}  // namespace

ModelDefinition BuildModel(const nlohmann::json& spec, const std::string& base_dir,
                           std::optional<ReductionRequest>* reduction) {
  using Builder = ModelDefinition (*)(InputFields&, const std::string&, double*);
  static const std::map<std::string, Builder> builders = {
      {"matrices", &BuildMatrixModel},
      {"rod", &BuildRodModel},
  };
  InputFields fields(spec, "model");
  const std::string type = fields.RequiredString("type");
  const auto found = builders.find(type);
  if (found == builders.end()) fields.Fail("type", "unknown model type \"" + type + "\"");
  std::optional<ReductionRequest> request = ReadReduction(fields);
  if (request && reduction == nullptr) {
    fields.Fail("reduction", "not available here (only in a case's model)");
  }
  ModelDefinition definition =
      found->second(fields, base_dir, request ? &request->modal_ratio : nullptr);
  if (reduction != nullptr) *reduction = std::move(request);
  fields.Finish();
  return definition;
}

}  // namespace nfrc
