#include "models/craig_bampton.h"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseLU>
#include <cmath>
#include <complex>
#include <numbers>

namespace nfrc {
namespace {

// A fixed–free chain of n equal masses m (kg) joined by springs k (N/m), the first spring to
// ground. Its eigenfrequencies are analytic (a discrete string):
//   ω_j = 2 √(k/m) sin((2j − 1) π / (2 (2n + 1))),  j = 1..n.
constexpr double kMass = 0.5;    // kg
constexpr double kSpring = 2e6;  // N/m

LinearModel Chain(int n, double rayleigh_beta = 0.0) {
  std::vector<Eigen::Triplet<double>> k, m;
  for (int i = 0; i < n; ++i) {
    m.emplace_back(i, i, kMass);
    k.emplace_back(i, i, i + 1 < n ? 2.0 * kSpring : kSpring);
    if (i + 1 < n) {
      k.emplace_back(i, i + 1, -kSpring);
      k.emplace_back(i + 1, i, -kSpring);
    }
  }
  LinearModel model;
  model.stiffness.resize(n, n);
  model.stiffness.setFromTriplets(k.begin(), k.end());
  model.mass.resize(n, n);
  model.mass.setFromTriplets(m.begin(), m.end());
  model.damping = rayleigh_beta * model.stiffness;
  return model;
}

double ChainFrequency(int n, int j) {
  return 2.0 * std::sqrt(kSpring / kMass) *
         std::sin((2.0 * j - 1.0) * std::numbers::pi / (2.0 * (2.0 * n + 1.0)));
}

Eigen::VectorXd DenseFrequencies(const LinearModel& model) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      Eigen::MatrixXd(model.stiffness), Eigen::MatrixXd(model.mass), Eigen::EigenvaluesOnly);
  return solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

// Lanczos stops at a relative Ritz-value residual of 1e-10 (craig_bampton.cc); the chain's
// eigenvalues are well separated, so ω (a square root) is good to about half that, and 1e-9
// leaves room for round-off in the factor (condition of K ~ 4n² ≈ 10⁶).
constexpr double kEigenTolerance = 1e-9;
// A reduction with every interior mode is an exact change of basis: only round-off
// (condition of K_ii ~ 10⁴ for these chains times machine ε, then squared-root) separates it.
constexpr double kExactTolerance = 1e-9;

TEST_CASE("LowestEigenpairs: shift-invert Lanczos against the analytic chain") {
  const int n = 600;  // above the dense limit (400): the Spectra + CHOLMOD path
  const LinearModel chain = Chain(n);
  Eigen::MatrixXd vectors;
  const Eigen::VectorXd lambda = LowestEigenpairs(chain.stiffness, chain.mass, 6, -1.0, &vectors);
  REQUIRE(lambda.size() == 6);
  for (int j = 0; j < 6; ++j) {
    CHECK(std::sqrt(lambda(j)) ==
          doctest::Approx(ChainFrequency(n, j + 1)).epsilon(kEigenTolerance));
    // M-normalised and an eigenvector: ‖K v − λ M v‖ small against ‖K v‖.
    const Eigen::VectorXd v = vectors.col(j);
    CHECK(v.dot(chain.mass * v) == doctest::Approx(1.0).epsilon(1e-12));
    const Eigen::VectorXd residual = chain.stiffness * v - lambda(j) * (chain.mass * v);
    CHECK(residual.norm() < 1e-7 * (chain.stiffness * v).norm());
  }
}

TEST_CASE("Craig-Bampton: every interior mode reproduces the full model") {
  const int n = 60;
  const LinearModel chain = Chain(n);
  CraigBamptonOptions options;
  options.modes = n - 2;  // interior = all but the two boundary DOFs
  options.check_frequencies = 8;
  options.keep_recovery = true;
  const CraigBamptonModel cb = ReduceCraigBampton(chain, {n - 1, n / 2}, options);
  REQUIRE(cb.model.num_dofs() == n);
  CHECK(cb.model.dof_names[0] == std::to_string(n - 1));
  CHECK(cb.model.dof_names[2] == "cb_mode_1");
  const Eigen::VectorXd reduced = DenseFrequencies(cb.model);
  for (int j = 0; j < n; ++j) {
    CHECK(reduced(j) == doctest::Approx(ChainFrequency(n, j + 1)).epsilon(kExactTolerance));
  }
  REQUIRE(cb.report.eigenfrequencies.size() == 8);
  for (const EigenfrequencyCheck& check : cb.report.eigenfrequencies) {
    CHECK(std::abs(check.relative_error) < kExactTolerance);
  }
  CHECK(cb.recovery.rows() == n);
  CHECK(cb.recovery.cols() == n);
}

TEST_CASE("Craig-Bampton: low eigenfrequencies converge from above as modes are added") {
  const int n = 800;  // interior above the dense limit: Lanczos on the K_ii factor
  const LinearModel chain = Chain(n);
  std::vector<double> previous(4, INFINITY);
  for (int modes : {2, 4, 8, 16, 32}) {
    CraigBamptonOptions options;
    options.modes = modes;
    options.check_frequencies = 4;
    const CraigBamptonModel cb = ReduceCraigBampton(chain, {n - 1, n / 3}, options);
    CHECK(cb.report.modes == modes);
    const Eigen::VectorXd reduced = DenseFrequencies(cb.model);
    for (int j = 0; j < 4; ++j) {
      const double exact = ChainFrequency(n, j + 1);
      // Rayleigh–Ritz: the reduced ω_j bounds the full one from above (up to round-off,
      // 1e-10 relative), and adding modes never raises it.
      CHECK(reduced(j) >= exact * (1.0 - 1e-10));
      CHECK(reduced(j) <= previous[static_cast<size_t>(j)] * (1.0 + 1e-10));
      previous[static_cast<size_t>(j)] = reduced(j);
      // The report's full frequencies are the analytic ones.
      CHECK(cb.report.eigenfrequencies[static_cast<size_t>(j)].full ==
            doctest::Approx(exact).epsilon(kEigenTolerance));
    }
  }
  // With 32 modes the first four are within 0.1 % (the chain's 4th mode is far below the
  // 33rd fixed-interface mode, ω_4 / ω_33 ≈ 0.1, and the error goes like that ratio squared
  // times the small neglected modal participation).
  for (int j = 0; j < 4; ++j) {
    CHECK(previous[static_cast<size_t>(j)] ==
          doctest::Approx(ChainFrequency(n, j + 1)).epsilon(1e-3));
  }
}

TEST_CASE("Craig-Bampton: FRF well below the retained modes matches the full sparse solve") {
  const int n = 500;
  // s: stiffness-proportional Rayleigh damping, ζ_j = βω_j/2 (3e-6 in the first mode at
  // 6.3 rad/s, 3e-4 at the 20th fixed-interface mode): light, the test is about projection.
  const double beta = 1e-6;
  LinearModel chain = Chain(n, beta);
  CraigBamptonOptions options;
  options.modes = 20;
  options.keep_recovery = true;
  const int tip = n - 1;
  const CraigBamptonModel cb = ReduceCraigBampton(chain, {tip}, options);
  // Damping maps exactly: Tᵀ(βK)T = β K_r.
  CHECK((Eigen::MatrixXd(cb.model.damping) - beta * Eigen::MatrixXd(cb.model.stiffness)).norm() <
        1e-12 * beta * Eigen::MatrixXd(cb.model.stiffness).norm());
  const double highest_retained = cb.report.fixed_interface_frequencies.back();  // rad/s
  using Complex = std::complex<double>;
  // Frequencies between the 1st and 5th full modes (resonances avoided: between them),
  // all below half the last retained fixed-interface mode.
  for (double omega : {0.5 * ChainFrequency(n, 1), 1.5 * ChainFrequency(n, 1),
                       0.5 * (ChainFrequency(n, 3) + ChainFrequency(n, 4))}) {
    REQUIRE(omega < 0.5 * highest_retained);
    Eigen::SparseMatrix<Complex> z =
        (chain.stiffness - omega * omega * chain.mass).cast<Complex>() +
        Complex(0.0, omega) * chain.damping.cast<Complex>();
    Eigen::SparseLU<Eigen::SparseMatrix<Complex>> lu(z);
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(n);
    force(tip) = 1.0;  // N
    const Eigen::VectorXcd x_full = lu.solve(force);
    const Eigen::MatrixXcd z_r =
        Eigen::MatrixXd(cb.model.stiffness - omega * omega * cb.model.mass).cast<Complex>() +
        Complex(0.0, omega) * Eigen::MatrixXd(cb.model.damping).cast<Complex>();
    Eigen::VectorXcd f_r = Eigen::VectorXcd::Zero(z_r.rows());
    f_r(0) = 1.0;
    const Eigen::VectorXcd q = z_r.partialPivLu().solve(f_r);
    // CB's error below the retained modes is the neglected modes' dynamic part, ~(ω/ω_{m+1})²
    // of their (small) participation: measured 1e-5 at the tip and 5e-5 over the recovered
    // field at these ω; 1e-4 bounds both (an error in T or in the projection gives O(1)).
    constexpr double kFrfTolerance = 1e-4;
    CHECK(std::abs(q(0) - x_full(tip)) < kFrfTolerance * std::abs(x_full(tip)));
    const Eigen::VectorXcd recovered = cb.recovery.cast<Complex>() * q;
    CHECK((recovered - x_full).norm() < kFrfTolerance * x_full.norm());
  }
}

TEST_CASE("Craig-Bampton: modes from a frequency band") {
  const int n = 700;
  const LinearModel chain = Chain(n);
  CraigBamptonOptions options;
  options.max_frequency = 3.0 * ChainFrequency(n, 3);
  const CraigBamptonModel cb = ReduceCraigBampton(chain, {n - 1}, options);
  // The fixed-interface problem of a chain with its tip held is the fixed–fixed chain of
  // n − 1 masses: ω_j = 2 √(k/m) sin(jπ / (2n)).
  const double limit = kBandFactor * options.max_frequency;
  const auto fixed_fixed = [&](int j) {
    return 2.0 * std::sqrt(kSpring / kMass) * std::sin(j * std::numbers::pi / (2.0 * n));
  };
  int expected = 0;
  while (fixed_fixed(expected + 1) <= limit) ++expected;
  CHECK(cb.report.modes == expected);
  for (int j = 0; j < cb.report.modes; ++j) {
    CHECK(cb.report.fixed_interface_frequencies[static_cast<size_t>(j)] ==
          doctest::Approx(fixed_fixed(j + 1)).epsilon(kEigenTolerance));
  }
}

TEST_CASE("Craig-Bampton: bad arguments") {
  const LinearModel chain = Chain(20);
  CraigBamptonOptions options;
  options.modes = 3;
  CHECK_THROWS_AS(ReduceCraigBampton(chain, {}, options), std::invalid_argument);
  CHECK_THROWS_AS(ReduceCraigBampton(chain, {3, 3}, options), std::invalid_argument);
  CHECK_THROWS_AS(ReduceCraigBampton(chain, {20}, options), std::invalid_argument);
  options.modes = 20;  // the interior has 19 DOFs
  CHECK_THROWS_AS(ReduceCraigBampton(chain, {19}, options), std::invalid_argument);
  options.modes = -1;  // neither modes nor max_frequency
  CHECK_THROWS_AS(ReduceCraigBampton(chain, {19}, options), std::invalid_argument);
  // A free chain (no spring to ground) with its boundary in the middle still holds the
  // interior; one whose boundary is a spring-free DOF pair... here: remove the ground spring
  // and hold nothing that fixes the rigid motion of one side.
  LinearModel free_chain = Chain(20);
  free_chain.stiffness.coeffRef(0, 0) = kSpring;  // the ground spring removed
  options.modes = 3;
  CHECK_NOTHROW(ReduceCraigBampton(free_chain, {0}, options));  // holding an end fixes it
  // Two free pieces: with DOF 10 held, 0..9 and 11..19 each still hang on it: fine. Cut the
  // spring 4–5 instead so that 0..4 floats.
  free_chain.stiffness.coeffRef(4, 5) = 0.0;
  free_chain.stiffness.coeffRef(5, 4) = 0.0;
  free_chain.stiffness.coeffRef(4, 4) = kSpring;
  free_chain.stiffness.coeffRef(5, 5) = kSpring;
  CHECK_THROWS_AS(ReduceCraigBampton(free_chain, {19}, options), std::runtime_error);
}

TEST_CASE(
    "Craig-Bampton: no interior, an indefinite interior mass and too many checks are refused") {
  // Every DOF a boundary DOF: nothing to reduce (CHOLMOD was handed an empty K_ii).
  LinearModel two = Chain(2);
  for (const int modes : {0, -1}) {
    CraigBamptonOptions options;
    options.modes = modes;
    options.max_frequency = 1e4;
    CHECK_THROWS_WITH_AS(ReduceCraigBampton(two, {0, 1}, options),
                         doctest::Contains("no interior to reduce"), std::invalid_argument);
  }
  // A negative interior mass: the fixed-interface modes of (K_ii, M_ii) mean nothing.
  LinearModel negative = Chain(6);
  negative.mass.coeffRef(3, 3) = -kMass;
  CraigBamptonOptions two_modes;
  two_modes.modes = 2;
  CHECK_THROWS_WITH_AS(ReduceCraigBampton(negative, {5}, two_modes),
                       doctest::Contains("interior mass M_ii is not positive definite"),
                       std::runtime_error);
  // An explicit check of more frequencies than the reduced model has (1 + 2 DOFs).
  CraigBamptonOptions checks = two_modes;
  checks.check_frequencies = 4;
  CHECK_THROWS_WITH_AS(ReduceCraigBampton(Chain(6), {5}, checks),
                       doctest::Contains("check_frequencies: 4 asked, the reduced model has 3"),
                       std::invalid_argument);
  // The default (5) is clipped to the reduced size.
  CHECK(ReduceCraigBampton(Chain(6), {5}, two_modes).report.eigenfrequencies.size() == 3);
}

}  // namespace
}  // namespace nfrc
