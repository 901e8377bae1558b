#include "continuation/block_elimination.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace nfrc {
namespace {

// Well-conditioned random systems of a few dozen unknowns solved two ways agree to ~1e-14;
// a wrong sign or a missed coupling is O(1).
constexpr double kSameSolution = 1e-11;

// A matrix whose unknowns 0..2m−1 form m blocks of two (interleaved, as harmonics are), each
// coupled to the rest only through `coupled` columns of the rest (a force) and through every
// row of the rest (the law's equations depend on all of them), plus a dense border row.
Eigen::MatrixXd BlockMatrix(int m, int rest, unsigned seed, EliminationBlocks* blocks) {
  std::srand(seed);
  const int n = 2 * m + rest + 1;
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  blocks->clear();
  for (int k = 0; k < m; ++k) blocks->push_back({k, k + m});
  for (int i = 0; i < 2 * m; ++i) {
    for (int j = 0; j < 2 * m; ++j) {
      if (i % m != j % m) a(i, j) = 0.0;  // blocks {k, k + m} are uncoupled
    }
    for (int j = 2 * m; j < n - 1; ++j) {
      if ((j - 2 * m) % m != i % m) a(i, j) = 0.0;  // a force column per block
    }
  }
  a.diagonal().array() += 4.0;
  return a;
}

TEST_CASE("block elimination: equals the dense solve of a block-structured system") {
  // 240 other unknowns: the Schur complement goes to LAPACK (DenseLu::kLapackMinSize).
  for (const std::pair<int, int>& sizes : {std::pair{5, 10}, {30, 30}, {1, 3}, {20, 240}}) {
    const int m = sizes.first, rest = sizes.second;  // INFO captures: no structured bindings
    INFO(m << " blocks, " << rest << " other unknowns");
    EliminationBlocks blocks;
    const Eigen::MatrixXd a = BlockMatrix(m, rest, 7u + m, &blocks);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(a.rows());
    Eigen::VectorXd x;
    REQUIRE(SolveEliminating(a, b, blocks, &x));
    const Eigen::VectorXd reference = a.fullPivLu().solve(b);
    CHECK((x - reference).norm() <= kSameSolution * reference.norm());
  }
}

// The sign of det a through the blocks and the Schur complement (the orientation index of a
// bordered matrix) against the determinant of a full-pivoting LU, a different factorisation;
// the matrices are chosen with both signs.
TEST_CASE("block elimination: the determinant's sign is the whole matrix's") {
  int negative = 0, positive = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    for (const std::pair<int, int>& sizes : {std::pair{5, 10}, {12, 7}, {1, 3}, {6, 220}}) {
      const int m = sizes.first, rest = sizes.second;
      INFO("seed " << seed << ", " << m << " blocks, " << rest << " other unknowns");
      EliminationBlocks blocks;
      Eigen::MatrixXd a = BlockMatrix(m, rest, seed, &blocks);
      if (seed % 2 == 0) a.row(a.rows() - 1) *= -1.0;  // flips the sign of det a
      const double determinant = a.fullPivLu().determinant();
      REQUIRE(std::abs(determinant) > 0.0);
      Eigen::VectorXd x;
      int sign = 0;
      REQUIRE(SolveEliminating(a, Eigen::VectorXd::Ones(a.rows()), blocks, &x, &sign));
      CHECK(sign == (determinant > 0.0 ? 1 : -1));
      CHECK(DeterminantSign(a.partialPivLu()) == sign);
      (sign > 0 ? positive : negative) += 1;
    }
  }
  CHECK(positive > 0);
  CHECK(negative > 0);
}

TEST_CASE("block elimination: coupled blocks are a broken promise, singular ones decline") {
  EliminationBlocks blocks;
  Eigen::MatrixXd a = BlockMatrix(4, 6, 3u, &blocks);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  Eigen::VectorXd x;
  Eigen::MatrixXd coupled = a;
  coupled(0, 1) = 0.5;  // unknowns 0 and 1 are in blocks 0 and 1
  CHECK_THROWS_AS(SolveEliminating(coupled, b, blocks, &x), std::logic_error);
  Eigen::MatrixXd singular = a;
  singular.row(2).setZero();  // block {2, 6}'s first row: the block is singular
  singular.row(2)(6) = 0.0;
  CHECK_FALSE(SolveEliminating(singular, b, blocks, &x));
}

// The elimination's whole solve: blocks, Schur complement, back substitution.
Eigen::VectorXd SolveWith(const BlockElimination& elimination, const Eigen::MatrixXd& a,
                          const Eigen::VectorXd& b) {
  Eigen::MatrixXd schur;
  Eigen::VectorXd schur_rhs, x;
  const Eigen::VectorXd block_solutions = elimination.BlockSolutions(b);
  elimination.Reduce(a, b, block_solutions, &schur, &schur_rhs);
  elimination.BackSubstitute(block_solutions, schur.fullPivLu().solve(schur_rhs), &x);
  return x;
}

// Refactor reuses one object's storage across matrices (the Newton iterations of one
// correction): each result must be a fresh Factor's, bit for bit, whether the next matrix
// has the last one's structure, another one, or follows a singular block.
TEST_CASE("block elimination: refactored in place, bit for bit a fresh factorisation") {
  BlockElimination reused;
  for (const std::tuple<int, int, unsigned>& sizes :
       {std::tuple{5, 10, 1u}, {5, 10, 2u}, {8, 12, 3u}, {8, 12, 0u}, {2, 30, 4u}, {5, 10, 1u}}) {
    const int m = std::get<0>(sizes), rest = std::get<1>(sizes);
    const unsigned seed = std::get<2>(sizes);
    INFO(m << " blocks, " << rest << " other unknowns, seed " << seed);
    EliminationBlocks blocks;
    Eigen::MatrixXd a = BlockMatrix(m, rest, seed == 0 ? 9u : seed, &blocks);
    if (seed == 0) a.row(0).setZero();  // block {0, m} singular: both decline
    const Eigen::VectorXd b = Eigen::VectorXd::Random(a.rows());
    const std::optional<BlockElimination> fresh = BlockElimination::Factor(a, blocks);
    const bool refactored = reused.Refactor(a, blocks);
    REQUIRE(refactored == fresh.has_value());
    if (!refactored) continue;
    CHECK(reused.rest() == fresh->rest());
    CHECK(reused.determinant_sign() == fresh->determinant_sign());
    const Eigen::VectorXd x = SolveWith(reused, a, b);
    CHECK(x == SolveWith(*fresh, a, b));
    CHECK((a * x - b).norm() <= kSameSolution * b.norm());
  }
}

// The same systems with their unknowns reordered (rows and columns alike): the blocks' rows
// and the rest then form no runs, or the rest comes first, and the elimination reads them
// through its index lists instead of as runs.
TEST_CASE("block elimination: any order of the unknowns") {
  for (const bool shuffled : {true, false}) {
    INFO((shuffled ? "shuffled" : "the rest first"));
    EliminationBlocks blocks;
    const Eigen::MatrixXd a = BlockMatrix(20, 30, 11u, &blocks);
    const int n = static_cast<int>(a.rows());
    // new_of[i]: where unknown i goes.
    std::vector<int> new_of(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      new_of[static_cast<size_t>(i)] = shuffled ? (37 * i + 5) % n : (i + n - 40) % n;
    }
    Eigen::MatrixXd permuted(n, n);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        permuted(new_of[static_cast<size_t>(i)], new_of[static_cast<size_t>(j)]) = a(i, j);
      }
    }
    EliminationBlocks permuted_blocks = blocks;
    for (std::vector<int>& block : permuted_blocks) {
      for (int& i : block) i = new_of[static_cast<size_t>(i)];
    }
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    Eigen::VectorXd permuted_b(n);
    for (int i = 0; i < n; ++i) permuted_b(new_of[static_cast<size_t>(i)]) = b(i);
    Eigen::VectorXd x;
    REQUIRE(SolveEliminating(permuted, permuted_b, permuted_blocks, &x));
    const Eigen::VectorXd reference = a.fullPivLu().solve(b);
    Eigen::VectorXd back(n);
    for (int i = 0; i < n; ++i) back(i) = x(new_of[static_cast<size_t>(i)]);
    CHECK((back - reference).norm() <= kSameSolution * reference.norm());
    Eigen::MatrixXd coupled = permuted;
    coupled(new_of[37], new_of[0]) = 0.5;  // unknowns 37 and 0 are in blocks 17 and 0
    CHECK_THROWS_AS(SolveEliminating(coupled, permuted_b, permuted_blocks, &x), std::logic_error);
  }
}

// A coupling between blocks deep in a block's column (past the first chunks the scan tests at
// once), and one that is NaN, are both found.
TEST_CASE("block elimination: couplings anywhere in a long run of blocks' rows") {
  EliminationBlocks blocks;
  const Eigen::MatrixXd a = BlockMatrix(20, 30, 5u, &blocks);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  Eigen::VectorXd x;
  for (const double value : {1e-300, std::nan("")}) {
    Eigen::MatrixXd coupled = a;
    coupled(37, 3) = value;  // unknowns 37 and 3 are in blocks 17 and 3
    CHECK_THROWS_AS(SolveEliminating(coupled, b, blocks, &x), std::logic_error);
  }
}

TEST_CASE("block elimination: bad blocks are rejected") {
  CHECK_THROWS_AS(ValidateEliminationBlocks({{0, 1}, {1, 2}}, 4), std::invalid_argument);
  CHECK_THROWS_AS(ValidateEliminationBlocks({{0, 5}}, 4), std::invalid_argument);
  CHECK_NOTHROW(ValidateEliminationBlocks({{0, 2}, {1}}, 4));
}

}  // namespace
}  // namespace nfrc
