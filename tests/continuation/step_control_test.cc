#include "continuation/step_control.h"

#include <doctest/doctest.h>

#include <cmath>

namespace nfrc {
namespace {

// Closed-form quantities computed in a handful of flops agree to rounding.
constexpr double kRoundoff = 1e-13;

doctest::Approx Near(double value) { return doctest::Approx(value).epsilon(kRoundoff); }

TEST_CASE("step control: grows after easy steps, shrinks after hard ones, within bounds") {
  ContinuationOptions options;  // target 4, increase 2, decrease 0.5, max_tangent_angle 0.35
  const StepController controller(options);
  CHECK(controller.AfterSuccess(0.01, 4, 0.0) == Near(0.01));
  CHECK(controller.AfterSuccess(0.01, 2, 0.0) == Near(0.02));
  CHECK(controller.AfterSuccess(0.01, 1, 0.0) == Near(0.02));  // capped at ×2
  CHECK(controller.AfterSuccess(0.01, 8, 0.0) == Near(0.005));
  CHECK(controller.AfterSuccess(0.01, 15, 0.0) == Near(0.005));  // floored at ×0.5
  CHECK(controller.AfterSuccess(0.09, 1, 0.0) == Near(options.max_step));
  // A turn of 0.35 rad (the limit) aims the next step at half of it.
  CHECK(controller.AfterSuccess(0.01, 2, 0.35) == Near(0.005));
  CHECK(controller.AfterSuccess(0.01, 2, 0.0875) == Near(0.02));
}

TEST_CASE("step control: with a plot, the chord error sets the step as its square root") {
  ContinuationOptions options;
  options.plot_tolerance = 1e-3;
  const StepController controller(options);
  // A chord error of a quarter of the tolerance is half the target (tolerance/2): the chord
  // error grows as the step squared, so the step may grow by √2 (2 Newton iterations allow ×2).
  CHECK(controller.AfterPlottedSuccess(0.01, 2, 2.5e-4) == Near(0.01 * std::sqrt(2.0)));
  // At the tolerance the next step aims at half of it: ×1/√2.
  CHECK(controller.AfterPlottedSuccess(0.01, 4, 1e-3) == Near(0.01 / std::sqrt(2.0)));
  // The Newton effort still limits it, and so do the bounds.
  CHECK(controller.AfterPlottedSuccess(0.01, 8, 1e-5) == Near(0.005));
  CHECK(controller.AfterPlottedSuccess(0.01, 2, 0.0) == Near(0.02));
}

TEST_CASE("step control: failures cut the step, try min_step once, then give up") {
  ContinuationOptions options;
  options.min_step = 1e-3;
  const StepController controller(options);
  CHECK(*controller.AfterFailure(0.01) == Near(0.005));
  CHECK(*controller.AfterFailure(1.5e-3) == Near(1e-3));
  CHECK_FALSE(controller.AfterFailure(1e-3).has_value());
}

}  // namespace
}  // namespace nfrc
