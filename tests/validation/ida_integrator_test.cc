#include "validation/ida_integrator.h"

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/errors.h"
#include "validation/transient.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;

// IDA at rtol 1e-10 and a steady state declared at 1e-8 per period leave well under 1e-6 of
// the amplitude between the recorded period and the exact harmonic solution.
constexpr double kHarmonicTolerance = 1e-6;
// Quadratures over one period share that accuracy, relative to the exact integral.
constexpr double kEnergyTolerance = 1e-6;
// Dense and KLU solve the same Newton systems; only round-off and step-size decisions driven
// by it differ, far below the integration tolerance.
constexpr double kSolverAgreement = 1e-7;
// Sampled max of 64 points of a slowly swept sine: 1 − cos(π/64) ≈ 1.2e-3 sampling loss plus
// the quasi-static error of the sweep, a fraction of a percent at this rate.
constexpr double kChirpTolerance = 0.01;

TransientModel LinearChain(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c,
                           const Eigen::MatrixXd& k, std::vector<ForcingTerm> forcing) {
  TransientModel model;
  model.model.mass = m.sparseView();
  model.model.damping = c.sparseView();
  model.model.stiffness = k.sparseView();
  model.forcing = std::move(forcing);
  return model;
}

// M = I, K = [[2, −1], [−1, 1]], C = 0.05 (M + K), cos ωt on DOF 0.
TransientModel TwoDof() {
  Eigen::MatrixXd k(2, 2);
  k << 2, -1, -1, 1;
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2, 2);
  return LinearChain(m, 0.05 * (m + k), k, {ForcingTerm{0, 1, 1.0, 0.0}});
}

// A fixed–fixed chain of n unit masses and unit springs, C = 0.2 M + 0.02 K, cos ωt at the
// middle.
TransientModel Chain(int n) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) = 2.0;
    if (i > 0) k(i, i - 1) = k(i - 1, i) = -1.0;
  }
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n);
  return LinearChain(m, 0.2 * m + 0.02 * k, k, {ForcingTerm{n / 2, 1, 1.0, 0.0}});
}

// X = (K − ω²M + iωC)⁻¹F for f = Re(F e^{iωt}).
Eigen::VectorXcd Harmonic(const TransientModel& model, double omega) {
  const Eigen::MatrixXd m(model.model.mass), c(model.model.damping), k(model.model.stiffness);
  const Eigen::MatrixXcd z =
      k.cast<Complex>() - omega * omega * m.cast<Complex>() + Complex(0, omega) * c.cast<Complex>();
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(m.rows());
  for (const auto& term : model.forcing) f(term.dof) += Complex(term.cos, -term.sin);
  return z.fullPivLu().solve(f);
}

TransientOptions FastOptions() {
  TransientOptions options;
  options.relative_tolerance = 1e-10;
  options.steady_tolerance = 1e-8;
  options.samples_per_period = 64;
  options.max_periods = 1000;
  return options;
}

// Largest deviation of the recorded samples from Re(X e^{iωt}), relative to max |X|; and the
// same for the first harmonic by a DFT of the samples.
struct HarmonicErrors {
  double samples = 0.0;
  double first_harmonic = 0.0;
};

HarmonicErrors CompareWithHarmonic(const PeriodRecord& record, const Eigen::VectorXcd& x,
                                   double omega) {
  HarmonicErrors errors;
  const double scale = x.cwiseAbs().maxCoeff();
  const int samples = static_cast<int>(record.t.size());
  for (int d = 0; d < x.size(); ++d) {
    Complex dft = 0.0;
    for (int i = 0; i < samples; ++i) {
      const Complex rotation = std::exp(Complex(0, omega * record.t(i)));
      const double exact = (x(d) * rotation).real();
      errors.samples = std::max(errors.samples, std::abs(record.x(d, i) - exact) / scale);
      dft += 2.0 / samples * record.x(d, i) / rotation;
    }
    errors.first_harmonic = std::max(errors.first_harmonic, std::abs(dft - x(d)) / scale);
  }
  return errors;
}

TEST_CASE("IDA: linear 2-DOF reaches the exact harmonic solution and its energies") {
  for (double omega : {0.5, 1.0, 1.7}) {
    CAPTURE(omega);
    TransientModel model = TwoDof();
    IdaIntegrator ida(model, FastOptions());
    const TransientResult result = ida.RunToSteadyState(omega, {});
    REQUIRE_MESSAGE(result.periodic(), result.message);
    CHECK(result.method == "ida");
    CHECK(result.events == 0);
    CHECK(result.steps > 0);
    CHECK(result.period_differences.size() == static_cast<size_t>(result.periods));
    const Eigen::VectorXcd x = Harmonic(model, omega);
    const HarmonicErrors errors = CompareWithHarmonic(result.last_period, x, omega);
    MESSAGE("omega " << omega << ": sample error " << errors.samples << ", first harmonic "
                     << errors.first_harmonic << ", periods " << result.periods << ", steps "
                     << result.steps << ", " << result.wall_seconds << " s");
    CHECK(errors.samples < kHarmonicTolerance);
    CHECK(errors.first_harmonic < kHarmonicTolerance);

    // Means over a period of x = Re(X e^{iωt}): <xᵀKx> = ½ Re(X^H K X), etc.
    const Eigen::MatrixXd m(model.model.mass), c(model.model.damping), k(model.model.stiffness);
    const double period = 2 * std::numbers::pi / omega;
    const double mean_energy =
        0.25 * (omega * omega * x.dot(m.cast<Complex>() * x) + x.dot(k.cast<Complex>() * x)).real();
    const double damping_work = 0.5 * period * omega * omega * x.dot(c.cast<Complex>() * x).real();
    const double input_work = 0.5 * period * (Complex(0, omega) * x(0)).real();
    const PeriodRecord& r = result.last_period;
    CHECK(std::abs(r.mean_energy - mean_energy) < kEnergyTolerance * mean_energy);
    CHECK(std::abs(r.work_damping - damping_work) < kEnergyTolerance * damping_work);
    CHECK(std::abs(r.work_input - input_work) < kEnergyTolerance * damping_work);
    CHECK(std::abs(r.work_laws) < kEnergyTolerance * damping_work);
    CHECK(std::abs(r.energy_change) < kEnergyTolerance * damping_work);
  }
}

TEST_CASE("IDA: 40-DOF chain with KLU matches the harmonic solution and the dense solver") {
  constexpr int kDofs = 40;  // 84 unknowns: beyond kDenseLimit, so kAuto picks KLU
  constexpr double kOmega = 1.1;
  TransientOptions options = FastOptions();
  options.steady_tolerance = 1e-8;
  TransientModel sparse_model = Chain(kDofs);
  const TransientResult sparse = IdaIntegrator(sparse_model, options).RunToSteadyState(kOmega, {});
  REQUIRE_MESSAGE(sparse.periodic(), sparse.message);
  const HarmonicErrors errors =
      CompareWithHarmonic(sparse.last_period, Harmonic(sparse_model, kOmega), kOmega);
  MESSAGE("KLU: sample error " << errors.samples << ", first harmonic " << errors.first_harmonic
                               << ", " << sparse.steps << " steps, " << sparse.wall_seconds
                               << " s");
  CHECK(errors.samples < kHarmonicTolerance);
  CHECK(errors.first_harmonic < kHarmonicTolerance);

  options.linear_solver = TransientOptions::LinearSolver::kDense;
  TransientModel dense_model = Chain(kDofs);
  const TransientResult dense = IdaIntegrator(dense_model, options).RunToSteadyState(kOmega, {});
  REQUIRE_MESSAGE(dense.periodic(), dense.message);
  const double scale = sparse.last_period.x.cwiseAbs().maxCoeff();
  const double difference = (sparse.last_period.x - dense.last_period.x).cwiseAbs().maxCoeff();
  MESSAGE("dense vs KLU: " << difference / scale << ", dense " << dense.wall_seconds << " s");
  CHECK(difference < kSolverAgreement * scale);
}

TEST_CASE("IDA: a massless damped DOF (algebraic velocity) matches the harmonic solution") {
  // M = diag(1, 0): DOF 1 is a massless node held by springs and a dashpot, so its velocity is
  // an algebraic unknown of the DAE, found from C v + K x = f on its row.
  Eigen::MatrixXd k(2, 2), m = Eigen::MatrixXd::Zero(2, 2), c = Eigen::MatrixXd::Zero(2, 2);
  k << 3, -1, -1, 1;
  m(0, 0) = 1.0;
  c(0, 0) = 0.1;
  c(1, 1) = 0.3;
  constexpr double kOmega = 1.3;
  TransientModel model = LinearChain(m, c, k, {ForcingTerm{0, 1, 1.0, 0.5}});
  const TransientResult result = IdaIntegrator(model, FastOptions()).RunToSteadyState(kOmega, {});
  REQUIRE_MESSAGE(result.periodic(), result.message);
  CHECK(model.massless == std::vector<bool>{false, true});
  const HarmonicErrors errors =
      CompareWithHarmonic(result.last_period, Harmonic(model, kOmega), kOmega);
  MESSAGE("massless DOF: sample error " << errors.samples << ", first harmonic "
                                        << errors.first_harmonic);
  CHECK(errors.samples < kHarmonicTolerance);
  CHECK(errors.first_harmonic < kHarmonicTolerance);
}

TEST_CASE("IDA: an undamped oscillator forced off resonance never becomes T-periodic") {
  // x'' + x = cos 0.7t from rest: x = (cos 0.7t − cos t)/(1 − 0.49). The free part never
  // decays; since 7 · (2π/0.7) = 10 · 2π the motion is exactly 7T-periodic and no shorter
  // multiple of T is a period of it.
  Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = LinearChain(one, 0 * one, one, {ForcingTerm{0, 1, 1.0, 0.0}});
  TransientOptions options = FastOptions();
  options.steady_tolerance = 1e-7;
  options.max_periods = 12;
  const TransientResult result = IdaIntegrator(model, options).RunToSteadyState(0.7, {});
  CHECK(result.status == TransientStatus::kNotPeriodic);
  CHECK(std::string(ToString(result.status)) == "not_periodic");
  CHECK(result.periods == 12);
  CHECK(result.period_multiple == 7);
  for (double d : result.period_differences) CHECK(d > 1e-3);
  // The recorded last period still follows the exact solution.
  const PeriodRecord& r = result.last_period;
  double error = 0.0;
  for (int i = 0; i < r.t.size(); ++i) {
    const double exact = (std::cos(0.7 * r.t(i)) - std::cos(r.t(i))) / 0.51;
    error = std::max(error, std::abs(r.x(0, i) - exact));
  }
  MESSAGE("undamped: error " << error << " after " << result.t_end);
  CHECK(error < kHarmonicTolerance * 2 / 0.51);
}

TEST_CASE("IDA: a slow chirp far from resonance follows the linear amplitude") {
  // x'' + 0.1x' + x = cos φ(t), ω from 3 to 3.5 over 400 s; the start transient decays as
  // e^{−0.05t}, so cycles after t = 150 (e^{−7.5} ≈ 5e-4) are compared.
  Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = LinearChain(one, 0.1 * one, one, {ForcingTerm{0, 1, 1.0, 0.0}});
  TransientOptions options;
  options.relative_tolerance = 1e-8;
  const Excitation chirp = Excitation::Chirp(model.forcing, 3.0, 3.5, 400.0);
  const ChirpResult result = IdaIntegrator(model, options).RunChirp(chirp, 64);
  REQUIRE_MESSAGE(result.status == TransientStatus::kPeriodic, result.message);
  CHECK(result.method == "ida");
  REQUIRE(result.cycles.size() > 150);
  double worst_amplitude = 0.0, worst_energy = 0.0;
  int compared = 0;
  for (const ChirpCycle& cycle : result.cycles) {
    if (cycle.t_start < 150.0) continue;
    ++compared;
    const double w = cycle.omega;
    const double amplitude = 1.0 / std::abs(Complex(1.0 - w * w, 0.1 * w));
    const double energy = 0.25 * (w * w + 1.0) * amplitude * amplitude;
    worst_amplitude = std::max(worst_amplitude, std::abs(cycle.max_abs(0) / amplitude - 1.0));
    worst_energy = std::max(worst_energy, std::abs(cycle.mean_energy / energy - 1.0));
    CHECK(std::abs(w - chirp.InstantaneousOmega(0.5 * (cycle.t_start + cycle.t_end))) < 1e-3);
  }
  MESSAGE("chirp: amplitude error " << worst_amplitude << ", energy error " << worst_energy
                                    << " over " << compared << " cycles, " << result.wall_seconds
                                    << " s");
  CHECK(compared > 50);
  CHECK(worst_amplitude < kChirpTolerance);
  CHECK(worst_energy < 2 * kChirpTolerance);
}

TEST_CASE("IDA: excitation phase and frequency of a chirp (Vadcard et al. eq. 66)") {
  const Excitation chirp = Excitation::Chirp({ForcingTerm{0, 2, 1.0, 0.5}}, 2.0, 4.0, 10.0);
  // φ(t) = (ω1 + (ω2 − ω1) t/(2T_s)) t: at T_s, φ = (ω1 + ω2) T_s / 2.
  CHECK(chirp.Phase(10.0) == doctest::Approx(30.0));
  CHECK(chirp.InstantaneousOmega(5.0) == doctest::Approx(3.0));
  const double h = 1e-6;
  CHECK((chirp.Phase(3.0 + h) - chirp.Phase(3.0 - h)) / (2 * h) ==
        doctest::Approx(chirp.InstantaneousOmega(3.0)).epsilon(1e-8));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2);
  chirp.AddForce(3.0, f);
  const double phase = chirp.Phase(3.0);
  CHECK(f(0) == doctest::Approx(std::cos(2 * phase) + 0.5 * std::sin(2 * phase)));
  CHECK(f(1) == 0.0);
  const Excitation harmonic = Excitation::Harmonic({}, 1.5);
  CHECK(harmonic.Phase(2.0) == doctest::Approx(3.0));
  CHECK(harmonic.InstantaneousOmega(7.0) == 1.5);
}

TEST_CASE("IDA: options, status names and phase logs") {
  CHECK(std::string(ToString(TransientStatus::kPeriodic)) == "periodic");
  CHECK(std::string(ToString(TransientStatus::kFailed)) == "failed");
  TransientOptions options;
  CHECK_NOTHROW(options.Validate());
  options.relative_tolerance = -1;
  CHECK_THROWS_WITH_AS(options.Validate(),
                       doctest::Contains("validation.transient.relative_tolerance"), InputError);
  options = TransientOptions();
  options.max_periods = 2;
  CHECK_THROWS_WITH_AS(options.Validate(), doctest::Contains("validation.transient.max_periods"),
                       InputError);
  options = TransientOptions();
  options.samples_per_period = 0;
  CHECK_THROWS_AS(options.Validate(), InputError);

  // Over [0, 10): in phase at the start, out at 2, in at 7 (to the end: the same phase as the
  // one at the start, cyclically), so one phase covering 2 + 3 = 5.
  LawPhaseLog log;
  log.in_phase_at_start = true;
  log.changes = {{2.0, false}, {7.0, true}};
  CHECK(log.CountPhases(0.0, 10.0) == 1);
  CHECK(log.PhaseFraction(0.0, 10.0) == doctest::Approx(0.5));
  log.in_phase_at_start = false;
  log.changes = {{1.0, true}, {2.0, false}, {5.0, true}, {8.0, false}};
  CHECK(log.CountPhases(0.0, 10.0) == 2);
  CHECK(log.PhaseFraction(0.0, 10.0) == doctest::Approx(0.4));
  log.changes.clear();
  CHECK(log.CountPhases(0.0, 10.0) == 0);
  CHECK(log.PhaseFraction(0.0, 10.0) == 0.0);
  log.in_phase_at_start = true;
  CHECK(log.CountPhases(0.0, 10.0) == 1);
  CHECK(log.PhaseFraction(0.0, 10.0) == 1.0);

  // Bad inputs to the integrator.
  TransientModel model = TwoDof();
  IdaIntegrator ida(model, FastOptions());
  CHECK_THROWS_AS(ida.RunToSteadyState(-1.0, {}), InputError);
  InitialState wrong{Eigen::VectorXd::Zero(3), Eigen::VectorXd()};
  CHECK_THROWS_WITH_AS(ida.RunToSteadyState(1.0, wrong), doctest::Contains("initial_state"),
                       InputError);
  TransientModel rigid = TwoDof();
  rigid.rigid_contacts.push_back(ContactGeometry{});
  CHECK_THROWS_AS(IdaIntegrator(rigid, FastOptions()), InputError);
}

TEST_CASE("IDA: a massless DOF without damping has no consistent state: a failed status") {
  // M = diag(1, 0), C = 0: the massless row K x = f holds no velocity, so the velocity of DOF 1
  // is undetermined (an index-2 DAE): the start is refused with a message, not an abort.
  Eigen::MatrixXd k(2, 2), m = Eigen::MatrixXd::Zero(2, 2);
  k << 3, -1, -1, 1;
  m(0, 0) = 1.0;
  TransientModel model = LinearChain(m, Eigen::MatrixXd::Zero(2, 2), k, {ForcingTerm{0, 1, 1, 0}});
  const TransientResult result = IdaIntegrator(model, FastOptions()).RunToSteadyState(1.0, {});
  CHECK(result.status == TransientStatus::kFailed);
  CHECK(result.message.find("consistent") != std::string::npos);
  CHECK(result.periods == 0);
}

TEST_CASE("IDA: the wall-clock limit fails the run with a message") {
  Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
  TransientModel model = LinearChain(one, 0 * one, one, {ForcingTerm{0, 1, 1.0, 0.0}});
  TransientOptions options = FastOptions();
  options.max_seconds = 1e-9;
  const TransientResult result = IdaIntegrator(model, options).RunToSteadyState(0.7, {});
  CHECK(result.status == TransientStatus::kFailed);
  CHECK(result.message.find("wall-clock") != std::string::npos);
}

}  // namespace
}  // namespace nfrc
