// Transient validation (ValidateCase) and the HBM solutions at one ω (SolveAt) on the Duffing
// oscillator ẍ + 0.05ẋ + x + 0.1x³ = 0.18 cos ωt (cases/duffing.json, H = 7).
#include "analysis/validate.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "analysis/solve_at.h"
#include "tools/case_file.h"
#include "validation/make_integrator.h"
#include "validation/period_measures.h"

namespace nfrc {
namespace {

constexpr double kC = 0.05, kK3 = 0.1, kF = 0.18;

// IDA runs at rtol 1e-10 and stops at a 1e-7 relative period-to-period change; H = 7 leaves a
// truncation error of the Duffing response (0.1x³ with |x| ≲ 2.5) of about the 9th harmonic's
// size, ~1e-7 relative. 1e-5 leaves two orders of margin and still catches any real mismatch.
constexpr double kDuffingAgreement = 1e-5;
// det Φ = exp(−cT) whatever the cubic (Liouville: the state matrix's trace is −c). The FD
// monodromy is accurate to ~1e-7 (tests/validation/monodromy_test.cc); starting from the HBM
// state, off the orbit by its truncation error (~1e-7 relative), moves Φ by as much. 1e-5
// leaves margin.
constexpr double kLiouvilleAgreement = 1e-5;

// The HBM state at t = 0 with the slider's force is on the orbit to the truncation (H = 59;
// 2.8e-4 measured at 0.2); 1e-3 is far below the 0.14 of a slider started at rest.
constexpr double kOrbitClosure = 1e-3;
// Hill with the stick memory against the transient monodromy: the memory's force perturbation
// jumps where stick ends, so Hill's truncation error is ~1/H (~1.5e-3 on the real multiplier
// 0.227 at 0.2, H = 59); the monodromy's FD noise is ~1e-4 (MonodromyOptions). 5e-3 keeps a
// margin and is 100 times smaller than the quasi-static error it replaces.
constexpr double kMemoryMultiplierAgreement = 5e-3;

Case DuffingCase() { return LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/duffing.json"); }

TEST_CASE("validate: Duffing transients match the HBM branch and the middle solution is unstable") {
  Case the_case = DuffingCase();
  ValidationSettings settings;
  // 0.8: one solution; 1.2: inside the folds at 1.116 and 1.270, three solutions.
  settings.omegas = {0.8, 1.2};
  const ValidationResult result = ValidateCase(the_case, settings);
  REQUIRE(result.points.size() == 2);
  CHECK(result.complete);

  const ValidationPoint& single = result.points[0];
  REQUIRE(single.solutions.size() == 1);
  REQUIRE(single.transients.size() == 1);
  REQUIRE(single.primary >= 0);
  const TransientRun& t = single.transients[single.primary];
  CHECK(t.result.periodic());
  REQUIRE(t.comparison.has_value());
  CHECK(t.comparison->stayed);
  CHECK(t.comparison->h1[0] < kDuffingAgreement);
  CHECK(t.comparison->energy < kDuffingAgreement);
  CHECK(t.comparison->rms[0] < kDuffingAgreement);
  CHECK(!t.comparison->overlay.columns.empty());

  const ValidationPoint& fold = result.points[1];
  REQUIRE(fold.solutions.size() == 3);
  REQUIRE(fold.transients.size() == 3);
  int stayed = 0;
  for (const TransientRun& run : fold.transients) {
    REQUIRE(run.result.periodic());
    REQUIRE(run.comparison.has_value());
    CHECK(run.comparison->label != "middle");  // a transient never settles on the saddle
    if (run.comparison->stayed) {
      ++stayed;
      CHECK(run.comparison->h1[0] < kDuffingAgreement);
    }
  }
  CHECK(stayed == 2);  // the lower and upper solutions are stable

  // The transient monodromy from each HBM solution agrees: only the middle one is unstable.
  REQUIRE(single.stability.size() == 1);
  REQUIRE(fold.stability.size() == 3);
  for (const ValidationPoint* point : {&single, &fold}) {
    const double liouville = std::exp(-kC * 2.0 * std::numbers::pi / point->omega);
    for (size_t i = 0; i < point->solutions.size(); ++i) {
      REQUIRE(point->stability[i].monodromy.has_value());
      const MonodromyResult& m = *point->stability[i].monodromy;
      REQUIRE_MESSAGE(m.ok, m.message);
      REQUIRE(m.multipliers.size() == 2);
      const std::string& label = point->solutions[i].label;
      MESSAGE("omega " << point->omega << ", " << label << ": mu " << m.multipliers[0] << ", "
                       << m.multipliers[1] << ", det/exp(-cT) "
                       << std::abs(m.multipliers[0] * m.multipliers[1]) / liouville << ", closure "
                       << m.closure);
      CHECK(std::abs(m.multipliers[0] * m.multipliers[1] - liouville) <
            kLiouvilleAgreement * liouville);
      CHECK(m.closure < kDuffingAgreement);
      CHECK((m.max_modulus() > 1.0) == (label == "middle"));
    }
  }
}

// The two-DOF contact oscillator (cases/validation/contact_friction_oscillator.json, at H = 31
// to keep the test short): at ω = 0.4 the tangent DOF sticks and slips in permanent contact;
// at ω = 1.7 three solutions coexist, the upper one separating. Friction with sticking
// converges like 1/H. Measured relative differences of h1 with the transient at H = 31: ≤ 0.09 %
// for the normal DOF, ≤ 3.0 % for the tangent DOF (largest at 1.7 lower, where it mostly sticks
// and h1 is only 0.03 m; 2.0 % at H = 63 over the case's 11 frequencies). Without friction the
// tangent h1 changes by 60 % (0.4) to ×10 (1.7 lower), so the tolerances below still see the law.
constexpr double kNormalAgreement = 0.01;
constexpr double kTangentAgreement = 0.05;

TEST_CASE("validate: contact with friction, HBM against IDA through stick-slip and separation") {
  Case the_case =
      LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/validation/contact_friction_oscillator.json");
  the_case.harmonics = HarmonicSet(31, false, 1024);
  ValidationSettings settings = the_case.validation;
  settings.omegas = {0.4, 1.7};
  settings.chirp.enabled = false;
  const ValidationResult result = ValidateCase(the_case, settings);
  REQUIRE(result.points.size() == 2);
  CHECK(result.complete);
  const ValidationPoint& stick_slip = result.points[0];
  REQUIRE(stick_slip.solutions.size() == 1);
  const ValidationPoint& separation = result.points[1];
  REQUIRE(separation.solutions.size() == 3);
  for (const ValidationPoint* point : {&stick_slip, &separation}) {
    for (size_t i = 0; i < point->solutions.size(); ++i) {
      const TransientRun& run = point->transients.at(i);
      REQUIRE(run.result.periodic());
      REQUIRE(run.comparison.has_value());
      const std::string& label = point->solutions[i].label;
      CAPTURE(point->omega);
      CAPTURE(label);
      MESSAGE("omega " << point->omega << ", " << label << " -> " << run.comparison->label
                       << ": h1 differences " << run.comparison->h1[0] << ", "
                       << run.comparison->h1[1] << ", energy " << run.comparison->energy);
      // The saddle's transient leaves it; the stable solutions' stay and agree. (Stick-phase
      // counts are not compared: a second stick about one period of the 31st harmonic long is
      // below the HBM's phase resolution at 0.4 and 1.7 lower.)
      CHECK(run.comparison->stayed == (label != "middle"));
      if (!run.comparison->stayed) continue;
      CHECK(run.comparison->h1[0] < kNormalAgreement);
      CHECK(run.comparison->h1[1] < kTangentAgreement);
      REQUIRE(point->stability.at(i).monodromy.has_value());
      CHECK(point->stability[i].monodromy->max_modulus() < 1.0);
    }
  }
  // Stick-slip in permanent contact at 0.4; at 1.7 the upper solution leaves the obstacle.
  const std::map<std::string, double>& slipping = stick_slip.solutions[0].signals.measures.laws[0];
  CHECK(slipping.at("stick_phases") >= 1.0);
  CHECK(slipping.at("stick_fraction") < 0.9);
  CHECK(slipping.at("contact_fraction") == 1.0);
  CHECK(separation.solutions[2].signals.measures.laws[0].at("contact_fraction") < 0.9);
}

TEST_CASE(
    "validate: Jenkins element, Hill's multipliers with the stick memory equal the monodromy") {
  // Fig. 7's oscillator with a Jenkins element (k_t = 10 N/m) in stick-slip. The start carries
  // the slider's force at t = 0 (without it the transient began 0.14-0.19 off the orbit), and
  // Hill's method restores the stick phases' Floquet factor e^{-s(t - t_a)}: with it taken as 1
  // Hill's largest |mu| was 0.008 at 0.2 and 0.65 at 0.4, where the monodromy has 0.551 and
  // 0.764.
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/validation/jenkins_n10.json");
  ValidationSettings settings = the_case.validation;
  settings.omegas = {0.2, 0.4};
  settings.chirp.enabled = false;
  const ValidationResult result = ValidateCase(the_case, settings);
  REQUIRE(result.points.size() == 2);
  for (const ValidationPoint& point : result.points) {
    REQUIRE(point.solutions.size() == 1);
    const SolutionStability& stability = point.stability.at(0);
    REQUIRE(stability.monodromy.has_value());
    REQUIRE(stability.monodromy->ok);
    REQUIRE(stability.hill.computed);
    CAPTURE(point.omega);
    CHECK(stability.monodromy->closure < kOrbitClosure);
    const std::vector<std::complex<double>>& hill = stability.hill.multipliers;
    const std::vector<std::complex<double>>& transient = stability.monodromy->multipliers;
    REQUIRE(hill.size() == transient.size());
    // Both ways: each multiplier of one has a partner in the other.
    double worst = 0.0;
    for (const auto* pair : {&hill, &transient}) {
      const auto& other = pair == &hill ? transient : hill;
      for (const std::complex<double>& mu : *pair) {
        double nearest = INFINITY;
        for (const std::complex<double>& nu : other) nearest = std::min(nearest, std::abs(mu - nu));
        worst = std::max(worst, nearest);
      }
    }
    MESSAGE("Jenkins omega " << point.omega << ": Hill max |mu| " << stability.hill.max_modulus
                             << ", monodromy " << stability.monodromy->max_modulus()
                             << ", worst multiplier distance " << worst << ", closure "
                             << stability.monodromy->closure);
    CHECK(worst < kMemoryMultiplierAgreement);
  }
}

TEST_CASE("validate: monodromy off computes none") {
  Case the_case = DuffingCase();
  ValidationSettings settings;
  settings.omegas = {0.8};
  settings.monodromy.enabled = false;
  const ValidationResult result = ValidateCase(the_case, settings);
  REQUIRE(result.points.size() == 1);
  REQUIRE(result.points[0].stability.size() == 1);
  CHECK(!result.points[0].stability[0].monodromy.has_value());
}

// ‖harmonic balance residual‖ of the Duffing equation for coefficients c (HarmonicSet layout
// of all harmonics 0..H) at ω, computed here from the equation on a grid of 256 samples,
// which projects the cubic term (harmonics up to 3H = 21) exactly onto harmonics ≤ H = 7:
// independent of the library's AFT. Largest projection, relative to the forcing amplitude.
double DuffingBalanceDefect(const Eigen::VectorXd& c, int max_harmonic, double omega) {
  constexpr int kSamples = 256;
  Eigen::VectorXd residual(kSamples);
  for (int j = 0; j < kSamples; ++j) {
    const double theta = 2.0 * std::numbers::pi * j / kSamples;
    double x = c(0), x_theta = 0.0, x_theta2 = 0.0;
    for (int k = 1; k <= max_harmonic; ++k) {
      const double a = c(2 * k - 1), b = c(2 * k);
      x += a * std::cos(k * theta) + b * std::sin(k * theta);
      x_theta += k * (-a * std::sin(k * theta) + b * std::cos(k * theta));
      x_theta2 -= k * k * (a * std::cos(k * theta) + b * std::sin(k * theta));
    }
    residual(j) = omega * omega * x_theta2 + kC * omega * x_theta + x + kK3 * x * x * x -
                  kF * std::cos(theta);
  }
  double worst = std::abs(residual.mean());
  for (int k = 1; k <= max_harmonic; ++k) {
    double cos_part = 0.0, sin_part = 0.0;
    for (int j = 0; j < kSamples; ++j) {
      const double theta = 2.0 * std::numbers::pi * j / kSamples;
      cos_part += 2.0 / kSamples * residual(j) * std::cos(k * theta);
      sin_part += 2.0 / kSamples * residual(j) * std::sin(k * theta);
    }
    worst = std::max({worst, std::abs(cos_part), std::abs(sin_part)});
  }
  return worst / kF;
}

TEST_CASE("solve at: Duffing at 1.2 has a lower, a middle and an upper solution") {
  const Case the_case = DuffingCase();
  constexpr double kOmega = 1.2;  // inside the folds at 1.116 and 1.270
  const SolveAtResult result = SolveAt(the_case, kOmega);
  REQUIRE(result.trace.branch.folds.size() == 2);
  REQUIRE(result.solutions.size() == 3);

  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  Eigen::VectorXd zero_residual;
  system->Evaluate(Eigen::VectorXd::Zero(system->NumUnknowns()), kOmega, &zero_residual, nullptr,
                   nullptr);
  std::map<std::string, const CrossingSolution*> by_label;
  for (const CrossingSolution& s : result.solutions) {
    CAPTURE(s.label);
    CHECK(s.converged);
    CHECK(s.omega == kOmega);
    by_label[s.label] = &s;
    // The library's residual at the returned y, on a fresh system of the same case, against
    // the scale the continuation measures it with (‖R(0, ω)‖, the forcing).
    Eigen::VectorXd residual;
    REQUIRE(system->Evaluate(s.y, kOmega, &residual, nullptr, nullptr));
    CHECK(residual.norm() / zero_residual.norm() < the_case.continuation.residual_tolerance);
    // The same equations written out here from the ODE.
    REQUIRE(s.coefficients.rows() == 1);
    REQUIRE(s.coefficients.cols() == the_case.harmonics.NumCoefficients());
    CHECK(DuffingBalanceDefect(s.coefficients.row(0).transpose(), 7, kOmega) < 1e-8);
    CHECK(s.signals.fine.columns.size() == 4);  // θ, t, x_0, v_0
  }
  REQUIRE(by_label.count("lower") == 1);
  REQUIRE(by_label.count("middle") == 1);
  REQUIRE(by_label.count("upper") == 1);
  const auto h1 = [&](const std::string& label) {
    return by_label[label]->signals.measures.response.h1[0];
  };
  CHECK(h1("lower") < h1("middle"));
  CHECK(h1("middle") < h1("upper"));

  // The stable ones against a time integration (IDA) started on them: the steady state it
  // settles to has the same first harmonic.
  TransientModel model = MakeTransientModel(the_case.model, the_case.laws);
  const std::unique_ptr<TransientIntegrator> integrator =
      MakeTransientIntegrator(model, TransientOptions{});
  for (const std::string label : {"lower", "upper"}) {
    CAPTURE(label);
    const SignalTable& fine = by_label[label]->signals.fine;
    InitialState start;  // x and v at θ = 0, the fine signals' first samples
    start.x = Eigen::VectorXd::Constant(1, fine.columns[2](0));
    start.v = Eigen::VectorXd::Constant(1, fine.columns[3](0));
    const TransientResult run = integrator->RunToSteadyState(kOmega, start);
    REQUIRE(run.periodic());
    const double transient_h1 = MeasurePeriod(run.last_period, {0}).h1[0];
    CHECK(std::abs(transient_h1 - h1(label)) / h1(label) < kDuffingAgreement);
  }
}

TEST_CASE("solve at: with one harmonic the amplitudes are the roots of the amplitude equation") {
  // One-harmonic balance: ((1 − ω²) + ¾k₃A²)²A² + (cωA)² = F², a cubic in A² with three
  // positive roots at ω = 1.2 (found by bisection on the three brackets of its sign).
  Case the_case = DuffingCase();
  the_case.harmonics = HarmonicSet(1, false);
  constexpr double kOmega = 1.2;
  const auto g = [&](double a2) {
    const double d = 1 - kOmega * kOmega + 0.75 * kK3 * a2;
    return d * d * a2 + kC * kC * kOmega * kOmega * a2 - kF * kF;
  };
  std::vector<double> roots;
  for (const auto& [low0, high0] : {std::pair{0.0, 1.0}, {1.0, 5.5}, {5.5, 10.0}}) {
    double low = low0, high = high0;
    REQUIRE(g(low) * g(high) < 0);
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (low + high);
      (g(low) * g(mid) <= 0 ? high : low) = mid;
    }
    roots.push_back(std::sqrt(0.5 * (low + high)));
  }
  const SolveAtResult result = SolveAt(the_case, kOmega);
  REQUIRE(result.solutions.size() == 3);
  for (const CrossingSolution& s : result.solutions) {
    const int rank = s.label == "lower" ? 0 : s.label == "middle" ? 1 : 2;
    CAPTURE(s.label);
    CHECK(std::abs(s.signals.measures.response.h1[0] - roots[rank]) / roots[rank] < 1e-8);
  }
}

}  // namespace
}  // namespace nfrc
