#pragma once

#include <string>
#include <utility>
#include <vector>

#include "nonlinearities/contact_geometry.h"
#include "validation/time_law.h"

namespace nfrc {

// Unilateral contact with Coulomb friction in the time domain: a penalty contact against a
// flexible massless obstacle (as ContactTimeLaw) whose normal force sets the friction limit of
// an exact Coulomb slider (as FrictionTimeLaw) on a tangential pair of DOFs.
//
// Normal: the gap g = g0(φ) − n (x_dof − x_other) of ContactGeometry and the normal force
// λ_N = k·max(0, −g) ≥ 0 (N), +n·λ_N on `normal.dof`'s momentum row and −n·λ_N on
// `normal.other`'s. A preload N0 ≥ 0 (N) presses `normal.dof` toward the obstacle in every mode:
// the structure receives +n·N0 there (f_nl gets −n·N0) and −n·N0 on `normal.other`.
// Tangential: the sliding velocity v = v_tangent_dof − v_tangent_other (m/s) and the friction
// force r, the law's one algebraic own unknown, acting on `tangent_dof` (−r in its momentum row,
// +r in `tangent_other`'s), with the limit μλ_N.
//
// Modes: open (g > 0): r = 0, and no force but the preload; closed and slip+ (v > 0):
// r = −μλ_N(x); slip−: r = +μλ_N(x); stick: the relative tangential acceleration vanishes
// (index 1: r follows from the equations of motion). λ_N = −k g without the max while closed, so
// each mode's residual is smooth. Roots: g (always); v in slip; μλ_N(1 + tolerance) ∓ r in stick
// (release), the gap staying active so that a sticking contact still opens. Closing: slip in
// the direction of v however small (the limit grows from zero, and a slip against v could be
// reversed by it before v crosses zero, its root never firing), stick only at v = 0 and then
// only with r = 0 (zero limit), else slip against r; opening: open. The limit also vanishes
// at an opening: a stick releases where |r| reaches μλ_N just before the gap opens, or, with
// r = 0, opens together with it (the gap root is handled first). Exactly on g = 0 (a start from
// rest on the obstacle) ġ, then g̈, decide open or closed, since IDA ignores a root function
// that is zero where it starts. Elsewhere the stick/slip decisions are FrictionTimeLaw's, with
// "v near zero" measured on the tangential DOFs' own scale.
//
// Every DOF of the law needs mass: the stick row is the relative acceleration (see
// set_massless).
class ContactFrictionTimeLaw : public TimeLaw {
 public:
  enum class Mode { kSlipPositive = 0, kSlipNegative = 1, kStick = 2, kOpen = 3 };

  // obstacle_stiffness k > 0 (N/m; the rigid obstacle has no time-domain form here), μ ≥ 0,
  // preload N0 ≥ 0 (N), all finite; normal.dof ≥ 0, tangent_dof ≥ 0, the others ≥ 0 or −1, and
  // no two of normal.dof, normal.other, tangent_dof, tangent_other equal (−1 aside). Throws
  // std::invalid_argument naming the field ("obstacle_stiffness: ...", "mu: ...",
  // "preload: ...", "dof: ...", "other: ...", "direction: ...", "gap: ...",
  // "tangent_dof: ...", "tangent_other: ...", "admissibility_tolerance: ...").
  ContactFrictionTimeLaw(ContactGeometry normal, double obstacle_stiffness, int tangent_dof,
                         int tangent_other, double mu, double preload,
                         double admissibility_tolerance = 1e-9);

  // Whether any of the law's DOFs has no mass, as the wiring code knows it: true throws
  // std::invalid_argument ("dof: ..."). The stick row is the relative tangential acceleration,
  // and the decisions read the DOFs' velocities and accelerations, which a massless DOF does
  // not have (FrictionTimeLaw's massless forms are not carried over).
  void set_massless(bool massless);

  Mode mode() const { return mode_; }
  const ContactGeometry& normal() const { return normal_; }
  double obstacle_stiffness() const { return stiffness_; }
  double mu() const { return mu_; }
  double preload() const { return preload_; }

  std::string type() const override { return "contact_friction"; }
  int NumOwn() const override { return 1; }
  void Residual(const TimeLawLayout& layout, const DaeView& s,
                Eigen::Ref<Eigen::VectorXd> residual) const override;
  void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                std::vector<Eigen::Triplet<double>>* entries) const override;
  // Root 0 the gap; root 1 v in slip; roots 2 and 3 the release bounds μλ_N(1 + tol) ∓ r in
  // stick (constants where inactive). Distinct indices for v and the releases: the integrator
  // takes a root fired again right after a restart by the same index for the one just handled.
  int NumRoots() const override { return 4; }
  void Roots(const TimeLawLayout& layout, const DaeView& s, double* g) const override;
  void InitMode(const TimeLawLayout& layout, const DaeView& s) override;
  void OnRoot(const TimeLawLayout& layout, const DaeView& s, int root) override;
  bool Admissible(const TimeLawLayout& layout, const DaeView& s) override;
  void Force(const TimeLawLayout& layout, const DaeView& s,
             Eigen::Ref<Eigen::VectorXd> f_nl) const override;
  bool InPhase() const override { return mode_ == Mode::kStick; }
  std::string PhaseName() const override { return "stick"; }
  int ModeIndex() const override { return static_cast<int>(mode_); }
  // k at normal.dof and at normal.other (if any): the obstacle's spring.
  std::vector<std::pair<int, double>> StiffnessBound() const override;
  // "gap" g (m), "normal_force" λ_N = k·max(0, −g) (N), "friction_force" r as applied (N; 0
  // when open) and "velocity" v (m/s).
  std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                      const DaeView& s) const override;
  // The law needs its mode and its force r: no explicit form (false).
  bool ExplicitForce(double phase, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const override;

  // g at displacement x and excitation phase φ (m).
  double Gap(double phase, const Eigen::VectorXd& x) const;

 private:
  bool Closed() const { return mode_ != Mode::kOpen; }
  bool IsSlip() const { return mode_ == Mode::kSlipPositive || mode_ == Mode::kSlipNegative; }
  // v_tangent_dof − v_tangent_other (m/s).
  double SlidingVelocity(const DaeView& s) const;
  // The friction limit μ·max(0, −k g) at s (N).
  double Limit(const DaeView& s) const;
  // The tangential pair's velocity scale (m/s) for "v near zero": max |v|, |ẋ| plus ω max |x|
  // over tangent_dof and tangent_other. Not the whole state's, as FrictionTimeLaw takes (the
  // normal motion may be far larger than the sliding), and without accelerations, so that it is
  // the same in every mode of one settling (a mode-dependent band can cycle between modes).
  double VelocityScale(const DaeView& s) const;
  // On closing at s: slip in the direction of v (v ≠ 0 or μ = 0), stick if v = 0.
  void Close(const DaeView& s);
  // Whether the gap, zero at s, is about to close (−1: ġ < 0, or ġ = 0 and g̈ < 0), to open
  // (+1) or neither (0).
  int GapTrend(const DaeView& s) const;

  ContactGeometry normal_;
  double stiffness_;
  int tangent_dof_;
  int tangent_other_;
  double mu_;
  double preload_;
  double tolerance_;
  Mode mode_ = Mode::kOpen;
  // Set by Close, read by the next Admissible: that slip follows v's sign, not the acceleration.
  bool closing_ = false;
};

}  // namespace nfrc
