// Arnoldi started from the previous point's Ritz vectors (SolveHill's krylov_start) against a
// random start: the same multipliers along the stick-slip stretch of Fig. 7, in fewer
// applications of the shift-invert operator.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "analysis/case.h"
#include "analysis/hill.h"
#include "analysis/trace.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// Both solves converge their Ritz values to 1e-8 relative; the multipliers then agree to
// ~1e-9 (measured below), well under the 1e-6 that decides stability.
constexpr double kSameMultiplier = 1e-7;

TEST_CASE("hill: a warm-started Arnoldi gives the cold start's multipliers in fewer solves") {
  const CaseFile file = ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json");
  Case the_case = file.the_case;
  // Across the resonance, where samples switch between stick and slip from point to point.
  the_case.continuation.lambda_start = 0.45;
  the_case.continuation.lambda_end = 0.75;
  the_case.stability.enabled = false;
  auto system = BuildSystem(the_case);
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, nullptr);
  const Branch branch = Trace(*system, the_case.continuation, nullptr, &guess, the_case.Plot());
  REQUIRE(branch.points.size() >= 100);

  HillAssembler assembler(*system);
  const HillOptions options;
  Eigen::VectorXd start;
  int cold_applications = 0, warm_applications = 0, compared = 0;
  double largest_difference = 0.0;
  for (size_t i = 0; i < branch.points.size(); i += 2) {
    const BranchPoint& point = branch.points[i];
    CAPTURE(point.lambda);
    const HillPencil pencil = assembler.Assemble(point.y, point.lambda);
    const FloquetResult cold = SolveHill(pencil, options);
    const FloquetResult warm = SolveHill(pencil, options, &start);
    REQUIRE(cold.computed);
    REQUIRE(warm.computed);
    REQUIRE(warm.multipliers.size() == cold.multipliers.size());
    REQUIRE(cold.operator_applications > static_cast<int>(pencil.d0.rows()) / 20);
    for (const auto& mu : warm.multipliers) {
      double nearest = 1e300;
      for (const auto& other : cold.multipliers) nearest = std::min(nearest, std::abs(mu - other));
      CHECK(nearest <= kSameMultiplier * std::max(1.0, std::abs(mu)));
      largest_difference = std::max(largest_difference, nearest);
    }
    CHECK(warm.num_unstable == cold.num_unstable);
    if (i > 0) {  // the first warm solve started at random too
      cold_applications += cold.operator_applications;
      warm_applications += warm.operator_applications;
    }
    ++compared;
  }
  MESSAGE("largest multiplier difference " << largest_difference << "; operator applications "
                                           << cold_applications << " cold, " << warm_applications
                                           << " warm, over " << compared << " points");
  CHECK(compared >= 50);
  CHECK(warm_applications < cold_applications);
}

}  // namespace
}  // namespace nfrc
