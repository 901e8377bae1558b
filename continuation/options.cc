#include "continuation/options.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nfrc {
namespace {

void Require(bool condition, const char* field, const char* rule) {
  if (!condition) throw std::invalid_argument(std::string(field) + ": " + rule);
}

}  // namespace

void ContinuationOptions::Validate() const {
  Require(std::isfinite(lambda_start), "lambda_start", "must be finite");
  Require(std::isfinite(lambda_end) && lambda_end != lambda_start, "lambda_end",
          "must be finite and differ from lambda_start");
  Require(std::isnan(lambda_min) ||
              (std::isfinite(lambda_min) && lambda_min <= std::min(lambda_start, lambda_end)),
          "lambda_min", "must be NaN (unset) or finite and at most lambda_start and lambda_end");
  Require(std::isnan(lambda_max) ||
              (std::isfinite(lambda_max) && lambda_max >= std::max(lambda_start, lambda_end)),
          "lambda_max", "must be NaN (unset) or finite and at least lambda_start and lambda_end");
  Require(std::isfinite(max_step) && max_step > 0.0, "max_step", "must be positive and finite");
  Require(min_step > 0.0 && min_step < max_step, "min_step", "must be positive and below max_step");
  Require(initial_step >= min_step && initial_step <= max_step, "initial_step",
          "must lie in [min_step, max_step]");
  Require(std::isfinite(step_increase) && step_increase >= 1.0, "step_increase",
          "must be finite and at least 1");
  Require(step_decrease > 0.0 && step_decrease < 1.0, "step_decrease", "must lie in (0, 1)");
  Require(max_points >= 1, "max_points", "must be at least 1");
  Require(max_newton_iterations >= 1, "max_newton_iterations", "must be at least 1");
  Require(target_newton_iterations >= 1 && target_newton_iterations <= max_newton_iterations,
          "target_newton_iterations", "must lie in [1, max_newton_iterations]");
  Require(max_start_iterations >= 1, "max_start_iterations", "must be at least 1");
  Require(std::isfinite(newton_tolerance) && newton_tolerance > 0.0, "newton_tolerance",
          "must be positive and finite");
  Require(std::isfinite(residual_tolerance) && residual_tolerance > 0.0, "residual_tolerance",
          "must be positive and finite");
  Require(max_tangent_angle > 0.0 && max_tangent_angle < std::numbers::pi, "max_tangent_angle",
          "must lie in (0, pi)");
  Require(std::isfinite(plot_tolerance) && plot_tolerance >= 0.0, "plot_tolerance",
          "must be finite and non-negative (0 = off)");
  Require(max_plot_turn_angle > 0.0 && max_plot_turn_angle < std::numbers::pi,
          "max_plot_turn_angle", "must lie in (0, pi)");
  Require(std::isfinite(fold_tolerance) && fold_tolerance > 0.0, "fold_tolerance",
          "must be positive and finite");
  Require(max_fold_iterations >= 1, "max_fold_iterations", "must be at least 1");
  Require(std::isfinite(lambda_scale) && lambda_scale >= 0.0, "lambda_scale",
          "must be finite and non-negative (0 = automatic)");
  Require(scale_floor >= 0.0 && scale_floor <= 1.0, "scale_floor", "must lie in [0, 1]");
}

double ContinuationOptions::LowerBound() const {
  return std::isnan(lambda_min) ? std::min(lambda_start, lambda_end) : lambda_min;
}

double ContinuationOptions::UpperBound() const {
  return std::isnan(lambda_max) ? std::max(lambda_start, lambda_end) : lambda_max;
}

}  // namespace nfrc
