#pragma once

#include "validation/transient.h"
#include "validation/transient_driver.h"
#include "validation/transient_model.h"

namespace nfrc {

// The transient driver over explicit central differences with Lagrange multipliers for rigid
// unilateral contacts (validation/central_difference_stepper.h), the reference scheme of
// Vadcard et al. 2022. Other laws must have an explicit force (springs, penalty contacts).
class CentralDifferenceIntegrator : public TransientDriver {
 public:
  // Throws InputError naming the law (model.law_paths) if it has no explicit force, naming
  // model.M for a mass matrix that is not positive definite, and for bad options.
  CentralDifferenceIntegrator(TransientModel& model, TransientOptions options);
  ~CentralDifferenceIntegrator() override;

  // The time step used at ω (s), after rounding to the period.
  double StepFor(double omega) const;
};

}  // namespace nfrc
