#include "continuation/step_control.h"

#include <algorithm>
#include <cmath>

namespace nfrc {
namespace {

// The next step aims at this fraction of max_tangent_angle, leaving room for curvature
// growing along the step before the hard limit rejects it.
constexpr double kAngleTarget = 0.5;
// The next chord aims at this fraction of plot_tolerance, for the same reason.
constexpr double kPlotTarget = 0.5;

}  // namespace

StepController::StepController(const ContinuationOptions& options) : options_(options) {}

double StepController::AfterSuccess(double step, int iterations, double angle) const {
  double factor = static_cast<double>(options_.target_newton_iterations) / std::max(iterations, 1);
  if (angle > 0.0) factor = std::min(factor, kAngleTarget * options_.max_tangent_angle / angle);
  factor = std::clamp(factor, options_.step_decrease, options_.step_increase);
  return std::clamp(step * factor, options_.min_step, options_.max_step);
}

double StepController::AfterPlottedSuccess(double step, int iterations, double chord_error) const {
  double factor = static_cast<double>(options_.target_newton_iterations) / std::max(iterations, 1);
  if (chord_error > 0.0) {
    factor = std::min(factor, std::sqrt(kPlotTarget * options_.plot_tolerance / chord_error));
  }
  factor = std::clamp(factor, options_.step_decrease, options_.step_increase);
  return std::clamp(step * factor, options_.min_step, options_.max_step);
}

std::optional<double> StepController::AfterFailure(double step) const {
  const double next = step * options_.step_decrease;
  if (next >= options_.min_step) return next;
  if (step > options_.min_step) return options_.min_step;
  return std::nullopt;
}

}  // namespace nfrc
