// nfrc's Lemke (core/lemke.h) against the LCP solvers of Siconos numerics on a collection of
// random and degenerate problems; the LCP-HBM rod's W, q: tests/analysis/lcp_siconos_rod_test.cc.
// Built only with Siconos (NFRC_HAVE_SICONOS).
#ifdef NFRC_HAVE_SICONOS

#include "core/lcp_siconos.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "core/lemke.h"

namespace nfrc {
namespace {

// Both solvers' z (or w) against each other, relative to max(1, ‖·‖∞): nfrc's point is one
// LU solve of the final basis (~1e-15 here), Siconos's the end of its updated tableau, whose
// error grows with the pivots and the condition of the bases (≲ 1e4 on these O(1) matrices).
constexpr double kAgreementTol = 1e-8;
// A solution's residuals relative to the data: w ≥ 0 and w − Mz − q to this times max(1, ‖q‖∞)
// (a genuine solution of these O(1) problems has ‖z‖∞ ≲ 1e3, so rounding stays ~1e-13),
// z ≥ 0 to this times max(1, ‖z‖∞), w_i z_i to the product of both. Scaling w's test by ‖z‖
// would pass the ~1e16-sized garbage Siconos returns with info 0 on some infeasible problems.
constexpr double kResidualTol = 1e-8;

Eigen::MatrixXd Random(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd a(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) a(i, j) = uniform(rng);
  }
  return a;
}

double Relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

// Whether z solves LCP(q, M), with w recomputed from it.
bool Solves(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const Eigen::VectorXd& z) {
  const Eigen::VectorXd w = m * z + q;
  const double w_scale = std::max(1.0, q.lpNorm<Eigen::Infinity>());
  const double z_scale = std::max(1.0, z.lpNorm<Eigen::Infinity>());
  return z.minCoeff() >= -kResidualTol * z_scale && w.minCoeff() >= -kResidualTol * w_scale &&
         w.cwiseProduct(z).lpNorm<Eigen::Infinity>() <= kResidualTol * w_scale * z_scale;
}

struct Tally {
  int problems = 0;
  int nfrc_solved = 0;
  int siconos_solved = 0;   // lcp_lexicolemke returned info 0 and its z checks out
  int siconos_claimed = 0;  // info 0, whether or not z checks out
  std::vector<std::string> siconos_failures;
};

// Solves with both; `unique` = the solution z is unique (P-matrix), `same_w` = w is common to
// all solutions (symmetric positive semidefinite M). Returns whether nfrc solved it.
bool Compare(const std::string& name, const Eigen::MatrixXd& m, const Eigen::VectorXd& q,
             bool unique, bool same_w, Tally* tally) {
  CAPTURE(name);
  ++tally->problems;
  const LemkeResult ours = SolveLcp(m, q);
  const SiconosLcpResult theirs = SolveLcpSiconos(m, q, SiconosLcpSolver::kLexicoLemke);
  const bool ours_ok = ours.ok() && Solves(m, q, ours.z);
  const bool theirs_ok = theirs.ok && Solves(m, q, theirs.z);
  tally->nfrc_solved += ours_ok;
  tally->siconos_solved += theirs_ok;
  tally->siconos_claimed += theirs.ok;
  if (!theirs_ok) tally->siconos_failures.push_back(name + " (" + theirs.message + ")");
  if (ours.ok()) CHECK_MESSAGE(ours_ok, ours.message);
  if (ours_ok && theirs_ok) {
    if (unique) CHECK(Relative(theirs.z, ours.z) <= kAgreementTol);
    if (same_w) CHECK(Relative(m * theirs.z + q, ours.w) <= kAgreementTol);
  }
  // Lemke terminates at a ray only if no solution exists for these classes: Siconos cannot
  // have found one.
  if (ours.status == LemkeStatus::kRayTermination) CHECK_FALSE(theirs_ok);
  return ours_ok;
}

void Report(const std::string& family, const Tally& t) {
  MESSAGE(family << ": " << t.problems << " problems, nfrc Lemke solved " << t.nfrc_solved
                 << ", Siconos lexicolemke solved " << t.siconos_solved << " (claimed "
                 << t.siconos_claimed << ")");
  for (const std::string& f : t.siconos_failures) MESSAGE("  Siconos failed: " << f);
}

TEST_CASE("Siconos: nfrc's Lemke and lcp_lexicolemke agree on random P-matrices") {
  Tally tally;
  for (int n : {5, 20, 60}) {
    for (unsigned seed = 0; seed < 8; ++seed) {
      std::mt19937 rng(seed + 100 * n);
      const Eigen::MatrixXd a = Random(n, n, rng);
      const Eigen::MatrixXd c = Random(n, n, rng);
      // Positive definite plus skew: a P-matrix, so exactly one solution for every q.
      const Eigen::MatrixXd m =
          a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n) + c - c.transpose();
      const Eigen::VectorXd q = Random(n, 1, rng);
      CHECK(Compare("P n=" + std::to_string(n) + " seed " + std::to_string(seed), m, q, true, false,
                    &tally));
    }
  }
  Report("P-matrices", tally);
  // A P-matrix LCP always has a solution and Lemke finds it: failures are Siconos's alone.
  CHECK(tally.nfrc_solved == tally.problems);
}

TEST_CASE("Siconos: lcp_pivot (Lemke rule) and lcp_enum agree with nfrc on small P-matrices") {
  // lcp_enum tries up to 2^n bases: n ≤ 8 keeps it under a millisecond.
  for (int n : {3, 6, 8}) {
    for (unsigned seed = 0; seed < 4; ++seed) {
      CAPTURE(n);
      CAPTURE(seed);
      std::mt19937 rng(seed + 17 * n);
      const Eigen::MatrixXd a = Random(n, n, rng);
      const Eigen::MatrixXd m = a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
      const Eigen::VectorXd q = Random(n, 1, rng);
      const LemkeResult ours = SolveLcp(m, q);
      REQUIRE(ours.ok());
      for (SiconosLcpSolver solver : {SiconosLcpSolver::kPivotLemke, SiconosLcpSolver::kEnum}) {
        CAPTURE(ToString(solver));
        const SiconosLcpResult theirs = SolveLcpSiconos(m, q, solver);
        CHECK_MESSAGE(theirs.ok, theirs.message);
        CHECK(Relative(theirs.z, ours.z) <= kAgreementTol);
      }
    }
  }
}

TEST_CASE("Siconos: both solve the feasible positive semidefinite problems, singular included") {
  Tally tally;
  int feasible = 0;
  for (int n : {6, 30}) {
    for (int rank : {n, n / 3, 1}) {
      for (unsigned seed = 0; seed < 6; ++seed) {
        std::mt19937 rng(seed + 1000 * rank + 10 * n);
        const Eigen::MatrixXd a = Random(n, rank, rng);
        const Eigen::MatrixXd m = a * a.transpose();
        // Half the problems made feasible by construction: q = w − M z with z, w ≥ 0
        // complementary; the others random (often infeasible when M is singular).
        Eigen::VectorXd q = Random(n, 1, rng);
        if (seed % 2 == 0) {
          const Eigen::VectorXd u = Random(n, 1, rng).cwiseAbs();
          Eigen::VectorXd z = Eigen::VectorXd::Zero(n), w = Eigen::VectorXd::Zero(n);
          for (int i = 0; i < n; ++i) (i % 3 == 0 ? z : w)(i) = u(i);
          q = w - m * z;
        }
        const std::string name = "PSD n=" + std::to_string(n) + " rank " + std::to_string(rank) +
                                 " seed " + std::to_string(seed);
        const bool solved = Compare(name, m, q, rank == n, true, &tally);
        if (seed % 2 == 0) CHECK_MESSAGE(solved, name);
        feasible += solved;
      }
    }
  }
  Report("positive semidefinite", tally);
  CHECK(feasible >= tally.problems / 2);
}

TEST_CASE("Siconos: both handle degenerate q (ties in every ratio test)") {
  Tally tally;
  for (int n : {4, 12, 40}) {
    std::mt19937 rng(7 * n);
    const Eigen::MatrixXd a = Random(n, n, rng);
    const Eigen::MatrixXd m = a * a.transpose() + Eigen::MatrixXd::Identity(n, n);
    // Every entry equal: z0's entering ties all rows. Zeros: w_i = 0 basic at the start.
    const Eigen::VectorXd equal = -Eigen::VectorXd::Ones(n);
    Eigen::VectorXd zeros = -Eigen::VectorXd::Ones(n);
    for (int i = 0; i < n; i += 2) zeros(i) = 0.0;
    // Twin contacts: rows and columns 2k + 1 repeat 2k, and q too. M stays symmetric positive
    // semidefinite (singular), so a solution exists with a common w, but z is not unique (a
    // force can be split between the twins) and the ratios tie in pairs all along the path.
    Eigen::MatrixXd twins(n, n);
    const Eigen::VectorXd base_q = Random(n, 1, rng);
    Eigen::VectorXd twin_q(n);
    for (int i = 0; i < n; ++i) {
      twin_q(i) = base_q(i - i % 2);
      for (int j = 0; j < n; ++j) twins(i, j) = m(i - i % 2, j - j % 2);
    }
    const std::string size = " n=" + std::to_string(n);
    CHECK(Compare("equal q" + size, m, equal, true, true, &tally));
    CHECK(Compare("zeros in q" + size, m, zeros, true, true, &tally));
    CHECK(Compare("twin contacts" + size, twins, twin_q, false, true, &tally));
  }
  Report("degenerate q", tally);
}

}  // namespace
}  // namespace nfrc

#endif  // NFRC_HAVE_SICONOS
