#include "validation/central_difference.h"

#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "validation/contact_time_law.h"
#include "validation/friction_time_law.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

Eigen::SparseMatrix<double> Sparse(const Eigen::MatrixXd& dense) { return dense.sparseView(); }

// A one-DOF oscillator m ẍ + c ẋ + k x = F cos ωt.
struct Oscillator {
  double m = 1.0;      // kg
  double c = 0.1;      // N·s/m, ζ = 0.05
  double k = 1.0;      // N/m
  double force = 1.0;  // N
  double omega = 0.5;  // rad/s, below the resonance at 1 rad/s
  double stop = 0.5;   // m, rigid stop on the positive side, inside the linear amplitude 1.33 m
  double period() const { return 2 * kPi / omega; }
};

TransientModel OscillatorModel(const Oscillator& o) {
  TransientModel model;
  model.model.mass = Sparse(Eigen::MatrixXd::Constant(1, 1, o.m));
  model.model.damping = Sparse(Eigen::MatrixXd::Constant(1, 1, o.c));
  model.model.stiffness = Sparse(Eigen::MatrixXd::Constant(1, 1, o.k));
  model.forcing = {ForcingTerm{0, 1, o.force, 0.0}};
  model.massless = {false};
  return model;
}

ContactGeometry Stop(double gap) {
  ContactGeometry contact;
  contact.dof = 0;
  contact.direction = 1.0;
  contact.gap = gap;
  return contact;
}

// First harmonic X of samples x_i at t_i over one period: x ≈ Re(X e^{iωt}).
Complex FirstHarmonic(const Eigen::VectorXd& t, const Eigen::VectorXd& x, double omega) {
  Complex sum = 0.0;
  for (int i = 0; i < x.size(); ++i) sum += x(i) * std::exp(Complex(0.0, -omega * t(i)));
  return 2.0 * sum / static_cast<double>(x.size());
}

// Event-driven solution of the oscillator against a rigid stop at x = stop, written from the
// closed-form linear solution: free flight x = x_p + e^{−ζω_n τ}(A cos ω_d τ + B sin ω_d τ),
// impact found by scanning and bisection on it, perfectly inelastic impact (v = 0), sticking
// at the stop while the net force F cos ωt − k·stop pushes into it, release where it vanishes.
class ImpactReference {
 public:
  struct Segment {
    double t0, t1;
    bool stuck;
    double x0, v0;  // state at t0 (free flight)
  };

  explicit ImpactReference(const Oscillator& o)
      : o_(o),
        omega_n_(std::sqrt(o.k / o.m)),
        zeta_(o.c / (2 * std::sqrt(o.k * o.m))),
        omega_d_(omega_n_ * std::sqrt(1 - zeta_ * zeta_)),
        amplitude_(o.force / Complex(o.k - o.m * o.omega * o.omega, o.c * o.omega)) {}

  // From rest at t = 0 to t_end; impact velocities are kept with their times.
  void Run(double t_end) {
    double t = 0.0, x = 0.0, v = 0.0;
    bool stuck = false;
    const double ratio = o_.k * o_.stop / o_.force;
    REQUIRE(std::abs(ratio) < 1.0);
    while (t < t_end) {
      if (stuck) {
        const double release_phase = std::acos(ratio);
        double j = std::ceil((o_.omega * t - release_phase) / (2 * kPi));
        double t_release = (release_phase + 2 * kPi * j) / o_.omega;
        if (t_release <= t) t_release += 2 * kPi / o_.omega;
        segments_.push_back({t, t_release, true, o_.stop, 0.0});
        t = t_release;
        x = o_.stop;
        v = 0.0;
        stuck = false;
        continue;
      }
      const Segment free{t, t_end, false, x, v};
      const double scan = o_.period() / 4000;
      double t_impact = -1.0;
      for (double b = t + scan; b < t_end + scan; b += scan) {
        if (Free(free, b).first >= o_.stop) {
          double a = b - scan, c = b;
          for (int i = 0; i < 200 && c - a > 1e-15 * c; ++i) {
            const double mid = 0.5 * (a + c);
            (Free(free, mid).first >= o_.stop ? c : a) = mid;
          }
          t_impact = c;
          break;
        }
      }
      if (t_impact < 0.0) {
        segments_.push_back(free);
        break;
      }
      segments_.push_back({t, t_impact, false, x, v});
      impacts_.push_back({t_impact, Free(free, t_impact).second});

      t = t_impact;
      x = o_.stop;
      v = 0.0;
      stuck = o_.force * std::cos(o_.omega * t) - o_.k * o_.stop > 0.0;
    }
  }

  // (x, v) at t.
  std::pair<double, double> State(double t) const {
    for (const Segment& s : segments_) {
      if (t >= s.t0 && t <= s.t1) return s.stuck ? std::make_pair(o_.stop, 0.0) : Free(s, t);
    }
    FAIL("t outside the reference run");
    return {0.0, 0.0};
  }

  // Contact phases in [t0, t0 + T): each starts with an impact, whether the mass then sticks
  // or leaves at once; and the share of the period spent sticking.
  std::pair<int, double> Contact(double t0) const {
    const double t1 = t0 + o_.period();
    int count = 0;
    for (const auto& impact : impacts_) count += impact.first >= t0 && impact.first < t1;
    double time = 0.0;
    for (const Segment& s : segments_) {
      if (s.stuck) time += std::max(0.0, std::min(s.t1, t1) - std::max(s.t0, t0));
    }
    return {count, time / o_.period()};
  }

  // Kinetic energy lost in the impacts within [t0, t0 + T) (J).
  double ImpactLoss(double t0) const {
    double loss = 0.0;
    for (const auto& [t, v] : impacts_) {
      if (t >= t0 && t < t0 + o_.period()) loss += 0.5 * o_.m * v * v;
    }
    return loss;
  }

 private:
  std::pair<double, double> Free(const Segment& s, double t) const {
    const auto particular = [&](double time) {
      const Complex e = amplitude_ * std::exp(Complex(0.0, o_.omega * time));
      return std::make_pair(e.real(), (Complex(0.0, o_.omega) * e).real());
    };
    const auto [xp0, vp0] = particular(s.t0);
    const double a = s.x0 - xp0;
    const double b = (s.v0 - vp0 + zeta_ * omega_n_ * a) / omega_d_;
    const double tau = t - s.t0;
    const double decay = std::exp(-zeta_ * omega_n_ * tau);
    const double cs = std::cos(omega_d_ * tau), sn = std::sin(omega_d_ * tau);
    const auto [xp, vp] = particular(t);
    return {xp + decay * (a * cs + b * sn),
            vp + decay * ((-zeta_ * omega_n_ * a + omega_d_ * b) * cs +
                          (-zeta_ * omega_n_ * b - omega_d_ * a) * sn)};
  }

  Oscillator o_;
  double omega_n_, zeta_, omega_d_;
  Complex amplitude_;
  std::vector<Segment> segments_;
  std::vector<std::pair<double, double>> impacts_;  // (time, velocity before impact)
};

// Steady-state measures of a period starting at t0, on `samples` uniform points.
struct PeriodMeasures {
  double max_x = 0.0, min_x = 0.0;
  Complex first;
};

PeriodMeasures MeasureSamples(const Eigen::VectorXd& t, const Eigen::VectorXd& x, double omega) {
  return {x.maxCoeff(), x.minCoeff(), FirstHarmonic(t, x, omega)};
}

PeriodMeasures MeasureReference(const ImpactReference& reference, double t0, double omega,
                                int samples) {
  const double period = 2 * kPi / omega;
  Eigen::VectorXd t(samples), x(samples);
  for (int i = 0; i < samples; ++i) {
    t(i) = t0 + period * i / samples;
    x(i) = reference.State(t(i)).first;
  }
  return MeasureSamples(t, x, omega);
}

// The reference integrates this many periods from rest; its state at the last two period
// boundaries must agree to kReferencePeriodicity (it decays by e^{−ζω_nT} ≈ 0.53 per free
// period at least, so 60 periods leave < 1e-12 of the start transient).
constexpr int kReferencePeriods = 60;
constexpr double kReferencePeriodicity = 1e-10;
// Dense sampling of the reference: the first harmonic by the rectangle rule on a continuous
// function with kinks in ẋ errs by O(1/N²) ≈ 1e-9; min x by O((ωT/N)²) ≈ 1e-8.
constexpr int kReferenceSamples = 20000;

ImpactReference SteadyReference(const Oscillator& o) {
  ImpactReference reference(o);
  reference.Run(kReferencePeriods * o.period() + 1e-9);
  const auto a = reference.State((kReferencePeriods - 1) * o.period());
  const auto b = reference.State((kReferencePeriods - 2) * o.period());
  REQUIRE(std::abs(a.first - b.first) < kReferencePeriodicity);
  REQUIRE(std::abs(a.second - b.second) < kReferencePeriodicity);
  return reference;
}

TransientResult RunRigid(const Oscillator& o, double step_fraction) {
  TransientModel model = OscillatorModel(o);
  model.rigid_contacts = {Stop(o.stop)};
  TransientOptions options;
  options.explicit_step_fraction = step_fraction;
  options.samples_per_period = 2048;
  CentralDifferenceIntegrator integrator(model, options);
  TransientResult result = integrator.RunToSteadyState(o.omega, InitialState{});
  REQUIRE(result.periodic());
  return result;
}

TEST_CASE("Central difference: linear 2-DOF converges to the harmonic solution as O(h^2)") {
  TransientModel model;
  Eigen::MatrixXd mass(2, 2), stiffness(2, 2);
  mass << 1.0, 0.0, 0.0, 0.5;
  stiffness << 3.0, -1.0, -1.0, 1.0;
  const Eigen::MatrixXd damping = 0.1 * mass + 0.02 * stiffness;
  model.model.mass = Sparse(mass);
  model.model.damping = Sparse(damping);
  model.model.stiffness = Sparse(stiffness);
  model.forcing = {ForcingTerm{0, 1, 1.0, 0.0}, ForcingTerm{1, 1, 0.0, 0.3}};
  model.massless = {false, false};
  const double omega = 0.9;  // rad/s, between the modes (0.84 and 2.0 rad/s undamped)
  const Eigen::VectorXcd force = (Eigen::VectorXcd(2) << 1.0, Complex(0.0, -0.3)).finished();
  const Eigen::VectorXcd exact = (stiffness.cast<Complex>() - omega * omega * mass.cast<Complex>() +
                                  Complex(0.0, omega) * damping.cast<Complex>())
                                     .partialPivLu()
                                     .solve(force);

  // Steady state is declared at 1e-10 relative change per period, so the recorded period
  // matches the discrete periodic solution to about that, amplified by 1/(1 − e^{−ζωT}) ≈ 10.
  constexpr double kDiscreteTolerance = 1e-8;
  double errors[2];
  const double fractions[2] = {0.04, 0.02};
  for (int r = 0; r < 2; ++r) {
    TransientOptions options;
    options.explicit_step_fraction = fractions[r];
    options.steady_tolerance = 1e-10;
    CentralDifferenceIntegrator integrator(model, options);
    const double h = integrator.StepFor(omega);
    const int steps = static_cast<int>(std::lround(2 * kPi / omega / h));
    options.samples_per_period = steps;  // samples on the steps: no interpolation error
    CentralDifferenceIntegrator sampled(model, options);
    const TransientResult result = sampled.RunToSteadyState(omega, InitialState{});
    REQUIRE(result.periodic());
    CHECK(result.method == "central_difference");

    // The exact periodic solution of the difference equations, x_n = Re(X_h e^{iωt_n}).
    const Eigen::MatrixXcd discrete_operator =
        stiffness.cast<Complex>() + (2 * std::cos(omega * h) - 2) / (h * h) * mass.cast<Complex>() +
        Complex(0.0, std::sin(omega * h) / h) * damping.cast<Complex>();
    const Eigen::VectorXcd discrete = discrete_operator.partialPivLu().solve(force);
    Eigen::VectorXcd first(2);
    for (int dof = 0; dof < 2; ++dof) {
      first(dof) =
          FirstHarmonic(result.last_period.t, result.last_period.x.row(dof).transpose(), omega);
      CHECK(std::abs(first(dof) - discrete(dof)) < kDiscreteTolerance * std::abs(discrete(dof)));
      // The samples of a pure harmonic on the steps miss its crest by at most 1 − cos(ωh/2).
      const double max_abs = result.last_period.x.row(dof).cwiseAbs().maxCoeff();
      CHECK(std::abs(max_abs - std::abs(exact(dof))) <
            std::abs(discrete(dof) - exact(dof)) +
                (1 - std::cos(omega * h / 2) + kDiscreteTolerance) * std::abs(exact(dof)));
    }
    const double error = (first - exact).norm() / exact.norm();
    // A priori bound from the difference operator D_h − D = O(h²):
    // ‖X_h − X‖ ≤ ‖D_h⁻¹‖ ‖D_h − D‖ ‖X‖ (spectral norms).
    const Eigen::MatrixXcd continuous_operator = stiffness.cast<Complex>() -
                                                 omega * omega * mass.cast<Complex>() +
                                                 Complex(0.0, omega) * damping.cast<Complex>();
    const double bound = (discrete_operator - continuous_operator).jacobiSvd().singularValues()(0) /
                         discrete_operator.jacobiSvd().singularValues()(1);
    CHECK(error < bound + kDiscreteTolerance);
    errors[r] = error;
    MESSAGE("fraction " << fractions[r] << ": h = " << h << " s, " << steps
                        << " steps per period, relative error of the first harmonic " << error
                        << " (a priori bound " << bound << ")");
  }
  // Second order: halving h divides the error by 4; 3..5 allows the O(h⁴) remainder.
  CHECK(errors[0] / errors[1] > 3.0);
  CHECK(errors[0] / errors[1] < 5.0);
}

TEST_CASE("Central difference: impact oscillator matches the event-driven solution to O(h)") {
  const Oscillator o;
  const ImpactReference reference = SteadyReference(o);
  const double t0_reference = (kReferencePeriods - 1) * o.period();
  const PeriodMeasures exact =
      MeasureReference(reference, t0_reference, o.omega, kReferenceSamples);
  const auto [exact_count, exact_fraction] = reference.Contact(t0_reference);
  MESSAGE("reference: min x " << exact.min_x << " m, |X1| " << std::abs(exact.first)
                              << " m, contact phases " << exact_count << ", sticking fraction "
                              << exact_fraction);
  // One impact from far (0.86 m/s, the mass leaves at once) and one slow (0.22 m/s) that sticks.
  REQUIRE(exact_count == 2);

  double errors[2];
  const double fractions[2] = {0.01, 0.0025};
  for (int r = 0; r < 2; ++r) {
    const TransientResult result = RunRigid(o, fractions[r]);
    const PeriodRecord& record = result.last_period;
    const double h = record.period / std::ceil(record.period / (2 * fractions[r]));
    const PeriodMeasures measured = MeasureSamples(record.t, record.x.row(0).transpose(), o.omega);
    const double error_first = std::abs(measured.first - exact.first);
    const double error_min = std::abs(measured.min_x - exact.min_x);
    // First order: an impact lands up to a few steps off, so x errs by about h·max|ẋ|, with
    // max|ẋ| < 1 m/s here; the tolerance is h × 1 m/s.
    const double tolerance = h * 1.0;
    CHECK(std::abs(measured.max_x - o.stop) < 1e-12);  // the gap closes exactly, no overshoot
    CHECK(error_first < tolerance);
    CHECK(error_min < tolerance);
    REQUIRE(record.phases.size() == 1);
    CHECK(record.phases[0].type == "rigid_contact");
    CHECK(record.phases[0].phase_name == "contact");
    CHECK(record.phases[0].CountPhases(record.t0, record.period) == exact_count);
    // Each phase starts at the step before its impact (up to one more step early for the slow
    // impact, whose time errs by δx/v) and ends at a step; the impact that bounces off lasts
    // two steps: within 3h per phase.
    const double fraction = record.phases[0].PhaseFraction(record.t0, record.period);
    CHECK(std::abs(fraction - exact_fraction) < 3.0 * h * exact_count / record.period);
    errors[r] = error_first;
    MESSAGE("fraction " << fractions[r] << ": h = " << h << " s, |X1| error " << error_first
                        << " m, min x error " << error_min << " m, contact fraction error "
                        << fraction - exact_fraction << ", " << result.periods << " periods, "
                        << result.wall_seconds << " s");
  }
  // First order (errors ∝ h, with irregular offsets as impacts move between steps): a step
  // four times smaller gains at least a factor 2.
  CHECK(errors[0] / errors[1] > 2.0);
}

// Two uncoupled copies solved as one LCP (Lemke): DOF 0 against the stop of the reference at
// +0.5 m, DOF 1 forced by −F against a stop at −0.3 m (direction −1), the mirror image of the
// reference with its stop at +0.3 m.
TEST_CASE("Central difference: two contacts on both sides match the event-driven solution") {
  Oscillator o;
  Oscillator mirrored = o;
  mirrored.stop = 0.3;
  TransientModel model;
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(2, 2);
  model.model.mass = Sparse(o.m * identity);
  model.model.damping = Sparse(o.c * identity);
  model.model.stiffness = Sparse(o.k * identity);
  model.forcing = {ForcingTerm{0, 1, o.force, 0.0}, ForcingTerm{1, 1, -o.force, 0.0}};
  model.massless = {false, false};
  ContactGeometry lower = Stop(mirrored.stop);
  lower.dof = 1;
  lower.direction = -1.0;
  model.rigid_contacts = {Stop(o.stop), lower};
  TransientOptions options;
  options.explicit_step_fraction = 0.005;
  options.samples_per_period = 2048;
  CentralDifferenceIntegrator integrator(model, options);
  const double h = integrator.StepFor(o.omega);
  const TransientResult result = integrator.RunToSteadyState(o.omega, InitialState{});
  REQUIRE(result.periodic());
  const PeriodRecord& record = result.last_period;
  REQUIRE(record.phases.size() == 2);
  REQUIRE(record.law_signals.size() == 2);

  const double sign[2] = {1.0, -1.0};
  const Oscillator* oscillators[2] = {&o, &mirrored};
  for (int dof = 0; dof < 2; ++dof) {
    const ImpactReference reference = SteadyReference(*oscillators[dof]);
    const double t0_reference = (kReferencePeriods - 1) * o.period();
    const PeriodMeasures exact =
        MeasureReference(reference, t0_reference, o.omega, kReferenceSamples);
    const Eigen::VectorXd x = sign[dof] * record.x.row(dof).transpose();
    const PeriodMeasures measured = MeasureSamples(record.t, x, o.omega);
    // As for one contact: first order, h × max|ẋ| with max|ẋ| < 1 m/s.
    CHECK(std::abs(measured.first - exact.first) < h * 1.0);
    CHECK(std::abs(measured.min_x - exact.min_x) < h * 1.0);
    CHECK(std::abs(measured.max_x - oscillators[dof]->stop) < 1e-12);
    CHECK(record.phases[dof].CountPhases(record.t0, record.period) ==
          reference.Contact(t0_reference).first);
    // The gap signal is never negative beyond round-off, and the force never negative.
    CHECK(record.law_signals[dof][0].first == "gap");
    CHECK(record.law_signals[dof][0].second.minCoeff() > -1e-12);
    CHECK(record.law_signals[dof][1].first == "force");
    CHECK(record.law_signals[dof][1].second.minCoeff() >= 0.0);
    MESSAGE("DOF " << dof << ": |X1| error " << std::abs(measured.first - exact.first)
                   << " m, h = " << h << " s");
  }
}

// Quasi-static forcing (ω = 0.05 ω_n) and heavy damping (ζ = 0.5): the penalty obstacle is an
// elastic spring, whose stiff limit is an elastic impact, not the inelastic one of the rigid
// scheme. With the mass arriving slowly and its rebound damped out the two limits nearly agree
// (their gap grows like ω²: at ω = 0.1 it already hides the penetration of k_obs = 1000 k),
// and what is left is the penetration, which scales with the compliance 1/k_obs.
TEST_CASE("Central difference: a stiffer penalty obstacle approaches the rigid stop") {
  Oscillator o;
  o.c = 1.0;
  o.omega = 0.05;
  const ImpactReference reference = SteadyReference(o);
  const double t0_reference = (kReferencePeriods - 1) * o.period();
  const Complex rigid = MeasureReference(reference, t0_reference, o.omega, kReferenceSamples).first;
  double previous = INFINITY;
  for (double ratio : {10.0, 100.0, 1000.0}) {
    TransientModel model = OscillatorModel(o);
    model.laws.push_back(
        std::make_unique<ContactTimeLaw>("penalty_contact", Stop(o.stop), ratio * o.k));
    model.law_paths = {"nonlinearities[0]"};
    TransientOptions options;
    options.explicit_step_fraction = 0.05;
    CentralDifferenceIntegrator integrator(model, options);
    const TransientResult result = integrator.RunToSteadyState(o.omega, InitialState{});
    REQUIRE(result.periodic());
    const Complex first =
        FirstHarmonic(result.last_period.t, result.last_period.x.row(0).transpose(), o.omega);
    const double distance = std::abs(first - rigid);
    MESSAGE("k_obs/k = " << ratio << ": |X1| " << std::abs(first) << " m, rigid " << std::abs(rigid)
                         << " m, distance " << distance << " m, h = " << integrator.StepFor(o.omega)
                         << " s, " << result.periods << " periods, " << result.wall_seconds
                         << " s");
    // Monotone, and about like 1/k_obs: a tenfold stiffness divides the distance by > 5.
    CHECK(distance < previous / 5.0);
    // The law's own signals are sampled; its phases are not tracked by this scheme.
    REQUIRE(result.last_period.law_signals.size() == 1);
    REQUIRE(result.last_period.law_signals[0].size() == 2);
    CHECK(result.last_period.law_signals[0][0].first == "gap");
    // The penetration max(0, −g) carries the force k_obs·max(0, −g) (N).
    const Eigen::VectorXd& gap = result.last_period.law_signals[0][0].second;
    const Eigen::VectorXd& force = result.last_period.law_signals[0][1].second;
    CHECK((force - ratio * o.k * (-gap).cwiseMax(0.0)).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE(result.last_period.phases.size() == 1);
    CHECK(result.last_period.phases[0].type == "penalty_contact");
    CHECK(result.last_period.phases[0].changes.empty());
    previous = distance;
  }
}

TEST_CASE("Central difference: energy balance of the rigid impact oscillator") {
  const Oscillator o;
  const ImpactReference reference = SteadyReference(o);
  const double t0_reference = (kReferencePeriods - 1) * o.period();
  const double fraction = 0.005;
  const TransientResult result = RunRigid(o, fraction);
  const PeriodRecord& record = result.last_period;
  const double balance =
      record.work_input - record.work_damping - record.work_laws - record.energy_change;
  MESSAGE("input " << record.work_input << " J, damping " << record.work_damping << " J, laws "
                   << record.work_laws << " J, energy change " << record.energy_change
                   << " J, reference impact loss " << reference.ImpactLoss(t0_reference) << " J");
  // The trapezoidal sums telescope exactly to the scheme's energy at half steps; over a
  // period that converged to 1e-7 only the residual transient remains: 1e-6 of the input.
  CHECK(std::abs(balance) < 1e-6 * record.work_input);
  CHECK(record.work_laws > 0.0);
  // The impact loss ½mv² of the reference, to O(h): the impact velocity errs by h·max|ẍ|
  // (max|ẍ| < 2 m/s² here), so the loss by m·v·2h with v < 1 m/s.
  const double h = o.period() / std::ceil(o.period() / (2 * fraction));
  CHECK(std::abs(record.work_laws - reference.ImpactLoss(t0_reference)) < 2.0 * o.m * h);
  // The input work ∫F cos(ωt) ẋ dt of the reference (trapezoidal rule on its dense samples,
  // error ~1e-7 J): x errs by h·1 m/s along a path of four swings, so W by 4F·h·1 m/s.
  double input = 0.0;
  const double dt = o.period() / kReferenceSamples;
  for (int i = 0; i < kReferenceSamples; ++i) {
    const double t = t0_reference + i * dt;
    input += dt * o.force * std::cos(o.omega * t) * reference.State(t).second;
  }
  CHECK(std::abs(record.work_input - input) < 4.0 * o.force * h * 1.0);
  MESSAGE("reference input work " << input << " J, h = " << h << " s");
}

TEST_CASE("Central difference: constant-frequency chirp reaches the harmonic amplitude") {
  Oscillator o;
  o.c = 0.4;  // ζ = 0.2: the start transient decays by e^{−ζω_n t} < 1e-5 after 60 s
  TransientModel model = OscillatorModel(o);
  TransientOptions options;
  options.explicit_step_fraction = 0.01;
  CentralDifferenceIntegrator integrator(model, options);
  const Excitation chirp = Excitation::Chirp(model.forcing, o.omega, o.omega, 200.0);
  const ChirpResult result = integrator.RunChirp(chirp, 256);
  REQUIRE(result.status == TransientStatus::kPeriodic);
  // Whole cycles only: floor(ωT_s / 2π) of them.
  CHECK(result.cycles.size() == static_cast<size_t>(std::floor(o.omega * 200.0 / (2 * kPi))));
  const double amplitude =
      std::abs(o.force / Complex(o.k - o.m * o.omega * o.omega, o.c * o.omega));
  // ⟨½mẋ² + ½kx²⟩ = ¼(mω² + k)|X|² for x = Re(X e^{iωt}).
  const double energy = 0.25 * (o.m * o.omega * o.omega + o.k) * amplitude * amplitude;
  // Step error (ωh)² ≈ 4e-4 relative, plus the transient left (< 1e-5).
  constexpr double kTolerance = 1e-3;
  const ChirpCycle& last = result.cycles.back();
  CHECK(std::abs(last.omega - o.omega) < 1e-9);
  CHECK(std::abs(last.max_abs(0) - amplitude) < kTolerance * amplitude);
  CHECK(std::abs(last.mean_energy - energy) < kTolerance * energy);
}

TEST_CASE("Central difference: input errors") {
  const Oscillator o;
  TransientModel friction = OscillatorModel(o);
  FrictionParameters parameters;
  parameters.limit = 0.2;
  friction.laws.push_back(std::make_unique<FrictionTimeLaw>(0, -1, parameters, false));
  friction.law_paths = {"nonlinearities[3]"};
  CHECK_THROWS_WITH_AS((void)CentralDifferenceIntegrator(friction, TransientOptions{}),
                       doctest::Contains("nonlinearities[3]"), InputError);

  TransientModel singular = OscillatorModel(o);
  singular.model.mass = Sparse(Eigen::MatrixXd::Zero(1, 1));
  CHECK_THROWS_WITH_AS((void)CentralDifferenceIntegrator(singular, TransientOptions{}),
                       doctest::Contains("model.M"), InputError);
}

}  // namespace
}  // namespace nfrc
