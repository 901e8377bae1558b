#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "validation/central_difference.h"
#include "validation/ida_integrator.h"
#include "validation/transient.h"

namespace nfrc {
namespace {

// m = 1 kg, c = 0.1 N·s/m, k = 1 N/m, cos(0.5 t) N.
TransientModel Oscillator() {
  TransientModel model;
  model.model.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  model.model.damping = Eigen::MatrixXd::Constant(1, 1, 0.1).sparseView();
  model.model.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  model.forcing = {ForcingTerm{0, 1, 1.0, 0.0}};
  model.massless = {false};
  return model;
}

TEST_CASE("Transient statistics: IDA reports its SUNDIALS counters") {
  TransientModel model = Oscillator();
  TransientOptions options;
  options.samples_per_period = 64;
  const TransientResult result = IdaIntegrator(model, options).RunToSteadyState(0.5, {});
  REQUIRE(result.periodic());
  const TransientStatistics& s = result.statistics;
  CHECK(s.steps > 0);
  CHECK(result.steps == s.steps);
  CHECK(result.events == s.events);
  CHECK(s.events == 0);
  // Each step evaluates the residual at least once per Newton iteration.
  CHECK(s.nonlinear_iterations >= s.steps);
  CHECK(s.residual_evaluations >= s.nonlinear_iterations);
  CHECK(s.jacobian_evaluations > 0);
  CHECK(s.jacobian_evaluations <= s.residual_evaluations);
  CHECK(s.nonlinear_convergence_failures >= 0);
  CHECK(s.error_test_failures >= 0);
  MESSAGE("IDA: " << s.steps << " steps, " << s.residual_evaluations << " residuals, "
                  << s.jacobian_evaluations << " Jacobians, " << s.nonlinear_iterations
                  << " Newton iterations, " << s.nonlinear_convergence_failures
                  << " convergence failures, " << s.error_test_failures
                  << " error-test failures over " << result.periods << " periods");
}

TEST_CASE("Transient statistics: the explicit scheme counts steps and events only") {
  TransientModel model = Oscillator();
  ContactGeometry stop;
  stop.dof = 0;
  stop.direction = 1.0;
  stop.gap = 0.5;  // m, inside the linear amplitude 1.33 m: impacts every period
  model.rigid_contacts = {stop};
  TransientOptions options;
  options.explicit_step_fraction = 0.05;
  CentralDifferenceIntegrator integrator(model, options);
  const TransientResult result = integrator.RunToSteadyState(0.5, {});
  REQUIRE(result.periodic());
  const TransientStatistics& s = result.statistics;
  // One step per node, node 0 included: whole periods of 2π/(0.5 h) steps.
  const long steps_per_period = std::lround(2 * std::numbers::pi / 0.5 / integrator.StepFor(0.5));
  CHECK(s.steps == result.periods * steps_per_period + 1);
  CHECK(s.events >= 2 * (result.periods - 1));
  CHECK(result.steps == s.steps);
  CHECK(result.events == s.events);
  CHECK(s.residual_evaluations == 0);
  CHECK(s.jacobian_evaluations == 0);
  CHECK(s.nonlinear_iterations == 0);
  CHECK(s.nonlinear_convergence_failures == 0);
  CHECK(s.error_test_failures == 0);
}

}  // namespace
}  // namespace nfrc
