// A fine unreduced mesh under the arclength corrector: the rigid-obstacle rod of
// cases/rod/rigid_nh20.json refined to 20 000 elements, condensed onto its end. There the
// rounding of the condensed operator moves with ω above the residual tolerance; the static
// split and the corrector's noise floor must let every step converge on the arclength
// hyperplane (no fixed-ω fallback), and each point must still solve its fixed-ω problem.
#include <doctest/doctest.h>

#include <string>
#include <variant>

#include "analysis/case.h"
#include "analysis/trace.h"
#include "continuation/fixed_lambda.h"
#include "models/damping.h"
#include "models/rod.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

TEST_CASE("A 20 000-element rod in contact is traced without fixed-omega fallbacks") {
  const CaseFile file = ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/rod/rigid_nh20.json");
  Case the_case = file.the_case;
  RodParameters rod;
  rod.elements = 20000;
  rod.length = file.source["model"]["length"].get<double>();
  rod.area = file.source["model"]["area"].get<double>();
  rod.young = file.source["model"]["young"].get<double>();
  rod.density = file.source["model"]["density"].get<double>();
  the_case.model.model = BuildRod(rod);
  const int end = the_case.model.model.FindDof("end");
  // Rayleigh damping C = βK with ζ = 0.75 % at the first mode (ω0 = 63 954 rad/s): the
  // stiffness-proportional part makes the damping's condensation cancel like K's.
  constexpr double kOmega0 = 63954.0;
  the_case.model.model.damping = RayleighDamping(
      the_case.model.model.mass, the_case.model.model.stiffness, 0.0, 2.0 * 0.0075 / kOmega0);
  for (ForcingTerm& term : the_case.model.forcing) term.dof = end;
  std::get<DlftContactSpec>(the_case.laws[0]).contact.geometry.dof = end;
  the_case.output_dofs = {end};
  the_case.continuation.lambda_start = 6.3e4;  // in contact
  the_case.continuation.lambda_end = 6.6e4;
  the_case.continuation.max_points = 6;

  auto system = BuildSystem(the_case);
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, nullptr);
  const Branch branch = Trace(*system, the_case.continuation, nullptr, &guess, the_case.Plot());
  REQUIRE(branch.points.size() == 6);
  for (const StepRecord& record : branch.summary.history) {
    INFO(record.note);
    CHECK(record.note.rfind("natural-parameter", 0) != 0);
  }
  // The points are solutions: Newton at each one's fixed ω (where the operator's rounding
  // does not move, so the strict tolerance is met) stays within the noise-level distance.
  // Measured: moves of ~1e-9 relative; 1e-6 would still be far below any plotted change.
  constexpr double kSameSolution = 1e-6;
  for (const BranchPoint& point : branch.points) {
    const FixedLambdaSolution fixed =
        SolveAtFixedLambda(*system, point.y, point.lambda, point.y, the_case.continuation);
    REQUIRE(fixed.converged);
    CHECK((fixed.y - point.y).norm() <= kSameSolution * point.y.norm());
  }
}

}  // namespace
}  // namespace nfrc
