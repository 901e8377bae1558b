#include "analysis/hill_reduction.h"

#include <stdexcept>
#include <string>

#include "core/errors.h"
#include "models/craig_bampton.h"

namespace nfrc {

std::shared_ptr<const HillModel> HillReduction(const HarmonicSystem& system, int modes) {
  const std::vector<int>& boundary = system.retained();
  CraigBamptonOptions options;
  options.modes = modes;
  options.check_frequencies = 0;  // the pencil's own error is what matters, measured by a trace
  auto result = std::make_shared<HillModel>();
  try {
    result->model = ReduceCraigBampton(system.model(), boundary, options).model;
  } catch (const std::invalid_argument& error) {  // more modes than interior DOFs
    throw InputError("stability.hill_modes: " + std::string(error.what()));
  } catch (const std::runtime_error& error) {  // K_ii not positive definite, no convergence
    throw InputError("stability.hill_modes: " + std::string(error.what()));
  }
  result->dof_of.assign(static_cast<size_t>(system.model().num_dofs()), -1);
  for (size_t k = 0; k < boundary.size(); ++k) {
    result->dof_of[static_cast<size_t>(boundary[k])] = static_cast<int>(k);
  }
  return result;
}

}  // namespace nfrc
