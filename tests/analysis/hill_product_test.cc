// HillProduct against the assembled Δ1 q + Δ2 w: the factored product (Kronecker products of
// C and M, the DLFT law's rows taken from the linear product, the rest sparse) on a contact
// pencil with dense damping, a friction pencil (the law's velocity Jacobian) and a Jenkins
// pencil with memory unknowns; and a pencil without factors, applied through d1 and d2.
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

// A chain of n DOFs with friction at its last (normal load in N), 15 coefficients per signal;
// `dense_damping` couples every DOF.
Case FrictionChain(int n, double normal_load, bool dense_damping) {
  Case c = testing::ChainCase(n);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(7, false, 64);
  c.laws.push_back(testing::Friction(n - 1, 0.3, normal_load));
  if (dense_damping) {
    c.model.model.damping =
        (Eigen::MatrixXd(c.model.model.damping) + 0.003 * Eigen::MatrixXd::Ones(n, n)).sparseView();
  }
  return c;
}

TEST_CASE("hill product: friction's velocity Jacobian in the sparse rest") {
  // Four DOFs: C⊗I (240 entries), M⊗D and M⊗I outnumber the force's velocity block (15²).
  const HillPencil pencil = testing::PencilOf(FrictionChain(4, 0.05, true), 0.9, 0.01, 7);
  REQUIRE(pencil.factors.has_value());
  REQUIRE(pencil.factors->laws_d1.nonZeros() > 0);
  CHECK(ProductDifference(pencil) <= kSameProduct);
}

TEST_CASE("hill product: no factors where the laws' rest outnumbers the linear part") {
  // Two DOFs (Fig. 7's shape), partly stuck: the linear parts of Δ1 and Δ2 have 4·15 + 2·14 +
  // 2·15 = 118 entries, fewer than the friction force's velocity block (up to 15²).
  const HillPencil pencil = testing::PencilOf(FrictionChain(2, 0.2, false), 0.9, 0.01, 7);
  MESSAGE("Δ1: " << pencil.d1.nonZeros() << " entries");
  CHECK(pencil.d1.nonZeros() - 88 >= 118);  // the linear Δ1 has 88
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
