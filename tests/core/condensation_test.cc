#include "core/condensation.h"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/dynamic_stiffness.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;
using Method = Condensation::Method;

// Error of a against b relative to the largest entry of b; absolute if b is zero (harmonics
// without forcing), where entries of these O(1) models would be O(1) if wrong.
template <typename A, typename B>
double RelError(const A& a, const B& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return (a - b).cwiseAbs().maxCoeff() / (scale > 0.0 ? scale : 1.0);
}

// Complex forcing vector of every DOF for harmonic k, built from the terms by hand.
Eigen::VectorXcd FullForcing(int n, const std::vector<ForcingTerm>& forcing, int k) {
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  for (const ForcingTerm& t : forcing) {
    if (t.harmonic == k) f(t.dof) += Complex(t.cos, k == 0 ? 0.0 : -t.sin);
  }
  return f;
}

// Real coefficients (row = DOF) of complex amplitudes per harmonic: a = Re X, b = −Im X.
Eigen::MatrixXd ToReal(const HarmonicSet& set, const std::vector<Eigen::VectorXcd>& x) {
  Eigen::MatrixXd real(x[0].size(), set.NumCoefficients());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    real.col(set.CosIndex(p)) = x[p].real();
    if (set.harmonics()[p] != 0) real.col(set.SinIndex(p)) = -x[p].imag();
  }
  return real;
}

// Condensed unknown vector (DOF-major) of the retained rows of full real coefficients.
Eigen::VectorXd Condensed(const Eigen::MatrixXd& real, const std::vector<int>& retained) {
  const int n_c = static_cast<int>(real.cols());
  Eigen::VectorXd x(retained.size() * n_c);
  for (size_t i = 0; i < retained.size(); ++i) x.segment(i * n_c, n_c) = real.row(retained[i]);
  return x;
}

LinearModel RandomModel(int n, bool symmetric, unsigned seed) {
  std::srand(seed);
  auto random = [&](double diagonal) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    if (symmetric) a = (a + a.transpose()).eval() / 2.0;
    return Eigen::MatrixXd(a + diagonal * Eigen::MatrixXd::Identity(n, n));
  };
  LinearModel model;
  model.mass = random(4.0).sparseView();
  model.damping = (0.2 * random(1.0)).sparseView();
  model.stiffness = random(6.0).sparseView();
  return model;
}

// Condensation at ω compared with a dense solve of the full complex system Z x = F.
void CheckAgainstFullSolve(const LinearModel& model, const std::vector<int>& retained,
                           const HarmonicSet& set, const std::vector<ForcingTerm>& forcing,
                           Method method, double omega, double tol) {
  const int n = model.num_dofs();
  Condensation condensation(model, retained, set, forcing, method);
  condensation.Update(omega);
  CHECK(condensation.omega() == omega);
  std::vector<Eigen::VectorXcd> full(set.num_harmonics());
  std::vector<Eigen::VectorXcd> reduced(set.num_harmonics());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    INFO("harmonic " << k);
    const Eigen::MatrixXcd z(DynamicStiffness(model, k, omega));
    full[p] = z.fullPivLu().solve(FullForcing(n, forcing, k));
    reduced[p] = condensation.Z(p).fullPivLu().solve(condensation.F(p));
    Eigen::VectorXcd expected(retained.size());
    for (size_t i = 0; i < retained.size(); ++i) expected(i) = full[p](retained[i]);
    CHECK(RelError(reduced[p], expected) < tol);
  }
  const Eigen::MatrixXd full_real = ToReal(set, full);
  const Eigen::VectorXd x = Condensed(full_real, retained);
  // The real operator solves to the same condensed coefficients.
  const Eigen::VectorXd x_real =
      condensation.RealOperator().fullPivLu().solve(condensation.RealForcing());
  CHECK(RelError(x_real, x) < tol);
  // Recovery from the retained coefficients gives every DOF.
  CHECK(RelError(condensation.Recover(x), full_real) < tol);
}

// dZ_red and dF_red (complex and real forms) against central differences in ω.
void CheckDerivatives(const LinearModel& model, const std::vector<int>& retained,
                      const HarmonicSet& set, const std::vector<ForcingTerm>& forcing,
                      Method method, double omega) {
  // Z_red is rational in ω. With h = 1e-5 the truncation error h²|Z'''|/6 measures ~9e-9
  // relative here (it scales as h²) and rounding eps|Z|/h ~1e-10: 1e-7 leaves 10× margin,
  // while a missing or wrong term of dZ_red is O(1) relative.
  constexpr double kTol = 1e-7;
  const double h = 1e-5;
  Condensation plus(model, retained, set, forcing, method);
  Condensation minus(model, retained, set, forcing, method);
  Condensation at(model, retained, set, forcing, method);
  plus.Update(omega + h);
  minus.Update(omega - h);
  at.Update(omega);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int k = set.harmonics()[p];
    INFO("harmonic " << k);
    const Eigen::MatrixXcd dz = (plus.Z(p) - minus.Z(p)) / (2 * h);
    const Eigen::VectorXcd df = (plus.F(p) - minus.F(p)) / (2 * h);
    if (k == 0) {
      CHECK(at.dZ(p).cwiseAbs().maxCoeff() == 0.0);
      CHECK(at.dF(p).cwiseAbs().maxCoeff() == 0.0);
      continue;
    }
    CHECK(RelError(at.dZ(p), dz) < kTol);
    CHECK(RelError(at.dF(p), df) < kTol);
  }
  const Eigen::MatrixXd d_real = (plus.RealOperator() - minus.RealOperator()) / (2 * h);
  const Eigen::VectorXd df_real = (plus.RealForcing() - minus.RealForcing()) / (2 * h);
  CHECK(RelError(at.RealOperatorDerivative(), d_real) < kTol);
  CHECK(RelError(at.RealForcingDerivative(), df_real) < kTol);
}

TEST_CASE("Condensation of small dense models equals the full solve") {
  // Well-conditioned 8-DOF models (diagonally dominant, damped): dense and sparse LU agree
  // with the full solve to ~1e-14; 1e-10 leaves room and still catches any wrong term.
  constexpr double kTol = 1e-10;
  const std::vector<int> retained = {5, 1, 6};  // unsorted on purpose
  // Forcing on retained and condensed DOFs, including a constant term.
  const std::vector<ForcingTerm> full_forcing = {{.dof = 5, .harmonic = 1, .cos = 1.0, .sin = 0.5},
                                                 {.dof = 2, .harmonic = 1, .cos = -0.3, .sin = 0.7},
                                                 {.dof = 7, .harmonic = 3, .cos = 0.2, .sin = -1.0},
                                                 {.dof = 0, .harmonic = 0, .cos = 0.4, .sin = 0.0}};
  const std::vector<ForcingTerm> odd_forcing(full_forcing.begin(), full_forcing.begin() + 3);
  for (bool symmetric : {true, false}) {
    const LinearModel model = RandomModel(8, symmetric, symmetric ? 1 : 2);
    for (Method method : {Method::kDense, Method::kSparse, Method::kAuto}) {
      INFO("symmetric " << symmetric << ", method " << static_cast<int>(method));
      const HarmonicSet full(3, false);
      const HarmonicSet odd(5, true);
      CheckAgainstFullSolve(model, retained, full, full_forcing, method, 1.3, kTol);
      CheckAgainstFullSolve(model, retained, odd, odd_forcing, method, 0.8, kTol);
      CheckDerivatives(model, retained, full, full_forcing, method, 1.3);
      CheckDerivatives(model, retained, odd, odd_forcing, method, 0.8);
    }
  }
}

TEST_CASE("Condensation real operator is the documented arrangement of the complex blocks") {
  const LinearModel model = RandomModel(5, false, 3);
  const HarmonicSet set(2, false);
  const std::vector<int> retained = {3, 0};
  const std::vector<ForcingTerm> forcing = {{.dof = 1, .harmonic = 2, .cos = 1.0, .sin = 2.0}};
  Condensation condensation(model, retained, set, forcing);
  condensation.Update(0.7);
  const Eigen::MatrixXd real = condensation.RealOperator();
  const Eigen::VectorXd f = condensation.RealForcing();
  const int n_c = set.NumCoefficients();
  REQUIRE(real.rows() == condensation.num_unknowns());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    const int ic = set.CosIndex(p), is = set.SinIndex(p);
    for (int i = 0; i < 2; ++i) {
      CHECK(f(i * n_c + ic) == condensation.F(p)(i).real());
      if (p > 0) CHECK(f(i * n_c + is) == -condensation.F(p)(i).imag());
      for (int j = 0; j < 2; ++j) {
        const Complex z = condensation.Z(p)(i, j);
        CHECK(real(i * n_c + ic, j * n_c + ic) == z.real());
        if (p == 0) continue;
        CHECK(real(i * n_c + ic, j * n_c + is) == z.imag());
        CHECK(real(i * n_c + is, j * n_c + ic) == -z.imag());
        CHECK(real(i * n_c + is, j * n_c + is) == z.real());
      }
    }
  }
  // No coupling between different harmonics.
  CHECK(real(0 * n_c + 1, 1 * n_c + 3) == 0.0);
  CHECK(real(1 * n_c + 0, 0 * n_c + 4) == 0.0);
}

// Calls check(derivative, RealOperator() or its derivative) at two frequencies.
template <typename Check>
void AtTwoFrequencies(Condensation& condensation, Check check) {
  for (const double omega : {0.7, 1.9}) {
    condensation.Update(omega);
    for (const bool derivative : {false, true}) {
      CAPTURE(omega);
      CAPTURE(derivative);
      check(derivative,
            derivative ? condensation.RealOperatorDerivative() : condensation.RealOperator());
    }
  }
}

// WriteRealOperator fills the layout's blocks only: a matrix of a sentinel shows both the
// entries it writes (RealOperator's, bit for bit) and the ones it must leave (RealOperator's
// zeros), in a whole matrix and in the corner of a larger one (a Jacobian's).
TEST_CASE("Condensation writes its real operator's blocks in place and nothing else") {
  const LinearModel model = RandomModel(5, false, 3);
  const HarmonicSet set(3, false);
  const std::vector<int> retained = {3, 0};
  const std::vector<ForcingTerm> forcing = {{.dof = 1, .harmonic = 2, .cos = 1.0, .sin = 2.0}};
  Condensation condensation(model, retained, set, forcing);
  constexpr double kSentinel = 12345.0;
  AtTwoFrequencies(condensation, [&](bool derivative, const Eigen::MatrixXd& real) {
    const Eigen::Index n = real.rows();
    Eigen::MatrixXd whole = Eigen::MatrixXd::Constant(n, n, kSentinel);
    condensation.WriteRealOperator(derivative, whole);
    Eigen::MatrixXd larger = Eigen::MatrixXd::Constant(n + 3, n + 2, kSentinel);
    condensation.WriteRealOperator(derivative, larger.topLeftCorner(n, n));
    int written = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) {
        const bool in_layout = whole(i, j) != kSentinel;
        written += in_layout ? 1 : 0;
        CHECK(whole(i, j) == (in_layout ? real(i, j) : kSentinel));
        CHECK(larger(i, j) == whole(i, j));
        if (!in_layout) CHECK(real(i, j) == 0.0);
      }
    }
    // A 2 × 2 block per harmonic and retained pair, one entry for the constant.
    CHECK(written == 4 * (1 + 4 * (set.num_harmonics() - 1)));
    CHECK((larger.bottomRows(3).array() == kSentinel).all());
    CHECK((larger.rightCols(2).array() == kSentinel).all());
  });
  Eigen::MatrixXd wrong(3, 3);
  CHECK_THROWS_AS(condensation.WriteRealOperator(false, wrong), std::invalid_argument);
}

// ApplyRealOperator replaces the dense product with RealOperator() in the residuals of one
// retained DOF: the traces stay the same only if it is that product bit for bit (sign bits
// included), also above 128 columns, where Eigen's product sums in blocks of columns. Checked
// on iterates with zeros, negative zeros and magnitudes far apart. With several retained DOFs
// it is the same sum up to the association of its terms.
TEST_CASE("Condensation applies its real operator as the dense product does") {
  // Two associations of a sum of four terms differ by at most ~3 eps of the terms' magnitudes.
  constexpr double kReassociation = 8 * std::numeric_limits<double>::epsilon();
  const std::vector<ForcingTerm> forcing = {{.dof = 1, .harmonic = 2, .cos = 1.0, .sin = 2.0}};
  struct Setup {
    std::vector<int> retained;
    int max_harmonic;
  };
  for (const Setup& setup : {Setup{{3}, 4}, Setup{{2}, 70}, Setup{{3, 0}, 4}, Setup{{1, 4}, 70}}) {
    CAPTURE(setup.retained.size());
    CAPTURE(setup.max_harmonic);
    const HarmonicSet set(setup.max_harmonic, false);
    Condensation condensation(RandomModel(6, false, 4), setup.retained, set, forcing);
    std::srand(7);
    AtTwoFrequencies(condensation, [&](bool derivative, const Eigen::MatrixXd& real) {
      const Eigen::Index n = real.rows();
      Eigen::VectorXd x = Eigen::VectorXd::Random(n);
      for (Eigen::Index i = 0; i < n; i += 5) x(i) = 0.0;
      for (Eigen::Index i = 2; i < n; i += 7) x(i) = -0.0;
      for (Eigen::Index i = 1; i < n; i += 3) x(i) *= 1e9;
      const Eigen::VectorXd dense = real * x;
      const Eigen::VectorXd magnitudes = real.cwiseAbs() * x.cwiseAbs();
      Eigen::VectorXd applied = Eigen::VectorXd::Constant(n, 12345.0);
      condensation.ApplyRealOperator(derivative, x, applied);
      int differing = 0, beyond_rounding = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (std::bit_cast<std::uint64_t>(applied(i)) != std::bit_cast<std::uint64_t>(dense(i))) {
          ++differing;
        }
        if (std::abs(applied(i) - dense(i)) > kReassociation * magnitudes(i)) ++beyond_rounding;
      }
      if (setup.retained.size() == 1) CHECK(differing == 0);
      CHECK(beyond_rounding == 0);
    });
    Eigen::VectorXd wrong(3), out(3);
    CHECK_THROWS_AS(condensation.ApplyRealOperator(false, wrong, out), std::invalid_argument);
  }
}

TEST_CASE("Condensation with every DOF retained is the plain dynamic stiffness") {
  const LinearModel model = RandomModel(4, false, 4);
  const HarmonicSet set(2, false);
  const std::vector<int> retained = {2, 0, 3, 1};
  const std::vector<ForcingTerm> forcing = {{.dof = 3, .harmonic = 1, .cos = 1.0, .sin = -2.0}};
  for (Method method : {Method::kDense, Method::kSparse}) {
    Condensation condensation(model, retained, set, forcing, method);
    condensation.Update(1.1);
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[p];
      const Eigen::MatrixXcd z(DynamicStiffness(model, k, 1.1));
      const Eigen::MatrixXcd dz(DynamicStiffnessDerivative(model, k, 1.1));
      const Eigen::VectorXcd f = FullForcing(4, forcing, k);
      for (int i = 0; i < 4; ++i) {
        CHECK(condensation.F(p)(i) == f(retained[i]));
        CHECK(condensation.dF(p)(i) == Complex(0.0));
        for (int j = 0; j < 4; ++j) {
          CHECK(condensation.Z(p)(i, j) == z(retained[i], retained[j]));
          CHECK(condensation.dZ(p)(i, j) == dz(retained[i], retained[j]));
        }
      }
    }
    const Eigen::VectorXd x = Eigen::VectorXd::Random(condensation.num_unknowns());
    const Eigen::MatrixXd all = condensation.Recover(x);
    for (int i = 0; i < 4; ++i) {
      CHECK(all.row(retained[i]).transpose() ==
            x.segment(i * set.NumCoefficients(), set.NumCoefficients()));
    }
  }
}

TEST_CASE("Condensation caches per frequency and is movable") {
  const LinearModel model = RandomModel(6, true, 5);
  const HarmonicSet set(3, true);
  Condensation condensation(model, {1, 4}, set, {{.dof = 0, .harmonic = 3, .cos = 1.0}});
  CHECK_THROWS_AS((void)condensation.Z(0), std::logic_error);
  condensation.Update(0.9);
  const Eigen::MatrixXcd z = condensation.Z(1);
  condensation.Update(0.9);
  CHECK(condensation.Z(1) == z);
  condensation.Update(1.4);
  CHECK(condensation.omega() == 1.4);
  CHECK(condensation.Z(1) != z);
  Condensation moved(std::move(condensation));
  moved.Update(0.9);
  CHECK(moved.Z(1) == z);
  CHECK_THROWS_WITH_AS((void)moved.Z(2), doctest::Contains("position"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(moved.Recover(Eigen::VectorXd::Zero(3)), doctest::Contains("x"),
                       std::invalid_argument);
}

TEST_CASE("Condensation rejects bad input") {
  const LinearModel model = RandomModel(4, true, 6);
  const HarmonicSet odd(3, true);
  auto make = [&](std::vector<int> retained, std::vector<ForcingTerm> forcing) {
    Condensation condensation(model, std::move(retained), odd, std::move(forcing));
  };
  CHECK_THROWS_WITH_AS(make({}, {}), doctest::Contains("retained"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(make({0, 4}, {}), doctest::Contains("retained"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(make({-1}, {}), doctest::Contains("retained"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(make({2, 1, 2}, {}), doctest::Contains("retained"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(make({0}, {{.dof = 4, .harmonic = 1}}), doctest::Contains("forcing"),
                       std::invalid_argument);
  // Harmonics 0 and 2 are not in an odd set.
  CHECK_THROWS_WITH_AS(make({0}, {{.dof = 1, .harmonic = 2}}), doctest::Contains("harmonic"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(make({0}, {{.dof = 1, .harmonic = 0}}), doctest::Contains("forcing"),
                       std::invalid_argument);
  LinearModel bad = model;
  bad.mass.resize(3, 3);
  CHECK_THROWS_WITH_AS(Condensation(bad, {0}, odd, {}), doctest::Contains("mass"),
                       std::invalid_argument);
}

TEST_CASE("Condensation with a stiffness-free interior DOF uses the direct form") {
  // DOF 1 is tied to DOF 0 by a damper only: K_ll = 0, so there are no static modes, while
  // Z_ll = −Ω²m + iΩc is regular for the odd harmonics.
  LinearModel model;
  const Eigen::Matrix3d k{{2.0, 0.0, -1.0}, {0.0, 0.0, 0.0}, {-1.0, 0.0, 1.5}};
  const Eigen::Matrix3d c{{0.3, -0.3, 0.0}, {-0.3, 0.3, 0.0}, {0.0, 0.0, 0.05}};
  model.stiffness = k.sparseView();
  model.damping = c.sparseView();
  model.mass = Eigen::Vector3d(1.0, 0.5, 1.0).asDiagonal().toDenseMatrix().sparseView();
  const HarmonicSet set(3, true);
  // A 3-DOF model solved two ways agrees to rounding (~1e-15); 1e-10 as for the random ones.
  constexpr double kSmallModelTol = 1e-10;
  const std::vector<ForcingTerm> forcing = {{.dof = 1, .harmonic = 1, .cos = 1.0, .sin = 0.2}};
  Condensation condensation(model, {0, 2}, set, forcing);
  condensation.Update(0.9);
  CHECK_FALSE(condensation.static_split());
  CheckAgainstFullSolve(model, {0, 2}, set, forcing, Method::kAuto, 0.9, kSmallModelTol);
  CheckDerivatives(model, {0, 2}, set, forcing, Method::kAuto, 0.9);
}

// K = [[3, −1], [−1, 4]], M = I, C = 0: undamped, so that Z_ll (DOF 1 condensed) vanishes at
// Ω = 2 and the whole model resonates at Ω² = (7 ∓ √5)/2.
LinearModel UndampedPair() {
  LinearModel model;
  const Eigen::Matrix2d k{{3.0, -1.0}, {-1.0, 4.0}};
  model.stiffness = k.sparseView();
  model.mass = Eigen::Matrix2d::Identity().sparseView();
  model.damping.resize(2, 2);
  return model;
}

TEST_CASE("Condensation reports a singular Z_ll with harmonic and frequency") {
  // Condensed DOF 1: k = 4, m = 1, no damping, so Z_ll of harmonic 1 vanishes at ω = 2.
  const LinearModel model = UndampedPair();
  const HarmonicSet set(3, true);
  // kModal: H_rr vanishes there, so that harmonic takes the direct form, which reports it.
  for (Method method : {Method::kDense, Method::kSparse, Method::kModal}) {
    Condensation condensation(model, {0}, set, {}, method);
    CHECK_THROWS_WITH_AS(condensation.Update(2.0), doctest::Contains("harmonic 1, omega = 2"),
                         std::runtime_error);
    CHECK_THROWS_AS((void)condensation.Z(0), std::logic_error);  // no stale result
    // A regular frequency afterwards works again.
    condensation.Update(1.5);
    const Complex z = condensation.Z(0)(0, 0);
    CHECK(z.real() == doctest::Approx(3.0 - 2.25 - 1.0 / (4.0 - 2.25)));
    CHECK(z.imag() == 0.0);
  }
}

// A symmetric n-DOF model (M and K positive definite) with proportional damping: Rayleigh,
// C = 0.1 M + 0.05 K, or modal, C = M Φ diag(2ζ_m ω_m) Φᵀ M with ζ_m = 0.1 (1 + 0.2 m) from
// the mass-normalised modes Φ of (K, M), assembled in floating point as the rod's is. The
// modes lie at 1.3–2.3 rad/s; damping of 6–24 % keeps the harmonics near them smooth enough
// for CheckDerivatives' central differences (at 1 %, harmonic 3 at ω = 1.3 measured 1e-6).
LinearModel ProportionalModel(int n, bool modal_damping, unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd m = a.transpose() * a + n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd k = 3.0 * (b.transpose() * b + n * Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd c = 0.1 * m + 0.05 * k;
  if (modal_damping) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(k, m);
    Eigen::VectorXd rates(n);
    for (int i = 0; i < n; ++i)
      rates(i) = 2.0 * 0.1 * (1 + 0.2 * i) * std::sqrt(modes.eigenvalues()(i));
    c = m * modes.eigenvectors() * rates.asDiagonal() * modes.eigenvectors().transpose() * m;
  }
  LinearModel model;
  model.mass = m.sparseView();
  model.stiffness = k.sparseView();
  model.damping = c.sparseView();
  return model;
}

TEST_CASE("Modal condensation of proportionally damped models equals the full solve") {
  // The same well-conditioned 8-DOF setting as the dense and sparse forms above, and the same
  // 1e-10: the modal sums and the full solve agree to ~1e-14.
  constexpr double kTol = 1e-10;
  const std::vector<int> retained = {5, 1, 6};
  const std::vector<ForcingTerm> full_forcing = {{.dof = 5, .harmonic = 1, .cos = 1.0, .sin = 0.5},
                                                 {.dof = 2, .harmonic = 1, .cos = -0.3, .sin = 0.7},
                                                 {.dof = 7, .harmonic = 3, .cos = 0.2, .sin = -1.0},
                                                 {.dof = 0, .harmonic = 0, .cos = 0.4, .sin = 0.0}};
  const std::vector<ForcingTerm> odd_forcing(full_forcing.begin(), full_forcing.begin() + 3);
  const HarmonicSet full(3, false);
  const HarmonicSet odd(5, true);
  for (bool modal_damping : {false, true}) {
    INFO("modal damping " << modal_damping);
    const LinearModel model = ProportionalModel(8, modal_damping, 11);
    for (const std::vector<int>& kept : {retained, std::vector<int>{3}}) {
      CheckAgainstFullSolve(model, kept, full, full_forcing, Method::kModal, 1.3, kTol);
      CheckAgainstFullSolve(model, kept, odd, odd_forcing, Method::kModal, 0.8, kTol);
      CheckDerivatives(model, kept, full, full_forcing, Method::kModal, 1.3);
      CheckDerivatives(model, kept, odd, odd_forcing, Method::kModal, 0.8);
    }
    // kAuto takes the modal form here, and every harmonic used it.
    Condensation automatic(model, retained, full, full_forcing);
    automatic.Update(1.3);
    CHECK(automatic.modal());
    CHECK_FALSE(automatic.static_split());
    // Its rounding estimate covers the difference from the dense LU's result, itself
    // within the dense form's own estimate.
    Condensation dense(model, retained, full, full_forcing, Method::kDense);
    dense.Update(1.3);
    const Condensation::Rounding modal_rounding = automatic.EstimateRounding();
    const Condensation::Rounding dense_rounding = dense.EstimateRounding();
    for (int p = 0; p < full.num_harmonics(); ++p) {
      INFO("harmonic " << full.harmonics()[p]);
      const Eigen::MatrixXd bound = modal_rounding.z[p] + dense_rounding.z[p];
      CHECK(((automatic.Z(p) - dense.Z(p)).cwiseAbs().array() <= bound.array()).all());
      CHECK(modal_rounding.z[p].maxCoeff() > 0.0);
      // Not an empty bound: within 1e3 eps of |Z|.
      CHECK(modal_rounding.z[p].maxCoeff() < 1e3 * 2.2e-16 * dense.Z(p).cwiseAbs().maxCoeff());
      const Eigen::VectorXd f_bound = modal_rounding.f[p] + dense_rounding.f[p];
      CHECK(((automatic.F(p) - dense.F(p)).cwiseAbs().array() <= f_bound.array()).all());
    }
  }
}

TEST_CASE("Modal condensation names why a model does not qualify") {
  const HarmonicSet set(3, true);
  const auto modal = [&](const LinearModel& model) {
    Condensation condensation(model, {0}, set, {}, Method::kModal);
  };
  // Random damping: not diagonal in the modes.
  LinearModel model = ProportionalModel(6, false, 12);
  LinearModel random_damping = model;
  random_damping.damping = RandomModel(6, true, 13).damping;
  CHECK_THROWS_WITH_AS(modal(random_damping), doctest::Contains("method: modal condensation"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(modal(random_damping), doctest::Contains("C is not diagonal"),
                       std::invalid_argument);
  LinearModel asymmetric = model;
  asymmetric.stiffness.coeffRef(0, 1) += 0.5;
  CHECK_THROWS_WITH_AS(modal(asymmetric), doctest::Contains("symmetric"), std::invalid_argument);
  LinearModel massless = model;
  massless.mass = Eigen::MatrixXd(Eigen::MatrixXd(model.mass).array() * 0.0).sparseView();
  CHECK_THROWS_WITH_AS(modal(massless), doctest::Contains("M is not positive definite"),
                       std::invalid_argument);
  // A free-free pair (a rigid-body mode): H(0) does not exist.
  LinearModel free;
  const Eigen::Matrix2d k{{1.0, -1.0}, {-1.0, 1.0}};
  free.stiffness = k.sparseView();
  free.mass = Eigen::Matrix2d::Identity().sparseView();
  free.damping = (0.01 * k).sparseView();
  CHECK_THROWS_WITH_AS(modal(free), doctest::Contains("K is not positive definite"),
                       std::invalid_argument);
  // kAuto condenses all of them the direct way.
  for (const LinearModel& m : {random_damping, asymmetric}) {
    Condensation automatic(m, {0}, set, {});
    automatic.Update(0.7);
    CHECK_FALSE(automatic.modal());
  }
}

TEST_CASE("Modal condensation at an undamped resonance of the whole model takes the direct form") {
  // K = [[3, −1], [−1, 4]], M = I, C = 0: the whole model resonates at Ω² = (7 − √5)/2, where
  // 1/d_0 does not exist, while Z_ll = 4 − Ω² is regular and Z_red = 3 − Ω² − 1/(4 − Ω²).
  const LinearModel model = UndampedPair();
  const HarmonicSet set(3, true);
  Condensation condensation(model, {0}, set, {}, Method::kModal);
  const double squared = (7.0 - std::sqrt(5.0)) / 2.0;
  condensation.Update(std::sqrt(squared));
  CHECK_FALSE(condensation.modal());
  // Z_red vanishes there (one retained DOF of a singular Z): to the rounding of 3 − Ω² − ….
  constexpr double kCancellationTol = 1e-14;
  CHECK(std::abs(condensation.Z(0)(0, 0)) < kCancellationTol);
  // Harmonic 3 is off resonance and modal; both forms agree with the closed form.
  const double z3 = 3.0 - 9.0 * squared - 1.0 / (4.0 - 9.0 * squared);
  CHECK(std::abs(condensation.Z(1)(0, 0) - z3) < kCancellationTol * std::abs(z3) * 10);
}

}  // namespace
}  // namespace nfrc
