#include "continuation/reused_factorization.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <optional>

#include "continuation/bordered_view.h"

namespace nfrc {
namespace {

// Well-conditioned random systems of 100–320 unknowns: a dense LU's solution and the Woodbury
// update's (backward error ≤ 1e-10 by construction, condition ~1e2) agree to ~1e-9 or better.
constexpr double kSameSolution = 1e-8;

// m blocks of two unknowns {k, k + m} (a harmonic's coefficients), each coupled to the rest
// through one force column and through every rest row (the laws' equations), as in a friction
// problem's Jacobian; the rest are the last `rest` unknowns.
Eigen::MatrixXd BlockMatrix(int m, int rest, EliminationBlocks* blocks) {
  const int n = 2 * m + rest;
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  blocks->clear();
  for (int k = 0; k < m; ++k) blocks->push_back({k, k + m});
  for (int i = 0; i < 2 * m; ++i) {
    for (int j = 0; j < 2 * m; ++j) {
      if (i % m != j % m) a(i, j) = 0.0;
    }
    for (int j = 2 * m; j < n; ++j) {
      if ((j - 2 * m) % m != i % m) a(i, j) = 0.0;
    }
  }
  a.diagonal().array() += 6.0;
  return a;
}

double RelativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

// The rest rows changed by a rank-r term u vᵀ: what a law's rows do when r samples switch.
void ChangeRestRows(int m, int rank, Eigen::MatrixXd* a) {
  const Eigen::Index n = a->rows(), rest = n - 2 * m;
  const Eigen::MatrixXd u = Eigen::MatrixXd::Random(rest, rank);
  const Eigen::MatrixXd v = Eigen::MatrixXd::Random(n, rank);
  a->bottomRows(rest) += 0.3 * u * v.transpose();
}

// A seeded BlockMatrix and right-hand side, with a solver that has factorised it once.
struct Factorised {
  Factorised(unsigned seed, int m, int rest) {
    std::srand(seed);
    a = BlockMatrix(m, rest, &blocks);
    b = Eigen::VectorXd::Random(a.rows());
    solver.emplace(blocks);
    REQUIRE(solver->Solve(a, b, &x));
  }
  EliminationBlocks blocks;
  Eigen::MatrixXd a;
  Eigen::VectorXd b, x;
  std::optional<ReusedFactorization> solver;
};

// Schur complements of 80 and 240 unknowns: Eigen's LU and LAPACK's (DenseLu::kLapackMinSize).
TEST_CASE("reused factorisation: low-rank changes of the laws' rows are updates of exact rank") {
  constexpr int kBlocks = 40;
  for (const int rest : {80, 240}) {
    CAPTURE(rest);
    Factorised f(11, kBlocks, rest);
    const Eigen::MatrixXd& a = f.a;
    const Eigen::VectorXd& b = f.b;
    Eigen::VectorXd& x = f.x;
    ReusedFactorization& solver = *f.solver;
    CHECK(RelativeError(x, a.partialPivLu().solve(b)) < kSameSolution);
    CHECK(solver.counts().factorisations == 1);
    int expected_updates = 0;
    for (int rank : {1, 3, 5}) {
      CAPTURE(rank);
      Eigen::MatrixXd changed = a;
      ChangeRestRows(kBlocks, rank, &changed);
      REQUIRE(solver.Solve(changed, b, &x));
      CHECK(RelativeError(x, changed.partialPivLu().solve(b)) < kSameSolution);
      ++expected_updates;
      CHECK(solver.counts().factorisations == 1);
      CHECK(solver.counts().updates == expected_updates);
      // The range finder finds the rank of the change, not more.
      CHECK(solver.counts().largest_rank == rank);
    }
    // The same matrix again: a zero change, solved by the kept LU alone.
    REQUIRE(solver.Solve(a, b, &x));
    CHECK(RelativeError(x, a.partialPivLu().solve(b)) < kSameSolution);
    CHECK(solver.counts().factorisations == 1);
  }
}

// The fixed-λ corrector's use: the scaled bordered matrix of a Jacobian with R_λ's column
// zero and the border row e_n, read in place, against its materialised copy. The view's
// entries are the copy's, rounded alike, so both solvers do the same arithmetic: their
// solutions agree bit for bit, through a first factorisation and a low-rank update.
TEST_CASE("reused factorisation: the bordered matrix read in place solves as its copy") {
  constexpr int kBlocks = 40, kRest = 81;
  std::srand(17);
  EliminationBlocks blocks;
  const Eigen::MatrixXd a = BlockMatrix(kBlocks, kRest, &blocks);
  const Eigen::Index n = a.rows() - 1;  // the last unknown is the border's λ
  Eigen::MatrixXd jacobian = a.topLeftCorner(n, n);
  const Eigen::VectorXd zero_lambda = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd scales = (Eigen::VectorXd::Random(n + 1).array() + 1.5).matrix();
  const Eigen::VectorXd border = Eigen::VectorXd::Unit(n + 1, n);
  constexpr double kResidualScale = 2.5;
  const Eigen::VectorXd b = Eigen::VectorXd::Random(n + 1);
  ReusedFactorization in_place(blocks), copied(blocks);
  for (int round = 0; round < 2; ++round) {
    CAPTURE(round);
    if (round == 1) {  // the laws' rows change by rank 2: an update in both
      jacobian.bottomRows(kRest - 1) +=
          0.3 * Eigen::MatrixXd::Random(kRest - 1, 2) * Eigen::MatrixXd::Random(2, n);
    }
    const BorderedView view(jacobian, zero_lambda, scales, kResidualScale, border);
    Eigen::MatrixXd copy;
    view.Materialize(&copy);
    Eigen::VectorXd x_view, x_copy;
    REQUIRE(in_place.Solve(view, b, &x_view));
    REQUIRE(copied.Solve(copy, b, &x_copy));
    CHECK(x_view == x_copy);
    CHECK(RelativeError(x_view, copy.partialPivLu().solve(b)) < kSameSolution);
    CHECK(in_place.counts().factorisations == 1);
    CHECK(in_place.counts().updates == round);
  }
}

TEST_CASE("reused factorisation: a change of high rank or of the blocks' rows factorises again") {
  constexpr int kBlocks = 30, kRest = 96;  // rank limit 96/12 = 8
  Factorised f(12, kBlocks, kRest);
  const Eigen::MatrixXd& a = f.a;
  const Eigen::VectorXd& b = f.b;
  Eigen::VectorXd& x = f.x;
  ReusedFactorization& solver = *f.solver;

  Eigen::MatrixXd high = a;
  ChangeRestRows(kBlocks, 20, &high);
  REQUIRE(solver.Solve(high, b, &x));
  CHECK(RelativeError(x, high.partialPivLu().solve(b)) < kSameSolution);
  CHECK(solver.counts().factorisations == 2);
  CHECK(solver.counts().updates == 0);

  // A block's own entry (ω moved, in a continuation step): new blocks, new LU.
  Eigen::MatrixXd moved = high;
  moved(0, 0) += 0.5;
  REQUIRE(solver.Solve(moved, b, &x));
  CHECK(RelativeError(x, moved.partialPivLu().solve(b)) < kSameSolution);
  CHECK(solver.counts().factorisations == 3);
  // A block's coupling to the rest, in a column that was zero.
  Eigen::MatrixXd coupled = moved;
  coupled(1, 2 * kBlocks + 5) = 0.7;
  REQUIRE(solver.Solve(coupled, b, &x));
  CHECK(RelativeError(x, coupled.partialPivLu().solve(b)) < kSameSolution);
  CHECK(solver.counts().factorisations == 4);
  CHECK(solver.counts().updates == 0);
}

TEST_CASE("reused factorisation: an update onto a nearly singular system is not trusted") {
  Factorised f(13, 10, 60);
  const Eigen::MatrixXd& a = f.a;
  const Eigen::VectorXd& b = f.b;
  ReusedFactorization& solver = *f.solver;
  // A rank-one change of the last rest row that makes it (nearly) a copy of another: the
  // capacitance matrix is then near singular and the update's residual is checked.
  Eigen::MatrixXd singular = a;
  const Eigen::Index last = a.rows() - 1;
  singular.row(last) = singular.row(last - 1) * (1.0 + 1e-13);
  Eigen::VectorXd y;
  const bool solved = solver.Solve(singular, b, &y);
  if (solved) {
    // Whatever path solved it, the answer satisfies the system to its conditioning.
    CHECK((singular * y - b).norm() <= 1e-6 * b.norm() * singular.norm() * y.norm());
  }
}

TEST_CASE("reused factorisation: an overflowing change ends the range finder (no endless loop)") {
  // A law parameter of 1e300 makes ΔS overflow: the range finder saw a non-finite norm, added
  // no direction and looped for ever. It must give the update up; the caller then factorises
  // (and the overflowed system is refused as not regular, or solved, never hung on).
  Factorised f(13, 20, 60);
  Eigen::MatrixXd huge = f.a;
  huge.bottomRows(60).array() *= 1e300;
  huge.bottomRows(60).array() *= 1e300;  // inf where the entries were non-zero
  Eigen::VectorXd x;
  CHECK_FALSE(f.solver->Solve(huge, f.b, &x));
  // A finite change afterwards is solved again.
  Eigen::MatrixXd changed = f.a;
  ChangeRestRows(20, 2, &changed);
  REQUIRE(f.solver->Solve(changed, f.b, &x));
  CHECK(RelativeError(x, changed.partialPivLu().solve(f.b)) < kSameSolution);
}

}  // namespace
}  // namespace nfrc
