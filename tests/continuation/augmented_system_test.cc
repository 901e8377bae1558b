#include "continuation/augmented_system.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>

#include "continuation/bordered_view.h"

namespace nfrc {
namespace {

// A harmonic problem's layout: kBlocks blocks of two displacement unknowns (cosine, sine)
// first, each coupled to the rest only through its own force column, then kRest law unknowns;
// 2·kBlocks = 80 rows of blocks, so that the elimination scans them in chunks.
constexpr int kBlocks = 40;
constexpr int kRest = 9;
constexpr int kSize = 2 * kBlocks + kRest;

Linearization HarmonicLikeLinearization(unsigned seed) {
  std::srand(seed);
  Linearization at;
  at.residual = Eigen::VectorXd::Zero(kSize);
  at.jacobian_y = Eigen::MatrixXd::Random(kSize, kSize);
  at.jacobian_lambda = Eigen::VectorXd::Random(kSize);
  EliminationBlocks blocks;
  for (int k = 0; k < kBlocks; ++k) blocks.push_back({2 * k, 2 * k + 1});
  for (int i = 0; i < 2 * kBlocks; ++i) {
    for (int j = 0; j < kSize; ++j) {
      const bool own_block = j < 2 * kBlocks && j / 2 == i / 2;
      const bool own_force = j >= 2 * kBlocks && (j - 2 * kBlocks) == (i / 2) % kRest;
      if (!own_block && !own_force) at.jacobian_y(i, j) = 0.0;
    }
  }
  at.jacobian_y.diagonal().array() += 3.0;
  at.elimination = std::make_shared<const EliminationBlocks>(std::move(blocks));
  return at;
}

// Scales of two groups, several orders apart (displacements and forces), and r ≠ 1: the
// scaled entries then round differently from the Jacobian's.
Scaling TwoGroupScaling() {
  std::vector<int> groups(kSize, 0);
  for (int i = 2 * kBlocks; i < kSize; ++i) groups[static_cast<size_t>(i)] = 1;
  Scaling scaling(groups, 0.7, 1e-9);
  Eigen::VectorXd typical(kSize);
  typical.head(2 * kBlocks).setConstant(3e-4);
  typical.tail(kRest).setConstant(20.0);
  scaling.Include(typical);
  return scaling;
}

constexpr double kResidualScale = 1.7;

TEST_CASE("bordered view: its entries and column segments are AugmentedMatrix's, bit for bit") {
  const Linearization at = HarmonicLikeLinearization(3);
  const Scaling scaling = TwoGroupScaling();
  const Eigen::VectorXd row = Eigen::VectorXd::Random(kSize + 1);
  const Eigen::MatrixXd a = AugmentedMatrix(at, scaling, kResidualScale, row);
  const BorderedView view(at.jacobian_y, at.jacobian_lambda, scaling.scales(), kResidualScale, row);
  REQUIRE(view.rows() == kSize + 1);
  for (int j = 0; j <= kSize; ++j) {
    for (int i = 0; i <= kSize; ++i) REQUIRE(view(i, j) == a(i, j));
    // Segments above the border, ending on it, and the whole column.
    for (const auto& [start, length] : {std::pair{0, 7}, {kSize - 4, 5}, {0, kSize + 1}}) {
      Eigen::VectorXd segment(length);
      view.ReadColumn(j, start, length, segment);
      CHECK(segment == a.col(j).segment(start, length));
    }
  }
  Eigen::MatrixXd made;
  view.Materialize(&made);
  CHECK(made == a);
}

// The corrector's route (the elimination reading the Jacobians in place) against the
// materialised matrix's: the same operations on the same entries, so the same bits, for
// the solution, the determinant's sign and a further right-hand side.
TEST_CASE("augmented solver: the in-place solve is the materialised one, bit for bit") {
  const Scaling scaling = TwoGroupScaling();
  for (unsigned seed = 1; seed <= 6; ++seed) {
    CAPTURE(seed);
    Linearization at = HarmonicLikeLinearization(seed);
    const bool singular_block = seed % 3 == 0;
    // A singular block: the elimination gives way to the whole matrix's LU.
    if (singular_block) at.jacobian_y.block(4, 4, 2, 2).setZero();
    const Eigen::VectorXd row = Eigen::VectorXd::Random(kSize + 1);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(kSize + 1);
    const Eigen::VectorXd b2 = Eigen::VectorXd::Random(kSize + 1);
    for (const bool eliminate : {true, false}) {
      const EliminationBlocks* blocks = eliminate ? at.elimination.get() : nullptr;
      AugmentedSolver materialised;
      AugmentedMatrix(at, scaling, kResidualScale, row, &materialised.matrix());
      Eigen::VectorXd expected, expected2;
      REQUIRE(materialised.Solve(b, &expected, blocks));
      REQUIRE(materialised.SolveAgain(b2, &expected2));

      AugmentedSolver in_place;
      const BorderedView view(at.jacobian_y, at.jacobian_lambda, scaling.scales(), kResidualScale,
                              row);
      Eigen::VectorXd x, x2;
      REQUIRE(in_place.Solve(view, b, &x, blocks));
      REQUIRE(in_place.SolveAgain(b2, &x2));
      CAPTURE(eliminate);
      CHECK(x == expected);
      CHECK(x2 == expected2);
      CHECK(in_place.determinant_sign() == materialised.determinant_sign());
      CHECK(in_place.determinant_sign() != 0);
      CHECK(in_place.last_row() == row);
      // The matrix is made exactly where the elimination did not solve.
      if (singular_block || !eliminate) CHECK(in_place.matrix() == materialised.matrix());
      if (!singular_block && eliminate) CHECK(in_place.matrix().size() == 0);
      // And it solves the system (independent of both routes' shared operations).
      CHECK((materialised.matrix() * x - b).norm() <= 1e-10 * b.norm() * x.norm());
    }
  }
}

}  // namespace
}  // namespace nfrc
