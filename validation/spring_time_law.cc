#include "validation/spring_time_law.h"

#include <cassert>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace nfrc {
namespace {

// f(u) and df/du of the polynomial Σ c_p u^p.
std::pair<double, double> Evaluate(const std::vector<PolynomialSpring::Term>& terms, double u) {
  double force = 0.0;
  double slope = 0.0;
  for (const auto& term : terms) {
    force += term.coefficient * std::pow(u, term.power);
    slope += term.coefficient * term.power * std::pow(u, term.power - 1);
  }
  return {force, slope};
}

}  // namespace

SpringTimeLaw::SpringTimeLaw(std::string type, int dof, int other,
                             std::vector<PolynomialSpring::Term> terms)
    : type_(std::move(type)), dof_(dof), other_(other), terms_(std::move(terms)) {
  if (dof_ < 0 || dof_ == other_) throw std::invalid_argument("spring: bad dof/other");
  if (terms_.empty()) throw std::invalid_argument("spring: no terms");
  for (const auto& term : terms_) {
    if (term.power < 2) throw std::invalid_argument("spring: power must be >= 2");
  }
}

void SpringTimeLaw::Residual(const TimeLawLayout& layout, const DaeView& s,
                             Eigen::Ref<Eigen::VectorXd> residual) const {
  const double u = s.x(dof_) - (other_ >= 0 ? s.x(other_) : 0.0);
  const double force = Evaluate(terms_, u).first;
  residual(layout.Momentum(dof_)) += force;
  if (other_ >= 0) residual(layout.Momentum(other_)) -= force;
}

void SpringTimeLaw::Jacobian(const TimeLawLayout& layout, const DaeView& s, double /*cj*/,
                             std::vector<Eigen::Triplet<double>>* entries) const {
  const double u = s.x(dof_) - (other_ >= 0 ? s.x(other_) : 0.0);
  const double slope = Evaluate(terms_, u).second;
  entries->emplace_back(layout.Momentum(dof_), layout.X(dof_), slope);
  if (other_ < 0) return;
  entries->emplace_back(layout.Momentum(dof_), layout.X(other_), -slope);
  entries->emplace_back(layout.Momentum(other_), layout.X(dof_), -slope);
  entries->emplace_back(layout.Momentum(other_), layout.X(other_), slope);
}

void SpringTimeLaw::Force(const TimeLawLayout& /*layout*/, const DaeView& s,
                          Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double u = s.x(dof_) - (other_ >= 0 ? s.x(other_) : 0.0);
  const double force = Evaluate(terms_, u).first;
  f_nl(dof_) += force;
  if (other_ >= 0) f_nl(other_) -= force;
}

std::vector<std::pair<std::string, double>> SpringTimeLaw::Signals(const TimeLawLayout& /*layout*/,
                                                                   const DaeView& s) const {
  const double u = s.x(dof_) - (other_ >= 0 ? s.x(other_) : 0.0);
  return {{"force", Evaluate(terms_, u).first}, {"displacement", u}};
}

bool SpringTimeLaw::ExplicitForce(double /*phase*/, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& /*v*/,
                                  Eigen::Ref<Eigen::VectorXd> f_nl) const {
  const double u = x(dof_) - (other_ >= 0 ? x(other_) : 0.0);
  const double force = Evaluate(terms_, u).first;
  f_nl(dof_) += force;
  if (other_ >= 0) f_nl(other_) -= force;
  return true;
}

}  // namespace nfrc
