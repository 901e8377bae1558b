// The hysteretic friction laws with a stiff stick phase (jenkins at large k_t, dlft_friction at
// N_phi = 60) on the two-DOF friction oscillator of Legrand & Pierre (2024, Fig. 7), against
// the equality-based Coulomb law they tend to: the start (stiffness homotopy), the trace through
// the sharp super-harmonic peaks, and the curves.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "analysis/trace.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// The largest |μ| along the N = 10 curve (0.9617, near the resonance, where the curve is
// smooth): the stiff laws' and Coulomb's differ by the laws' own difference (k_t, ε = 1e4
// against a rigid stick, ~1e-4 in the peak) and Hill's truncation; 1e-3 leaves margin.
constexpr double kLargestModulusAgreement = 1e-3;

// Fig. 7 at N = 10 with `law` in place of coulomb_friction, `harmonics` odd harmonics up to
// H (N_φ = H + 1 coefficients), stability off (the curves are what is checked).
Case Fig7Case(const nlohmann::json& law, int max_harmonic, int samples) {
  nlohmann::json source =
      ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json").source;
  source["nonlinearities"] = nlohmann::json::array({law});
  source["harmonics"] = {{"max", max_harmonic}, {"odd_only", true}, {"samples", samples}};
  source["stability"] = {{"enabled", false}};
  return ParseCase(source, std::string(NFRC_SOURCE_DIR) + "/cases/friction");
}

nlohmann::json Coulomb() {
  return {{"type", "coulomb_friction"}, {"dof", 1}, {"mu", 0.9}, {"normal_load", 10}};
}

struct Peak {
  double omega = 0.0;
  double max_abs = 0.0;  // of x1
};

Peak PeakOf(const TraceResult& result) {
  Peak peak;
  for (const TracePoint& point : result.points) {
    if (point.measures.response.max_abs[0] > peak.max_abs) {
      peak = {point.point.lambda, point.measures.response.max_abs[0]};
    }
  }
  return peak;
}

bool HasNote(const TraceResult& result, const std::string& text) {
  const auto& notes = result.branch.summary.notes;
  return std::any_of(notes.begin(), notes.end(),
                     [&](const std::string& note) { return note.find(text) != std::string::npos; });
}

// The whole curve to omega_end without a fold, its resonance peak within 1 % of the equality
// law's in amplitude and 0.2 % in ω (same harmonics).
void CheckCurveAgainstCoulomb(const TraceResult& result, const TraceResult& exact) {
  const Peak a = PeakOf(result), b = PeakOf(exact);
  CHECK(result.branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(result.points.back().point.lambda == doctest::Approx(0.8));
  CHECK(result.folds.empty());
  CHECK(std::abs(a.max_abs - b.max_abs) < 0.01 * b.max_abs);
  CHECK(std::abs(a.omega - b.omega) < 0.002 * b.omega);
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// k_t = 1e4 (10⁴ times K at the DOF): Newton from the linear guess fails at every rung of the
// harmonic ladder; the stiffness homotopy starts it, and the branch passes the sharp
// super-harmonic peaks without spurious folds up to omega_end, its resonance peak within 1 % of
// the equality law's in amplitude and 0.2 % in ω at the same harmonics.
TEST_CASE("jenkins at k_t = 1e4: homotopy start, the whole curve, the Coulomb peak") {
  const auto started = std::chrono::steady_clock::now();
  const nlohmann::json jenkins = {
      {"type", "jenkins"}, {"dof", 1}, {"mu", 0.9}, {"normal_load", 10}, {"stiffness", 1e4}};
  const TraceResult stiff = TraceCase(Fig7Case(jenkins, 19, 256));
  const TraceResult exact = TraceCase(Fig7Case(Coulomb(), 19, 256));
  const Peak a = PeakOf(stiff), b = PeakOf(exact);
  MESSAGE("jenkins k_t = 1e4: " << stiff.points.size() << " points, peak " << a.max_abs << " at "
                                << a.omega << "; coulomb_friction: peak " << b.max_abs << " at "
                                << b.omega << " (" << Seconds(started) << " s)");
  CheckCurveAgainstCoulomb(stiff, exact);
  CHECK(HasNote(stiff, "start: stiffness homotopy: started from the linear guess"));
}

// The homotopy is an option: without it the same start fails (and says so).
TEST_CASE("jenkins at k_t = 1e4: without the start homotopy the start fails") {
  const nlohmann::json jenkins = {
      {"type", "jenkins"}, {"dof", 1}, {"mu", 0.9}, {"normal_load", 10}, {"stiffness", 1e4}};
  Case the_case = Fig7Case(jenkins, 19, 256);
  the_case.start.homotopy = false;
  const TraceResult result = TraceCase(the_case);
  CHECK(result.branch.summary.reason == TerminationReason::kStartFailed);
  CHECK_FALSE(HasNote(result, "stiffness homotopy"));
}

// DLFT friction at N_φ = 60 (the acceptance's resolution; sampled, its return mapping stalled
// or turned back at spurious folds) with ε = 1e4 at N = 10.5: the start comes down the harmonic
// ladder and up the stiffness homotopy from the coarser solution; the whole curve follows, its
// peak within 1 % of the equality law's.
TEST_CASE("dlft friction at N_phi = 60: the whole curve and the Coulomb peak") {
  const auto started = std::chrono::steady_clock::now();
  const nlohmann::json dlft = {
      {"type", "dlft_friction"}, {"dof", 1}, {"mu", 0.9}, {"normal_load", 10.5}, {"epsilon", 1e4}};
  nlohmann::json coulomb = Coulomb();
  coulomb["normal_load"] = 10.5;
  const TraceResult result = TraceCase(Fig7Case(dlft, 59, 1024));
  const TraceResult exact = TraceCase(Fig7Case(coulomb, 59, 1024));
  const Peak a = PeakOf(result), b = PeakOf(exact);
  MESSAGE("dlft_friction: " << result.points.size() << " points, peak " << a.max_abs << " at "
                            << a.omega << "; coulomb_friction: peak " << b.max_abs << " at "
                            << b.omega << " (" << Seconds(started) << " s)");
  CheckCurveAgainstCoulomb(result, exact);
  CHECK(HasNote(result, "started from the coarser harmonics' solution"));
}

// Hill's method with the stick pieces' memory (analysis/hill_memory.h) on the hysteretic laws
// against the equality-based Coulomb law's Hill (own unknowns, no memory): along the whole
// N = 10 curve every point is stable and the largest |μ| is Coulomb's. With the anchor's
// Floquet factor taken as 1, 53 (Jenkins) and 50 (DLFT) of ~1080 points were unstable, with
// |μ| up to 6.6, and 8 Neimark–Sacker points were reported on each curve.
TEST_CASE("jenkins and dlft friction: Hill with the stick memory, stable as Coulomb's law") {
  Case coulomb = Fig7Case(Coulomb(), 19, 256);
  coulomb.stability.enabled = true;
  auto largest = [](const TraceResult& result) {
    double largest_modulus = 0.0;
    int unstable = 0;
    for (const TracePoint& point : result.points) {
      REQUIRE(point.floquet.computed);
      largest_modulus = std::max(largest_modulus, point.floquet.max_modulus);
      if (!point.floquet.stable()) ++unstable;
    }
    return std::pair{largest_modulus, unstable};
  };
  const auto [reference, reference_unstable] = largest(TraceCase(coulomb));
  REQUIRE(reference_unstable == 0);
  for (const nlohmann::json& law :
       {nlohmann::json{
            {"type", "jenkins"}, {"dof", 1}, {"mu", 0.9}, {"normal_load", 10}, {"stiffness", 1e4}},
        nlohmann::json{{"type", "dlft_friction"},
                       {"dof", 1},
                       {"mu", 0.9},
                       {"normal_load", 10},
                       {"epsilon", 1e4}}}) {
    Case the_case = Fig7Case(law, 19, 256);
    the_case.stability.enabled = true;
    const TraceResult result = TraceCase(the_case);
    const auto [modulus, unstable] = largest(result);
    MESSAGE(law["type"] << ": " << result.points.size() << " points, " << unstable
                        << " unstable, largest |mu| " << modulus << " (coulomb_friction "
                        << reference << "), " << result.bifurcations.size() << " bifurcations");
    CHECK(unstable == 0);
    CHECK(result.bifurcations.empty());
    CHECK(std::abs(modulus - reference) < kLargestModulusAgreement);
  }
}

// cases/friction/frc_n10_dlft.json (N = 10, ε = 1e4): near ω = 0.114 the branch turns by more
// than 90° at a corner while ω goes on; oriented by the previous tangent, the step past it
// pointed back (a false corner fold at ω = 0.11397, and the branch retraced to omega_start:
// 154 points). The orientation index keeps ω increasing (the summary notes how often it did).
TEST_CASE("dlft friction at N = 10, epsilon = 1e4: no false fold past the sharp corners") {
  Case the_case =
      ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10_dlft.json").the_case;
  the_case.stability.enabled = false;
  const TraceResult result = TraceCase(the_case);
  MESSAGE(result.points.size() << " points, " << result.folds.size()
                               << " folds; notes: " << result.branch.summary.notes.size());
  CHECK(result.branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(result.points.back().point.lambda == doctest::Approx(0.8));
  CHECK(result.folds.empty());
}

}  // namespace
}  // namespace nfrc
