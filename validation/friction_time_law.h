#pragma once

#include "nonlinearities/friction_equality.h"
#include "validation/time_law.h"

namespace nfrc {

// Coulomb friction under a constant normal load in the time domain, on `dof` against ground
// or relative to `other` (sliding velocity v_rel = v_dof − v_other); the friction force r acts
// on `dof` (−r on `other`), so the momentum rows get −r (+r), as in CoulombFriction.
//
// Exact laws (min_max, hueber): r is an own algebraic unknown and the mode is slip+ (r = −μN),
// slip− (r = +μN) or stick, posed in index-1 form: the relative acceleration is zero (ẋ_rel = 0
// instead when the DOF is massless) and r follows from the equations of motion. Slip → stick
// where v_rel reaches zero and the sticking force is admissible (|r| ≤ μN(1 + tolerance)),
// else slip reverses; stick → slip where |r| reaches μN.
// Regularised laws (tanh, arctan, piecewise_linear): r = r(v_rel) is a force, no own unknown;
// piecewise_linear switches mode at |v_rel| = δ. "sign" has no time-domain form.
class FrictionTimeLaw : public TimeLaw {
 public:
  enum class Mode { kSlipPositive = 0, kSlipNegative = 1, kStick = 2 };

  // `massless` says that `dof` has no mass (its v is algebraic); throws std::invalid_argument
  // for the sign law or μN < 0.
  FrictionTimeLaw(int dof, int other, FrictionParameters parameters, bool massless,
                  double admissibility_tolerance = 1e-9);

  // Massless and undamped DOF (exact laws): the integrator differentiates its momentum row,
  // since in slip that row with r = ∓μN fixed would pin x (index 2). r then becomes a
  // differential unknown held by ṙ = 0 in slip (snapped to ∓μN at each re-initialisation);
  // the stick row ẋ_rel = 0 stays, and the differentiated row yields ṙ there.
  void set_differentiated(bool differentiated) { differentiated_ = differentiated; }
  bool differentiated() const { return differentiated_; }

  std::string type() const override { return "coulomb_friction"; }
  int NumOwn() const override;
  bool OwnIsDifferential(int k) const override;
  void SnapOwn(const TimeLawLayout& layout, const DaeView& s,
               Eigen::Ref<Eigen::VectorXd> own) const override;
  void Residual(const TimeLawLayout& layout, const DaeView& s,
                Eigen::Ref<Eigen::VectorXd> residual) const override;
  void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                std::vector<Eigen::Triplet<double>>* entries) const override;
  int NumRoots() const override;
  void Roots(const TimeLawLayout& layout, const DaeView& s, double* g) const override;
  void InitMode(const TimeLawLayout& layout, const DaeView& s) override;
  void OnRoot(const TimeLawLayout& layout, const DaeView& s, int root) override;
  bool Admissible(const TimeLawLayout& layout, const DaeView& s) override;
  void Force(const TimeLawLayout& layout, const DaeView& s,
             Eigen::Ref<Eigen::VectorXd> f_nl) const override;
  bool InPhase() const override { return mode_ == Mode::kStick; }
  std::string PhaseName() const override { return "stick"; }
  int ModeIndex() const override { return static_cast<int>(mode_); }
  // "force" r and "velocity" v_rel.
  std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                      const DaeView& s) const override;
  bool ExplicitForce(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const override;

 private:
  int dof_;
  int other_;
  FrictionParameters parameters_;
  bool massless_;
  double tolerance_;
  bool differentiated_ = false;
  Mode mode_ = Mode::kStick;
};

}  // namespace nfrc
