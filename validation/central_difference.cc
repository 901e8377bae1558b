#include "validation/central_difference.h"

#include <memory>

#include "validation/central_difference_stepper.h"

namespace nfrc {

CentralDifferenceIntegrator::CentralDifferenceIntegrator(TransientModel& model,
                                                         TransientOptions options)
    : TransientDriver(model, options, std::make_unique<CentralDifferenceStepper>(model, options)) {}

CentralDifferenceIntegrator::~CentralDifferenceIntegrator() = default;

double CentralDifferenceIntegrator::StepFor(double omega) const {
  return static_cast<const CentralDifferenceStepper&>(stepper()).StepFor(
      omega, options().samples_per_period);
}

}  // namespace nfrc
