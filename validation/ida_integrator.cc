#include "validation/ida_integrator.h"

#include <memory>

#include "validation/ida_stepper.h"

namespace nfrc {

IdaIntegrator::IdaIntegrator(TransientModel& model, TransientOptions options)
    : TransientDriver(model, options, std::make_unique<IdaStepper>(model, options)) {}

IdaIntegrator::~IdaIntegrator() = default;

}  // namespace nfrc
