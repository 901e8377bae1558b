#include "models/model_check.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/errors.h"

namespace nfrc {
namespace {

Eigen::SparseMatrix<double> Dense(const Eigen::MatrixXd& matrix) { return matrix.sparseView(); }

LinearModel Model(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c, const Eigen::MatrixXd& k) {
  LinearModel model;
  model.mass = Dense(m);
  model.damping = Dense(c);
  model.stiffness = Dense(k);
  return model;
}

bool Warns(const ModelCheck& check, const std::string& text) {
  for (const std::string& warning : check.warnings) {
    if (warning.find(text) != std::string::npos) return true;
  }
  return false;
}

// A fixed–free chain of n unit masses and springs (positive definite K and M), with Rayleigh
// damping 0.01 K: the well-posed model every check leaves alone.
LinearModel Chain(int n) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) = i + 1 < n ? 2.0 : 1.0;
    if (i + 1 < n) k(i, i + 1) = k(i + 1, i) = -1.0;
  }
  return Model(Eigen::MatrixXd::Identity(n, n), 0.01 * k, k);
}

TEST_CASE("model check: a damped chain passes, a massless DOF too") {
  CHECK(CheckLinearModel(Chain(5)).warnings.empty());
  LinearModel massless = Chain(5);
  massless.mass.coeffRef(4, 4) = 0.0;  // mass at a friction interface may be zero
  CHECK(CheckLinearModel(massless).warnings.empty());
}

TEST_CASE("model check: a negative or non-symmetric mass is refused, naming model.M") {
  LinearModel negative = Chain(3);
  negative.mass.coeffRef(1, 1) = -1.0;
  CHECK_THROWS_WITH_AS(CheckLinearModel(negative),
                       doctest::Contains("model.M: not positive semidefinite, 1 negative "
                                         "eigenvalue (the lowest -1)"),
                       InputError);
  LinearModel skew = Chain(3);
  skew.mass.coeffRef(0, 1) = 0.5;
  CHECK_THROWS_WITH_AS(CheckLinearModel(skew), doctest::Contains("model.M: not symmetric"),
                       InputError);
}

TEST_CASE("model check: the issue's negatively damped mode, an indefinite and a circulatory K") {
  // C = [[0.01, 0.2], [0.2, 0.01]]: eigenvalues 0.21 and -0.19 (closed form 0.01 ± 0.2).
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(2, 2);
  Eigen::MatrixXd c(2, 2), k(2, 2);
  c << 0.01, 0.2, 0.2, 0.01;
  k << 1.0, 0.0, 0.0, 4.0;
  const ModelCheck damped = CheckLinearModel(Model(identity, c, k));
  CHECK(Warns(damped,
              "model.C: its symmetric part is indefinite, 1 negative eigenvalue (the "
              "lowest -0.19)"));
  // The undamped modes are the unit vectors: their modal damping is C's diagonal, 0.01 > 0.
  CHECK(Warns(damped, "no undamped mode has negative modal damping"));
  Eigen::MatrixXd c_mode(2, 2);
  c_mode << -0.02, 0.0, 0.0, 0.01;
  CHECK(Warns(CheckLinearModel(Model(identity, c_mode, k)),
              "negatively damped: mode 1 (omega 1, damping ratio -0.01)"));

  // With K = [[2, -1], [-1, 2]] the modes (1, 1) and (1, -1) also diagonalise C: the second
  // (ω² = 3) has modal damping 0.01 - 0.2 = -0.19, so s² - 0.19 s + 3 = 0 and the pair
  // s = 0.095 ± i√(3 - 0.095²) grows (closed form). With K = diag(1, 4) the same C leaves
  // every exponent in the left half-plane (real parts -0.0051 and -0.0049).
  Eigen::MatrixXd coupled(2, 2);
  coupled << 2.0, -1.0, -1.0, 2.0;
  const ModelCheck unstable = CheckLinearModel(Model(identity, c, coupled));
  CHECK(Warns(unstable, "negatively damped: mode 2"));
  CHECK(Warns(unstable,
              "model: the linear structure alone (without the laws) is unstable: 2 "
              "exponents of M s^2 + C s + K with a positive real part (the largest "
              "growth rate 0.095 per time unit)"));
  CHECK_FALSE(Warns(damped, "the linear structure alone"));

  Eigen::MatrixXd bistable(2, 2);
  bistable << -1.0, 0.0, 0.0, 4.0;
  CHECK(Warns(CheckLinearModel(Model(identity, 0.01 * identity, bistable)),
              "model.K: indefinite, 1 negative eigenvalue (the lowest -1)"));
  Eigen::MatrixXd circulatory(2, 2);
  circulatory << 1.0, 0.3, -0.3, 4.0;
  CHECK(Warns(CheckLinearModel(Model(identity, 0.01 * identity, circulatory)),
              "model.K: not symmetric"));
}

TEST_CASE("model check: the sparse inertia of a large chain agrees with the dense eigenvalues") {
  // Above kDenseCheckDofs the inertia comes from a sparse LDL^T. A chain with one spring of
  // the wrong sign has exactly one negative eigenvalue (counted densely on a small twin).
  auto with_negative_spring = [](int n) {
    LinearModel model = Chain(n);
    model.stiffness.coeffRef(0, 0) = 1.0 - 3.0;  // the ground spring now -2
    return model;
  };
  const ModelCheck small = CheckLinearModel(with_negative_spring(50));
  const ModelCheck large = CheckLinearModel(with_negative_spring(kDenseCheckDofs + 500));
  CHECK(Warns(small, "model.K: indefinite, 1 negative eigenvalue"));
  CHECK(Warns(large, "model.K: indefinite, 1 negative eigenvalue"));
  CHECK(CheckLinearModel(Chain(kDenseCheckDofs + 500)).warnings.empty());
  LinearModel negative_mass = Chain(kDenseCheckDofs + 500);
  negative_mass.mass.coeffRef(7, 7) = -1.0;
  CHECK_THROWS_WITH_AS(CheckLinearModel(negative_mass), doctest::Contains("model.M"), InputError);
}

}  // namespace
}  // namespace nfrc
