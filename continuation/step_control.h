#pragma once

#include <optional>

#include "continuation/options.h"

namespace nfrc {

// Adapts the scaled arclength step: AUTO-style towards a target Newton effort, limited by
// the turn of the tangent, and cut after failures down to min_step.
class StepController {
 public:
  explicit StepController(const ContinuationOptions& options);

  // Next step after an accepted one that needed `iterations` corrector iterations and turned
  // the tangent by `angle` rad: scaled by target/iterations and by half the angle budget
  // over the angle, the factor clamped to [step_decrease, step_increase].
  double AfterSuccess(double step, int iterations, double angle) const;

  // Step to retry with after a failed one: step·step_decrease, once min_step itself, then
  // nothing (the run is stalled).
  std::optional<double> AfterFailure(double step) const;

 private:
  ContinuationOptions options_;
};

}  // namespace nfrc
