#include "continuation/tangent.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <memory>

#include "continuation/augmented_system.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::CubicProblem;
using testing::DuffingProblem;

// Closed-form quantities computed in a handful of flops agree to rounding.
constexpr double kRoundoff = 1e-13;

doctest::Approx Near(double value) { return doctest::Approx(value).epsilon(kRoundoff); }

TEST_CASE("tangent: the first one points towards lambda_end, even from a fold") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  Scaling scaling({0}, 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Constant(1, 2.0));
  Linearization regular;
  // y = 2: R_y = 3, R_λ = −1, so dy/dλ = 1/3 and the scaled tangent ∝ (1/3 / 2, 1).
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(2.0, 2.0 / 3.0), &regular));
  Eigen::VectorXd up, down;
  REQUIRE(InitialTangent(regular, scaling, 1.0, 1.0, &up));
  REQUIRE(InitialTangent(regular, scaling, 1.0, -1.0, &down));
  CHECK(up(1) > 0.0);
  CHECK(down(1) < 0.0);
  CHECK(up.norm() == Near(1.0));
  CHECK(up(0) / up(1) == Near(1.0 / 6.0));

  Linearization fold;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(-1.0, 2.0 / 3.0), &fold));
  Eigen::VectorXd at_fold;
  REQUIRE(InitialTangent(fold, scaling, 1.0, 1.0, &at_fold));
  CHECK(std::abs(at_fold(0)) == Near(1.0));
  CHECK(at_fold(1) == Near(0.0));
}

TEST_CASE("tangent: the first one is the null vector of the scaled [R_y, R_lambda]") {
  DuffingProblem problem(/*with_energy=*/true);
  Evaluator evaluator(problem);
  Scaling scaling({0, 0, 1}, 0.5, 1e-6);
  scaling.Include(Eigen::Vector3d(1.0, 2.0, 5.0));
  Linearization at;
  // Any (y, ω): the tangent of [R_y, R_λ] is defined off the branch too.
  REQUIRE(evaluator.Linearize(Eigen::Vector4d(0.7, -0.4, 0.3, 1.1), &at));
  Eigen::VectorXd tangent;
  REQUIRE(InitialTangent(at, scaling, 2.0, -1.0, &tangent));
  // Closed form: Δy = −R_y⁻¹R_λ Δλ, scaled by the unknowns' scales; λ decreasing.
  const Eigen::Vector3d dy = -at.jacobian_y.lu().solve(at.jacobian_lambda);
  Eigen::Vector4d expected;
  expected << dy.cwiseQuotient(scaling.scales().head(3)), 1.0 / scaling.scales()(3);
  expected = -expected.normalized();
  for (int i = 0; i < 4; ++i) CHECK(tangent(i) == Near(expected(i)));
}

TEST_CASE("tangent: the bordered tangent keeps the orientation of the previous one") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  Scaling scaling({0}, 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Constant(1, 1.0));
  Linearization fold;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(-1.0, 2.0 / 3.0), &fold));
  for (double sign : {1.0, -1.0}) {
    const Eigen::Vector2d previous = sign * Eigen::Vector2d(1.0, 0.1).normalized();
    Eigen::VectorXd tangent;
    REQUIRE(NextTangent(fold, scaling, 1.0, previous, &tangent));
    CHECK(tangent.dot(previous) > 0.0);
    CHECK(tangent(0) == Near(sign));
    CHECK(tangent(1) == Near(0.0));
  }
}

// Along R = y³/3 − y − λ, parametrised by y, the tangent (1, y² − 1) turns through the folds
// at y = ±1 (its λ component changes sign) while det[R_y, R_λ; τᵀ] = (y² − 1)² + 1 keeps its
// sign: the orientation index is the curve's, in any positive scaling.
TEST_CASE("tangent: the orientation index keeps its sign through folds, whatever the scaling") {
  CubicProblem problem;
  Evaluator evaluator(problem);
  for (double y_scale : {1.0, 1e-3, 1e4}) {
    CAPTURE(y_scale);
    Scaling scaling({0}, 3.0, 1e-6);
    scaling.Include(Eigen::VectorXd::Constant(1, y_scale));
    for (double y : {-2.0, -1.0, -0.5, 0.0, 1.0, 2.0}) {
      CAPTURE(y);
      Linearization at;
      REQUIRE(evaluator.Linearize(Eigen::Vector2d(y, y * y * y / 3.0 - y), &at));
      const Eigen::VectorXd tangent = scaling.UnitScaled(Eigen::Vector2d(1.0, y * y - 1.0));
      CHECK(OrientationIndex(at, scaling, 1.0, tangent) == 1);
      CHECK(OrientationIndex(at, scaling, 1.0, -tangent) == -1);
    }
  }
}

// Across a corner of a piecewise-linear R the index keeps the curve's orientation where the
// rule τᵀτ_prev > 0 reverses it: R = y − (1 − 50|λ − 1/2|) (y, λ scaled alike) turns by
// ~177° at λ = 1/2. Going up the left arm, τ ∝ (50, 1); on the right arm the tangent line is
// ±(−50, 1), and τ_prev·(−50, 1) < 0 makes NextTangent choose (50, −1): back up the peak.
TEST_CASE("tangent: across a corner the orientation index keeps the direction of travel") {
  class Peak : public ContinuationProblem {
   public:
    int NumUnknowns() const override { return 1; }
    bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                  Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
      (*residual)(0) = y(0) - (1.0 - 50.0 * std::abs(lambda - 0.5));
      if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 1.0;
      if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = lambda > 0.5 ? 50.0 : -50.0;
      return true;
    }
  } problem;
  Evaluator evaluator(problem);
  Scaling scaling({0}, 1.0, 1e-6);
  scaling.Include(Eigen::VectorXd::Constant(1, 1.0));
  Linearization left, right;
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(0.95, 0.499), &left));
  REQUIRE(evaluator.Linearize(Eigen::Vector2d(0.95, 0.501), &right));
  const Eigen::VectorXd incoming = Eigen::Vector2d(50.0, 1.0).normalized();
  Eigen::VectorXd next;
  REQUIRE(NextTangent(right, scaling, 1.0, incoming, &next));
  CHECK(next(1) < 0.0);  // the previous tangent's rule: back up the peak (a false fold)
  CHECK(OrientationIndex(left, scaling, 1.0, incoming) !=
        OrientationIndex(right, scaling, 1.0, next));
  CHECK(OrientationIndex(left, scaling, 1.0, incoming) ==
        OrientationIndex(right, scaling, 1.0, -next));  // λ goes on: −next
}

// Random bordered systems of kBlockedSize unknowns y (and λ): with blocks, unknowns {0, 1},
// {2, 3}, {4, 5} couple only with themselves and the rest 6..8, as harmonics of a condensed
// linear part do, and are declared the elimination's blocks.
constexpr int kBlockedSize = 9;

Scaling BlockedScaling() {
  Scaling scaling({0, 0, 0, 0, 0, 0, 1, 1, 1}, 2.0, 1e-6);
  scaling.Include(Eigen::VectorXd::LinSpaced(kBlockedSize, 0.5, 3.0));
  return scaling;
}

void DecoupleBlocks(Eigen::MatrixXd* matrix) {
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      if (a != b) matrix->block(2 * a, 2 * b, 2, 2).setZero();
    }
  }
}

Linearization RandomLinearization(bool blocks) {
  Linearization at;
  at.residual = Eigen::VectorXd::Zero(kBlockedSize);
  at.jacobian_y = Eigen::MatrixXd::Random(kBlockedSize, kBlockedSize);
  at.jacobian_lambda = Eigen::VectorXd::Random(kBlockedSize);
  if (blocks) {
    DecoupleBlocks(&at.jacobian_y);
    at.elimination =
        std::make_shared<const EliminationBlocks>(EliminationBlocks{{0, 1}, {2, 3}, {4, 5}});
  }
  return at;
}

// The index that InitialTangent and NextTangent take from their own factorisation (border
// eₙ or τ_prev, by the determinant lemma) against OrientationIndex's separate LU of
// [J; τᵀ], on random matrices with and without elimination blocks and with borders of either
// sign: two routes to one determinant sign.
TEST_CASE("tangent: the orientation from the tangent's own factorisation is OrientationIndex") {
  std::srand(7);
  const Scaling scaling = BlockedScaling();
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    CAPTURE(trial);
    const Linearization at = RandomLinearization(trial % 2 == 1);
    for (double direction : {1.0, -1.0}) {
      Eigen::VectorXd tangent;
      int orientation = 0;
      REQUIRE(InitialTangent(at, scaling, 1.5, direction, &tangent, &orientation));
      CHECK(orientation != 0);
      CHECK(orientation == OrientationIndex(at, scaling, 1.5, tangent));
    }
    const Eigen::VectorXd previous = Eigen::VectorXd::Random(kBlockedSize + 1).normalized();
    Eigen::VectorXd tangent;
    int orientation = 0;
    // NextTangent refuses a tangent against the border (τᵀτ_prev ≤ 0 after a fallback only).
    if (!NextTangent(at, scaling, 1.5, previous, &tangent, &orientation)) continue;
    CHECK(orientation != 0);
    CHECK(orientation == OrientationIndex(at, scaling, 1.5, tangent));
    CHECK(-orientation == OrientationIndex(at, scaling, 1.5, -tangent));
    ++checked;
  }
  CHECK(checked >= 30);
}

// The corrector keeps the factorisation of its last Newton matrix, whose Jacobians are one
// update away from the point's: the tangent refined from it is the point's own (fresh LU) to
// the refinement's 1e-10, with its orientation; across a kink (an O(1) change of the Jacobian
// in that update) the refinement does not converge and says so.
TEST_CASE("tangent: refined from a factorisation one Newton update away") {
  constexpr double kUpdate = 1e-8;       // the Jacobians' change over the last update
  constexpr double kSameTangent = 1e-9;  // the refinement's 1e-10, amplified by κ(A) ~ 10
  std::srand(11);
  const Scaling scaling = BlockedScaling();
  const Eigen::VectorXd unit = Eigen::VectorXd::Unit(kBlockedSize + 1, kBlockedSize);
  int refined = 0, refused = 0;
  for (int trial = 0; trial < 40; ++trial) {
    CAPTURE(trial);
    const bool blocks = trial % 2 == 1;
    const Linearization at = RandomLinearization(blocks);
    Eigen::MatrixXd change = Eigen::MatrixXd::Random(kBlockedSize, kBlockedSize);
    if (blocks) DecoupleBlocks(&change);
    const Eigen::VectorXd previous = Eigen::VectorXd::Random(kBlockedSize + 1).normalized();
    Eigen::VectorXd fresh;
    int fresh_orientation = 0;
    if (!NextTangent(at, scaling, 1.5, previous, &fresh, &fresh_orientation)) continue;
    const bool kink = trial % 4 >= 2;
    Linearization before = at;
    before.jacobian_y += (kink ? 1.0 : kUpdate) * change;
    before.jacobian_lambda += kUpdate * Eigen::VectorXd::Random(kBlockedSize);
    AugmentedSolver last_step;
    AugmentedMatrix(before, scaling, 1.5, previous, &last_step.matrix());
    Eigen::VectorXd unused;
    REQUIRE(last_step.Solve(unit, &unused, before.elimination.get()));
    Eigen::VectorXd tangent;
    int orientation = 0;
    const bool found = NextTangent(last_step, at, scaling, 1.5, previous, &tangent, &orientation);
    if (kink) {
      CHECK_FALSE(found);
      ++refused;
      continue;
    }
    REQUIRE(found);
    CHECK((tangent - fresh).norm() <= kSameTangent);
    CHECK(orientation == fresh_orientation);
    ++refined;
  }
  CHECK(refined >= 15);
  CHECK(refused >= 15);
}

}  // namespace
}  // namespace nfrc
