#pragma once

#include "nonlinearities/contact_geometry.h"
#include "validation/time_law.h"

namespace nfrc {

// Unilateral contact against a flexible massless obstacle (a penalty spring of stiffness k,
// N/m) in the time domain: λ = k·max(0, −g) with the gap g = g0(φ) − n(x_dof − x_other) of
// ContactGeometry, pushing the DOF back with −n·λ in f_nl (the HBM laws' sign). Modes: open
// and closed; the root function is g, so the kink of max(0, ·) is never inside a step.
class ContactTimeLaw : public TimeLaw {
 public:
  // stiffness > 0 (the rigid obstacle belongs to the explicit scheme, central_difference.h).
  ContactTimeLaw(std::string type, ContactGeometry geometry, double stiffness);

  std::string type() const override { return type_; }
  void Residual(const TimeLawLayout& layout, const DaeView& s,
                Eigen::Ref<Eigen::VectorXd> residual) const override;
  void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                std::vector<Eigen::Triplet<double>>* entries) const override;
  int NumRoots() const override { return 1; }
  void Roots(const TimeLawLayout& layout, const DaeView& s, double* g) const override;
  void InitMode(const TimeLawLayout& layout, const DaeView& s) override;
  void OnRoot(const TimeLawLayout& layout, const DaeView& s, int root) override;
  bool Admissible(const TimeLawLayout& layout, const DaeView& s) override;
  void Force(const TimeLawLayout& layout, const DaeView& s,
             Eigen::Ref<Eigen::VectorXd> f_nl) const override;
  bool InPhase() const override { return closed_; }
  std::string PhaseName() const override { return "contact"; }
  int ModeIndex() const override { return closed_ ? 1 : 0; }
  std::vector<std::pair<int, double>> StiffnessBound() const override;
  // "gap" g and "force" λ.
  std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                      const DaeView& s) const override;
  bool ExplicitForce(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const override;

  // g at displacement x and excitation phase φ.
  double Gap(double phase, const Eigen::VectorXd& x) const;

 private:
  std::string type_;
  ContactGeometry geometry_;
  double stiffness_;
  bool closed_ = false;
};

}  // namespace nfrc
