// Fold curves of the Duffing oscillator ẍ + 0.05ẋ + x + 0.1x³ = P cos ωt in the forcing P.
#include "analysis/fold_curve.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

constexpr double kK = 1.0, kC = 0.05, kK3 = 0.1, kBeta = 0.75 * kK3;
// The issue asks for the fold curve to 1e-6 in ω against the closed form.
constexpr double kOmegaTolerance = 1e-6;
// From P = 0.18 (folds at 1.1156 and 1.2675) down below the cusp (P_c ≈ 0.048).
constexpr double kFrom = 0.18, kTo = 0.03;

Case DuffingCase(const std::string& name) {
  return LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
}

// The one-harmonic amplitude equation F(a, ω) = [(k − ω² + βa)² + (cω)²]a − P² = 0, a = A²,
// β = ¾k₃, has a fold in ω where ∂F/∂a = 0: 3β²a² + 4βda + d² + c²ω² = 0 with d = k − ω²,
// a = (−2d ± √(d² − 3c²ω²))/(3β). The fold curve is P(ω) on the two roots; they meet at the
// cusp, where d² = 3c²ω².
double ClosedFormP(double omega, int root) {
  const double d = kK - omega * omega;
  const double discriminant = std::max(0.0, d * d - 3.0 * kC * kC * omega * omega);
  const double a = (-2.0 * d + root * std::sqrt(discriminant)) / (3.0 * kBeta);
  const double u = d + kBeta * a;
  return std::sqrt((u * u + kC * kC * omega * omega) * a);
}

double CuspOmega() { return 0.5 * (std::sqrt(3.0) * kC + std::sqrt(3.0 * kC * kC + 4.0 * kK)); }

// Distance in ω from (P, ω) to the closed-form fold curve: the P mismatch on the nearer root
// over that root's |dP/dω| (a first-order ω error; the curve is smooth off the cusp).
double OmegaError(double p, double omega) {
  constexpr double kStep = 1e-7;
  double best = std::numeric_limits<double>::infinity();
  for (int root : {-1, 1}) {
    const double slope =
        (ClosedFormP(omega + kStep, root) - ClosedFormP(omega - kStep, root)) / (2.0 * kStep);
    const double mismatch = std::abs(ClosedFormP(omega, root) - p);
    best = std::min(best, mismatch / std::max(std::abs(slope), 1e-3));
  }
  return best;
}

TEST_CASE("fold curve of Duffing with one harmonic in the forcing: closed form through the cusp") {
  const Case the_case = DuffingCase("duffing_h1.json");
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  REQUIRE(forcing.Get(the_case) == kFrom);
  FoldCurveOptions options;
  options.to = kTo;
  const FoldCurveResult result = TraceFoldCurves(the_case, forcing, options);
  REQUIRE(result.branch_folds == 2);
  // Down in P from one fold, through the cusp, and back up to P = 0.18 at the other fold: one
  // curve, and the second fold lies on it.
  REQUIRE(result.curves.size() == 1);
  const FoldCurve& curve = result.curves[0];
  CHECK(curve.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(curve.turns.size() == 1);
  CHECK(curve.turns[0].cusp);
  const double cusp_omega = CuspOmega();
  const double cusp_p = ClosedFormP(cusp_omega, 1);
  CHECK(std::abs(curve.turns[0].omega - cusp_omega) < kOmegaTolerance);
  CHECK(std::abs(curve.turns[0].parameter - cusp_p) < kOmegaTolerance * cusp_p);
  double worst = 0.0;
  for (const FoldCurvePoint& point : curve.points)
    worst = std::max(worst, OmegaError(point.parameter, point.omega));
  CHECK(worst < kOmegaTolerance);
  CHECK(std::abs(curve.points.back().parameter - kFrom) < 1e-12);
  MESSAGE("H = 1 fold curve: " << curve.points.size() << " points, largest ω error " << worst
                               << "; cusp at P = " << curve.turns[0].parameter
                               << ", ω = " << curve.turns[0].omega << " (closed form " << cusp_p
                               << ", " << cusp_omega << ")");
}

TEST_CASE("fold curve of Duffing with seven harmonics against fixed-P traces") {
  const Case the_case = DuffingCase("duffing.json");
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  FoldCurveOptions options;
  options.to = kTo;
  const FoldCurveResult result = TraceFoldCurves(the_case, forcing, options);
  REQUIRE(result.curves.size() == 1);
  const FoldCurve& curve = result.curves[0];
  REQUIRE(curve.points.size() > 10);
  // A fixed-P trace at the P of some curve points finds a fold at the curve's ω.
  double worst = 0.0;
  for (size_t i = 1; i + 1 < curve.points.size(); i += curve.points.size() / 5) {
    const FoldCurvePoint& point = curve.points[i];
    CAPTURE(point.parameter);
    const Case at_p = forcing.With(the_case, point.parameter);
    TraceOptions trace_options;
    const TraceResult trace = TraceCase(at_p, trace_options);
    double nearest = std::numeric_limits<double>::infinity();
    for (const TraceFold& fold : trace.folds) {
      nearest = std::min(nearest, std::abs(fold.fold.lambda - point.omega));
    }
    CHECK(nearest < kOmegaTolerance);
    worst = std::max(worst, nearest);
  }
  MESSAGE("H = 7 fold curve: " << curve.points.size() << " points; largest ω difference to the "
                               << "fixed-P traces' folds " << worst);
}

TEST_CASE("fold curves do not start at the corners of a nonsmooth branch, and say so") {
  // NLvib's unilateral spring as a sampled penalty law: every fold of its branch is a corner
  // (a sample enters or leaves contact there), where R_y has no null vector to follow.
  const Case the_case = DuffingCase("contact/nlvib.json#penalty");
  const CaseParameter forcing("model.forcing[0].cos", the_case);
  FoldCurveOptions options;
  options.to = 0.09;
  const FoldCurveResult result = TraceFoldCurves(the_case, forcing, options);
  REQUIRE(result.branch_folds > 0);
  CHECK(result.curves.empty());
  const auto corners = std::count_if(result.notes.begin(), result.notes.end(), [](const auto& n) {
    return n.find("is a corner of the nonsmooth branch") != std::string::npos;
  });
  CHECK(corners == result.branch_folds);
}

TEST_CASE("case parameters: paths name a numeric field, or the error names the parameter") {
  Case the_case = DuffingCase("duffing.json");
  const CaseParameter coefficient("nonlinearities[0].coefficient", the_case);
  CHECK(coefficient.Get(the_case) == 0.1);
  coefficient.Set(&the_case, 0.2);
  CHECK(std::get<CubicSpringSpec>(the_case.laws[0]).coefficient == 0.2);
  CHECK(coefficient.With(the_case, 0.3).laws.size() == 1);
  for (const char* bad :
       {"nonlinearities[1].coefficient", "nonlinearities[0].mu", "model.forcing[3].cos", "model.K",
        "", "nonlinearities[99999999].gap", "nonlinearities[x].gap", "nonlinearities[0].Gap",
        "model.forcing[0].tan", "nonlinearities[0]."}) {
    CAPTURE(bad);
    CHECK_THROWS_WITH_AS(CaseParameter(bad, the_case), doctest::Contains("parameter: \""),
                         InputError);
  }
}

}  // namespace
}  // namespace nfrc
