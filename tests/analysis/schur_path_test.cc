// The engine's Schur complement onto the friction force (HarmonicSystem::EliminationBlocks)
// against the whole LU it replaced: the same equations solved by both linear-algebra paths
// must give the same solutions, on the stick-slip stretch of the Fig. 7 curve.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "analysis/case.h"
#include "analysis/trace.h"
#include "continuation/block_elimination.h"
#include "continuation/fixed_lambda.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// The problem with its elimination blocks hidden: the engine factorises the whole matrix.
class WholeLu : public ContinuationProblem {
 public:
  explicit WholeLu(ContinuationProblem& inner) : inner_(inner) {}
  int NumUnknowns() const override { return inner_.NumUnknowns(); }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    return inner_.Evaluate(y, lambda, residual, jacobian_y, jacobian_lambda);
  }
  std::vector<int> ScaleGroups() const override { return inner_.ScaleGroups(); }
  Eigen::VectorXd StepWeights() const override { return inner_.StepWeights(); }
  double ResidualNoise(const Eigen::VectorXd& y, double lambda) override {
    return inner_.ResidualNoise(y, lambda);
  }

 private:
  ContinuationProblem& inner_;
};

TEST_CASE("the Schur complement onto the friction force gives the whole LU's solutions") {
  const CaseFile file = ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json");
  Case the_case = file.the_case;
  // Across the resonance, where samples switch between stick and slip from point to point.
  the_case.continuation.lambda_start = 0.45;
  the_case.continuation.lambda_end = 0.75;
  the_case.continuation.max_points = 400;
  auto system = BuildSystem(the_case);
  const std::vector<std::vector<int>> blocks = system->EliminationBlocks();
  REQUIRE_FALSE(blocks.empty());
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, nullptr);
  const Branch branch = Trace(*system, the_case.continuation, nullptr, &guess, the_case.Plot());
  REQUIRE(branch.points.size() >= 100);

  WholeLu whole(*system);
  // Both Newton solves stop at a scaled update of 1e-10 (newton_tolerance); from the same
  // start on the same semismooth equations they reach the same solution up to round-off
  // (measured: 2e-15 relative at most, printed below). 1e-10 is the bar for the
  // smooth cases, tighter than its "within the Newton tolerance" for the nonsmooth ones.
  constexpr double kSameSolution = 1e-10;
  int compared = 0;
  double least_stick = 1.0, most_stick = 0.0;  // the stick fraction of the friction force
  double largest_difference = 0.0;             // relative, between the two paths
  for (size_t i = 0; i < branch.points.size(); i += branch.points.size() / 12) {
    const BranchPoint& point = branch.points[i];
    CAPTURE(point.lambda);
    // The same start for both: the point moved off the curve.
    const Eigen::VectorXd start = 1.02 * point.y;
    const FixedLambdaSolution eliminated =
        SolveAtFixedLambda(*system, start, point.lambda, point.y, the_case.continuation);
    const FixedLambdaSolution full =
        SolveAtFixedLambda(whole, start, point.lambda, point.y, the_case.continuation);
    REQUIRE(eliminated.converged);
    REQUIRE(full.converged);
    CHECK((eliminated.y - full.y).norm() <= kSameSolution * full.y.norm());
    largest_difference =
        std::max(largest_difference, (eliminated.y - full.y).norm() / full.y.norm());
    CHECK((eliminated.y - point.y).norm() <= kSameSolution * point.y.norm());
    const double stick =
        system->laws()[0]
            ->Diagnostics(system->context(0), eliminated.y, point.lambda, system->fourier())
            .at("stick_fraction");
    least_stick = std::min(least_stick, stick);
    most_stick = std::max(most_stick, stick);
    // The eliminating path was taken there (it declines ill-conditioned blocks silently).
    Eigen::VectorXd residual, x;
    Eigen::MatrixXd jacobian;
    REQUIRE(system->Evaluate(eliminated.y, point.lambda, &residual, &jacobian, nullptr));
    CHECK(SolveEliminating(jacobian, residual, blocks, &x));
    ++compared;
  }
  MESSAGE("largest relative difference between the paths: " << largest_difference);
  CHECK(compared >= 10);
  // The stretch crosses stick-slip states: the law's active set differs between points.
  CHECK(least_stick < most_stick);
  CHECK(most_stick > 0.0);
}

}  // namespace
}  // namespace nfrc
