#include "core/dynamic_stiffness.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "core/harmonic_set.h"

namespace nfrc {
namespace {

using Complex = std::complex<double>;

// A small non-symmetric model with every matrix full, so any misplaced term shows.
LinearModel RandomModel(int n) {
  std::srand(7);
  LinearModel model;
  const Eigen::MatrixXd m = Eigen::MatrixXd::Random(n, n) + 3.0 * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd c = 0.1 * Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd k = Eigen::MatrixXd::Random(n, n) + 5.0 * Eigen::MatrixXd::Identity(n, n);
  model.mass = m.sparseView();
  model.damping = c.sparseView();
  model.stiffness = k.sparseView();
  return model;
}

TEST_CASE("DynamicStiffness real blocks equal the projected time-domain residual") {
  // The residual M ẍ + C ẋ + K x of x(θ) = a_0 + Σ a_k cos kθ + b_k sin kθ, θ = ωt, is
  // evaluated at N_t samples from hand-written derivatives and projected with the
  // trapezoidal rule, which is exact for harmonics ≤ H when N_t ≥ 2H + 1.
  // Terms are O(10); sums over N_t = 16 samples lose a few ulps (measured 7e-14).
  constexpr double kTol = 1e-11;
  const int n = 3;
  const LinearModel model = RandomModel(n);
  const Eigen::MatrixXd m(model.mass), c(model.damping), k_mat(model.stiffness);
  const double omega = 1.7;
  for (bool odd : {false, true}) {
    const HarmonicSet set(4, odd, 16);
    const int n_t = set.num_samples();
    const int n_c = set.NumCoefficients();
    const Eigen::MatrixXd coef = Eigen::MatrixXd::Random(n, n_c);  // row = DOF

    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, n_t), v = x, a = x;
    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[p];
      for (int j = 0; j < n_t; ++j) {
        const double theta = 2.0 * std::numbers::pi * j / n_t;
        const Eigen::VectorXd ak = coef.col(set.CosIndex(p));
        if (k == 0) {
          x.col(j) += ak;
          continue;
        }
        const Eigen::VectorXd bk = coef.col(set.SinIndex(p));
        const double w = k * omega;
        x.col(j) += ak * std::cos(k * theta) + bk * std::sin(k * theta);
        v.col(j) += w * (-ak * std::sin(k * theta) + bk * std::cos(k * theta));
        a.col(j) += -w * w * (ak * std::cos(k * theta) + bk * std::sin(k * theta));
      }
    }
    const Eigen::MatrixXd residual = m * a + c * v + k_mat * x;  // n × N_t

    for (int p = 0; p < set.num_harmonics(); ++p) {
      const int k = set.harmonics()[p];
      Eigen::VectorXd proj_a = Eigen::VectorXd::Zero(n), proj_b = proj_a;
      for (int j = 0; j < n_t; ++j) {
        const double theta = 2.0 * std::numbers::pi * j / n_t;
        const double scale = k == 0 ? 1.0 / n_t : 2.0 / n_t;
        proj_a += scale * residual.col(j) * std::cos(k * theta);
        proj_b += scale * residual.col(j) * std::sin(k * theta);
      }
      const Eigen::MatrixXcd z(DynamicStiffness(model, k, omega));
      const Eigen::MatrixXd re = z.real(), im = z.imag();
      const Eigen::VectorXd ak = coef.col(set.CosIndex(p));
      if (k == 0) {
        CHECK(im.cwiseAbs().maxCoeff() == 0.0);
        CHECK((re * ak - proj_a).cwiseAbs().maxCoeff() < kTol);
        continue;
      }
      const Eigen::VectorXd bk = coef.col(set.SinIndex(p));
      // [[Re Z, Im Z], [−Im Z, Re Z]] on (a_k, b_k).
      CHECK((re * ak + im * bk - proj_a).cwiseAbs().maxCoeff() < kTol);
      CHECK((-im * ak + re * bk - proj_b).cwiseAbs().maxCoeff() < kTol);
      // Complex form: Z (a − ib) = f_cos − i f_sin.
      const Eigen::VectorXcd f = z * (ak.cast<Complex>() - Complex(0, 1) * bk.cast<Complex>());
      CHECK((f.real() - proj_a).cwiseAbs().maxCoeff() < kTol);
      CHECK((-f.imag() - proj_b).cwiseAbs().maxCoeff() < kTol);
    }
  }
}

TEST_CASE("DynamicStiffnessDerivative matches central differences") {
  // Z is quadratic in ω, so central differences have no truncation error; what remains is
  // rounding, eps·|Z|/h ≈ 2e-16·250/1e-4 = 5e-10 for k = 7 (|Z| ≈ (kω)²|M|), against entries
  // of dZ/dω up to ~400.
  constexpr double kTol = 1e-8;
  const LinearModel model = RandomModel(4);
  const double omega = 0.9;
  const double h = 1e-4;
  for (int k : {0, 1, 3, 7}) {
    const Eigen::MatrixXcd fd = (Eigen::MatrixXcd(DynamicStiffness(model, k, omega + h)) -
                                 Eigen::MatrixXcd(DynamicStiffness(model, k, omega - h))) /
                                (2.0 * h);
    const Eigen::MatrixXcd dz(DynamicStiffnessDerivative(model, k, omega));
    CHECK((dz - fd).cwiseAbs().maxCoeff() < kTol);
    if (k > 0) CHECK(dz.cwiseAbs().maxCoeff() > 0.1);  // not trivially zero
  }
}

}  // namespace
}  // namespace nfrc
