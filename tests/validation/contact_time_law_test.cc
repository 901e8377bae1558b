#include "validation/contact_time_law.h"

#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "support/rk4.h"
#include "validation/ida_integrator.h"
#include "validation/time_law_check.h"

namespace nfrc {
namespace {

// The law is linear in y within a mode, so central
// differences with a 1e-7 step are exact up to round-off of order 1e-9 relative.
constexpr double kFdTolerance = 1e-7;
// IDA (rtol 1e-10) and a T/4096 RK4 with located crossings both sit near 1e-9 of the
// amplitude; the steady-state criterion (1e-9 per period) adds less than that.
constexpr double kReferenceTolerance = 1e-6;
// Energy bookkeeping over the recorded period: quadratures at rtol 1e-10 and a periodic orbit
// to 1e-9 close the balance to far better than this share of the input work.
constexpr double kBalanceTolerance = 1e-6;

ContactGeometry Geometry(int dof, int other, double direction, double gap) {
  ContactGeometry g;
  g.dof = dof;
  g.other = other;
  g.direction = direction;
  g.gap = gap;
  return g;
}

TimeLawLayout Layout(int n) {
  TimeLawLayout layout;
  layout.num_dofs = n;
  layout.own_offset = 2 * n;
  return layout;
}

TEST_CASE("Contact time law: gap, force sign and explicit force") {
  // n = +1, obstacle 0.1 above DOF 0 (relative to DOF 1): x0 − x1 = 0.15 penetrates by 0.05.
  ContactTimeLaw law("penalty_contact", Geometry(0, 1, 1.0, 0.1), 200.0);
  const TimeLawLayout layout = Layout(2);
  Eigen::VectorXd y(4), yp = Eigen::VectorXd::Zero(4);
  y << 0.25, 0.1, 0.3, -0.2;
  CHECK(law.Gap(0.0, y.head(2)) == doctest::Approx(-0.05));
  const DaeView s = MakeDaeView(law, layout, 0.0, 0.0, y, yp);
  CHECK_FALSE(law.InPhase());
  law.InitMode(layout, s);
  CHECK(law.InPhase());
  CHECK(law.PhaseName() == "contact");
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(4);
  law.Residual(layout, s, residual);
  // λ = k·0.05 = 10 N pushes DOF 0 back with +n λ in the residual and DOF 1 with −n λ.
  CHECK(residual(2) == doctest::Approx(10.0));
  CHECK(residual(3) == doctest::Approx(-10.0));
  CHECK(residual(0) == 0.0);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(2), explicit_force = Eigen::VectorXd::Zero(2);
  law.Force(layout, s, force);
  CHECK(law.ExplicitForce(0.0, y.head(2), y.tail(2), explicit_force));
  CHECK((force - residual.tail(2)).norm() < 1e-12);
  CHECK((explicit_force - residual.tail(2)).norm() < 1e-12);
  const auto signals = law.Signals(layout, s);
  REQUIRE(signals.size() == 2);
  CHECK(signals[0].first == "gap");
  CHECK(signals[0].second == doctest::Approx(-0.05));
  CHECK(signals[1].first == "force");
  CHECK(signals[1].second == doctest::Approx(10.0));
  double g = 0.0;
  law.Roots(layout, s, &g);
  CHECK(g == doctest::Approx(-0.05));
  const auto bound = law.StiffnessBound();
  REQUIRE(bound.size() == 2);
  CHECK(bound[0] == std::pair<int, double>(0, 200.0));
  CHECK(bound[1] == std::pair<int, double>(1, 200.0));

  // Open: no force, the explicit force is zero too; a crossing back closes it again.
  Eigen::VectorXd open_y = y;
  open_y(0) = 0.15;  // gap 0.05
  const DaeView open = MakeDaeView(law, layout, 0.0, 0.0, open_y, yp);
  law.OnRoot(layout, open, 0);
  CHECK_FALSE(law.InPhase());
  CHECK(law.Admissible(layout, open));
  residual.setZero();
  law.Residual(layout, open, residual);
  CHECK(residual.norm() == 0.0);
  explicit_force.setZero();
  law.ExplicitForce(0.0, open_y.head(2), open_y.tail(2), explicit_force);
  CHECK(explicit_force.norm() == 0.0);
  law.OnRoot(layout, s, 0);
  CHECK(law.InPhase());
  CHECK(law.ModeIndex() == 1);

  // n = −1 against ground: the obstacle is below, x = −0.3 against gap 0.2 penetrates 0.1.
  ContactTimeLaw below("penalty_contact", Geometry(0, -1, -1.0, 0.2), 50.0);
  Eigen::VectorXd x(1);
  x << -0.3;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(1);
  below.ExplicitForce(0.0, x, x, f);
  CHECK(f(0) == doctest::Approx(-5.0));  // residual −5: pushes the DOF up
  CHECK(below.StiffnessBound().size() == 1);
  CHECK_THROWS_AS(ContactTimeLaw("penalty_contact", Geometry(0, -1, 1.0, 0.1), 0.0),
                  std::invalid_argument);
}

TEST_CASE("Contact time law: Jacobian matches finite differences in both modes") {
  for (int other : {-1, 1}) {
    for (bool closed : {false, true}) {
      CAPTURE(other);
      CAPTURE(closed);
      ContactGeometry geometry = Geometry(0, other, -1.0, 0.05);
      geometry.gap_harmonics.push_back({2, 0.01, -0.02});
      ContactTimeLaw law("penalty_contact", geometry, 300.0);
      const TimeLawLayout layout = Layout(2);
      const double phase = 0.7;
      Eigen::VectorXd y(4), yp(4);
      y << (closed ? -0.3 : 0.2), 0.04, 0.5, -0.1;
      yp << 0.5, -0.1, 2.0, 1.0;
      const DaeView s = MakeDaeView(law, layout, 1.0, phase, y, yp);
      law.InitMode(layout, s);
      CHECK(law.InPhase() == closed);
      for (double cj : {0.0, 1e3}) {
        const TimeLawCheck check = CheckTimeLawJacobian(law, layout, 1.0, phase, y, yp, cj);
        CHECK_MESSAGE(check.Passed(kFdTolerance), check.worst);
      }
    }
  }
}

// m ẍ + c ẋ + k x + kc max(0, x − gap) = F cos ωt: a unit oscillator below an obstacle.
struct ImpactOscillator {
  double c = 0.2;
  double k = 1.0;
  double kc = 10.0;
  double gap = 1.0;
  double force = 1.0;
  double omega = 0.8;

  double Accel(double t, double x, double v, bool closed) const {
    return force * std::cos(omega * t) - c * v - k * x - (closed ? kc * (x - gap) : 0.0);
  }
  // One RK4 step of length h in a fixed mode.
  void Step(double t, double h, bool closed, double* x, double* v) const {
    testing::Rk4Step([&](double tt, double xx, double vv) { return Accel(tt, xx, vv, closed); }, t,
                     h, x, v);
  }
};

// Fixed-step RK4 from rest over `periods` periods; a step that would change the contact mode
// is cut at the crossing (bisection on the sub-step length), so no step straddles the kink.
// Returns x at `samples` uniform times of the last period and the share of it in contact.
std::pair<Eigen::VectorXd, double> Rk4Reference(const ImpactOscillator& o, int periods, int samples,
                                                int steps_per_sample) {
  const double period = 2 * std::numbers::pi / o.omega;
  const int steps = samples * steps_per_sample;
  const double h = period / steps;
  double x = 0.0, v = 0.0;
  bool closed = false;
  Eigen::VectorXd recorded(samples);
  double contact_time = 0.0;
  for (int p = 0; p < periods; ++p) {
    const bool last = p == periods - 1;
    for (int i = 0; i < steps; ++i) {
      if (last && i % steps_per_sample == 0) recorded(i / steps_per_sample) = x;
      double t = (static_cast<double>(p) * steps + i) * h;
      double remaining = h;
      while (remaining > 0.0) {
        double xs = x, vs = v;
        o.Step(t, remaining, closed, &xs, &vs);
        const bool crosses = closed ? xs < o.gap : xs > o.gap;
        double taken = remaining;
        if (crosses) {
          double lo = 0.0, hi = remaining;
          for (int b = 0; b < 200 && hi - lo > 1e-16 * period; ++b) {
            const double mid = 0.5 * (lo + hi);
            double xm = x, vm = v;
            o.Step(t, mid, closed, &xm, &vm);
            ((closed ? xm < o.gap : xm > o.gap) ? hi : lo) = mid;
          }
          taken = hi;
          xs = x;
          vs = v;
          o.Step(t, taken, closed, &xs, &vs);
        }
        if (last && closed) contact_time += taken;
        x = xs;
        v = vs;
        t += taken;
        remaining -= taken;
        if (crosses) closed = !closed;
      }
    }
  }
  return {recorded, contact_time / period};
}

TransientModel ImpactModel(const ImpactOscillator& o) {
  TransientModel model;
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  model.model.mass = one.sparseView();
  model.model.damping = (o.c * one).sparseView();
  model.model.stiffness = (o.k * one).sparseView();
  model.forcing = {ForcingTerm{0, 1, o.force, 0.0}};
  model.laws.push_back(
      std::make_unique<ContactTimeLaw>("penalty_contact", Geometry(0, -1, 1.0, o.gap), o.kc));
  return model;
}

TEST_CASE("Contact time law: IDA impact oscillator against RK4, energy balance, one contact") {
  const ImpactOscillator o;
  TransientModel model = ImpactModel(o);
  TransientOptions options;
  options.relative_tolerance = 1e-10;
  options.steady_tolerance = 1e-9;
  options.samples_per_period = 64;
  options.max_periods = 400;
  const TransientResult result = IdaIntegrator(model, options).RunToSteadyState(o.omega, {});
  REQUIRE_MESSAGE(result.periodic(), result.message);
  const PeriodRecord& r = result.last_period;

  // (b) an independent fixed-step reference, started from rest, after the same decay.
  const auto [reference, contact_fraction] = Rk4Reference(o, result.periods, 64, 64);
  const double scale = reference.cwiseAbs().maxCoeff();
  const double error = (r.x.row(0).transpose() - reference).cwiseAbs().maxCoeff() / scale;
  REQUIRE(r.phases.size() == 1);
  const double fraction = r.phases[0].PhaseFraction(r.t0, r.period);
  MESSAGE("impact: RK4 difference " << error << ", contact fraction " << fraction << " vs "
                                    << contact_fraction << ", " << result.periods << " periods, "
                                    << result.events << " events, " << result.wall_seconds << " s");
  CHECK(error < kReferenceTolerance);
  CHECK(std::abs(fraction - contact_fraction) < kReferenceTolerance);
  CHECK(fraction > 0.05);  // really in contact for part of the period
  CHECK(fraction < 0.95);

  // (a) the energy balance closes, and the penalty spring gives back what it took.
  const double imbalance = r.work_input - r.work_damping - r.work_laws - r.energy_change;
  MESSAGE("impact: imbalance " << imbalance / r.work_input << ", law work "
                               << r.work_laws / r.work_input);
  CHECK(r.work_input > 0.0);
  CHECK(std::abs(imbalance) < kBalanceTolerance * r.work_input);
  CHECK(std::abs(r.work_laws) < kBalanceTolerance * r.work_input);

  // (c) one contact phase per period, two mode switches per period in steady state.
  CHECK(r.phases[0].phase_name == "contact");
  CHECK(r.phases[0].CountPhases(r.t0, r.period) == 1);
  CHECK(result.events >= 2 * (result.periods - 1));
  CHECK(result.events <= 2 * result.periods);

  // The recorded gap and force signals are those of the law: λ = kc·max(0, −g).
  REQUIRE(r.law_signals.size() == 1);
  REQUIRE(r.law_signals[0].size() == 2);
  const Eigen::VectorXd& gap = r.law_signals[0][0].second;
  const Eigen::VectorXd& force = r.law_signals[0][1].second;
  for (int i = 0; i < gap.size(); ++i) {
    CHECK(gap(i) == doctest::Approx(o.gap - r.x(0, i)).epsilon(1e-12));
    CHECK(force(i) == doctest::Approx(o.kc * std::max(0.0, -gap(i))).epsilon(1e-9));
  }
}

}  // namespace
}  // namespace nfrc
