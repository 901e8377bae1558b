#include "tools/reduction_reader.h"

#include <algorithm>
#include <stdexcept>

#include "models/damping.h"

namespace nfrc {

std::optional<ReductionRequest> ReadReduction(InputFields& model_fields) {
  if (!model_fields.Has("reduction")) return std::nullopt;
  InputFields fields(model_fields.RequiredObject("reduction"), model_fields.path() + ".reduction");
  const std::string type = fields.RequiredString("type");
  if (type != "craig_bampton") {
    fields.Fail("type", "unknown reduction \"" + type + "\" (expected \"craig_bampton\")");
  }
  ReductionRequest request;
  CraigBamptonOptions& options = request.options;
  if (fields.Has("modes") == fields.Has("max_frequency")) {
    fields.Fail("modes", "give exactly one of modes and max_frequency");
  }
  if (fields.Has("modes")) {
    options.modes = fields.RequiredInt("modes");
    if (options.modes < 0 || options.modes > kMaxReductionModes) {
      fields.Fail("modes", "must be between 0 and " + std::to_string(kMaxReductionModes) +
                               ", got " + std::to_string(options.modes));
    }
  } else {
    options.max_frequency = fields.RequiredNumber("max_frequency");
    if (!(options.max_frequency > 0.0)) fields.Fail("max_frequency", "must be positive (rad/s)");
  }
  // Each checked frequency costs a Lanczos vector on the full model; 50 is plenty for a check.
  constexpr int kMaxCheckFrequencies = 50;
  if (fields.Has("check_frequencies")) {
    options.check_frequencies = fields.RequiredInt("check_frequencies");
  }
  if (fields.Has("check_frequencies") &&
      (options.check_frequencies < 0 || options.check_frequencies > kMaxCheckFrequencies)) {
    fields.Fail("check_frequencies",
                "must be between 0 and " + std::to_string(kMaxCheckFrequencies));
  }
  fields.Finish();
  return request;
}

void ApplyReduction(Case& the_case, const ReductionRequest& request) {
  LinearModel& full = the_case.model.model;
  // Boundary DOFs in a stable order: laws, then forcing, then outputs, each once.
  std::vector<int> boundary;
  auto keep = [&](int dof) {
    if (std::find(boundary.begin(), boundary.end(), dof) == boundary.end()) {
      boundary.push_back(dof);
    }
  };
  for (const LawSpec& law : the_case.laws) {
    for (int dof : LawDofs(law)) keep(dof);
  }
  for (const ForcingTerm& term : the_case.model.forcing) keep(term.dof);
  for (int dof : the_case.output_dofs) keep(dof);

  CraigBamptonModel reduced;
  try {
    reduced = ReduceCraigBampton(full, boundary, request.options);
  } catch (const std::invalid_argument& error) {
    // "check_frequencies: ..." names a field of model.reduction; "boundary: ..." the DOFs.
    const std::string what = error.what();
    const bool field = what.rfind("check_frequencies:", 0) == 0 || what.rfind("modes:", 0) == 0 ||
                       what.rfind("max_frequency:", 0) == 0;
    throw InputError("model.reduction" + std::string(field ? "." : ": ") + what);
  } catch (const std::runtime_error& error) {
    throw InputError("model.reduction: " + std::string(error.what()));
  }
  std::vector<int> new_index(static_cast<size_t>(full.num_dofs()), -1);
  for (size_t k = 0; k < boundary.size(); ++k) {
    new_index[static_cast<size_t>(boundary[k])] = static_cast<int>(k);
  }
  for (LawSpec& law : the_case.laws) RemapLawDofs(law, new_index);
  for (ForcingTerm& term : the_case.model.forcing)
    term.dof = new_index[static_cast<size_t>(term.dof)];
  for (int& dof : the_case.output_dofs) dof = new_index[static_cast<size_t>(dof)];
  full = std::move(reduced.model);
  if (request.modal_ratio >= 0.0) {
    full.damping += ModalDamping(full.mass, full.stiffness, request.modal_ratio);
  }
  the_case.reduction = std::move(reduced.report);
}

}  // namespace nfrc
