// HillLinearSolver against Eigen's sparse LU of the same matrix: the eliminating path on a
// friction pencil (blocks per harmonic, Schur complement on the friction force), a contact
// pencil (the contact DOF's rows join the Schur complement, or, without the harmonics given,
// the sparse LU), and the fallback on a singular block.
#include "analysis/hill_solver.h"

#include <doctest/doctest.h>

#include <cstdlib>

#include "analysis/case.h"
#include "analysis/hill.h"
#include "support/chain_case.h"
#include "support/hill_pencil.h"

namespace nfrc {
namespace {

// Both are backward-stable solves: they differ by ~1e-16 here (printed); 1e-11 relative
// still holds for a condition number up to ~1e5 and catches any wrong block or coupling.
constexpr double kSameSolution = 1e-11;

Eigen::SparseMatrix<double> HillAt(const HillPencil& pencil, double sigma) {
  Eigen::SparseMatrix<double> hill = pencil.d0 + sigma * pencil.d1 + sigma * sigma * pencil.d2;
  hill.makeCompressed();
  return hill;
}

double Difference(const Eigen::SparseMatrix<double>& matrix, const HillLinearSolver& solver) {
  std::srand(3);
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(matrix.rows());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(matrix);
  REQUIRE(lu.info() == Eigen::Success);
  const Eigen::VectorXd reference = lu.solve(rhs);
  Eigen::VectorXd x;
  solver.Solve(rhs, &x);
  const double difference = (x - reference).norm() / reference.norm();
  MESSAGE("relative difference from the sparse LU: " << difference);
  return difference;
}

// The 4-DOF chain with friction at its last DOF, forced at its first, at ω = 0.9 with a
// perturbed linear guess (some samples sticking, some slipping).
HillPencil FrictionChainPencil(const HarmonicSet& harmonics) {
  Case c = testing::ChainCase(4);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = harmonics;
  c.laws.push_back(testing::Friction(3, 0.3, 0.05));
  return testing::PencilOf(c, 0.9, 0.01, 7);
}

TEST_CASE("hill solver: friction's blocks per harmonic and the Schur complement on its force") {
  const HillPencil pencil = FrictionChainPencil(HarmonicSet(5, false, 64));
  REQUIRE(pencil.own_offset > 0);
  REQUIRE(pencil.own_offset < pencil.d0.rows());
  const double sigma = 0.009;
  const Eigen::SparseMatrix<double> hill = HillAt(pencil, sigma);
  const HillLinearSolver solver(hill, pencil.own_offset);
  REQUIRE(solver.ok());
  CHECK(solver.eliminating());
  CHECK(solver.num_row_groups() == 1);  // every harmonic reaches all the force's rows
  CHECK(Difference(hill, solver) <= kSameSolution);
}

// 100 harmonics: the Schur complement on the force has 201 unknowns, factorised by LAPACK
// (DenseLu::kLapackMinSize) instead of Eigen.
TEST_CASE("hill solver: friction at 100 harmonics, a Schur complement for LAPACK") {
  const HillPencil pencil = FrictionChainPencil(HarmonicSet(100, false, 256));
  const Eigen::SparseMatrix<double> hill = HillAt(pencil, 0.009);
  const HillLinearSolver solver(hill, pencil.own_offset);
  REQUIRE(solver.ok());
  REQUIRE(solver.eliminating());
  CHECK(solver.schur_size() >= DenseLu::kLapackMinSize);
  CHECK(Difference(hill, solver) <= kSameSolution);
}

TEST_CASE("hill solver: a law coupling harmonics in the displacement rows joins the Schur set") {
  const Case c = testing::ChainAgainstRigidObstacle(HarmonicSet(30, false, 128));
  const HillPencil pencil = testing::PencilOf(c, 0.9, 0.05, 11);
  const Eigen::SparseMatrix<double> hill = HillAt(pencil, 0.009);
  REQUIRE(DisplacementEnd(pencil) == hill.rows());  // DLFT has no own unknowns
  // Without the harmonics, the displacement part is one block of 4·61 > kMaxBlock.
  const HillLinearSolver whole(hill, DisplacementEnd(pencil));
  REQUIRE(whole.ok());
  CHECK_FALSE(whole.eliminating());
  CHECK(Difference(hill, whole) <= kSameSolution);
  // With them, the contact DOF's 61 coefficients (its rows reach every harmonic through the
  // law) form the Schur complement and the three free DOFs split per harmonic.
  const HillLinearSolver split(hill, DisplacementEnd(pencil), DisplacementHarmonics(pencil));
  REQUIRE(split.ok());
  CHECK(split.eliminating());
  CHECK(split.schur_size() == c.harmonics.NumCoefficients());
  CHECK(Difference(hill, split) <= kSameSolution);
}

TEST_CASE("hill solver: a spring at every DOF of a long chain keeps the sparse LU") {
  // 30 DOFs with a cubic spring each, 21 coefficients: 630 coupled rows > kMaxCoupledRows.
  Case c = testing::ChainCase(30);
  c.model.forcing = {ForcingTerm{29, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(10, false, 64);
  for (int dof = 0; dof < 30; ++dof) {
    CubicSpringSpec spring;
    spring.dof = dof;
    spring.coefficient = 0.5;
    c.laws.push_back(spring);
  }
  const HillPencil pencil = testing::PencilOf(c, 0.9, 0.3, 13);
  const Eigen::SparseMatrix<double> hill = HillAt(pencil, 0.009);
  const HillLinearSolver solver(hill, DisplacementEnd(pencil), DisplacementHarmonics(pencil));
  REQUIRE(solver.ok());
  CHECK_FALSE(solver.eliminating());
  CHECK(Difference(hill, solver) <= kSameSolution);
  // Ten springs (210 coupled rows): their coefficients form the Schur complement.
  c.laws.resize(10);
  const HillPencil fewer = testing::PencilOf(c, 0.9, 0.3, 13);
  const Eigen::SparseMatrix<double> fewer_hill = HillAt(fewer, 0.009);
  const HillLinearSolver split(fewer_hill, DisplacementEnd(fewer), DisplacementHarmonics(fewer));
  REQUIRE(split.ok());
  CHECK(split.eliminating());
  CHECK(split.schur_size() == 10 * c.harmonics.NumCoefficients());
  CHECK(Difference(fewer_hill, split) <= kSameSolution);
}

TEST_CASE("hill solver: blocks reaching different own rows, with pivoting inside a block") {
  // Blocks {0, 1, 2} (a zero first pivot: rows swap), {3, 4}, {5} and {6}; own unknowns 7–9.
  // The first two reach own rows 7 and 8 (one group, side by side), {5} reaches row 9 (a
  // second group), {6} reaches none; every block has own columns.
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(10, 10);
  dense.topLeftCorner(3, 3) << 0, 2, 1,  //
      3, 1, 0,                           //
      1, 0, 4;
  dense.block(3, 3, 2, 2) << 2, 1,  //
      1, 3;
  dense(5, 5) = 1.5;
  dense(6, 6) = -2.0;
  dense.bottomRightCorner(3, 3) = Eigen::Vector3d(5.0, 6.0, 7.0).asDiagonal();
  dense(7, 0) = 1.0;
  dense(8, 2) = -1.0;
  dense(7, 4) = 0.5;
  dense(8, 3) = 2.0;
  dense(9, 5) = 1.0;
  for (int i = 0; i < 7; ++i) dense(i, 7 + i % 3) = 0.25 * (i + 1);
  const Eigen::SparseMatrix<double> matrix = dense.sparseView();
  const HillLinearSolver solver(matrix, 7);
  REQUIRE(solver.ok());
  REQUIRE(solver.eliminating());
  CHECK(solver.num_row_groups() == 2);
  CHECK(Difference(matrix, solver) <= kSameSolution);
}

// Groups that alternate along the blocks (the row places are kept while consecutive blocks
// share a group and set again when it changes), a block whose own rows appear out of order,
// and a matrix given uncompressed (its couplings are counted from the column lengths).
TEST_CASE("hill solver: alternating row groups, own rows out of order, an uncompressed matrix") {
  // Blocks {0, 1}, {2} and {3}; own unknowns 4–6. {0, 1} reaches row 6 from column 0 and row 4
  // from column 1; {2} reaches row 5; {3} reaches rows 4 and 6 again, the first group.
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(7, 7);
  dense.topLeftCorner(2, 2) << 2, 1,  //
      1, 3;
  dense(2, 2) = 1.5;
  dense(3, 3) = -2.0;
  dense.bottomRightCorner(3, 3) = Eigen::Vector3d(5.0, 6.0, 7.0).asDiagonal();
  dense(6, 0) = 1.0;
  dense(4, 1) = 0.5;
  dense(5, 2) = 1.0;
  dense(4, 3) = 2.0;
  dense(6, 3) = -1.0;
  for (int i = 0; i < 4; ++i) dense(i, 4 + i % 3) = 0.25 * (i + 1);
  const Eigen::SparseMatrix<double> matrix = dense.sparseView();
  const HillLinearSolver solver(matrix, 4);
  REQUIRE(solver.ok());
  REQUIRE(solver.eliminating());
  CHECK(solver.num_row_groups() == 2);
  CHECK(Difference(matrix, solver) <= kSameSolution);
  Eigen::SparseMatrix<double> loose = matrix;
  loose.reserve(Eigen::VectorXi::Constant(7, 2));  // room in every column: uncompressed
  REQUIRE_FALSE(loose.isCompressed());
  const HillLinearSolver from_loose(loose, 4);
  REQUIRE(from_loose.eliminating());
  CHECK(from_loose.num_row_groups() == 2);
  CHECK(Difference(matrix, from_loose) <= kSameSolution);
}

TEST_CASE("hill solver: a singular block falls back to the sparse LU") {
  // Blocks {0, 1} and {2}, own unknown 3; block {0, 1} is singular, the whole is not.
  Eigen::MatrixXd dense(4, 4);
  dense << 1, 2, 0, 1,  //
      2, 4, 0, 1,       //
      0, 0, 3, 1,       //
      1, 0, 1, 0;
  const Eigen::SparseMatrix<double> matrix = dense.sparseView();
  const HillLinearSolver solver(matrix, 3);
  REQUIRE(solver.ok());
  CHECK_FALSE(solver.eliminating());
  CHECK(Difference(matrix, solver) <= kSameSolution);
  // The same structure with a regular block is eliminated, to the same solution, also with
  // zeros stored between the blocks (they must not join them or land in a block).
  dense(1, 1) = 5.0;
  std::vector<Eigen::Triplet<double>> triplets = {{0, 2, 0.0}, {2, 1, 0.0}};
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      if (dense(i, j) != 0.0) triplets.emplace_back(i, j, dense(i, j));
    }
  }
  Eigen::SparseMatrix<double> regular(4, 4);
  regular.setFromTriplets(triplets.begin(), triplets.end());
  REQUIRE(regular.nonZeros() == 12);  // ten entries and the two stored zeros
  const HillLinearSolver eliminating(regular, 3);
  CHECK(eliminating.eliminating());
  CHECK(Difference(regular, eliminating) <= kSameSolution);
}

}  // namespace
}  // namespace nfrc
