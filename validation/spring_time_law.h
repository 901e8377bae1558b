#pragma once

#include <vector>

#include "nonlinearities/polynomial_spring.h"
#include "validation/time_law.h"

namespace nfrc {

// The polynomial spring f(u) = Σ c_p u^p on u = x_dof − x_other in the time domain (smooth:
// no modes, no roots); +f on `dof`, −f on `other`. The cubic spring is the smooth baseline.
class SpringTimeLaw : public TimeLaw {
 public:
  SpringTimeLaw(std::string type, int dof, int other, std::vector<PolynomialSpring::Term> terms);

  std::string type() const override { return type_; }
  void Residual(const TimeLawLayout& layout, const DaeView& s,
                Eigen::Ref<Eigen::VectorXd> residual) const override;
  void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                std::vector<Eigen::Triplet<double>>* entries) const override;
  void Force(const TimeLawLayout& layout, const DaeView& s,
             Eigen::Ref<Eigen::VectorXd> f_nl) const override;
  // "force" f(u) and "displacement" u.
  std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                      const DaeView& s) const override;
  bool ExplicitForce(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const override;

 private:
  std::string type_;
  int dof_;
  int other_;
  std::vector<PolynomialSpring::Term> terms_;
};

}  // namespace nfrc
