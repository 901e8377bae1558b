#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "continuation/problem.h"

namespace nfrc::testing {

// R = y³/3 − y − λ: folds where R_y = y² − 1 = 0, i.e. at (y, λ) = (−1, 2/3) and (1, −2/3).
class CubicProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const double v = y(0);
    (*residual)(0) = v * v * v / 3.0 - v - lambda;
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = v * v - 1.0;
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = -1.0;
    return true;
  }
};

// R = y² + λ² − 1: the unit circle, a closed curve with folds at λ = ±1 (y = 0).
class CircleProblem : public ContinuationProblem {
 public:
  int NumUnknowns() const override { return 1; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    (*residual)(0) = y(0) * y(0) + lambda * lambda - 1.0;
    if (jacobian_y != nullptr) (*jacobian_y)(0, 0) = 2.0 * y(0);
    if (jacobian_lambda != nullptr) (*jacobian_lambda)(0) = 2.0 * lambda;
    return true;
  }
};

// One-harmonic balance of ẍ + c ẋ + x + γ x³ = F cos ωt with x = a cos ωt + b sin ωt, λ = ω:
//   (1 − ω²) a + c ω b + κ A² a − F = 0,  (1 − ω²) b − c ω a + κ A² b = 0,
// κ = 3γ/4, A² = a² + b². With `with_energy`, a third unknown z = A² (second scale group)
// is appended with R₃ = z − A², so that unknowns of two units are present.
class DuffingProblem : public ContinuationProblem {
 public:
  static constexpr double kDamping = 0.05;
  static constexpr double kCubic = 0.1;
  static constexpr double kForce = 0.18;

  explicit DuffingProblem(bool with_energy = false) : with_energy_(with_energy) {}

  int NumUnknowns() const override { return with_energy_ ? 3 : 2; }
  std::vector<int> ScaleGroups() const override {
    return with_energy_ ? std::vector<int>{0, 0, 1} : std::vector<int>{0, 0};
  }
  bool Evaluate(const Eigen::VectorXd& y, double omega, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const double kappa = 0.75 * kCubic, c = kDamping;
    const double a = y(0), b = y(1), amplitude2 = a * a + b * b, q = 1.0 - omega * omega;
    (*residual)(0) = q * a + c * omega * b + kappa * amplitude2 * a - kForce;
    (*residual)(1) = q * b - c * omega * a + kappa * amplitude2 * b;
    if (with_energy_) (*residual)(2) = y(2) - amplitude2;
    if (jacobian_y != nullptr) {
      jacobian_y->setZero();
      (*jacobian_y)(0, 0) = q + kappa * (amplitude2 + 2.0 * a * a);
      (*jacobian_y)(0, 1) = c * omega + 2.0 * kappa * a * b;
      (*jacobian_y)(1, 0) = -c * omega + 2.0 * kappa * a * b;
      (*jacobian_y)(1, 1) = q + kappa * (amplitude2 + 2.0 * b * b);
      if (with_energy_) {
        (*jacobian_y)(2, 0) = -2.0 * a;
        (*jacobian_y)(2, 1) = -2.0 * b;
        (*jacobian_y)(2, 2) = 1.0;
      }
    }
    if (jacobian_lambda != nullptr) {
      jacobian_lambda->setZero();
      (*jacobian_lambda)(0) = -2.0 * omega * a + c * b;
      (*jacobian_lambda)(1) = -2.0 * omega * b - c * a;
    }
    return true;
  }

 private:
  bool with_energy_;
};

// The same problem in other units: Y = y_unit ⊙ y, Λ = lambda_unit·λ, P = residual_unit·R.
class UnitsProblem : public ContinuationProblem {
 public:
  UnitsProblem(ContinuationProblem& inner, Eigen::VectorXd y_unit, double lambda_unit,
               double residual_unit)
      : inner_(inner),
        y_unit_(std::move(y_unit)),
        lambda_unit_(lambda_unit),
        residual_unit_(residual_unit) {}

  int NumUnknowns() const override { return inner_.NumUnknowns(); }
  std::vector<int> ScaleGroups() const override { return inner_.ScaleGroups(); }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    const Eigen::VectorXd inner_y = y.cwiseQuotient(y_unit_);
    if (!inner_.Evaluate(inner_y, lambda / lambda_unit_, residual, jacobian_y, jacobian_lambda)) {
      return false;
    }
    *residual *= residual_unit_;
    if (jacobian_y != nullptr) {
      *jacobian_y = residual_unit_ * *jacobian_y * y_unit_.cwiseInverse().asDiagonal();
    }
    if (jacobian_lambda != nullptr) *jacobian_lambda *= residual_unit_ / lambda_unit_;
    return true;
  }

 private:
  ContinuationProblem& inner_;
  Eigen::VectorXd y_unit_;
  double lambda_unit_;
  double residual_unit_;
};

// Fold frequencies of DuffingProblem computed without the engine: with p = A², q = 1 − ω²,
// the amplitude relation G = p[(q + κp)² + c²ω²] − F² = 0 has a fold in ω where also
// ∂G/∂p = 3κ²p² + 4κqp + q² + c²ω² = 0. For each root p(ω) of ∂G/∂p, G(p(ω), ω) changes
// sign at the fold; bisection on [lo, hi] finds it to rounding.
inline double DuffingFoldFrequency(double lo, double hi, bool larger_root) {
  const double kappa = 0.75 * DuffingProblem::kCubic, c = DuffingProblem::kDamping;
  auto g_on_fold_curve = [&](double omega) {
    const double q = 1.0 - omega * omega;
    const double qa = 3.0 * kappa * kappa, qb = 4.0 * kappa * q, qc = q * q + c * c * omega * omega;
    const double root = std::sqrt(qb * qb - 4.0 * qa * qc);
    const double p = (-qb + (larger_root ? root : -root)) / (2.0 * qa);
    const double shifted = q + kappa * p;
    return p * (shifted * shifted + c * c * omega * omega) -
           DuffingProblem::kForce * DuffingProblem::kForce;
  };
  const double g_lo = g_on_fold_curve(lo);
  for (int i = 0; i < 200 && hi - lo > 0.0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    ((g_on_fold_curve(mid) > 0.0) == (g_lo > 0.0) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace nfrc::testing
