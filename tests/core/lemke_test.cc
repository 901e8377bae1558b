#include "core/lemke.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace nfrc {
namespace {

// A complementary basic point of the enumeration counts as feasible down to this relative
// margin; on random data genuine solutions stay far further from the boundary.
constexpr double kEnumerationTol = 1e-9;
// Lemke's point against the enumerated one, relative to max(1, ‖z‖∞): both are LU solves of
// the same basis (~1e-15 on these O(1) matrices), with room for conditions up to ~1e5.
constexpr double kSolutionTol = 1e-9;
// Residuals of a returned solution, relative to ‖q‖∞ and ‖M‖·‖z‖: one LU solve of the final
// basis, whose condition reaches ~1e5 on the low-rank (Fourier) problems.
constexpr double kResidualTol = 1e-9;
// The enumeration skips principal submatrices whose LU pivot ratio is below this: singular
// ones come out near 1e-16, nonsingular ones of these random O(1) matrices far above it.
constexpr double kSingularPivotRatio = 1e-10;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Runs `f`, expecting std::invalid_argument whose message contains `field`.
template <typename F>
void CheckInvalid(F f, const std::string& field) {
  try {
    f();
    FAIL("expected std::invalid_argument naming " << field);
  } catch (const std::invalid_argument& e) {
    CHECK_MESSAGE(std::string(e.what()).find(field) != std::string::npos, e.what());
  }
}

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd a(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) a(i, j) = uniform(rng);
  }
  return a;
}

Eigen::VectorXd RandomVector(int n, std::mt19937& rng) { return RandomMatrix(n, 1, rng); }

struct LcpSolution {
  Eigen::VectorXd z, w;
};

// Reference solver: every solution at a nonsingular complementary basis, by trying all 2^n
// index sets α (z_α = −M_αα⁻¹ q_α, z_ᾱ = 0, w = Mz + q) and keeping the nonnegative ones.
std::vector<LcpSolution> EnumerateSolutions(const Eigen::MatrixXd& m, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  const double q_scale = std::max(1.0, q.lpNorm<Eigen::Infinity>());
  std::vector<LcpSolution> solutions;
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> alpha;
    for (int i = 0; i < n; ++i) {
      if (mask & (1 << i)) alpha.push_back(i);
    }
    const int k = static_cast<int>(alpha.size());
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    if (k > 0) {
      Eigen::MatrixXd m_aa(k, k);
      Eigen::VectorXd q_a(k);
      for (int a = 0; a < k; ++a) {
        q_a(a) = q(alpha[a]);
        for (int b = 0; b < k; ++b) m_aa(a, b) = m(alpha[a], alpha[b]);
      }
      Eigen::FullPivLU<Eigen::MatrixXd> lu(m_aa);
      lu.setThreshold(kSingularPivotRatio);
      if (!lu.isInvertible()) continue;
      const Eigen::VectorXd z_a = lu.solve(-q_a);
      for (int a = 0; a < k; ++a) z(alpha[a]) = z_a(a);
    }
    const Eigen::VectorXd w = m * z + q;
    const double z_scale = std::max(1.0, z.lpNorm<Eigen::Infinity>());
    if (z.minCoeff() >= -kEnumerationTol * z_scale && w.minCoeff() >= -kEnumerationTol * q_scale) {
      solutions.push_back({z, w});
    }
  }
  return solutions;
}

// Checks that r is a solution of LCP(q, M) from its own z and w, and that its residual fields
// agree with them.
void CheckSolution(const LemkeResult& r, const Eigen::MatrixXd& m, const Eigen::VectorXd& q) {
  REQUIRE_MESSAGE(r.ok(), r.message);
  // Natural sizes of w (units of q) and of z (units of q / M), never zero.
  const double q_scale = q.lpNorm<Eigen::Infinity>();
  const double m_scale = m.lpNorm<Eigen::Infinity>();
  const double z_scale = std::max(r.z.lpNorm<Eigen::Infinity>(), q_scale / m_scale);
  const double residual = (r.w - m * r.z - q).lpNorm<Eigen::Infinity>();
  CHECK(r.z.minCoeff() >= -kResidualTol * z_scale);
  CHECK(r.w.minCoeff() >= -kResidualTol * q_scale);
  CHECK(r.w.cwiseProduct(r.z).lpNorm<Eigen::Infinity>() <= kResidualTol * q_scale * z_scale);
  // n·‖M‖max·‖z‖∞ bounds ‖Mz‖∞.
  CHECK(residual <= kResidualTol * (q_scale + m_scale * z_scale * q.size()));
  CHECK(r.equation_residual == residual);
  CHECK(r.complementarity == r.w.cwiseProduct(r.z).lpNorm<Eigen::Infinity>());
  CHECK(r.feasibility == std::max({0.0, -r.w.minCoeff(), -r.z.minCoeff()}));
  CHECK(r.z0 == 0.0);
  for (int i = 0; i < r.z.size(); ++i) {
    const bool basic = std::find(r.basic_z.begin(), r.basic_z.end(), i) != r.basic_z.end();
    if (!basic) CHECK(r.z(i) == 0.0);
  }
}

double RelativeError(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

enum class PKind { kSymmetricDefinite, kDiagonallyDominant, kTriangular, kNonsymmetricDefinite };

// Random P-matrices (all principal minors > 0, so the LCP has exactly one solution for every q).
Eigen::MatrixXd RandomPMatrix(PKind kind, int n, std::mt19937& rng) {
  const Eigen::MatrixXd a = RandomMatrix(n, n, rng);
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  switch (kind) {
    case PKind::kSymmetricDefinite:
      return a * a.transpose() + 0.1 * identity;
    case PKind::kDiagonallyDominant: {
      // Strictly row diagonally dominant with a positive diagonal.
      Eigen::MatrixXd m = a;
      for (int i = 0; i < n; ++i) m(i, i) = a.row(i).cwiseAbs().sum() + 0.5;
      return m;
    }
    case PKind::kTriangular: {
      // Every principal minor is a product of diagonal entries.
      Eigen::MatrixXd m = a.triangularView<Eigen::StrictlyUpper>();
      m.diagonal() = a.diagonal().cwiseAbs() + Eigen::VectorXd::Constant(n, 0.5);
      return m;
    }
    case PKind::kNonsymmetricDefinite: {
      // xᵀMx = xᵀ(AAᵀ + 0.1 I)x > 0: the skew part adds nothing to it.
      const Eigen::MatrixXd c = 2.0 * RandomMatrix(n, n, rng);
      return a * a.transpose() + 0.1 * identity + c - c.transpose();
    }
  }
  return identity;
}

// Murty's lower-triangular matrix M̃(n): 1 on the diagonal, 2 below it.
Eigen::MatrixXd MurtyMatrix(int n) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    m(i, i) = 1.0;
    for (int j = 0; j < i; ++j) m(i, j) = 2.0;
  }
  return m;
}

// Murty's q̃(n): q̃_i = −(2^n + 2^(n−1) + ... + 2^(n−i)), i = 0..n−1.
Eigen::VectorXd MurtyVector(int n) {
  Eigen::VectorXd q(n);
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    sum += std::ldexp(1.0, n - i);
    q(i) = -sum;
  }
  return q;
}

// Real Fourier synthesis on N samples t_k = 2πk/N: columns 1, cos ht, sin ht for h = 1..H.
Eigen::MatrixXd FourierSynthesis(int num_samples, int max_harmonic) {
  Eigen::MatrixXd e(num_samples, 2 * max_harmonic + 1);
  for (int k = 0; k < num_samples; ++k) {
    const double t = 2.0 * std::numbers::pi * k / num_samples;
    e(k, 0) = 1.0;
    for (int h = 1; h <= max_harmonic; ++h) {
      e(k, 2 * h - 1) = std::cos(h * t);
      e(k, 2 * h) = std::sin(h * t);
    }
  }
  return e;
}

// Delassus-like operator of an oversampled HBM contact, M = E·K·P in m/N: P = analysis (P·E = I),
// K = damped harmonic compliance (1 / (1 + h²) with a 30 % quadrature part), so M has rank
// 2H + 1 and is positive semidefinite plus skew, like W sampled on N > 2H + 1 time samples.
Eigen::MatrixXd FourierDelassus(int num_samples, int max_harmonic) {
  const Eigen::MatrixXd e = FourierSynthesis(num_samples, max_harmonic);
  Eigen::MatrixXd p = e.transpose() * (2.0 / num_samples);
  p.row(0) *= 0.5;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(e.cols(), e.cols());
  k(0, 0) = 1.0;
  for (int h = 1; h <= max_harmonic; ++h) {
    const double a = 1.0 / (1.0 + h * h);
    k(2 * h - 1, 2 * h - 1) = a;
    k(2 * h, 2 * h) = a;
    k(2 * h - 1, 2 * h) = 0.3 * a;
    k(2 * h, 2 * h - 1) = -0.3 * a;
  }
  constexpr double kCompliance = 1e-10;  // m/N
  return kCompliance * e * k * p;
}

// A gap over one period (m) of amplitude 0.1 mm around 0.1 mm·`offset`, negative on part of it.
Eigen::VectorXd GapSignal(int num_samples, double offset = 0.2) {
  Eigen::VectorXd q(num_samples);
  for (int k = 0; k < num_samples; ++k) {
    const double t = 2.0 * std::numbers::pi * k / num_samples;
    q(k) = 1e-4 * (offset - std::cos(t) - 0.4 * std::sin(2.0 * t) + 0.1 * std::cos(7.0 * t));
  }
  return q;
}

TEST_CASE("Lemke: ToString names every LemkeStatus") {
  CHECK(ToString(LemkeStatus::kSolution) == "solution");
  CHECK(ToString(LemkeStatus::kRayTermination) == "ray termination");
  CHECK(ToString(LemkeStatus::kPivotLimit) == "pivot limit");
  CHECK(ToString(LemkeStatus::kSingularBasis) == "singular basis");
  CHECK(ToString(LemkeStatus::kInterrupted) == "interrupted");
}

TEST_CASE("Lemke: a raised stop flag ends it before its next pivot") {
  // M = I, q < 0: the solution z = -q takes one pivot per entry after z0 enters.
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(50, 50);
  const Eigen::VectorXd q = -Eigen::VectorXd::LinSpaced(50, 1.0, 2.0);
  REQUIRE(SolveLcp(m, q).ok());
  std::atomic<bool> stop{true};
  LemkeOptions options;
  options.stop = &stop;
  const LemkeResult r = SolveLcp(m, q, options);
  CHECK(r.status == LemkeStatus::kInterrupted);
  CHECK_FALSE(r.ok());
  CHECK(r.pivots <= 1);  // z0's entry, before the loop polls
}

TEST_CASE("Lemke: SolveLcp returns the trivial solution when q >= 0") {
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd q = Eigen::Vector3d(1.0, 0.0, 2.0);
  const LemkeResult r = SolveLcp(m, q);
  CHECK(r.ok());
  CHECK(r.trivial);
  CHECK(r.pivots == 0);
  CHECK(r.z == Eigen::VectorXd::Zero(3));
  CHECK(r.w == q);
  CHECK(r.basic_z.empty());

  // A negative entry within the relative feasibility tolerance is trivial too, and reported.
  const Eigen::VectorXd almost = Eigen::Vector3d(1e-4, -1e-16, 2e-4);
  const LemkeResult tiny = SolveLcp(m, almost);
  CHECK(tiny.ok());
  CHECK(tiny.trivial);
  CHECK(tiny.feasibility == 1e-16);

  const LemkeResult zero = SolveLcp(m, Eigen::VectorXd::Zero(3));
  CHECK(zero.trivial);
  const LemkeResult empty = SolveLcp(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0));
  CHECK(empty.ok());
  CHECK(empty.z.size() == 0);
}

TEST_CASE("Lemke: SolveLcp matches enumeration on random P-matrices") {
  for (PKind kind : {PKind::kSymmetricDefinite, PKind::kDiagonallyDominant, PKind::kTriangular,
                     PKind::kNonsymmetricDefinite}) {
    for (int n = 1; n <= 10; ++n) {
      for (unsigned seed = 0; seed < 5; ++seed) {
        CAPTURE(static_cast<int>(kind));
        CAPTURE(n);
        CAPTURE(seed);
        std::mt19937 rng(1000 * seed + n);
        const Eigen::MatrixXd m = RandomPMatrix(kind, n, rng);
        const Eigen::VectorXd q = RandomVector(n, rng);
        const std::vector<LcpSolution> reference = EnumerateSolutions(m, q);
        REQUIRE(reference.size() == 1);
        const LemkeResult r = SolveLcp(m, q);
        CheckSolution(r, m, q);
        CHECK(RelativeError(r.z, reference[0].z) <= kSolutionTol);
        CHECK(RelativeError(r.w, reference[0].w) <= kSolutionTol);
      }
    }
  }
}

TEST_CASE("Lemke: SolveLcp solves exactly the solvable positive semidefinite problems") {
  int solvable = 0;
  int unsolvable = 0;
  for (bool symmetric : {true, false}) {
    for (int n = 2; n <= 8; ++n) {
      for (unsigned seed = 0; seed < 12; ++seed) {
        CAPTURE(symmetric);
        CAPTURE(n);
        CAPTURE(seed);
        std::mt19937 rng(77 * seed + n);
        const Eigen::MatrixXd a = RandomMatrix(n, std::max(1, n / 2), rng);
        Eigen::MatrixXd m = a * a.transpose();
        if (!symmetric) {
          const Eigen::MatrixXd c = RandomMatrix(n, n, rng);
          m += c - c.transpose();
        }
        Eigen::VectorXd q = RandomVector(n, rng);
        if (seed % 3 == 0) {
          // Planted solution: z* ≥ 0 and w* ≥ 0 on complementary supports.
          Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
          Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
          for (int i = 0; i < n; ++i) {
            if (i % 2 == 0) {
              z(i) = 0.5 + 0.5 * std::abs(q(i));
            } else {
              w(i) = 0.5 + 0.5 * std::abs(q(i));
            }
          }
          q = w - m * z;
        }
        const std::vector<LcpSolution> reference = EnumerateSolutions(m, q);
        const LemkeResult r = SolveLcp(m, q);
        CHECK(r.ok() == !reference.empty());
        if (reference.empty()) {
          ++unsolvable;
          CHECK(r.status == LemkeStatus::kRayTermination);
          continue;
        }
        ++solvable;
        CheckSolution(r, m, q);
        if (symmetric) {
          // w is unique for a symmetric positive semidefinite M.
          for (const LcpSolution& s : reference) CHECK(RelativeError(r.w, s.w) <= kSolutionTol);
        }
      }
    }
  }
  CHECK(solvable > 10);
  CHECK(unsolvable > 10);
}

TEST_CASE("Lemke: Murty's example forces 2^n pivots") {
  // K. G. Murty, "Computational complexity of complementary pivot methods", Math. Programming
  // Study 7 (1978) 61-73: on LCP(q̃(n), M̃(n)) the complementary pivot method with covering
  // d = 1 takes 2^n pivot steps, counting the entry of z0 and its leaving: the path crosses one
  // almost complementary basis per subset of {1..n}, in Gray-code order (z0, z_n, z_(n−1), w_n,
  // z_(n−2), z_n, w_(n−1), w_n, ...). q̃ has distinct entries, so no tie is broken on the way.
  // The solution is z = 2^n·e_1: w_1 = 0 and w_i = 2^(n+1) − 2^n − ... − 2^(n−i+1) = 2^(n−i+1).
  for (int n = 1; n <= 10; ++n) {
    CAPTURE(n);
    const Eigen::MatrixXd m = MurtyMatrix(n);
    const Eigen::VectorXd q = MurtyVector(n);
    const LemkeResult r = SolveLcp(m, q);
    CheckSolution(r, m, q);
    CHECK(r.pivots == (1 << n));
    const Eigen::VectorXd expected = std::ldexp(1.0, n) * Eigen::VectorXd::Unit(n, 0);
    CHECK(RelativeError(r.z, expected) <= kSolutionTol);
    if (n <= 8) {
      const std::vector<LcpSolution> reference = EnumerateSolutions(m, q);
      REQUIRE(reference.size() == 1);
      CHECK(RelativeError(r.z, reference[0].z) <= kSolutionTol);
    }
    // The same problem in SI units follows the same path.
    const LemkeResult si = SolveLcp(1e-10 * m, 1e-4 * q);
    CHECK(si.ok());
    CHECK(si.pivots == r.pivots);
    CHECK(si.basic_z == r.basic_z);
    CHECK(RelativeError(1e-6 * si.z, r.z) <= kSolutionTol);
  }
}

TEST_CASE("Lemke: SolveLcp stops at the pivot limit") {
  const int n = 6;
  LemkeOptions options;
  options.max_pivots = 10;
  const LemkeResult r = SolveLcp(MurtyMatrix(n), MurtyVector(n), options);
  CHECK(r.status == LemkeStatus::kPivotLimit);
  CHECK_FALSE(r.ok());
  CHECK(r.pivots == 10);
  CHECK(r.z0 > 0.0);
  CHECK(r.message.find("pivot limit") != std::string::npos);
  // The last basic point satisfies w = Mz + q + d·z0 with d = 1, z0 in units of q.
  const Eigen::VectorXd gap = r.w - MurtyMatrix(n) * r.z - MurtyVector(n);
  CHECK((gap - Eigen::VectorXd::Constant(n, r.z0)).lpNorm<Eigen::Infinity>() <=
        kResidualTol * MurtyVector(n).lpNorm<Eigen::Infinity>());

  options.max_pivots = 1 << n;  // exactly enough
  CHECK(SolveLcp(MurtyMatrix(n), MurtyVector(n), options).ok());
}

TEST_CASE("Lemke: SolveLcp terminates with verified solutions on degenerate problems") {
  struct Case {
    Eigen::MatrixXd m;
    Eigen::VectorXd q;
    bool p_matrix;  // then every enumerated solution is the same one
  };
  std::vector<Case> cases;
  // Ties in the first ratio test.
  cases.push_back({Eigen::MatrixXd::Identity(3, 3), -Eigen::VectorXd::Ones(3), true});
  Eigen::MatrixXd tridiagonal(3, 3);
  tridiagonal << 2, 1, 0, 1, 2, 1, 0, 1, 2;
  cases.push_back({tridiagonal, -Eigen::VectorXd::Ones(3), true});
  // Cyclic P-matrix (minors 1, 1, 9) with q = −1: a three-way tie at the start, and the
  // solution z = 1/3 has w = 0 as well.
  Eigen::MatrixXd cyclic(3, 3);
  cyclic << 1, 2, 0, 0, 1, 2, 2, 0, 1;
  cases.push_back({cyclic, -Eigen::VectorXd::Ones(3), true});
  // Zeros in q.
  Eigen::Vector4d zeros(0.0, -1.0, 0.0, -2.0);
  std::mt19937 rng(5);
  cases.push_back({RandomPMatrix(PKind::kNonsymmetricDefinite, 4, rng), zeros, true});
  // Rank one, infinitely many solutions (any z ≥ 0 with Σz = 1).
  cases.push_back({Eigen::MatrixXd::Ones(4, 4), -Eigen::VectorXd::Ones(4), false});
  // Integer data with q ∈ {−1, 0}: exact ties everywhere.
  for (int n = 3; n <= 8; ++n) {
    std::uniform_int_distribution<int> entry(-2, 2);
    std::uniform_int_distribution<int> sign(-1, 0);
    Eigen::MatrixXd m(n, n);
    Eigen::MatrixXd a(n, 2);
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q(i) = sign(rng);
      for (int j = 0; j < n; ++j) m(i, j) = entry(rng);
      a(i, 0) = entry(rng);
      a(i, 1) = entry(rng);
    }
    m.diagonal() = m.cwiseAbs().rowwise().sum() + Eigen::VectorXd::Ones(n);
    q(0) = -1.0;
    cases.push_back({m, q, true});                   // diagonally dominant
    cases.push_back({a * a.transpose(), q, false});  // rank-2 symmetric PSD
    cases.push_back({MurtyMatrix(n), -Eigen::VectorXd::Ones(n), true});
  }
  for (size_t c = 0; c < cases.size(); ++c) {
    CAPTURE(c);
    const Case& k = cases[c];
    const std::vector<LcpSolution> reference = EnumerateSolutions(k.m, k.q);
    const LemkeResult r = SolveLcp(k.m, k.q);
    CHECK(r.ok() == !reference.empty());
    if (r.ok()) CheckSolution(r, k.m, k.q);
    if (k.p_matrix) {
      REQUIRE_FALSE(reference.empty());
      for (const LcpSolution& s : reference) CHECK(RelativeError(r.z, s.z) <= kSolutionTol);
    }
    // Ties are broken deterministically.
    const LemkeResult again = SolveLcp(k.m, k.q);
    CHECK(again.pivots == r.pivots);
    CHECK(again.basic_z == r.basic_z);
  }
  const LemkeResult cyclic_result = SolveLcp(cyclic, -Eigen::VectorXd::Ones(3));
  CHECK(RelativeError(cyclic_result.z, Eigen::VectorXd::Constant(3, 1.0 / 3.0)) <= kSolutionTol);
}

TEST_CASE("Lemke: SolveLcp reports a secondary ray when there is no solution") {
  struct Case {
    Eigen::MatrixXd m;
    Eigen::VectorXd q;
  };
  std::vector<Case> cases;
  cases.push_back({Eigen::MatrixXd::Constant(1, 1, -1.0), Eigen::VectorXd::Constant(1, -1.0)});
  Eigen::Matrix2d psd;
  psd << 1, -1, -1, 1;  // w1 + w2 = −2 whatever z
  cases.push_back({psd, Eigen::Vector2d(-1.0, -1.0)});
  cases.push_back({Eigen::MatrixXd::Zero(2, 2), Eigen::Vector2d(-1.0, 2.0)});
  // Positive semidefinite with a zero row: w_2 = q_2 < 0 always.
  Eigen::MatrixXd a(3, 2);
  a << 1, 2, 0, 0, -1, 1;
  cases.push_back({a * a.transpose(), Eigen::Vector3d(-1.0, -0.5, 1.0)});
  for (size_t c = 0; c < cases.size(); ++c) {
    CAPTURE(c);
    REQUIRE(EnumerateSolutions(cases[c].m, cases[c].q).empty());
    const LemkeResult r = SolveLcp(cases[c].m, cases[c].q);
    CHECK(r.status == LemkeStatus::kRayTermination);
    CHECK(r.z0 > 0.0);
    CHECK(r.message.find("ray") != std::string::npos);
  }
}

TEST_CASE("Lemke: SolveLcp reports a singular basis after pivoting on rounding noise") {
  // Rank-2 positive semidefinite M: entering columns in the span of the basic z columns have
  // rounding noise where exact zeros belong. With pivot_tolerance 0 that noise is pivoted on and
  // some paths end in a numerically singular basis; the default tolerance never does.
  int singular = 0;
  for (unsigned seed = 0; seed < 40; ++seed) {
    CAPTURE(seed);
    std::mt19937 rng(seed);
    const int n = 6;
    const Eigen::MatrixXd a = RandomMatrix(n, 2, rng) / 3.0;
    const Eigen::MatrixXd m = a * a.transpose();
    const Eigen::VectorXd q = RandomVector(n, rng);
    const LemkeResult r = SolveLcp(m, q);
    CHECK(r.ok() == !EnumerateSolutions(m, q).empty());
    CHECK(r.status != LemkeStatus::kSingularBasis);
    LemkeOptions no_tolerance;
    no_tolerance.pivot_tolerance = 0.0;
    const LemkeResult noisy = SolveLcp(m, q, no_tolerance);
    if (noisy.status == LemkeStatus::kSingularBasis) {
      ++singular;
      CHECK_FALSE(noisy.ok());
      CHECK(noisy.message.find("singular") != std::string::npos);
    }
  }
  CHECK(singular > 0);
}

TEST_CASE("Lemke: SolveLcp solves a low-rank Fourier-like problem in SI units") {
  const int num_samples = 60;
  const int max_harmonic = 3;
  const Eigen::MatrixXd m = FourierDelassus(num_samples, max_harmonic);
  REQUIRE(Eigen::FullPivLU<Eigen::MatrixXd>(m).rank() == 2 * max_harmonic + 1);
  const Eigen::VectorXd q = GapSignal(num_samples);
  REQUIRE(q.minCoeff() < 0.0);
  const LemkeResult r = SolveLcp(m, q);
  CheckSolution(r, m, q);
  // M_αα of a nonsingular basis has full rank, so at most rank(M) forces are basic.
  CHECK(static_cast<int>(r.basic_z.size()) <= 2 * max_harmonic + 1);

  // Planted solution: forces (N) on a few samples, gaps elsewhere.
  std::mt19937 rng(11);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(num_samples);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(num_samples);
  for (int k = 0; k < num_samples; ++k) {
    const double u = 0.5 + 0.5 * std::abs(RandomVector(1, rng)(0));
    if (k % 10 == 3) {
      z(k) = 1e6 * u;
    } else {
      w(k) = 1e-4 * u;
    }
  }
  const Eigen::VectorXd planted_q = w - m * z;
  CheckSolution(SolveLcp(m, planted_q), m, planted_q);
}

TEST_CASE("Lemke: SolveLcp warm starts from a previous basis") {
  std::mt19937 rng(3);
  const int n = 10;
  const Eigen::MatrixXd m = RandomPMatrix(PKind::kNonsymmetricDefinite, n, rng);
  const Eigen::VectorXd q = RandomVector(n, rng);
  const LemkeResult first = SolveLcp(m, q);
  REQUIRE(first.ok());
  REQUIRE(first.pivots > 2);

  LemkeOptions options;
  options.warm_basis = first.basic_z;
  for (double perturbation : {1e-6, 0.3}) {
    CAPTURE(perturbation);
    const Eigen::VectorXd nearby = q + perturbation * RandomVector(n, rng);
    const LemkeResult cold = SolveLcp(m, nearby);
    const LemkeResult warm = SolveLcp(m, nearby, options);
    CheckSolution(warm, m, nearby);
    CHECK(warm.warm_started);
    CHECK(RelativeError(warm.z, cold.z) <= kSolutionTol);
    CHECK(warm.basic_z == cold.basic_z);
    // A small change keeps the active set, so the warm basis is the solution.
    if (perturbation < 1e-3) CHECK(warm.pivots == 0);
  }

  // On the low-rank problem, a re-solve after a small change of the gap takes few pivots.
  const Eigen::MatrixXd w = FourierDelassus(60, 3);
  const Eigen::VectorXd gap = GapSignal(60);
  const LemkeResult base = SolveLcp(w, gap);
  REQUIRE(base.ok());
  LemkeOptions low_rank;
  low_rank.warm_basis = base.basic_z;
  const Eigen::VectorXd shifted = gap + Eigen::VectorXd::Constant(60, 1e-7);
  const LemkeResult again = SolveLcp(w, shifted, low_rank);
  CheckSolution(again, w, shifted);
  CHECK(again.warm_started);
  CHECK(again.pivots <= 2);
}

TEST_CASE("Lemke: SolveLcp tries a warm basis even when q >= 0") {
  // w = q − z with q = 1 has two solutions: z = 0 and z = 1; the warm basis {0} picks the latter.
  const Eigen::MatrixXd m = Eigen::MatrixXd::Constant(1, 1, -1.0);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 1.0);
  LemkeOptions options;
  options.warm_basis = {0};
  const LemkeResult branch = SolveLcp(m, q, options);
  CheckSolution(branch, m, q);
  CHECK(branch.warm_started);
  CHECK_FALSE(branch.trivial);
  CHECK(branch.pivots == 0);
  CHECK(branch.z(0) == 1.0);
  CHECK(SolveLcp(m, q).z(0) == 0.0);

  // For a P-matrix z = 0 is the only solution when q ≥ 0, and the warm path must reach it.
  std::mt19937 rng(21);
  const Eigen::MatrixXd p = RandomPMatrix(PKind::kNonsymmetricDefinite, 6, rng);
  const Eigen::VectorXd positive = RandomVector(6, rng).cwiseAbs();
  options.warm_basis = {1, 3, 4};
  const LemkeResult r = SolveLcp(p, positive, options);
  CheckSolution(r, p, positive);
  CHECK(r.warm_started);
  CHECK(r.z.lpNorm<Eigen::Infinity>() <= kSolutionTol);
}

TEST_CASE("Lemke: SolveLcp falls back to the cold start from a singular warm basis") {
  const Eigen::MatrixXd m = Eigen::MatrixXd::Ones(2, 2);  // M_αα singular for α = {0, 1}
  const Eigen::VectorXd q = Eigen::Vector2d(-1.0, -2.0);
  LemkeOptions options;
  options.warm_basis = {0, 1};
  const LemkeResult r = SolveLcp(m, q, options);
  CheckSolution(r, m, q);
  CHECK_FALSE(r.warm_started);
  CHECK(r.message.find("singular") != std::string::npos);
  CHECK(r.message.find("cold start") != std::string::npos);
}

TEST_CASE("Lemke: SolveLcp honours a covering vector") {
  std::mt19937 rng(8);
  const int n = 7;
  const Eigen::MatrixXd m = RandomPMatrix(PKind::kTriangular, n, rng);
  const Eigen::VectorXd q = RandomVector(n, rng);
  LemkeOptions options;
  options.covering = Eigen::VectorXd::LinSpaced(n, 0.5, 3.0);
  const LemkeResult r = SolveLcp(m, q, options);
  CheckSolution(r, m, q);
  const std::vector<LcpSolution> reference = EnumerateSolutions(m, q);
  REQUIRE(reference.size() == 1);
  CHECK(RelativeError(r.z, reference[0].z) <= kSolutionTol);
}

TEST_CASE("Lemke: SolveLcp validates its inputs") {
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd q = -Eigen::VectorXd::Ones(3);
  auto with = [&](LemkeOptions options) { return [&m, &q, options] { SolveLcp(m, q, options); }; };
  LemkeOptions options;
  options.covering = Eigen::VectorXd::Ones(2);
  CheckInvalid(with(options), "covering");
  for (double bad : {0.0, -1.0, kInf, std::nan("")}) {
    options.covering = Eigen::VectorXd::Ones(3);
    options.covering(1) = bad;
    CheckInvalid(with(options), "covering");
  }
  options = {};
  for (std::vector<int> bad :
       {std::vector<int>{-1}, std::vector<int>{3}, std::vector<int>{0, 2, 0}}) {
    options.warm_basis = bad;
    CheckInvalid(with(options), "warm_basis");
  }
  options = {};
  options.max_pivots = -1;
  CheckInvalid(with(options), "max_pivots");
  options = {};
  options.pivot_tolerance = -1e-12;
  CheckInvalid(with(options), "pivot_tolerance");
  options = {};
  options.feasibility_tolerance = std::nan("");
  CheckInvalid(with(options), "feasibility_tolerance");
  options = {};
  CHECK_NOTHROW(options.Validate(3));

  CheckInvalid([] { SolveLcp(Eigen::MatrixXd::Zero(2, 3), Eigen::VectorXd::Zero(2)); },
               "SolveLcp: M");
  CheckInvalid([&m] { SolveLcp(m, Eigen::VectorXd::Zero(2)); }, "SolveLcp: q");
  Eigen::MatrixXd nan_m = m;
  nan_m(0, 1) = std::nan("");
  CheckInvalid([&nan_m, &q] { SolveLcp(nan_m, q); }, "SolveLcp: M");
  Eigen::VectorXd inf_q = q;
  inf_q(2) = kInf;
  CheckInvalid([&m, &inf_q] { SolveLcp(m, inf_q); }, "SolveLcp: q");
}

TEST_CASE("Lemke: SolveLcp solves a size-600 low-rank problem") {
  // N_t = 600 samples of 20 harmonics plus the mean: rank 41. The gap is closed on most of
  // the period, so the cold path is a few hundred pivots long.
  const int num_samples = 600;
  const Eigen::MatrixXd m = FourierDelassus(num_samples, 20);
  const Eigen::VectorXd q = GapSignal(num_samples, -0.8);
  const LemkeResult r = SolveLcp(m, q);
  CheckSolution(r, m, q);

  LemkeOptions options;
  options.warm_basis = r.basic_z;
  const Eigen::VectorXd shifted = GapSignal(num_samples, -0.8 + 1e-3);
  const LemkeResult warm = SolveLcp(m, shifted, options);
  CheckSolution(warm, m, shifted);
  CHECK(warm.warm_started);
  CHECK(warm.pivots < r.pivots / 10);
}

}  // namespace
}  // namespace nfrc
