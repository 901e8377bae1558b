#include "validation/make_integrator.h"

#include "validation/central_difference.h"
#include "validation/ida_integrator.h"

namespace nfrc {

std::unique_ptr<TransientIntegrator> MakeTransientIntegrator(TransientModel& model,
                                                             const TransientOptions& options) {
  if (model.rigid_contacts.empty()) return std::make_unique<IdaIntegrator>(model, options);
  return std::make_unique<CentralDifferenceIntegrator>(model, options);
}

}  // namespace nfrc
