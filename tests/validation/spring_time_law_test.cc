#include "validation/spring_time_law.h"

#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "support/rk4.h"
#include "validation/ida_integrator.h"
#include "validation/time_law_check.h"

namespace nfrc {
namespace {

// Central differences of a cubic with a 1e-7 step: truncation h²·f'''/6 ≈ 1e-14 relative,
// round-off ≈ 1e-16/1e-7 = 1e-9 relative.
constexpr double kFdTolerance = 1e-7;
// IDA at rtol 1e-10 against a T/4096 RK4 (error ≈ (ωh)⁴ ≈ 1e-13): both well under 1e-8 of the
// amplitude; the steady-state criterion (1e-9 per period) adds less.
constexpr double kReferenceTolerance = 1e-6;

TimeLawLayout Layout(int n) {
  TimeLawLayout layout;
  layout.num_dofs = n;
  layout.own_offset = 2 * n;
  return layout;
}

std::vector<PolynomialSpring::Term> Terms() { return {{3, 0.5}, {2, -0.2}, {5, 0.03}}; }

double Polynomial(double u) { return 0.5 * u * u * u - 0.2 * u * u + 0.03 * std::pow(u, 5); }

TEST_CASE("Spring time law: force, residual and explicit force are the polynomial") {
  for (int other : {-1, 1}) {
    CAPTURE(other);
    SpringTimeLaw law("polynomial_spring", 0, other, Terms());
    CHECK(law.type() == "polynomial_spring");
    const TimeLawLayout layout = Layout(2);
    Eigen::VectorXd y(4), yp = Eigen::VectorXd::Zero(4);
    y << 0.9, -0.4, 0.1, 0.2;
    const double u = other >= 0 ? 1.3 : 0.9;
    const DaeView s = MakeDaeView(law, layout, 0.0, 0.0, y, yp);
    Eigen::VectorXd residual = Eigen::VectorXd::Zero(4);
    law.Residual(layout, s, residual);
    CHECK(residual(0) == 0.0);
    CHECK(residual(1) == 0.0);
    CHECK(residual(2) == doctest::Approx(Polynomial(u)));
    CHECK(residual(3) == doctest::Approx(other >= 0 ? -Polynomial(u) : 0.0));
    Eigen::VectorXd force = Eigen::VectorXd::Zero(2), explicit_force = Eigen::VectorXd::Zero(2);
    law.Force(layout, s, force);
    CHECK(law.ExplicitForce(0.0, y.head(2), y.tail(2), explicit_force));
    CHECK((force - residual.tail(2)).norm() < 1e-14);
    CHECK((explicit_force - residual.tail(2)).norm() < 1e-14);
    const auto signals = law.Signals(layout, s);
    REQUIRE(signals.size() == 2);
    CHECK(signals[0].first == "force");
    CHECK(signals[0].second == doctest::Approx(Polynomial(u)));
    CHECK(signals[1].first == "displacement");
    CHECK(signals[1].second == doctest::Approx(u));
    CHECK(law.NumRoots() == 0);
    CHECK(law.NumOwn() == 0);
  }
  CHECK_THROWS_AS(SpringTimeLaw("cubic_spring", 0, 0, Terms()), std::invalid_argument);
  CHECK_THROWS_AS(SpringTimeLaw("cubic_spring", 0, -1, {}), std::invalid_argument);
  CHECK_THROWS_AS(SpringTimeLaw("cubic_spring", 0, -1, {{1, 2.0}}), std::invalid_argument);
}

TEST_CASE("Spring time law: Jacobian matches finite differences") {
  for (int other : {-1, 1}) {
    CAPTURE(other);
    SpringTimeLaw law("polynomial_spring", 1, other == 1 ? 0 : -1, Terms());
    const TimeLawLayout layout = Layout(2);
    Eigen::VectorXd y(4), yp(4);
    y << -0.7, 0.6, 0.3, -0.8;
    yp << 0.3, -0.8, 1.5, 0.4;
    for (double cj : {0.0, 1e4}) {
      const TimeLawCheck check = CheckTimeLawJacobian(law, layout, 0.5, 0.2, y, yp, cj);
      CHECK_MESSAGE(check.Passed(kFdTolerance), check.worst);
    }
  }
}

// ẍ + c ẋ + x + β x³ = F cos ωt below the primary resonance (hardening: the coexistence band
// lies above ω ≈ 1.2 and the 3:1 superharmonic near 0.37), so the periodic orbit is unique.
struct Duffing {
  double c = 0.1;
  double beta = 0.5;
  double force = 0.5;
  double omega = 0.6;

  double Accel(double t, double x, double v) const {
    return force * std::cos(omega * t) - c * v - x - beta * x * x * x;
  }
};

// Fixed-step RK4 from rest over `periods` periods; x at `samples` times of the last period.
Eigen::VectorXd Rk4Reference(const Duffing& d, int periods, int samples, int steps_per_sample) {
  const int steps = samples * steps_per_sample;
  const double h = 2 * std::numbers::pi / d.omega / steps;
  double x = 0.0, v = 0.0;
  Eigen::VectorXd recorded(samples);
  for (int p = 0; p < periods; ++p) {
    for (int i = 0; i < steps; ++i) {
      if (p == periods - 1 && i % steps_per_sample == 0) recorded(i / steps_per_sample) = x;
      const double t = (static_cast<double>(p) * steps + i) * h;
      testing::Rk4Step([&](double tt, double xx, double vv) { return d.Accel(tt, xx, vv); }, t, h,
                       &x, &v);
    }
  }
  return recorded;
}

TEST_CASE("Spring time law: IDA Duffing oscillator against RK4") {
  const Duffing d;
  TransientModel model;
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  model.model.mass = one.sparseView();
  model.model.damping = (d.c * one).sparseView();
  model.model.stiffness = one.sparseView();
  model.forcing = {ForcingTerm{0, 1, d.force, 0.0}};
  model.laws.push_back(std::make_unique<SpringTimeLaw>(
      "cubic_spring", 0, -1, std::vector<PolynomialSpring::Term>{{3, d.beta}}));
  TransientOptions options;
  options.relative_tolerance = 1e-10;
  options.steady_tolerance = 1e-9;
  options.samples_per_period = 64;
  options.max_periods = 400;
  const TransientResult result = IdaIntegrator(model, options).RunToSteadyState(d.omega, {});
  REQUIRE_MESSAGE(result.periodic(), result.message);
  CHECK(result.events == 0);
  const PeriodRecord& r = result.last_period;
  const Eigen::VectorXd reference = Rk4Reference(d, result.periods, 64, 64);
  const double scale = reference.cwiseAbs().maxCoeff();
  const double error = (r.x.row(0).transpose() - reference).cwiseAbs().maxCoeff() / scale;
  // The spring is conservative: over a closed orbit it does no net work.
  MESSAGE("Duffing: RK4 difference " << error << ", amplitude " << scale << ", law work "
                                     << r.work_laws / r.work_input << ", " << result.periods
                                     << " periods, " << result.wall_seconds << " s");
  CHECK(error < kReferenceTolerance);
  CHECK(std::abs(r.work_laws) < kReferenceTolerance * r.work_input);
  CHECK(std::abs(r.work_input - r.work_damping) < kReferenceTolerance * r.work_input);
  // The cubic term matters here: the linear amplitude F/|1 − ω² + icω| is well away.
  CHECK(std::abs(scale - d.force / std::abs(std::complex<double>(1 - 0.36, 0.06))) > 0.02);
  REQUIRE(r.law_signals.size() == 1);
  CHECK(r.law_signals[0][0].first == "force");
  CHECK(r.law_signals[0][0].second(5) == doctest::Approx(d.beta * std::pow(r.x(0, 5), 3)));
}

}  // namespace
}  // namespace nfrc
