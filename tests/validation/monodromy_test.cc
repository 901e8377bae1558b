// The transient monodromy matrix against references that do not use the integrator: the
// closed-form eigenvalues of linear state matrices, Liouville's formula for det Φ, and for
// friction what the stick phases and the velocity reversals must do to det Φ.
#include "validation/monodromy.h"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "validation/central_difference.h"
#include "validation/friction_time_law.h"
#include "validation/ida_integrator.h"
#include "validation/jenkins_time_law.h"
#include "validation/spring_time_law.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// Linear systems: Φ's entries carry the FD round-off ε|P|/h ≈ 1e-16/1e-6 = 1e-10 and IDA's
// global error of the propagator (rtol 1e-10 over a period: ~1e-9); the map is linear so the
// truncation error is nil. 1e-6 relative to max |μ| leaves a margin of 1000.
constexpr double kLinearTolerance = 1e-6;
// det Φ is the product of the multipliers: each relative error ~1e-9..1e-7 (the cubic adds
// h²-truncation ~1e-12), summed over 2 of them; 1e-6 relative is the accuracy asked.
constexpr double kLiouvilleTolerance = 1e-6;
// With events (stick, reversal) the FD noise is ~rtol/h (see MonodromyOptions::relative_step):
// ≤ 6e-5 measured at the default step on the friction orbits; 1e-4 of max |μ|.
constexpr double kEventTolerance = 1e-4;

TransientModel Linear(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c, const Eigen::MatrixXd& k,
                      double force) {
  TransientModel model;
  model.model.mass = m.sparseView();
  model.model.damping = c.sparseView();
  model.model.stiffness = k.sparseView();
  model.forcing = {ForcingTerm{0, 1, force, 0.0}};
  model.massless.assign(static_cast<size_t>(m.rows()), false);
  return model;
}

TransientOptions Options() {
  TransientOptions options;
  options.steady_tolerance = 1e-9;
  options.samples_per_period = 64;
  options.max_periods = 2000;
  return options;
}

// The state at the start of the last recorded period (t0 = pT: excitation phase 0).
InitialState OnOrbit(TransientIntegrator& integrator, double omega) {
  const TransientResult result = integrator.RunToSteadyState(omega, {});
  REQUIRE_MESSAGE(result.periodic(), result.message);
  return {result.last_period.x.col(0), result.last_period.v.col(0)};
}

// exp(sT) for the eigenvalues s of [[0, I], [−M⁻¹K, −M⁻¹C]] (Eigen, not the integrator).
std::vector<Complex> LinearMultipliers(const TransientModel& model, double omega) {
  const Eigen::MatrixXd m(model.model.mass), c(model.model.damping), k(model.model.stiffness);
  const int n = static_cast<int>(m.rows());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m.lu().solve(k);
  a.bottomRightCorner(n, n) = -m.lu().solve(c);
  const Eigen::VectorXcd s = Eigen::EigenSolver<Eigen::MatrixXd>(a).eigenvalues();
  std::vector<Complex> mu;
  for (int i = 0; i < s.size(); ++i) mu.push_back(std::exp(s(i) * (2 * kPi / omega)));
  return mu;
}

// Largest distance from an expected multiplier to the nearest computed one, over max |μ|.
double SetError(const std::vector<Complex>& computed, const std::vector<Complex>& expected) {
  double worst = 0.0, scale = 0.0;
  for (const Complex& e : expected) {
    double best = INFINITY;
    for (const Complex& c : computed) best = std::min(best, std::abs(c - e));
    worst = std::max(worst, best);
    scale = std::max(scale, std::abs(e));
  }
  return worst / scale;
}

Complex Determinant(const std::vector<Complex>& mu) {
  Complex d = 1.0;
  for (const Complex& m : mu) d *= m;
  return d;
}

TEST_CASE("Monodromy: damped linear SDOF gives exp(sT) of the closed-form eigenvalues") {
  // m = 1, c = 0.1, k = 1: s = −ζω_n ± iω_n√(1 − ζ²), ζ = 0.05, ω_n = 1.
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = Linear(one, 0.1 * one, one, 1.0);
  IdaIntegrator ida(model, Options());
  for (double omega : {0.5, 1.0, 1.7}) {
    CAPTURE(omega);
    const InitialState z0 = OnOrbit(ida, omega);
    const MonodromyResult r = ComputeMonodromy(ida, model, omega, z0);
    REQUIRE_MESSAGE(r.ok, r.message);
    CHECK(r.state_dofs == std::vector<int>{0});
    CHECK(r.integrations == 5);
    CHECK(r.closure < 1e-7);  // on the orbit to the steady-state tolerance
    const double period = 2 * kPi / omega;
    const Complex s(-0.05, std::sqrt(1 - 0.05 * 0.05));
    const std::vector<Complex> expected = {std::exp(s * period), std::exp(std::conj(s) * period)};
    const double error = SetError(r.multipliers, expected);
    MESSAGE("SDOF ω = " << omega << ": μ = " << r.multipliers[0] << ", " << r.multipliers[1]
                        << ", expected " << expected[0] << ", error " << error << ", "
                        << r.wall_seconds << " s");
    CHECK(error < kLinearTolerance);
    CHECK(std::abs(r.multipliers[0]) >= std::abs(r.multipliers[1]));
  }
}

TEST_CASE("Monodromy: a sticking Jenkins slider is a state, with multiplier 1") {
  // ẍ + 0.1ẋ + x + f = cos ωt, f = k_t(x − w) with k_t = 2 and μN = 1e3, which the orbit never
  // reaches: the element is the spring k_t and the slider holds at w = 0. Its steady state is
  // x = Re(X e^{iωt}), X = 1/(k + k_t − ω² + icω), started with f(0) = k_t x(0) (own). The
  // state is (x, v, f): the linear pair of k + k_t, and 1 for f, since shifting the slider
  // shifts the orbit (a family of periodic solutions).
  const double c = 0.1, k = 1.0, k_t = 2.0, omega = 0.8;
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = Linear(one, c * one, k * one, 1.0);
  model.laws.push_back(std::make_unique<JenkinsTimeLaw>(0, -1, k_t, 1e3));
  model.law_paths = {"nonlinearities[0]"};
  model.law_sources = {0};
  IdaIntegrator ida(model, Options());
  const Complex amplitude = 1.0 / Complex(k + k_t - omega * omega, c * omega);
  InitialState z0;
  z0.x = Eigen::VectorXd::Constant(1, amplitude.real());
  z0.v = Eigen::VectorXd::Constant(1, (Complex(0, omega) * amplitude).real());
  z0.own = Eigen::VectorXd::Constant(1, k_t * amplitude.real());
  const MonodromyResult r = ComputeMonodromy(ida, model, omega, z0);
  REQUIRE_MESSAGE(r.ok, r.message);
  CHECK(r.state_own == std::vector<int>{0});
  REQUIRE(r.multipliers.size() == 3);
  CHECK(r.closure < 1e-7);  // the closed-form orbit, to IDA's accuracy
  const double zeta = c / (2.0 * std::sqrt(k + k_t)), omega_n = std::sqrt(k + k_t);
  const Complex s(-zeta * omega_n, omega_n * std::sqrt(1 - zeta * zeta));
  const double period = 2 * kPi / omega;
  const std::vector<Complex> expected = {std::exp(s * period), std::exp(std::conj(s) * period),
                                         1.0};
  const double error = SetError(r.multipliers, expected);
  MESSAGE("Jenkins in stick: μ = " << r.multipliers[0] << ", " << r.multipliers[1] << ", "
                                   << r.multipliers[2] << ", error " << error);
  CHECK(error < kLinearTolerance);

  // Started without the slider's force, f(0) follows from the rows (a slider at x(0)): a
  // different orbit of the family, and f is not a state.
  z0.own.resize(0);
  const MonodromyResult without = ComputeMonodromy(ida, model, omega, z0);
  REQUIRE_MESSAGE(without.ok, without.message);
  CHECK(without.multipliers.size() == 2);
  CHECK(without.closure > 1e-2);
}

TEST_CASE("Monodromy: damped 2-DOF linear system gives exp(sT) of the state matrix") {
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 0.5;
  k << 2, -1, -1, 1;
  TransientModel model = Linear(m, 0.05 * m + 0.02 * k, k, 1.0);
  IdaIntegrator ida(model, Options());
  const double omega = 0.8;
  const MonodromyResult r = ComputeMonodromy(ida, model, omega, OnOrbit(ida, omega));
  REQUIRE_MESSAGE(r.ok, r.message);
  REQUIRE(r.multipliers.size() == 4);
  const double error = SetError(r.multipliers, LinearMultipliers(model, omega));
  MESSAGE("2-DOF ω = " << omega << ": |μ| = " << std::abs(r.multipliers[0]) << ", "
                       << std::abs(r.multipliers[2]) << ", error " << error);
  CHECK(error < kLinearTolerance);
  for (size_t i = 1; i < r.multipliers.size(); ++i) {
    CHECK(std::abs(r.multipliers[i - 1]) >= std::abs(r.multipliers[i]));
  }
}

// ẍ + cẋ + x + βx³ = F cos ωt: the trace of the state Jacobian is −c whatever x, so
// det Φ = exp(−cT) (Liouville), independent of the cubic.
TEST_CASE("Monodromy: Duffing det Φ equals exp(−cT) and the step does not matter") {
  const double c = 0.1, beta = 0.5, force = 0.5;
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  for (double omega : {0.6, 1.3}) {
    CAPTURE(omega);
    TransientModel model = Linear(one, c * one, one, force);
    model.laws.push_back(std::make_unique<SpringTimeLaw>(
        "cubic_spring", 0, -1, std::vector<PolynomialSpring::Term>{{3, beta}}));
    IdaIntegrator ida(model, Options());
    const InitialState z0 = OnOrbit(ida, omega);
    const MonodromyResult r = ComputeMonodromy(ida, model, omega, z0);
    REQUIRE_MESSAGE(r.ok, r.message);
    const double liouville = std::exp(-c * 2 * kPi / omega);
    const Complex det = Determinant(r.multipliers);
    MESSAGE("Duffing ω = " << omega << ": μ = " << r.multipliers[0] << ", " << r.multipliers[1]
                           << ", det " << det << " vs exp(-cT) " << liouville << ", closure "
                           << r.closure << ", " << r.wall_seconds << " s");
    CHECK(std::abs(det - liouville) < kLiouvilleTolerance * liouville);
    CHECK(std::abs(det.real() - r.matrix.determinant()) < 1e-12);
    CHECK(r.max_modulus() < 1.0);  // a stable orbit reached from rest
    // The nonlinearity matters: Φ differs from the linear oscillator's.
    const double linear_error = SetError(r.multipliers, LinearMultipliers(model, omega));
    CHECK(linear_error > 1e-3);
    // Steps 10× larger and smaller: truncation (∝ h², ~1e-6 at 1e-3) and integration noise
    // (∝ 1/h) both stay below the tolerance, so Φ does not depend on the choice.
    for (double step : {1e-3, 1e-5}) {
      MonodromyOptions options;
      options.relative_step = step;
      const MonodromyResult other = ComputeMonodromy(ida, model, omega, z0, options);
      REQUIRE(other.ok);
      const double change =
          (other.matrix - r.matrix).cwiseAbs().maxCoeff() / r.matrix.cwiseAbs().maxCoeff();
      MESSAGE("  relative_step " << step << ": Φ changes by " << change);
      CHECK(change < kLiouvilleTolerance);
    }
  }
}

// The two-DOF friction oscillator of cases/friction (Legrand & Pierre 2024): M = diag(1, 1),
// C = [[0.04, −0.02], [−0.02, 0.02]], K = [[2, −1], [−1, 1]], f1 = 20 cos ωt, Coulomb friction
// on x2 against ground with limit μN.
TransientModel FrictionModel(double limit) {
  Eigen::Matrix2d m, c, k;
  m << 1, 0, 0, 1;
  c << 0.04, -0.02, -0.02, 0.02;
  k << 2, -1, -1, 1;
  TransientModel model = Linear(m, c, k, 20.0);
  FrictionParameters p;
  p.equality = FrictionEquality::kMinMax;
  p.limit = limit;
  model.laws.push_back(std::make_unique<FrictionTimeLaw>(1, -1, p, false));
  model.law_paths = {"nonlinearities[0]"};
  return model;
}

// Smooth flow between events: det = exp(−tr(M⁻¹C)T) = exp(−0.06 T). A stick phase freezes
// (x2, v2 = 0): Φ has rank ≤ 3, det Φ = 0. A reversal of v2 without sticking multiplies det
// by the saltation's a2⁺/a2⁻ ∈ (0, 1) (the friction force jumps against the new motion), so a
// sticking-free orbit has 0 < det Φ < exp(−0.06 T).
TEST_CASE("Monodromy: friction oscillator, stick-slip and slip-only orbits") {
  struct Case {
    double limit;
    double omega;
  };
  for (const Case& k : {Case{9.0, 0.308}, Case{9.0, 1.2}, Case{2.0, 1.2}}) {
    CAPTURE(k.limit);
    CAPTURE(k.omega);
    TransientModel model = FrictionModel(k.limit);
    TransientOptions options = Options();
    options.samples_per_period = 1024;
    IdaIntegrator ida(model, options);
    const TransientResult steady = ida.RunToSteadyState(k.omega, {});
    REQUIRE_MESSAGE(steady.periodic(), steady.message);
    const PeriodRecord& rec = steady.last_period;
    const int sticks = rec.phases.at(0).CountPhases(rec.t0, rec.period);
    const InitialState z0{rec.x.col(0), rec.v.col(0)};
    const MonodromyResult r = ComputeMonodromy(ida, model, k.omega, z0);
    REQUIRE_MESSAGE(r.ok, r.message);
    REQUIRE(r.matrix.allFinite());
    const double liouville = std::exp(-0.06 * 2 * kPi / k.omega);
    const double det = r.matrix.determinant();
    MESSAGE("friction μN = " << k.limit << ", ω = " << k.omega << ": " << sticks
                             << " stick phases, μ = " << r.multipliers[0] << ", "
                             << r.multipliers[1] << ", " << r.multipliers[2] << ", "
                             << r.multipliers[3] << ", det " << det << " vs exp(-tr T) "
                             << liouville << ", closure " << r.closure << ", " << r.wall_seconds
                             << " s");
    CHECK(r.max_modulus() < 1.0);  // reached from rest and settled: stable
    if (sticks > 0) {
      // Rank ≤ 3: the smallest multiplier is zero up to the FD noise of the events, measured
      // ≤ 6e-5 in Φ's entries between steps 1e-3 and 3e-5 around the default 1e-4.
      CHECK(std::abs(r.multipliers[3]) < kEventTolerance * r.max_modulus());
      CHECK(std::abs(det) < kEventTolerance * liouville);
    } else {
      CHECK(det > 0.0);
      CHECK(det < liouville);
    }
  }
}

// The rigid stop's impact is plastic (the multiplier zeroes the normal velocity) and at this
// point the slow impact sticks (x = stop, v = 0) for a while (the reference of
// central_difference_test.cc): every start near the orbit then leaves that contact phase in
// the same state, so P is locally constant and Φ = 0 exactly.
TEST_CASE("Monodromy: central differences with a sticking rigid stop forget the start") {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = Linear(one, 0.1 * one, one, 1.0);
  ContactGeometry stop;
  stop.dof = 0;
  stop.direction = 1.0;
  stop.gap = 0.5;  // inside the linear amplitude 1.33 m at ω = 0.5
  model.rigid_contacts = {stop};
  TransientOptions options = Options();
  options.explicit_step_fraction = 0.01;
  options.samples_per_period = 2048;
  CentralDifferenceIntegrator integrator(model, options);
  const double omega = 0.5;
  const MonodromyResult r = ComputeMonodromy(integrator, model, omega, OnOrbit(integrator, omega));
  REQUIRE_MESSAGE(r.ok, r.message);
  MESSAGE("rigid stop ω = 0.5: μ = " << r.multipliers[0] << ", " << r.multipliers[1] << ", closure "
                                     << r.closure);
  CHECK(r.matrix.allFinite());
  CHECK(r.matrix.cwiseAbs().maxCoeff() == 0.0);
  CHECK(r.max_modulus() == 0.0);
}

TEST_CASE("Monodromy: the linear oscillator by central differences converges as O(h^2)") {
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = Linear(one, 0.1 * one, one, 1.0);
  const double omega = 0.5;
  const std::vector<Complex> expected = LinearMultipliers(model, omega);
  double errors[2];
  const double fractions[2] = {0.02, 0.005};
  for (int i = 0; i < 2; ++i) {
    TransientOptions options = Options();
    options.explicit_step_fraction = fractions[i];
    CentralDifferenceIntegrator integrator(model, options);
    const MonodromyResult r =
        ComputeMonodromy(integrator, model, omega, OnOrbit(integrator, omega));
    REQUIRE_MESSAGE(r.ok, r.message);
    errors[i] = SetError(r.multipliers, expected);
    MESSAGE("central differences, step fraction " << fractions[i] << ": error " << errors[i]);
  }
  // Second order: a step 4× smaller divides the error by about 16 (> 8 allows the remainder).
  CHECK(errors[0] / errors[1] > 8.0);
}

TEST_CASE("Monodromy: options and inputs are checked") {
  MonodromyOptions options;
  options.relative_step = 0.0;
  CHECK_THROWS_WITH_AS(options.Validate(), doctest::Contains("validation.monodromy.relative_step"),
                       InputError);
  options = {};
  options.scale = -1.0;
  CHECK_THROWS_WITH_AS(options.Validate(), doctest::Contains("validation.monodromy.scale"),
                       InputError);
  const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = Linear(one, 0.1 * one, one, 1.0);
  IdaIntegrator ida(model, Options());
  // Linear: Φ does not depend on the state, so rest (off the orbit) serves.
  const InitialState rest{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1)};
  // At rest there is no scale for the steps unless one is given.
  const MonodromyResult at_rest = ComputeMonodromy(ida, model, 1.0, rest);
  CHECK_FALSE(at_rest.ok);
  CHECK(at_rest.message.find("validation.monodromy.scale") != std::string::npos);
  options = {};
  options.scale = 1.0;
  const MonodromyResult scaled = ComputeMonodromy(ida, model, 1.0, rest, options);
  REQUIRE(scaled.ok);
  CHECK(scaled.scale == 1.0);
  // Off the orbit the trajectory grows to ~3 m in the period, 3e4 × the steps: IDA's
  // step-decision noise rtol × 3 m / h ≈ 3e-6 shows (on the orbit it is far smaller).
  const double error = SetError(scaled.multipliers, LinearMultipliers(model, 1.0));
  MESSAGE("from rest with scale 1: error " << error);
  CHECK(error < 1e-4);
  CHECK_THROWS_AS(ComputeMonodromy(ida, model, 1.0, InitialState{}), InputError);
}

}  // namespace
}  // namespace nfrc
