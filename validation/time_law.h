#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace nfrc {

// The DAE state a time-domain law sees. The integrator's unknown vector is
//   y = [x (n) | v (n) | own unknowns of every law],
// with residual rows F = [ẋ − v (n) | M v̇ + C v + K x + Σ f_nl − f(t) (n) | laws' own rows].
// `a` is v̇ and `xdot` is ẋ (for a massless DOF, whose v is algebraic, ẋ is what to use).
struct DaeView {
  double t = 0.0;
  double phase = 0.0;  // excitation phase φ(t) (rad), for time-varying gaps
  int num_dofs = 0;
  Eigen::Map<const Eigen::VectorXd> x{nullptr, 0};
  Eigen::Map<const Eigen::VectorXd> v{nullptr, 0};
  Eigen::Map<const Eigen::VectorXd> xdot{nullptr, 0};
  Eigen::Map<const Eigen::VectorXd> a{nullptr, 0};
  Eigen::Map<const Eigen::VectorXd> own{nullptr, 0};      // this law's own unknowns
  Eigen::Map<const Eigen::VectorXd> own_dot{nullptr, 0};  // and their time derivatives
};

// Where a law's rows and columns sit in the DAE (set by the integrator before any call).
struct TimeLawLayout {
  int num_dofs = 0;
  int own_offset = 0;  // index in y of the law's first own unknown (≥ 2n)

  int X(int dof) const { return dof; }
  int V(int dof) const { return num_dofs + dof; }
  int Momentum(int dof) const { return num_dofs + dof; }  // residual row of DOF's equation
  int Own(int k) const { return own_offset + k; }         // own unknown k and its row
};

// A nonlinear law in the time domain, for the transient integrators (the extension point of
// validation/, as Nonlinearity is of the harmonic problem). Nonsmooth laws are piecewise
// smooth: a discrete mode selects the smooth piece, the residual never contains the switch,
// and root functions tell the integrator where the mode must change.
class TimeLaw {
 public:
  virtual ~TimeLaw() = default;

  // The case-file type it came from, e.g. "coulomb_friction".
  virtual std::string type() const = 0;

  // Own unknowns appended to y (e.g. the friction force); they are algebraic unless
  // OwnIsDifferential says otherwise.
  virtual int NumOwn() const { return 0; }

  // Whether own unknown k is differential (its ẏ enters the DAE); fixed for the law's life.
  // The integrator differentiates the momentum row of a massless, undamped DOF that such an
  // unknown acts on (index reduction: that row alone would pin x once the force is fixed).
  virtual bool OwnIsDifferential(int /*k*/) const { return false; }
  // The harmonic law's signal (LawSignal::name, same sign convention) whose value at a time
  // is own unknown k there, so that a start on an HBM solution carries the law's memory (a
  // Jenkins slider's force); empty: none, the unknown follows from the start's (x, v).
  virtual std::string OwnSignal(int /*k*/) const { return {}; }
  // For a differential own unknown k at `value`: the scale of its perturbations (its unit) when
  // it is a free component of the state there (a sticking Jenkins force strictly inside ±μN),
  // so that the monodromy matrix includes it; 0 when the mode fixes it (slip) or none.
  virtual double OwnStateScale(int /*k*/, double /*value*/) const { return 0.0; }
  // At a (re)initialisation, before consistent values are computed: sets the differential
  // own unknowns that the current mode fixes (a sliding force to exactly ∓μN), so that they
  // do not carry the root location's error into the mode.
  virtual void SnapOwn(const TimeLawLayout& /*layout*/, const DaeView& /*s*/,
                       Eigen::Ref<Eigen::VectorXd> /*own*/) const {}

  // Adds +f_nl to the momentum rows (`residual` is the whole F, size of y) and writes the
  // law's own rows, in the current mode.
  virtual void Residual(const TimeLawLayout& layout, const DaeView& s,
                        Eigen::Ref<Eigen::VectorXd> residual) const = 0;

  // Appends the law's entries of ∂F/∂y + cj·∂F/∂ẏ (current mode) at global (row, column).
  virtual void Jacobian(const TimeLawLayout& layout, const DaeView& s, double cj,
                        std::vector<Eigen::Triplet<double>>* entries) const = 0;

  // Root functions of the current mode (a fixed number per law; an inactive one returns a
  // constant). The integrator stops where one changes sign.
  virtual int NumRoots() const { return 0; }
  virtual void Roots(const TimeLawLayout& /*layout*/, const DaeView& /*s*/, double* /*g*/) const {}

  // Sets the mode from a state (at the start, before consistent values are computed).
  virtual void InitMode(const TimeLawLayout& /*layout*/, const DaeView& /*s*/) {}
  // Root `root` of this law fired at state s: switch to the candidate mode.
  virtual void OnRoot(const TimeLawLayout& /*layout*/, const DaeView& /*s*/, int /*root*/) {}
  // After the integrator made s consistent in the current mode: true if the mode is
  // admissible there; otherwise the law switches to another candidate and returns false.
  virtual bool Admissible(const TimeLawLayout& /*layout*/, const DaeView& /*s*/) { return true; }

  // The force the law puts on the structure, as n-vector f_nl (for energy bookkeeping and
  // outputs); the power it absorbs is f_nlᵀ v.
  virtual void Force(const TimeLawLayout& layout, const DaeView& s,
                     Eigen::Ref<Eigen::VectorXd> f_nl) const = 0;

  // Whether the current mode is the law's distinguished phase ("stick", "contact").
  virtual bool InPhase() const { return false; }
  virtual std::string PhaseName() const { return ""; }
  // Mode index for logs (law-specific meaning).
  virtual int ModeIndex() const { return 0; }

  // For the explicit scheme's stability limit: (DOF, stiffness N/m) pairs the law may add to
  // the diagonal of K at most (a penalty spring: its k at each of its DOFs). Empty: none known.
  virtual std::vector<std::pair<int, double>> StiffnessBound() const { return {}; }

  // Named scalar signals of the law at s for outputs (e.g. "force", "velocity", "gap").
  virtual std::vector<std::pair<std::string, double>> Signals(const TimeLawLayout& layout,
                                                              const DaeView& s) const = 0;

  // For explicit schemes (no own unknowns, no modes needed): adds f_nl(x, v) at phase φ to
  // `f_nl` and returns true; false if the law cannot be evaluated explicitly.
  virtual bool ExplicitForce(double /*phase*/, const Eigen::VectorXd& /*x*/,
                             const Eigen::VectorXd& /*v*/,
                             Eigen::Ref<Eigen::VectorXd> /*f_nl*/) const {
    return false;
  }
};

}  // namespace nfrc
