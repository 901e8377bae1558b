// HillProduct against the assembled Δ1 q + Δ2 w: the factored product (Kronecker products of
// C and M, the DLFT law's rows taken from the linear product, the rest dense or sparse) on a
// contact pencil with dense damping, friction pencils (the laws' velocity Jacobians as one
// dense block or sparse) and a Jenkins pencil with memory unknowns; and pencils without
// factors, applied through d1 and d2.
#include "analysis/hill_product.h"

#include <doctest/doctest.h>

#include <cstdlib>

#include "analysis/case.h"
#include "analysis/hill.h"
#include "support/chain_case.h"
#include "support/hill_pencil.h"

namespace nfrc {
namespace {

// The factored product sums the same terms in another order: each entry differs by a few
// ulps of the largest term (printed differences ~1e-16). 1e-13 relative allows sums of a few
// hundred terms and is far below a missing or doubled term (O(1) here).
constexpr double kSameProduct = 1e-13;

// Random q and w (w zero outside the dynamic unknowns, as the operator gives it), then the
// factored product's relative difference from d1 q + d2 w.
double ProductDifference(const HillPencil& pencil) {
  std::srand(5);
  const Eigen::Index n = pencil.d1.rows();
  const Eigen::VectorXd q = Eigen::VectorXd::Random(n);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  for (const int index : pencil.dynamic) w(index) = std::rand() / double(RAND_MAX) - 0.5;
  const Eigen::VectorXd reference = pencil.d1 * q + pencil.d2 * w;
  Eigen::VectorXd y;
  HillProduct(pencil).Apply(q, w, &y);
  const double difference = (y - reference).norm() / reference.norm();
  MESSAGE("relative difference from d1 q + d2 w: " << difference);
  return difference;
}

TEST_CASE("hill product: DLFT contact with dense damping, its rows from the linear product") {
  Case c = testing::ChainAgainstRigidObstacle(HarmonicSet(15, false, 64));
  // Every DOF damped against every other (modal damping's pattern): C⊗I is dense per block.
  const Eigen::MatrixXd ones = Eigen::MatrixXd::Ones(4, 4);
  c.model.model.damping = (Eigen::MatrixXd(c.model.model.damping) + 0.003 * ones).sparseView();
  const HillPencil pencil = testing::PencilOf(c, 0.9, 0.05, 11);
  REQUIRE(pencil.factors.has_value());
  REQUIRE_FALSE(pencil.factors->dependences.empty());
  CHECK(pencil.factors->laws_d1.nonZeros() == 0);  // DLFT's Δ1 rows are all dependences
  CHECK(ProductDifference(pencil) <= kSameProduct);
}

// A chain of n DOFs with friction at each of `friction_dofs` (normal load in N), 15
// coefficients per signal; `dense_damping` couples every DOF.
Case FrictionChain(int n, const std::vector<int>& friction_dofs, double normal_load,
                   bool dense_damping) {
  Case c = testing::ChainCase(n);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(7, false, 64);
  for (const int dof : friction_dofs) c.laws.push_back(testing::Friction(dof, 0.3, normal_load));
  if (dense_damping) {
    c.model.model.damping =
        (Eigen::MatrixXd(c.model.model.damping) + 0.003 * Eigen::MatrixXd::Ones(n, n)).sparseView();
  }
  return c;
}

TEST_CASE("hill product: friction's velocity block as a dense product") {
  // Two DOFs (Fig. 7's shape), partly stuck: the force's velocity Jacobian fills most of the
  // block of its own unknowns' rows and its DOF's columns.
  const HillPencil pencil = testing::PencilOf(FrictionChain(2, {1}, 0.2, false), 0.9, 0.01, 7);
  REQUIRE(pencil.factors.has_value());
  REQUIRE(pencil.factors->laws_d1_block.has_value());
  const HillFactors::DenseBlock& block = *pencil.factors->laws_d1_block;
  MESSAGE("block " << block.values.rows() << " x " << block.values.cols() << " at (" << block.row
                   << ", " << block.col << ")");
  CHECK(block.row == pencil.own_offset);
  CHECK(block.col == 15);  // the friction DOF's coefficients
  CHECK(pencil.factors->laws_d1.nonZeros() == 0);
  CHECK(ProductDifference(pencil) <= kSameProduct);
}

TEST_CASE("hill product: velocity Jacobians in the sparse rest") {
  // Friction at DOFs 1 and 3 of five: their columns are not contiguous, so no block; C⊗I (375
  // entries), M⊗D and M⊗I outnumber the forces' velocity blocks (up to 2·15²).
  const HillPencil pencil = testing::PencilOf(FrictionChain(5, {1, 3}, 0.05, true), 0.9, 0.01, 7);
  REQUIRE(pencil.factors.has_value());
  CHECK_FALSE(pencil.factors->laws_d1_block.has_value());
  REQUIRE(pencil.factors->laws_d1.nonZeros() > 0);
  CHECK(ProductDifference(pencil) <= kSameProduct);
}

TEST_CASE("hill product: no factors where the laws' rest outnumbers the linear part") {
  // Friction at DOFs 0 and 2 of three, without dense damping, both partly stuck: two velocity
  // blocks in columns that are not contiguous (no block), against the linear Δ1's 147 entries
  // and Δ2's 45.
  const HillPencil pencil = testing::PencilOf(FrictionChain(3, {0, 2}, 0.3, false), 0.9, 0.01, 7);
  MESSAGE("Δ1: " << pencil.d1.nonZeros() << " entries");
  CHECK(pencil.d1.nonZeros() - 147 > 15 * 15);  // more than one law's block
  CHECK_FALSE(pencil.factors.has_value());
  CHECK(ProductDifference(pencil) == 0.0);
}

TEST_CASE("hill product: a Jenkins element's memory unknowns") {
  Case c = testing::ChainCase(3);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(5, false, 64);
  JenkinsSpec jenkins;
  jenkins.dof = 2;
  jenkins.mu = 0.3;
  jenkins.normal_load = 0.2;
  jenkins.stiffness = 5.0;
  c.laws.push_back(jenkins);
  const HillPencil pencil = testing::PencilOf(c, 0.9, 0.0, 1);
  REQUIRE(pencil.factors.has_value());
  REQUIRE(pencil.memory_unknowns > 0);
  CHECK(ProductDifference(pencil) <= kSameProduct);
}

TEST_CASE("hill product: a pencil without factors is applied through d1 and d2") {
  Case c = testing::ChainAgainstRigidObstacle(HarmonicSet(5, false, 32));
  HillPencil pencil = testing::PencilOf(c, 0.9, 0.05, 11);
  pencil.factors.reset();
  CHECK(ProductDifference(pencil) == 0.0);
}

}  // namespace
}  // namespace nfrc
