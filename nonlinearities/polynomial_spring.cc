#include "nonlinearities/polynomial_spring.h"

#include <cmath>
#include <stdexcept>

#include "nonlinearities/law_spec.h"

namespace nfrc {

PolynomialSpring::PolynomialSpring(std::string type, int dof, int other, std::vector<Term> terms)
    : type_(std::move(type)), dof_(dof), other_(other), terms_(std::move(terms)) {
  if (terms_.empty()) throw std::invalid_argument("terms: at least one term is needed");
  for (const Term& term : terms_) {
    if (term.power < 2) {
      throw std::invalid_argument("power: must be at least 2 (linear terms belong in K), got " +
                                  std::to_string(term.power));
    }
  }
  if (dof_ == other_) throw std::invalid_argument("other: must differ from dof");
}

std::unique_ptr<Nonlinearity> CubicSpringSpec::MakeHarmonic(const LinearModel& /*model*/) const {
  return std::make_unique<PolynomialSpring>(std::string(kType), dof, other,
                                            std::vector<PolynomialSpring::Term>{{3, coefficient}});
}

std::unique_ptr<Nonlinearity> PolynomialSpringSpec::MakeHarmonic(
    const LinearModel& /*model*/) const {
  return std::make_unique<PolynomialSpring>(std::string(kType), dof, other, terms);
}

std::vector<int> PolynomialSpring::Dofs() const {
  if (other_ < 0) return {dof_};
  return {dof_, other_};
}

void PolynomialSpring::Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                double /*omega*/, Eigen::Ref<Eigen::VectorXd> residual,
                                Eigen::MatrixXd* jacobian, Eigen::VectorXd* d_omega) const {
  const FourierTransform& fourier = *ctx.fourier;
  const int nc = ctx.num_coefficients();
  const int row_dof = ctx.DofOffset(0);
  Eigen::VectorXd relative = y.segment(row_dof, nc);
  const bool grounded = other_ < 0;
  const int row_other = grounded ? -1 : ctx.DofOffset(1);
  if (!grounded) relative -= y.segment(row_other, nc);

  const Eigen::MatrixXd u = fourier.ToTime(relative);
  Eigen::MatrixXd force(u.rows(), 1);
  Eigen::VectorXd stiffness(u.rows());
  for (Eigen::Index j = 0; j < u.rows(); ++j) {
    double f = 0.0;
    double df = 0.0;
    for (const Term& term : terms_) {
      f += term.coefficient * std::pow(u(j, 0), term.power);
      df += term.coefficient * term.power * std::pow(u(j, 0), term.power - 1);
    }
    force(j, 0) = f;
    stiffness(j) = df;
  }
  const Eigen::VectorXd force_coefficients = fourier.ToCoefficients(force);
  residual.segment(row_dof, nc) += force_coefficients;
  if (!grounded) residual.segment(row_other, nc) -= force_coefficients;

  if (jacobian != nullptr) {
    const Eigen::MatrixXd block = fourier.WeightedProduct(stiffness);
    jacobian->block(row_dof, row_dof, nc, nc) += block;
    if (!grounded) {
      jacobian->block(row_dof, row_other, nc, nc) -= block;
      jacobian->block(row_other, row_dof, nc, nc) -= block;
      jacobian->block(row_other, row_other, nc, nc) += block;
    }
  }
  // A displacement law: no dependence on ω.
  (void)d_omega;
}

}  // namespace nfrc
