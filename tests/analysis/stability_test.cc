// Stability along traced branches: Duffing's middle branch is unstable exactly between its
// folds, and each fold is the +1 crossing of a real multiplier.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "analysis/bifurcation.h"
#include "analysis/trace.h"
#include "analysis/validate.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// At a fold localised to 1e-6 relative in ω the exponent is O(√1e-6) from 0 (ω is quadratic
// in the arclength there): |ln μ| = |s|T ≤ 1e-2 leaves margin above that and is far below
// the O(1) of a wrong crossing.
constexpr double kFoldMultiplierTolerance = 1e-2;

Case LoadSourceCase(const std::string& name) {
  return LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
}

TEST_CASE("stability: Duffing's middle branch is unstable exactly between the folds") {
  const TraceResult trace = TraceCase(LoadSourceCase("duffing.json"));
  REQUIRE(trace.branch.summary.success());
  REQUIRE(trace.folds.size() == 2);
  const int first = trace.folds[0].fold.after_point, second = trace.folds[1].fold.after_point;
  for (const TracePoint& point : trace.points) {
    CAPTURE(point.index);
    CAPTURE(point.point.lambda);
    REQUIRE(point.floquet.computed);
    const bool middle = point.index > first && point.index <= second;
    CHECK(point.floquet.stable() == !middle);
    if (middle) {
      // One real multiplier beyond +1 (a saddle), the other inside the unit circle.
      REQUIRE(point.floquet.num_unstable == 1);
      CHECK(point.floquet.multipliers[0].real() > 1.0);
      CHECK(std::abs(point.floquet.multipliers[0].imag()) < 1e-8);
    }
  }
  // The two stability changes are the engine's folds, nothing else.
  REQUIRE(trace.bifurcations.size() == 2);
  for (size_t i = 0; i < 2; ++i) {
    const Bifurcation& b = trace.bifurcations[i];
    CHECK(b.type == BifurcationType::kFold);
    CHECK(b.omega == trace.folds[i].fold.lambda);
    REQUIRE(b.crossing_multipliers.size() == 1);
    CHECK(std::abs(std::log(std::abs(b.crossing_multipliers[0]))) < kFoldMultiplierTolerance);
    CHECK(b.crossing_multipliers[0].real() > 0.0);
  }
}

TEST_CASE("stability: a jump across the unit circle stops its localisation at jump_tolerance") {
  // NLvib's unilateral spring as a sampled penalty law: dozens of Neimark-Sacker crossings
  // near the resonance are jumps where a sample enters or leaves contact. The reference is
  // the same trace localised by bisection down to bifurcation_tolerance (jump_tolerance too
  // small to apply), which must confirm each early stop as a jump inside its bracket.
  Case fast = LoadSourceCase("contact/nlvib.json#penalty");
  Case strict = fast;
  strict.stability.jump_tolerance = 1e-15;
  const TraceResult early = TraceCase(fast);
  const TraceResult reference = TraceCase(strict);
  REQUIRE(early.points.size() == reference.points.size());
  REQUIRE(early.bifurcations.size() == reference.bifurcations.size());
  int stopped = 0, smooth = 0, early_iterations = 0, reference_iterations = 0;
  for (size_t i = 0; i < early.bifurcations.size(); ++i) {
    const Bifurcation& b = early.bifurcations[i];
    const Bifurcation& r = reference.bifurcations[i];
    CAPTURE(b.omega);
    REQUIRE(b.after_point == r.after_point);
    REQUIRE(b.type == r.type);
    if (b.type != BifurcationType::kFold) {  // folds are the engine's, localised without Hill
      early_iterations += b.iterations;
      reference_iterations += r.iterations;
    }
    const bool early_stop = b.converged && b.discontinuous &&
                            b.omega_accuracy > fast.stability.bifurcation_tolerance * b.omega;
    if (early_stop) {
      ++stopped;
      CHECK(b.omega_accuracy <= fast.stability.jump_tolerance * b.omega);
      // Bisected on to 1e-6, the same crossing stays a jump, inside the early bracket.
      if (r.converged) {
        CHECK(r.discontinuous);
        CHECK(std::abs(b.omega - r.omega) <= b.omega_accuracy + r.omega_accuracy);
      }
    } else if (r.converged && !r.discontinuous) {
      // A smooth crossing never meets the jump test: the same localisation, to its accuracy
      // (not bit for bit: Arnoldi starts from the last analysis's Ritz vectors, and the two
      // traces analysed different points before it).
      ++smooth;
      CHECK(std::abs(b.omega - r.omega) <= b.omega_accuracy + r.omega_accuracy);
      CHECK_FALSE(b.discontinuous);
    }
  }
  MESSAGE(stopped << " jumps stopped early, " << smooth << " smooth crossings; Hill "
                  << "localisation iterations " << early_iterations << " against "
                  << reference_iterations);
  CHECK(stopped >= 10);
  CHECK(smooth >= 1);
  CHECK(early_iterations < reference_iterations);
}

TEST_CASE("stability: the one-DOF Coulomb oscillator is stable everywhere, stick-slip included") {
  // ẍ + 0.1ẋ + x + r = cos ωt with |r| ≤ 0.5: a damped one-DOF oscillator with a monotone
  // friction law contracts any two motions (the difference's energy only decreases), so its
  // periodic response is unique and every multiplier lies inside the unit circle. The stick
  // constraint's infinite exponents, once reported as multipliers ∞ with 19 "branch points"
  // between 0.40 and 0.50, must not surface.
  const TraceResult trace = TraceCase(LoadSourceCase("friction/one_dof_coulomb.json"));
  REQUIRE(trace.points.size() > 100);
  int stick_slip = 0;
  for (const TracePoint& p : trace.points) {
    CAPTURE(p.point.lambda);
    REQUIRE(p.floquet.computed);
    CHECK(p.floquet.num_unstable == 0);
    CHECK(p.floquet.max_modulus < 1.0);
    if (p.measures.laws[0].count("stick_phases") && p.measures.laws[0].at("stick_phases") > 0) {
      ++stick_slip;
    }
  }
  CHECK(stick_slip > 10);  // the check covers orbits with stick phases
  CHECK(trace.bifurcations.empty());
}

TEST_CASE("stability: off means no Floquet results and no bifurcations") {
  Case c = LoadSourceCase("duffing.json");
  c.stability.enabled = false;
  const TraceResult trace = TraceCase(c);
  REQUIRE_FALSE(trace.points.empty());
  for (const TracePoint& point : trace.points) CHECK_FALSE(point.floquet.computed);
  CHECK(trace.bifurcations.empty());
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

// Hill (H = 7, 64 samples) against the monodromy of the time integrator (IDA, rtol 1e-10,
// central differences of the period map): the bar on a smooth case is 1e-6; the
// truncation of Hill's matrix at H = 7 gives ~4e-7 on the resonant solutions at ω = 1.2.
constexpr double kHillMonodromyTolerance = 1e-6;

TEST_CASE("stability: Hill's multipliers agree with transient monodromy on Duffing") {
  Case c = LoadSourceCase("duffing.json");
  ValidationSettings settings = c.validation;
  settings.omegas = {0.8, 1.2, 1.5};
  settings.chirp.enabled = false;
  const ValidationResult result = ValidateCase(c, settings);
  int compared = 0;
  for (const ValidationPoint& point : result.points) {
    REQUIRE(point.stability.size() == point.solutions.size());
    for (const SolutionStability& s : point.stability) {
      CAPTURE(point.omega);
      REQUIRE(s.hill.computed);
      REQUIRE(s.monodromy);
      REQUIRE(s.monodromy->ok);
      REQUIRE(s.multiplier_difference);
      CHECK(*s.multiplier_difference < kHillMonodromyTolerance);
      CHECK(s.hill.multipliers.size() == s.monodromy->multipliers.size());
      ++compared;
    }
  }
  CHECK(compared == 5);  // one solution at 0.8 and 1.5, three inside the fold at 1.2
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

TEST_CASE("stability: quasi-periodic windows pair the Neimark-Sacker points") {
  // Points 0..5; a complex pair leaves the circle after point 1 and returns after point 3.
  std::vector<TracePoint> points(6);
  for (int i = 0; i < 6; ++i) {
    points[static_cast<size_t>(i)].index = i;
    points[static_cast<size_t>(i)].point.lambda = 1.0 + 0.1 * i;
    points[static_cast<size_t>(i)].floquet.computed = true;
    points[static_cast<size_t>(i)].floquet.num_unstable = (i >= 2 && i <= 3) ? 2 : 0;
  }
  Bifurcation open, close;
  open.type = close.type = BifurcationType::kNeimarkSacker;
  open.after_point = 1;
  open.omega = 1.15;
  close.after_point = 3;
  close.omega = 1.35;
  const std::vector<QuasiPeriodicWindow> windows = QuasiPeriodicWindows({open, close}, points);
  REQUIRE(windows.size() == 1);
  CHECK(windows[0].omega_from == 1.15);
  CHECK(windows[0].omega_to == 1.35);
  CHECK(windows[0].first_point == 2);
  CHECK(windows[0].last_point == 3);
  CHECK(windows[0].closed);
  // A branch that ends inside a window reports it open, up to its last point.
  const std::vector<QuasiPeriodicWindow> open_only = QuasiPeriodicWindows({open}, points);
  REQUIRE(open_only.size() == 1);
  CHECK_FALSE(open_only[0].closed);
  CHECK(open_only[0].omega_to == points.back().point.lambda);
}

}  // namespace
}  // namespace nfrc
