#include "continuation/dense_lu.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

namespace nfrc {
namespace {

// Random matrices with a dominant diagonal (condition ~10): a backward-stable solve recovers
// a known solution to ~n·ε·κ ≈ 1e-12 at 400 unknowns; a wrong permutation or triangle is O(1).
constexpr double kSolved = 1e-11;

Eigen::MatrixXd WellConditioned(int n, unsigned seed) {
  std::srand(seed);
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  a.diagonal().array() += 2.0 * std::sqrt(static_cast<double>(n));
  return a;
}

TEST_CASE("dense LU: LAPACK from kLapackMinSize up, Eigen below, by default") {
  CHECK(DenseLu(WellConditioned(DenseLu::kLapackMinSize, 1)).lapack());
  CHECK_FALSE(DenseLu(WellConditioned(DenseLu::kLapackMinSize - 1, 1)).lapack());
}

TEST_CASE("dense LU: both back ends solve a system with a known solution") {
  for (const int n : {1, 7, 64, 250, 400}) {
    const Eigen::MatrixXd a = WellConditioned(n, 3u + static_cast<unsigned>(n));
    const Eigen::MatrixXd exact = Eigen::MatrixXd::Random(n, 3);
    const Eigen::MatrixXd b = a * exact;
    for (const bool lapack : {false, true}) {
      INFO(n << " unknowns, " << (lapack ? "LAPACK" : "Eigen"));
      DenseLu lu;
      lu.Compute(a, lapack);
      CHECK(lu.lapack() == lapack);
      CHECK((lu.Solve(b) - exact).norm() <= kSolved * exact.norm());
      const Eigen::VectorXd column = b.col(1);
      CHECK((lu.Solve(column) - exact.col(1)).norm() <= kSolved * exact.col(1).norm());
      Eigen::VectorXd x(n);
      lu.Solve(column, &x);
      CHECK((x - exact.col(1)).norm() <= kSolved * exact.col(1).norm());
      CHECK(PivotsAbove(lu, 1e-3));
    }
  }
}

// A = Q D Qᵀ with Q orthogonal has det A = prod D: the sign is known without a determinant.
TEST_CASE("dense LU: the determinant's sign, from the pivots and the row interchanges") {
  for (const int n : {5, 240}) {
    std::srand(11);
    const Eigen::MatrixXd q =
        Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(n, n)).householderQ();
    for (const int negatives : {0, 1, 2, 3}) {
      Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
      d.head(negatives) *= -1.0;
      const Eigen::MatrixXd a = q * d.asDiagonal() * q.transpose();
      for (const bool lapack : {false, true}) {
        INFO(n << " unknowns, " << negatives << " negative, " << (lapack ? "LAPACK" : "Eigen"));
        DenseLu lu;
        lu.Compute(a, lapack);
        CHECK(lu.DeterminantSign() == (negatives % 2 == 0 ? 1 : -1));
      }
    }
  }
}

// A = P D with P a permutation of known cycles and D positive: det A = sign(P) exactly. A
// cycle of length L is L − 1 interchanges; the LU's own interchanges need not be P's.
TEST_CASE("dense LU: the determinant's sign of permuted diagonal matrices") {
  const int n = 7;
  const std::vector<std::pair<std::vector<std::vector<int>>, int>> permutations = {
      {{}, 1},
      {{{0, 1, 2}}, 1},
      {{{0, 1, 2, 3}}, -1},
      {{{0, 1}, {2, 3}}, 1},
      {{{0, 1, 2, 3, 4, 5, 6}}, 1},
      {{{0, 3}, {1, 5, 2}}, -1},
      {{{6, 0}}, -1},
  };
  for (const auto& permutation : permutations) {
    // Named copies: INFO captures them, and clang 14 cannot capture structured bindings.
    const std::vector<std::vector<int>>& cycles = permutation.first;
    const int sign = permutation.second;
    std::vector<int> image(n);
    for (int i = 0; i < n; ++i) image[i] = i;
    for (const std::vector<int>& cycle : cycles) {
      for (size_t k = 0; k < cycle.size(); ++k) image[cycle[k]] = cycle[(k + 1) % cycle.size()];
    }
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) a(image[i], i) = 1.0 + 0.1 * i;
    for (const bool lapack : {false, true}) {
      INFO(cycles.size() << " cycles, " << (lapack ? "LAPACK" : "Eigen"));
      DenseLu lu;
      lu.Compute(a, lapack);
      CHECK(lu.DeterminantSign() == sign);
      a.col(0) *= -1.0;
      lu.Compute(a, lapack);
      CHECK(lu.DeterminantSign() == -sign);
      a.col(0) *= -1.0;
    }
  }
}

TEST_CASE("dense LU: a singular matrix factorises with a zero pivot") {
  for (const int n : {6, 220}) {
    Eigen::MatrixXd a = WellConditioned(n, 5);
    a.col(n / 2).setZero();
    for (const bool lapack : {false, true}) {
      INFO(n << " unknowns, " << (lapack ? "LAPACK" : "Eigen"));
      DenseLu lu;
      lu.Compute(a, lapack);
      CHECK_FALSE(PivotsAbove(lu, 1e-12));
      CHECK(lu.DeterminantSign() == 0);
    }
  }
}

}  // namespace
}  // namespace nfrc
