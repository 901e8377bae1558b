#include "continuation/options.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace nfrc {
namespace {

std::string Text(double value) {
  std::ostringstream text;
  text.precision(8);
  text << value;
  return text.str();
}

// "field: rule, got value": the value said, as the user may not know the default that failed.
void Require(bool condition, const char* field, const std::string& rule, double value) {
  if (condition) return;
  std::ostringstream message;
  message.precision(8);
  message << field << ": " << rule << ", got " << value;
  throw std::invalid_argument(message.str());
}

}  // namespace

void ContinuationOptions::Validate() const {
  Require(std::isfinite(lambda_start), "lambda_start", "must be finite", lambda_start);
  Require(std::isfinite(lambda_end) && lambda_end != lambda_start, "lambda_end",
          "must be finite and differ from lambda_start", lambda_end);
  Require(std::isnan(lambda_min) ||
              (std::isfinite(lambda_min) && lambda_min <= std::min(lambda_start, lambda_end)),
          "lambda_min", "must be NaN (unset) or finite and at most lambda_start and lambda_end",
          lambda_min);
  Require(std::isnan(lambda_max) ||
              (std::isfinite(lambda_max) && lambda_max >= std::max(lambda_start, lambda_end)),
          "lambda_max", "must be NaN (unset) or finite and at least lambda_start and lambda_end",
          lambda_max);
  Require(std::isfinite(max_step) && max_step > 0.0, "max_step", "must be positive and finite",
          max_step);
  Require(min_step > 0.0 && min_step < max_step, "min_step",
          "must be positive and below max_step (" + Text(max_step) + ")", min_step);
  Require(initial_step >= min_step && initial_step <= max_step, "initial_step",
          "must lie in [min_step, max_step] = [" + Text(min_step) + ", " + Text(max_step) + "]",
          initial_step);
  Require(std::isfinite(step_increase) && step_increase >= 1.0, "step_increase",
          "must be finite and at least 1", step_increase);
  Require(step_decrease > 0.0 && step_decrease < 1.0, "step_decrease", "must lie in (0, 1)",
          step_decrease);
  Require(max_points >= 1, "max_points", "must be at least 1", static_cast<double>(max_points));
  Require(max_newton_iterations >= 1, "max_newton_iterations", "must be at least 1",
          static_cast<double>(max_newton_iterations));
  Require(target_newton_iterations >= 1 && target_newton_iterations <= max_newton_iterations,
          "target_newton_iterations", "must lie in [1, max_newton_iterations]",
          static_cast<double>(target_newton_iterations));
  Require(max_start_iterations >= 1, "max_start_iterations", "must be at least 1",
          static_cast<double>(max_start_iterations));
  Require(std::isfinite(newton_tolerance) && newton_tolerance > 0.0, "newton_tolerance",
          "must be positive and finite", newton_tolerance);
  Require(std::isfinite(residual_tolerance) && residual_tolerance > 0.0, "residual_tolerance",
          "must be positive and finite", residual_tolerance);
  Require(max_tangent_angle > 0.0 && max_tangent_angle < std::numbers::pi, "max_tangent_angle",
          "must lie in (0, pi)", max_tangent_angle);
  Require(std::isfinite(plot_tolerance) && plot_tolerance >= 0.0, "plot_tolerance",
          "must be finite and non-negative (0 = off)", plot_tolerance);
  Require(max_plot_turn_angle > 0.0 && max_plot_turn_angle < std::numbers::pi,
          "max_plot_turn_angle", "must lie in (0, pi)", max_plot_turn_angle);
  Require(std::isfinite(fold_tolerance) && fold_tolerance > 0.0, "fold_tolerance",
          "must be positive and finite", fold_tolerance);
  Require(max_fold_iterations >= 1, "max_fold_iterations", "must be at least 1",
          static_cast<double>(max_fold_iterations));
  Require(std::isfinite(lambda_scale) && lambda_scale >= 0.0, "lambda_scale",
          "must be finite and non-negative (0 = automatic)", lambda_scale);
  Require(scale_floor >= 0.0 && scale_floor <= 1.0, "scale_floor", "must lie in [0, 1]",
          scale_floor);
}

double ContinuationOptions::LowerBound() const {
  return std::isnan(lambda_min) ? std::min(lambda_start, lambda_end) : lambda_min;
}

double ContinuationOptions::UpperBound() const {
  return std::isnan(lambda_max) ? std::max(lambda_start, lambda_end) : lambda_max;
}

}  // namespace nfrc
