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

  // Next step after an accepted one whose chord departs from the plotted curve by
  // `chord_error` (PlotChordControl): scaled by target/iterations and by the square root of
  // half the plot tolerance over the error (the error of a chord grows as the step squared),
  // clamped as above.
  double AfterPlottedSuccess(double step, int iterations, double chord_error) const;

  // Step to retry with after a failed one: step·step_decrease, once min_step itself, then
  // nothing (the run is stalled).
  std::optional<double> AfterFailure(double step) const;

 private:
  ContinuationOptions options_;
};

}  // namespace nfrc
