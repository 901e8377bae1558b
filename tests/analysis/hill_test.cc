// Hill's method against independent references: the closed-form exponents of damped linear
// systems, Mathieu's equation (RK4 monodromy and the classical transition curves), and the
// assembled pencil against the condensed Jacobian it must reduce to.
#include "analysis/hill.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "analysis/case.h"
#include "support/chain_case.h"
#include "support/rk4.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;

// Hill's exponents of a linear system are exact up to round-off (no truncation: the
// Jacobian has no harmonics); 1e-8 relative on μ leaves room for the eigensolver.
constexpr double kLinearTolerance = 1e-8;
// RK4 with 4000 steps a period: global error ~ (2π/4000)⁴ ≈ 6e-12 per period, far below the
// truncation of Hill's exponents at H = 12 for ε ≤ 0.3 (~ε^H); 1e-6 is the bar.
constexpr double kMathieuTolerance = 1e-6;
constexpr int kRk4Steps = 4000;

// Closed-form multipliers exp(λT) of M ẍ + C ẋ + K x = 0 from the state matrix.
std::vector<Complex> StateMultipliers(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c,
                                      const Eigen::MatrixXd& k, double period) {
  const int n = static_cast<int>(m.rows());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m.inverse() * k;
  a.bottomRightCorner(n, n) = -m.inverse() * c;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(a);
  std::vector<Complex> mu;
  for (Eigen::Index i = 0; i < solver.eigenvalues().size(); ++i) {
    mu.push_back(std::exp(solver.eigenvalues()(i) * period));
  }
  return mu;
}

// Every expected multiplier has a distinct match in `actual` within `tolerance`.
void CheckMultipliers(std::vector<Complex> expected, std::vector<Complex> actual,
                      double tolerance) {
  REQUIRE(actual.size() == expected.size());
  for (const Complex& mu : expected) {
    auto best = std::min_element(actual.begin(), actual.end(), [&](Complex a, Complex b) {
      return std::abs(a - mu) < std::abs(b - mu);
    });
    CHECK(std::abs(*best - mu) <= tolerance * std::max(1.0, std::abs(mu)));
    actual.erase(best);
  }
}

Case TwoDofLinear(const HarmonicSet& set) {
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 0.5;
  k << 3.0, -1.0, -1.0, 1.0;
  Case c;
  c.model.model.mass = m.sparseView();
  c.model.model.stiffness = k.sparseView();
  c.model.model.damping = (0.03 * m + 0.01 * k).sparseView();
  c.model.forcing = {ForcingTerm{0, 1, 1.0, 0.0}};
  c.harmonics = set;
  c.output_dofs = {0};
  c.output_names = {"0"};
  return c;
}

TEST_CASE("hill: a damped linear system has the closed-form exponents, dense and Arnoldi") {
  for (const bool odd : {false, true}) {
    for (const int dense_limit : {1000, 0}) {
      CAPTURE(odd);
      CAPTURE(dense_limit);
      const Case c = TwoDofLinear(HarmonicSet(9, odd, 32));
      auto system = BuildSystem(c);
      const double omega = 1.3;
      const Eigen::VectorXd y = system->InitialGuess(omega);
      const HillPencil pencil = AssembleHillPencil(*system, y, omega);
      HillOptions options;
      options.dense_limit = dense_limit;
      const FloquetResult result = SolveHill(pencil, options);
      REQUIRE(result.computed);
      CHECK(result.message.empty());
      CheckMultipliers(StateMultipliers(Eigen::MatrixXd(c.model.model.mass),
                                        Eigen::MatrixXd(c.model.model.damping),
                                        Eigen::MatrixXd(c.model.model.stiffness),
                                        2.0 * std::numbers::pi / omega),
                       result.multipliers, kLinearTolerance);
      CHECK(result.num_unstable == 0);
    }
  }
}

// ẍ + c ẋ + (δ + ε cos t) x = 0 (ω = 1): Δ0 gets the projected product with ε cos t.
HillPencil MathieuPencil(double delta, double epsilon, double damping, int max_harmonic) {
  HillPencil pencil;
  pencil.set = HarmonicSet(max_harmonic, false);
  pencil.omega = 1.0;
  const FourierTransform fourier(pencil.set);
  const int nc = pencil.set.NumCoefficients();
  const int nt = pencil.set.num_samples();
  Eigen::VectorXd stiffness(nt);
  for (int j = 0; j < nt; ++j) {
    stiffness(j) = delta + epsilon * std::cos(2.0 * std::numbers::pi * j / nt);
  }
  const Eigen::MatrixXd d = fourier.DerivativeMatrix();
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(nc, nc);
  pencil.d0 = (fourier.WeightedProduct(stiffness) + damping * d + d * d).sparseView();
  pencil.d1 = (damping * identity + 2.0 * d).sparseView();
  pencil.d2 = identity.sparseView();
  for (int i = 0; i < nc; ++i) pencil.dynamic.push_back(i);
  pencil.signal_offsets = {0};
  pencil.state_dimension = 2;
  return pencil;
}

// Monodromy of the Mathieu equation over t ∈ [0, 2π] by RK4 (independent of Hill).
std::vector<Complex> MathieuMonodromy(double delta, double epsilon, double damping) {
  const double h = 2.0 * std::numbers::pi / kRk4Steps;
  auto accel = [&](double t, double x, double v) {
    return -damping * v - (delta + epsilon * std::cos(t)) * x;
  };
  Eigen::Matrix2d phi;
  for (int column = 0; column < 2; ++column) {
    double x = column == 0 ? 1.0 : 0.0, v = column == 0 ? 0.0 : 1.0;
    for (int i = 0; i < kRk4Steps; ++i) testing::Rk4Step(accel, i * h, h, &x, &v);
    phi(0, column) = x;
    phi(1, column) = v;
  }
  Eigen::EigenSolver<Eigen::Matrix2d> solver(phi);
  return {solver.eigenvalues()(0), solver.eigenvalues()(1)};
}

TEST_CASE("hill: Mathieu multipliers against RK4 monodromy, including the -1 tongue") {
  // Inside the first tongue (real negative multipliers, the failure mode of sorting), on its
  // stable sides (a complex pair near −1), in the 1:1 tongue near δ = 1, and damped.
  struct Point {
    double delta, epsilon, damping;
  };
  for (const Point p : {Point{0.25, 0.1, 0.0}, Point{0.2, 0.1, 0.0}, Point{0.3, 0.1, 0.0},
                        Point{0.26, 0.3, 0.02}, Point{1.0, 0.3, 0.0}, Point{0.7, 0.2, 0.05}}) {
    for (const int dense_limit : {1000, 0}) {
      CAPTURE(p.delta);
      CAPTURE(p.epsilon);
      CAPTURE(dense_limit);
      HillOptions options;
      options.dense_limit = dense_limit;
      const FloquetResult hill =
          SolveHill(MathieuPencil(p.delta, p.epsilon, p.damping, 12), options);
      REQUIRE(hill.computed);
      CheckMultipliers(MathieuMonodromy(p.delta, p.epsilon, p.damping), hill.multipliers,
                       kMathieuTolerance);
    }
  }
}

// Transition curves of ẍ + (δ + ε cos t)x = 0 from the Mathieu characteristic values a₁, b₁
// (y'' + (a − 2q cos 2z)y = 0 with δ = a/4, q = 2ε; Abramowitz & Stegun 20.2.25):
//   a₁ = 1 + q − q²/8 − q³/64 − q⁴/1536,  b₁ = 1 − q − q²/8 + q³/64 − q⁴/1536.
TEST_CASE("hill: the boundaries of the first Mathieu tongue match the classical series") {
  const double epsilon = 0.1, q = 2.0 * epsilon;
  const double a1 = 1 + q - q * q / 8 - q * q * q / 64 - std::pow(q, 4) / 1536;
  const double b1 = 1 - q - q * q / 8 + q * q * q / 64 - std::pow(q, 4) / 1536;
  // The series' next term is O(q⁵)/4 ≈ 1e-5·0.3; bisection is carried to 1e-9.
  constexpr double kSeriesTolerance = 2e-5;
  auto unstable = [&](double delta) {
    return SolveHill(MathieuPencil(delta, epsilon, 0.0, 12), HillOptions{}).num_unstable > 0;
  };
  for (const auto& [inside, outside, expected] :
       {std::tuple{0.25, 0.15, b1 / 4}, std::tuple{0.25, 0.35, a1 / 4}}) {
    double a = inside, b = outside;
    REQUIRE(unstable(a));
    REQUIRE_FALSE(unstable(b));
    while (std::abs(b - a) > 1e-9) {
      const double mid = 0.5 * (a + b);
      (unstable(mid) ? a : b) = mid;
    }
    CHECK(std::abs(a - expected) < kSeriesTolerance);
  }
}

// Schur complement of m onto `kept`, eliminating `eliminated` (index lists into m).
Eigen::MatrixXd SchurComplement(const Eigen::MatrixXd& m, const std::vector<int>& kept,
                                const std::vector<int>& eliminated) {
  auto block = [&](const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd b(rows.size(), cols.size());
    for (size_t i = 0; i < rows.size(); ++i)
      for (size_t j = 0; j < cols.size(); ++j) b(i, j) = m(rows[i], cols[j]);
    return b;
  };
  return block(kept, kept) - block(kept, eliminated) *
                                 block(eliminated, eliminated).lu().solve(block(eliminated, kept));
}

// Consecutive indices [first, last).
std::vector<int> Range(int first, int last) {
  std::vector<int> indices;
  for (int i = first; i < last; ++i) indices.push_back(i);
  return indices;
}

// A 4-DOF chain with a cubic spring at DOF 0 and friction at DOF 3 (retained: 0 and 3).
Case SpringAndFrictionCase() {
  Case c = testing::ChainCase(4);
  c.model.forcing = {ForcingTerm{0, 1, 0.3, 0.0}};
  c.harmonics = HarmonicSet(3, false, 32);
  c.laws.push_back(CubicSpringSpec{0, -1, 0.4});
  c.laws.push_back(testing::Friction(3, 0.3, 0.05));
  c.output_dofs = {0};
  c.output_names = {"0"};
  return c;
}

// Condensing Δ0 onto the retained DOFs and own unknowns gives back the system's Jacobian
// (FD-checked in harmonic_system_test): the assembly, the DOF map and the laws' blocks.
TEST_CASE(
    "hill: delta0 condensed is the harmonic system's Jacobian, with friction's velocity block") {
  const Case c = SpringAndFrictionCase();
  auto system = BuildSystem(c);
  const double omega = 0.9;
  Eigen::VectorXd y = system->InitialGuess(omega);
  std::srand(7);  // Eigen's Random draws from std::rand: a fixed, mixed stick/slip state
  y += 0.01 * Eigen::VectorXd::Random(y.size());
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  REQUIRE(system->Evaluate(y, omega, &residual, &jacobian, nullptr));
  const HillPencil pencil = AssembleHillPencil(*system, y, omega);
  const int nc = c.harmonics.NumCoefficients();
  // Full unknowns: DOFs 0..3 (blocks of nc), then the friction force. Retained: 0, 3.
  std::vector<int> kept = Range(0, nc);
  for (int i : Range(3 * nc, 5 * nc)) kept.push_back(i);
  const Eigen::MatrixXd d0(pencil.d0);
  const Eigen::MatrixXd schur = SchurComplement(d0, kept, Range(nc, 3 * nc));
  // Condensation and Schur complement differ by round-off only.
  CHECK((schur - jacobian).norm() <= 1e-10 * jacobian.norm());
  // Ψ depends on x only through v = ωDx: its x-block of Δ0 is Δ1's velocity block times ωD.
  const Eigen::MatrixXd d1(pencil.d1);
  const Eigen::MatrixXd derivative = system->fourier().DerivativeMatrix();
  const Eigen::MatrixXd velocity_block = d1.block(4 * nc, 3 * nc, nc, nc);
  CHECK(velocity_block.norm() > 0.0);
  CHECK((velocity_block * omega * derivative - d0.block(4 * nc, 3 * nc, nc, nc)).norm() <=
        1e-12 * d0.block(4 * nc, 3 * nc, nc, nc).norm());
}

// DLFT against a rigid obstacle: the law's force through the linear rows
// (LinearResidualPart) must condense back to DLFT's Jacobian, Z-dependence included, so that
// its folds are +1 crossings. (With a flexible obstacle the full pencil's structure row and
// the condensed relative row are different combinations of the same equations; their
// agreement is checked through the folds of the rod in stability_test.)
TEST_CASE("hill: delta0 condensed is DLFT's Jacobian against a rigid obstacle") {
  const Case c = testing::ChainAgainstRigidObstacle(HarmonicSet(4, false, 32));
  auto system = BuildSystem(c);
  const double omega = 0.9;
  Eigen::VectorXd y = system->InitialGuess(omega);
  std::srand(11);  // a state with contact on some samples and not on others
  y += 0.05 * Eigen::VectorXd::Random(y.size());
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  REQUIRE(system->Evaluate(y, omega, &residual, &jacobian, nullptr));
  const HillPencil pencil = AssembleHillPencil(*system, y, omega);
  const int nc = c.harmonics.NumCoefficients();
  REQUIRE(pencil.d0.rows() == 4 * nc);
  const Eigen::MatrixXd schur =
      SchurComplement(Eigen::MatrixXd(pencil.d0), Range(3 * nc, 4 * nc), Range(0, 3 * nc));
  const Eigen::MatrixXd weights =
      system->laws()[0]->LinearResidualPart(system->context(0), y, omega)->weights;
  CHECK(weights.norm() > 0.0);  // some samples in contact
  CHECK((schur - jacobian).norm() <= 1e-9 * jacobian.norm());
}

// Assemble moves the linear part to the point's ω itself (it no longer evaluates the
// system first): DLFT, which predicts its force from the condensed operator, gives the same
// pencil after an evaluation at another ω as after one at the point's, and a non-finite
// point is refused.
TEST_CASE("hill: the pencil is the point's whatever frequency the system was evaluated at") {
  const Case c = testing::ChainAgainstRigidObstacle(HarmonicSet(4, false, 32));
  const double omega = 0.9;
  auto reference_system = BuildSystem(c);
  Eigen::VectorXd y = reference_system->InitialGuess(omega);
  std::srand(11);
  y += 0.05 * Eigen::VectorXd::Random(y.size());
  Eigen::VectorXd residual;
  REQUIRE(reference_system->Evaluate(y, omega, &residual, nullptr, nullptr));
  const HillPencil reference = AssembleHillPencil(*reference_system, y, omega);
  for (const double elsewhere : {0.5, 1.7}) {
    auto system = BuildSystem(c);
    REQUIRE(system->Evaluate(y, elsewhere, &residual, nullptr, nullptr));
    const HillPencil pencil = AssembleHillPencil(*system, y, omega);
    CHECK(Eigen::MatrixXd(pencil.d0 - reference.d0).norm() == 0.0);
    CHECK(Eigen::MatrixXd(pencil.d1 - reference.d1).norm() == 0.0);
  }
  // Never evaluated: the assembly binds the laws.
  auto fresh = BuildSystem(c);
  CHECK(Eigen::MatrixXd(AssembleHillPencil(*fresh, y, omega).d0 - reference.d0).norm() == 0.0);
  Eigen::VectorXd broken = y;
  broken(1) = std::numeric_limits<double>::quiet_NaN();
  std::string message;
  try {
    AssembleHillPencil(*fresh, broken, omega);
  } catch (const std::runtime_error& error) {
    message = error.what();
  }
  CHECK(message.find("y is not finite") != std::string::npos);
}

// A trace reuses one HillAssembler (its Kronecker products and map are built once): after a
// pencil at another point and frequency it must give exactly the pencil assembled afresh.
TEST_CASE("hill: a reused assembler gives the pencil of each new point exactly") {
  auto system = BuildSystem(SpringAndFrictionCase());
  std::srand(5);
  const Eigen::VectorXd first = 0.01 * Eigen::VectorXd::Random(system->NumUnknowns());
  const Eigen::VectorXd second = 0.02 * Eigen::VectorXd::Random(system->NumUnknowns());
  HillAssembler assembler(*system);
  assembler.Assemble(first, 0.8);
  const HillPencil reused = assembler.Assemble(second, 1.1);
  const HillPencil fresh = AssembleHillPencil(*system, second, 1.1);
  for (auto [a, b] :
       {std::pair{&reused.d0, &fresh.d0}, {&reused.d1, &fresh.d1}, {&reused.d2, &fresh.d2}}) {
    CHECK(Eigen::MatrixXd(*a - *b).norm() == 0.0);
    CHECK(a->norm() > 0.0);
  }
  CHECK(reused.omega == 1.1);
  CHECK(reused.dynamic == fresh.dynamic);
  CHECK(reused.state_dimension == fresh.state_dimension);
}

// HillMatrix merges the three matrices in one pass; the traces' Floquet multipliers stay the
// same bit for bit only if it rounds as Eigen's two sums did, a missing term a zero added
// (a lone −0.0 becomes +0.0), with their pattern: checked, sign bits included, on random
// patterns that hold every overlap of the three, stored zeros and negative zeros.
TEST_CASE("hill: H(sigma) is Eigen's (d0 + s d1) + s^2 d2, pattern and bits") {
  constexpr int kSize = 40;
  std::srand(11);
  HillPencil pencil;
  for (Eigen::SparseMatrix<double>* matrix : {&pencil.d0, &pencil.d1, &pencil.d2}) {
    std::vector<Eigen::Triplet<double>> triplets;
    for (int j = 0; j < kSize; ++j) {
      for (int i = 0; i < kSize; ++i) {
        const int draw = std::rand() % 10;
        if (draw < 3) triplets.emplace_back(i, j, 1.0 + std::rand() % 1000 / 7.0);
        if (draw == 3) triplets.emplace_back(i, j, -0.0);
        if (draw == 4) triplets.emplace_back(i, j, 0.0);
      }
    }
    matrix->resize(kSize, kSize);
    matrix->setFromTriplets(triplets.begin(), triplets.end());
  }
  for (const double sigma : {0.37, -1.3e-3}) {
    const Eigen::SparseMatrix<double> first = pencil.d0 + sigma * pencil.d1;
    const Eigen::SparseMatrix<double> reference = first + (sigma * sigma) * pencil.d2;
    const Eigen::SparseMatrix<double> merged = HillMatrix(pencil, sigma);
    REQUIRE(merged.isCompressed());
    REQUIRE(merged.nonZeros() == reference.nonZeros());
    int differing = 0;
    for (int j = 0; j < kSize; ++j) {
      Eigen::SparseMatrix<double>::InnerIterator a(merged, j), b(reference, j);
      for (; a && b; ++a, ++b) {
        if (a.row() != b.row() ||
            std::bit_cast<std::uint64_t>(a.value()) != std::bit_cast<std::uint64_t>(b.value())) {
          ++differing;
        }
      }
      CHECK(!a);
      CHECK(!b);
    }
    CHECK(differing == 0);
  }
}

}  // namespace
}  // namespace nfrc
