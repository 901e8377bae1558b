#include "continuation/options.h"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace nfrc {
namespace {

// The message of the std::invalid_argument thrown by Validate, or "" if none.
std::string ValidationMessage(const std::function<void(ContinuationOptions&)>& change) {
  ContinuationOptions options;
  change(options);
  try {
    options.Validate();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST_CASE("options: defaults are valid") {
  CHECK(ValidationMessage([](ContinuationOptions&) {}).empty());
}

TEST_CASE("options: each invalid field is named in the message") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The value given and the bound it breaks are said.
  CHECK(ValidationMessage([](auto& o) { o.min_step = 0.0; }) ==
        "min_step: must be positive and below max_step (0.05), got 0");
  CHECK(ValidationMessage([](auto& o) { o.min_step = 1.0; }) ==
        "min_step: must be positive and below max_step (0.05), got 1");
  CHECK(ValidationMessage([](auto& o) { o.initial_step = 0.0; }) ==
        "initial_step: must lie in [min_step, max_step] = [1e-07, 0.05], got 0");
  CHECK(ValidationMessage([](auto& o) { o.lambda_end = o.lambda_start; }).rfind("lambda_end:", 0) ==
        0);
  CHECK(ValidationMessage([&](auto& o) { o.lambda_start = nan; }).rfind("lambda_start:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.max_step = -1.0; }).rfind("max_step:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.initial_step = 1.0; }).rfind("initial_step:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.step_increase = 0.5; }).rfind("step_increase:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.step_decrease = 1.0; }).rfind("step_decrease:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.max_points = 0; }).rfind("max_points:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.max_newton_iterations = 0;
        }).rfind("max_newton_iterations:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.target_newton_iterations = 20;
        }).rfind("target_newton_iterations:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.max_start_iterations = 0;
        }).rfind("max_start_iterations:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.newton_tolerance = 0.0;
        }).rfind("newton_tolerance:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.residual_tolerance = -1.0;
        }).rfind("residual_tolerance:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) {
          o.max_tangent_angle = 4.0;
        }).rfind("max_tangent_angle:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.plot_tolerance = -1e-3; }).rfind("plot_tolerance:", 0) ==
        0);
  CHECK(ValidationMessage([](auto& o) {
          o.max_plot_turn_angle = 0.0;
        }).rfind("max_plot_turn_angle:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.fold_tolerance = 0.0; }).rfind("fold_tolerance:", 0) ==
        0);
  CHECK(ValidationMessage([](auto& o) {
          o.max_fold_iterations = 0;
        }).rfind("max_fold_iterations:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.lambda_scale = -1.0; }).rfind("lambda_scale:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.scale_floor = 2.0; }).rfind("scale_floor:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.lambda_min = 0.5; }).rfind("lambda_min:", 0) == 0);
  CHECK(ValidationMessage([](auto& o) { o.lambda_max = 0.5; }).rfind("lambda_max:", 0) == 0);
}

TEST_CASE("options: the range defaults to lambda_start..lambda_end, bounds override it") {
  ContinuationOptions options;
  options.lambda_start = 2.0;
  options.lambda_end = -1.0;
  CHECK(options.LowerBound() == -1.0);
  CHECK(options.UpperBound() == 2.0);
  options.lambda_max = 5.0;
  CHECK(options.UpperBound() == 5.0);
  CHECK_NOTHROW(options.Validate());
}

TEST_CASE("options: Continue validates before doing anything") {
  testing::CubicProblem problem;
  ContinuationOptions options;
  options.step_decrease = 0.0;
  CHECK_THROWS_WITH_AS(Continue(problem, Eigen::VectorXd::Zero(1), options),
                       "step_decrease: must lie in (0, 1), got 0", std::invalid_argument);
  options = ContinuationOptions{};
  CHECK_THROWS_AS(Continue(problem, Eigen::VectorXd::Zero(2), options), std::invalid_argument);
}

}  // namespace
}  // namespace nfrc
