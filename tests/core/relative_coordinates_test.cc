#include "core/relative_coordinates.h"

#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/condensation.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;
constexpr Complex kI(0.0, 1.0);

// Error of a against b relative to the largest entry of b.
template <typename A, typename B>
double RelError(const A& a, const B& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return (a - b).cwiseAbs().maxCoeff() / (scale > 0.0 ? scale : 1.0);
}

// Random complex matrix with a dominant diagonal (well conditioned, as is Z + D⁻¹ below).
Eigen::MatrixXcd RandomComplex(int n, double diagonal) {
  Eigen::MatrixXcd a = Eigen::MatrixXcd::Random(n, n);
  a.diagonal().array() += diagonal;
  return a;
}

// ---------------------------------------------------------------------------------------
// ToRelativeCoordinates against the textbook formulas written with Z⁻¹.

// The implementation solves with I + Z D, the reference inverts Z and Z⁻¹ + D: both are
// O(1)-conditioned here (diagonals ≥ 4 against unit off-diagonal noise), so the two agree
// to a few ulps × condition numbers ≈ 1e-14; 1e-12 leaves margin while any wrong term
// (a missing D, a sign, a transposed product) changes entries by O(1).
constexpr double kFormulaTolerance = 1e-12;

TEST_CASE("relative coordinates: Z_r, F_r and their derivatives match the explicit formulas") {
  std::srand(7);
  const int n = 4;
  for (int trial = 0; trial < 5; ++trial) {
    CAPTURE(trial);
    const Eigen::MatrixXcd z = RandomComplex(n, 5.0);
    const Eigen::MatrixXcd dz = RandomComplex(n, 1.0);
    const Eigen::VectorXcd f = Eigen::VectorXcd::Random(n);
    const Eigen::VectorXcd df = Eigen::VectorXcd::Random(n);
    // Mixed: two flexible obstacles, two DOFs without (d = 0).
    Eigen::VectorXd d(n);
    d << 0.3, 0.0, 0.05 * (trial + 1), 0.0;

    const RelativeBlock block = ToRelativeCoordinates(d, z, dz, f, df);

    const Eigen::MatrixXcd z_inv = z.inverse();
    const Eigen::MatrixXcd d_matrix = d.cast<Complex>().asDiagonal();
    const Eigen::MatrixXcd z_r = (z_inv + d_matrix).inverse();
    const Eigen::VectorXcd f_r = z_r * z_inv * f;
    // d(A⁻¹) = −A⁻¹ dA A⁻¹ with A = Z⁻¹ + D, dA = −Z⁻¹ dZ Z⁻¹.
    const Eigen::MatrixXcd dz_r = z_r * z_inv * dz * z_inv * z_r;
    // F_r = T F with T = Z_r Z⁻¹, dT = dZ_r Z⁻¹ − Z_r Z⁻¹ dZ Z⁻¹.
    const Eigen::MatrixXcd dt = dz_r * z_inv - z_r * z_inv * dz * z_inv;
    const Eigen::VectorXcd df_r = dt * f + z_r * z_inv * df;

    CHECK(RelError(block.z, z_r) < kFormulaTolerance);
    CHECK(RelError(block.f, f_r) < kFormulaTolerance);
    CHECK(RelError(block.dz, dz_r) < kFormulaTolerance);
    CHECK(RelError(block.df, df_r) < kFormulaTolerance);
  }
}

TEST_CASE("relative coordinates: zero compliance leaves Z and F unchanged") {
  std::srand(11);
  const int n = 3;
  const Eigen::MatrixXcd z = RandomComplex(n, 4.0);
  const Eigen::MatrixXcd dz = RandomComplex(n, 1.0);
  const Eigen::VectorXcd f = Eigen::VectorXcd::Random(n);
  const Eigen::VectorXcd df = Eigen::VectorXcd::Random(n);
  const RelativeBlock block = ToRelativeCoordinates(Eigen::VectorXd::Zero(n), z, dz, f, df);
  // B = I: the solves are exact.
  CHECK(block.z == z);
  CHECK(block.f == f);
  CHECK(block.dz == dz);
  CHECK(block.df == df);
}

TEST_CASE("relative coordinates: a statically free structure condenses (Z singular)") {
  // Two free unit masses joined by a unit spring, harmonic 0: Z = K is singular, so the
  // Z⁻¹ formulas do not apply. An obstacle spring of stiffness 1/d at DOF 0 grounds it.
  // Reference: the regularised explicit formula with Z + δI, whose error is O(δ).
  Eigen::MatrixXcd z(2, 2);
  z << 1.0, -1.0, -1.0, 1.0;
  const Eigen::MatrixXcd dz = Eigen::MatrixXcd::Zero(2, 2);
  Eigen::VectorXcd f(2);
  f << 0.2, -0.7;
  Eigen::VectorXd d(2);
  d << 0.5, 0.0;
  const RelativeBlock block = ToRelativeCoordinates(d, z, dz, f, Eigen::VectorXcd::Zero(2));

  constexpr double kRegularisation = 1e-8;
  // Z_r and F_r are smooth in δ at δ = 0 (I + Z D is regular), so the reference is off by
  // O(δ) times O(1) derivatives; 1e-6 = 100δ.
  constexpr double kRegularisedTolerance = 1e-6;
  const Eigen::MatrixXcd z_reg = z + kRegularisation * Eigen::MatrixXcd::Identity(2, 2);
  const Eigen::MatrixXcd z_inv = z_reg.inverse();
  const Eigen::MatrixXcd z_r = (z_inv + d.cast<Complex>().asDiagonal().toDenseMatrix()).inverse();
  CHECK(block.z.allFinite());
  CHECK(RelError(block.z, z_r) < kRegularisedTolerance);
  CHECK(RelError(block.f, Eigen::VectorXcd(z_r * z_inv * f)) < kRegularisedTolerance);
}

TEST_CASE("relative coordinates: a singular I + Z·D throws") {
  // Z = −k_obs on a single DOF: the structure's dynamic stiffness cancels the obstacle's.
  const double k_obs = 4.0;
  const Eigen::MatrixXcd z = Eigen::MatrixXcd::Constant(1, 1, -k_obs);
  Eigen::VectorXd d(1);
  d << 1.0 / k_obs;
  CHECK_THROWS_AS(
      ToRelativeCoordinates(d, z, z, Eigen::VectorXcd::Ones(1), Eigen::VectorXcd::Zero(1)),
      std::runtime_error);
}

// ---------------------------------------------------------------------------------------
// Through a Condensation: ω-derivatives and recovery of absolute displacements.

// A damped five-DOF chain, clamped on the left of DOF 0, non-uniform so that no two
// entries coincide by symmetry; C = 0.02 K + 0.01 M.
LinearModel Chain(int n) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    const double spring = 1.0 + 0.3 * i;  // spring on the left of DOF i
    k(i, i) += spring;
    if (i > 0) {
      k(i - 1, i - 1) += spring;
      k(i - 1, i) -= spring;
      k(i, i - 1) -= spring;
    }
    m(i, i) = 1.0 + 0.1 * i;
  }
  LinearModel model;
  model.stiffness = k.sparseView();
  model.mass = m.sparseView();
  model.damping = (0.02 * k + 0.01 * m).sparseView();
  return model;
}

Eigen::MatrixXcd DenseZ(const LinearModel& model, int k, double omega) {
  const double w = k * omega;
  return Eigen::MatrixXd(model.stiffness).cast<Complex>() -
         w * w * Eigen::MatrixXd(model.mass).cast<Complex>() +
         kI * w * Eigen::MatrixXd(model.damping).cast<Complex>();
}

// Forcing on a retained DOF and on condensed ones (so F_red depends on ω), harmonics 0–2.
std::vector<ForcingTerm> Forcing() {
  return {{4, 1, 0.7, -0.2}, {1, 1, 0.3, 0.5}, {2, 2, -0.4, 0.1}, {3, 0, 0.25, 0.0}};
}

// Central differences in ω with step h = 1e-6 ω: truncation h²·|Z'''|/6 and round-off
// 1e-16/h, both ~1e-10 relative for these O(1) matrices with 2ω = 1.8 near a resonance
// (measured ≤ 3e-10); 1e-7 leaves margin while a wrong derivative term is O(1) off.
constexpr double kFdStep = 1e-6;
constexpr double kFdTolerance = 1e-7;

TEST_CASE("relative coordinates: dZ_r and dF_r of a Condensation match central differences") {
  const HarmonicSet set(2, false);
  const std::vector<int> retained = {4, 2};
  // The chain's Rayleigh damping qualifies for the modal form: both forms are checked.
  for (Condensation::Method method : {Condensation::Method::kModal, Condensation::Method::kDense}) {
    CAPTURE(static_cast<int>(method));
    Condensation condensation(Chain(5), retained, set, Forcing(), method);
    condensation.SetObstacleCompliance({0.4, 2.0});
    const double omega = 0.9;
    const double h = kFdStep * omega;
    for (int p = 0; p < set.num_harmonics(); ++p) {
      CAPTURE(set.harmonics()[p]);
      condensation.Update(omega + h);
      const Eigen::MatrixXcd z_plus = condensation.Z(p);
      const Eigen::VectorXcd f_plus = condensation.F(p);
      condensation.Update(omega - h);
      const Eigen::MatrixXcd z_minus = condensation.Z(p);
      const Eigen::VectorXcd f_minus = condensation.F(p);
      condensation.Update(omega);
      const Eigen::MatrixXcd dz_fd = (z_plus - z_minus) / (2 * h);
      const Eigen::VectorXcd df_fd = (f_plus - f_minus) / (2 * h);
      if (set.harmonics()[p] == 0) {
        // K condensed: independent of ω, both ways.
        CHECK(condensation.dZ(p).cwiseAbs().maxCoeff() == 0.0);
        CHECK(dz_fd.cwiseAbs().maxCoeff() == 0.0);
        continue;
      }
      // Scale: the derivatives themselves, which are O(1) here.
      CHECK(RelError(condensation.dZ(p), dz_fd) < kFdTolerance);
      CHECK(RelError(condensation.dF(p), df_fd) < kFdTolerance);
      // The real forms carry the same numbers.
      const Eigen::MatrixXd rows = condensation.RealOperatorRows(0, true);
      const int nc = set.NumCoefficients();
      CHECK(rows(set.CosIndex(p), set.CosIndex(p)) == condensation.dZ(p)(0, 0).real());
      CHECK(rows(set.CosIndex(p), nc + set.SinIndex(p)) == condensation.dZ(p)(0, 1).imag());
    }
    CHECK(condensation.modal() == (method == Condensation::Method::kModal));
  }
}

// Recovery against an independent full solve. A linear interface spring k_c joins each
// flexible-obstacle DOF to its obstacle, a massless DOF held to ground by k_obs = 1/d; the
// condensed problem (Z_r + k_c) x_r = F_r is solved in nfrc's relative coordinates and
// Recover's absolute displacements are compared with a dense complex solve of the model
// augmented by explicit obstacle DOFs (mass 0), which knows nothing of relative
// coordinates. Both are direct solves of O(10)-conditioned systems: 1e-11 relative.
constexpr double kRecoverTolerance = 1e-11;

TEST_CASE("relative coordinates: Recover returns the absolute displacements of a full solve") {
  const int n = 5;
  const LinearModel model = Chain(n);
  const HarmonicSet set(2, false);
  const int nc = set.NumCoefficients();
  // Retained: DOF 4 (flexible obstacle), DOF 1 (no obstacle), DOF 2 (flexible obstacle).
  const std::vector<int> retained = {4, 1, 2};
  const std::vector<double> compliance = {0.5, 0.0, 0.25};
  const std::vector<double> interface = {3.0, 0.0, 1.5};  // k_c per retained DOF
  for (Condensation::Method method : {Condensation::Method::kModal, Condensation::Method::kDense}) {
    CAPTURE(static_cast<int>(method));
    Condensation condensation(model, retained, set, Forcing(), method);
    condensation.SetObstacleCompliance(compliance);
    REQUIRE(condensation.has_obstacles());

    for (double omega : {0.4, 1.3}) {
      CAPTURE(omega);
      condensation.Update(omega);
      // Condensed solve in relative coordinates, in nfrc's real layout.
      Eigen::MatrixXd a = condensation.RealOperator();
      for (int i = 0; i < 3; ++i) {
        a.block(i * nc, i * nc, nc, nc).diagonal().array() += interface[i];
      }
      const Eigen::VectorXd x_rel = a.partialPivLu().solve(condensation.RealForcing());
      const Eigen::MatrixXd recovered = condensation.Recover(x_rel);
      REQUIRE(recovered.rows() == n);

      // Augmented model: DOFs 0..4 of the chain, then obstacle DOFs 5 (behind 4) and 6
      // (behind 2), each massless and undamped, joined to its DOF by k_c and to ground by k_obs.
      const int n_aug = n + 2;
      const std::vector<std::pair<int, int>> obstacle = {{0, 5}, {2, 6}};  // (retained i, DOF)
      for (int p = 0; p < set.num_harmonics(); ++p) {
        const int k = set.harmonics()[p];
        CAPTURE(k);
        Eigen::MatrixXcd z = Eigen::MatrixXcd::Zero(n_aug, n_aug);
        z.topLeftCorner(n, n) = DenseZ(model, k, omega);
        for (const auto& [i, o] : obstacle) {
          const int s = retained[i];
          z(s, s) += interface[i];
          z(o, o) += interface[i] + 1.0 / compliance[i];
          z(s, o) -= interface[i];
          z(o, s) -= interface[i];
        }
        Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n_aug);
        for (const ForcingTerm& t : Forcing()) {
          if (t.harmonic == k) f(t.dof) += Complex(t.cos, k == 0 ? 0.0 : -t.sin);
        }
        const Eigen::VectorXcd x = z.partialPivLu().solve(f);
        // Real coefficients a = Re X, b = −Im X.
        Eigen::VectorXd expected(n), got(n);
        for (int dof = 0; dof < n; ++dof) {
          expected(dof) = x(dof).real();
          got(dof) = recovered(dof, set.CosIndex(p));
        }
        const double scale = x.head(n).cwiseAbs().maxCoeff();
        CHECK((got - expected).cwiseAbs().maxCoeff() < kRecoverTolerance * scale);
        if (k != 0) {
          for (int dof = 0; dof < n; ++dof) {
            expected(dof) = -x(dof).imag();
            got(dof) = recovered(dof, set.SinIndex(p));
          }
          CHECK((got - expected).cwiseAbs().maxCoeff() < kRecoverTolerance * scale);
        }
        // The relative unknowns are x − x_obs of the full solve.
        for (const auto& [i, o] : obstacle) {
          const Complex relative = x(retained[i]) - x(o);
          CHECK(std::abs(x_rel(i * nc + set.CosIndex(p)) - relative.real()) <
                kRecoverTolerance * scale);
        }
      }
      CHECK(condensation.modal() == (method == Condensation::Method::kModal));
    }
  }
}

TEST_CASE("relative coordinates: SetObstacleCompliance rejects bad input") {
  const HarmonicSet set(1, false);
  Condensation condensation(Chain(3), {2, 0}, set, {{2, 1, 1.0, 0.0}});
  auto message_of = [&](std::vector<double> compliance) -> std::string {
    try {
      condensation.SetObstacleCompliance(std::move(compliance));
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  CHECK(message_of({1.0}).find("compliance") != std::string::npos);
  CHECK(message_of({1.0, 0.0, 0.0}).find("compliance") != std::string::npos);
  CHECK(message_of({-1.0, 0.0}).find("compliance") != std::string::npos);
  CHECK(message_of({0.0, std::numeric_limits<double>::quiet_NaN()}).find("compliance") !=
        std::string::npos);
  CHECK(message_of({std::numeric_limits<double>::infinity(), 0.0}).find("compliance") !=
        std::string::npos);

  // All zero: no obstacle at all.
  CHECK(message_of({0.0, 0.0}).empty());
  CHECK_FALSE(condensation.has_obstacles());

  // A new compliance invalidates the condensed blocks until the next Update.
  condensation.Update(0.7);
  const Eigen::MatrixXcd rigid = condensation.Z(1);
  CHECK(message_of({0.5, 0.0}).empty());
  CHECK(condensation.has_obstacles());
  CHECK_THROWS_AS(condensation.Z(1), std::logic_error);
  condensation.Update(0.7);
  CHECK(RelError(condensation.Z(1), rigid) > 1e-3);  // the obstacle softens the contact DOF
}

}  // namespace
}  // namespace nfrc
