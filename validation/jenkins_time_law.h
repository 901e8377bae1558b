#pragma once

#include <string>
#include <utility>
#include <vector>

#include "validation/time_law.h"

namespace nfrc {

// The Jenkins element (elastic dry friction) in the time domain: a tangential spring of
// stiffness k_t (N/m) in series with a Coulomb slider of limit μN (N), on the relative
// displacement u = x_dof − x_other (other = −1: against ground). Its force f = k_t (u − w), w the
// slider position (m), acts as a spring k u does: +f on `dof`'s momentum row, −f on `other`'s;
// |f| ≤ μN.
//
// f is one DIFFERENTIAL own unknown (the element has memory: f, not u, says where the slider
// is). Modes: stick, ḟ = k_t u̇ (the slider holds, the spring deforms); slip+ and slip−, ḟ = 0
// with f = ±μN (snapped by SnapOwn at a re-initialisation, so that f does not carry the root
// location's error). Stick → slip± where f reaches ±μN(1 + tolerance); slip → stick where u̇
// changes sign (the spring unloads). An integrator that does not snap (IdaDae does, at every
// restart) leaves a slip with the f its release root left, at or just beyond μN(1 + tolerance):
// the stick that follows accepts it while the spring unloads and moves its release bound just
// beyond it (Admissible).
class JenkinsTimeLaw : public TimeLaw {
 public:
  enum class Mode { kSlipPositive = 0, kSlipNegative = 1, kStick = 2 };

  // stiffness k_t > 0 (N/m), limit μN ≥ 0 (N), both finite; `dof` ≥ 0 and `other` ≠ `dof`.
  // Throws std::invalid_argument naming the field ("stiffness: ...", "mu*normal_load: ...",
  // "other: ...", "dof: ...", "admissibility_tolerance: ...").
  JenkinsTimeLaw(int dof, int other, double stiffness, double limit,
                 double admissibility_tolerance = 1e-9);

  // `dof` or `other` has no mass (its v is algebraic, its v̇ meaningless): the relative velocity
  // is then taken from ẋ, and a near-zero velocity is not decided by the acceleration.
  void set_massless(bool massless) { massless_ = massless; }
  bool massless() const { return massless_; }

  double stiffness() const { return stiffness_; }
  double limit() const { return limit_; }
  Mode mode() const { return mode_; }

  std::string type() const override { return "jenkins"; }
  int NumOwn() const override { return 1; }
  bool OwnIsDifferential(int k) const override { return k == 0; }
  // f is the harmonic Jenkins law's "force" signal.
  std::string OwnSignal(int k) const override { return k == 0 ? "force" : ""; }
  // μN while f sticks at least kFreeMargin·μN inside the bound: a perturbation of a few
  // 1e-4 μN (the monodromy's steps) then keeps the stick; nearer, f is taken as fixed (slip).
  double OwnStateScale(int k, double value) const override;
  void SnapOwn(const TimeLawLayout& layout, const DaeView& s,
               Eigen::Ref<Eigen::VectorXd> own) const override;
  void Residual(const TimeLawLayout& layout, const DaeView& s,
                Eigen::Ref<Eigen::VectorXd> residual) const override;
  void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                std::vector<Eigen::Triplet<double>>* entries) const override;
  int NumRoots() const override { return 2; }
  void Roots(const TimeLawLayout& layout, const DaeView& s, double* g) const override;
  void InitMode(const TimeLawLayout& layout, const DaeView& s) override;
  void OnRoot(const TimeLawLayout& layout, const DaeView& s, int root) override;
  bool Admissible(const TimeLawLayout& layout, const DaeView& s) override;
  void Force(const TimeLawLayout& layout, const DaeView& s,
             Eigen::Ref<Eigen::VectorXd> f_nl) const override;
  bool InPhase() const override { return mode_ == Mode::kStick; }
  std::string PhaseName() const override { return "stick"; }
  int ModeIndex() const override { return static_cast<int>(mode_); }
  // k_t at `dof` and at `other` (if any): the stick spring.
  std::vector<std::pair<int, double>> StiffnessBound() const override;
  // "force" f (N), "displacement" u (m) and "slider" w = u − f/k_t (m).
  std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                      const DaeView& s) const override;
  // A hysteretic law needs its state f: no explicit form (false).
  bool ExplicitForce(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const override;

 private:
  // μN(1 + tolerance) (N): the release bound of stick, and its admissibility bound.
  double Bound() const { return limit_ * (1.0 + tolerance_); }
  // u̇ = v_dof − v_other (m/s); ẋ for a massless DOF.
  double RelativeVelocity(const DaeView& s) const;
  // Stick accepted with force f (N): sets its release bound.
  void AcceptStick(double f);

  int dof_;
  int other_;
  double stiffness_;
  double limit_;
  double tolerance_;
  bool massless_ = false;
  Mode mode_ = Mode::kStick;
  // The release bound of the current stick (N): Bound(), or just beyond the |f| it was
  // entered with when a sliding force that the integrator did not snap exceeded Bound().
  double release_bound_ = 0.0;
};

}  // namespace nfrc
