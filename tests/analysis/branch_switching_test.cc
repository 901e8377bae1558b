// Branch switching at a period doubling of the escape oscillator ẍ + 0.1ẋ + x − x² = F cos ωt
// (an asymmetric softening oscillator with a period-doubling cascade on the way to escape).
#include "analysis/branch_switching.h"

#include <doctest/doctest.h>

#include <cmath>

#include "analysis/validate.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// The period doubling is localised to 1e-6 relative (StabilityOptions default); its crossing
// multiplier is −1 to the accuracy Hill's exponent has there (|μ + 1| ~ slope × Δω ≪ 1e-4).
constexpr double kMinusOneTolerance = 1e-4;

TEST_CASE("branch switching: the period-2 branch of a period doubling") {
  const Case base = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/escape_oscillator.json");
  const TraceResult trace = TraceCase(base);
  REQUIRE(trace.branch.summary.success());
  const Bifurcation* pd = nullptr;
  for (const Bifurcation& b : trace.bifurcations) {
    if (b.type == BifurcationType::kPeriodDoubling) pd = &b;
  }
  REQUIRE(pd != nullptr);
  CHECK(pd->converged);
  REQUIRE(pd->crossing_multipliers.size() == 1);
  CHECK(std::abs(pd->crossing_multipliers[0] + 1.0) < kMinusOneTolerance);

  const SwitchedBranch period2 = FollowPeriodDoubling(base, *pd);
  REQUIRE(period2.started);
  REQUIRE(period2.trace.points.size() > 5);
  // It leaves the period doubling into the side where the period-1 branch is unstable
  // (ω below it here), with odd ν-harmonics that vanish at the point (a pitchfork in ν).
  CHECK(period2.start_omega < pd->omega);
  const HarmonicSet& set = period2.the_case.harmonics;
  const double near = OddHarmonicContent(period2.trace.points.front().point.y, set, 1);
  const double far = OddHarmonicContent(period2.trace.points[5].point.y, set, 1);
  CHECK(near > 0.0);
  CHECK(far > near);
  // Stable where it is born (a supercritical doubling: the period-2 orbit takes over).
  CHECK(period2.trace.points[1].floquet.stable());

  // The cascade goes on: the period-2 branch doubles again (to period 4) further down in ω.
  bool doubles_again = false;
  for (const Bifurcation& b : period2.trace.bifurcations) {
    if (b.type == BifurcationType::kPeriodDoubling && 2.0 * b.omega < pd->omega) {
      doubles_again = true;
    }
  }
  CHECK(doubles_again);

  // Independent check: integrate the ODE from the period-2 HBM state at one ω; the transient
  // must settle on a 2T-periodic orbit equal to it (T-periodic in the period-2 case's terms).
  const double nu = period2.trace.points[3].point.lambda;
  ValidationSettings settings = period2.the_case.validation;
  settings.omegas = {nu};
  settings.chirp.enabled = false;
  const ValidationResult validated = ValidateCase(period2.the_case, settings);
  REQUIRE(validated.points.size() == 1);
  const ValidationPoint& point = validated.points[0];
  REQUIRE(point.primary >= 0);
  const TransientRun& run = point.transients[static_cast<size_t>(point.primary)];
  CHECK(run.result.periodic());
  REQUIRE(run.comparison);
  // HBM with 24 harmonics of ν against IDA at rtol 1e-10: max |x| to 1e-4 relative.
  CHECK(run.comparison->max_abs[0] < 1e-4);
}

}  // namespace
}  // namespace nfrc

namespace nfrc {
namespace {

// At a symmetric solution x1 = x2 of two identical coupled oscillators the Jacobian is
// [[A, B], [B, A]]: A + B acts on in-phase perturbations, A − B on antisymmetric ones. A
// symmetry-breaking pitchfork is where A − B is singular and A + B is not (a fold is the
// reverse). Localised to 1e-6 in ω, σ_min(A − B)/σ_max is O(1e-6); 1e-4 separates it from
// a regular matrix (σ_min/σ_max of A + B there is ~3e-3: both points lie near the fold at
// ω ≈ 1.11, where A + B becomes singular).
constexpr double kSingular = 1e-4;

double RelativeSmallestSingularValue(const Eigen::MatrixXd& m) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  return svd.singularValues().minCoeff() / svd.singularValues().maxCoeff();
}

TEST_CASE("branch switching: the other branch of a symmetry-breaking pitchfork") {
  const Case base =
      LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/coupled_duffing_pitchfork.json");
  const TraceResult trace = TraceCase(base);
  REQUIRE(trace.branch.summary.success());
  std::vector<const Bifurcation*> points;
  for (const Bifurcation& b : trace.bifurcations) {
    if (b.type == BifurcationType::kBranchPoint) points.push_back(&b);
  }
  REQUIRE(points.size() == 2);
  auto system = BuildSystem(base);
  const int nc = base.harmonics.NumCoefficients();
  for (const Bifurcation* b : points) {
    CAPTURE(b->omega);
    CHECK(b->converged);
    REQUIRE(b->crossing_multipliers.size() == 1);
    CHECK(std::abs(b->crossing_multipliers[0] - 1.0) < 1e-2);
    Eigen::VectorXd residual;
    Eigen::MatrixXd j;
    REQUIRE(system->Evaluate(b->y, b->omega, &residual, &j, nullptr));
    const Eigen::MatrixXd a = j.topLeftCorner(nc, nc), c = j.block(0, nc, nc, nc);
    CHECK(RelativeSmallestSingularValue(a - c) < kSingular);
    CHECK(RelativeSmallestSingularValue(a + c) > 10 * kSingular);
  }
  const SwitchedBranch other = FollowBranchPoint(base, *points[0]);
  REQUIRE(other.started);
  REQUIRE(other.trace.points.size() > 10);
  // The new branch is asymmetric: x1 ≠ x2 (a localised response), unlike the first branch.
  const Eigen::VectorXd& y = other.trace.points[10].point.y;
  CHECK((y.head(nc) - y.segment(nc, nc)).norm() > 1e-2 * y.head(nc).norm());
}

}  // namespace
}  // namespace nfrc
