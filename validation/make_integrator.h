#pragma once

#include <memory>

#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// The integrator a model needs: the explicit Lagrange-multiplier scheme when it has rigid
// contacts (IDA cannot integrate them), IDA otherwise. Keeps a reference to `model`.
std::unique_ptr<TransientIntegrator> MakeTransientIntegrator(TransientModel& model,
                                                             const TransientOptions& options);

}  // namespace nfrc
