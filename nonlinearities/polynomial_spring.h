#pragma once

#include <memory>
#include <vector>

#include "core/linear_model.h"
#include "core/nonlinearity.h"

namespace nfrc {

// Polynomial stiffness f(u) = Σ_p c_p u^p on the relative displacement u = x_dof − x_other
// (or u = x_dof against ground), evaluated by alternating frequency–time: +f acts on
// `dof`, −f on `other`. The cubic spring is the single term p = 3.
class PolynomialSpring : public Nonlinearity {
 public:
  struct Term {
    int power = 3;             // p ≥ 2 (linear terms belong in K)
    double coefficient = 0.0;  // force / length^p
  };

  // other < 0 means ground. Throws std::invalid_argument for an empty term list, p < 2,
  // or dof == other.
  PolynomialSpring(std::string type, int dof, int other, std::vector<Term> terms);

  std::string type() const override { return type_; }
  std::vector<int> Dofs() const override;
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;

  int dof() const { return dof_; }
  int other() const { return other_; }
  const std::vector<Term>& terms() const { return terms_; }

 private:
  std::string type_;
  int dof_;
  int other_;
  std::vector<Term> terms_;
};

}  // namespace nfrc
