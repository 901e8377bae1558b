#pragma once

#include <Eigen/Dense>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/condensation.h"
#include "core/fourier_transform.h"
#include "core/harmonic_set.h"

namespace nfrc {

// Where a nonlinearity's quantities sit in the harmonic problem's unknown vector
// y = [x (retained DOFs, DOF-major coefficients) | own unknowns of each law].
struct NonlinearityContext {
  const FourierTransform* fourier = nullptr;
  // Condensed linear part at the current ω; laws such as DLFT need it, force laws do not.
  const Condensation* condensation = nullptr;
  // Position among the retained DOFs of each of the law's Dofs(), in the same order.
  std::vector<int> local_dofs;
  // Index in y of the law's first own unknown.
  int own_offset = 0;

  const HarmonicSet& harmonic_set() const { return fourier->harmonic_set(); }
  int num_coefficients() const { return harmonic_set().NumCoefficients(); }
  // First index in y of the coefficients of the law's i-th DOF.
  int DofOffset(int i) const { return local_dofs[i] * num_coefficients(); }
};

// A time signal of a law at a solution, sampled on a FourierTransform's grid (for output).
struct LawSignal {
  std::string name;  // e.g. "force", "velocity"
  Eigen::VectorXd samples;
};

// What analyses read about a law at a solution, typed; Diagnostics() names the same facts for
// outputs.
struct LawSummary {
  struct Phase {
    std::string name;       // "stick" (friction with a stick branch) or "contact"
    int count = 0;          // phases per period
    double fraction = 0.0;  // share of the period they cover
  };
  std::optional<Phase> phase;
  std::optional<double> min_gap;    // m, contact laws: smallest gap on the law's samples
  std::optional<double> min_force;  // N, contact laws: smallest truncated force (fine grid)
};

// A law's Summarize and Diagnostics at one solution.
struct LawReport {
  LawSummary summary;
  std::map<std::string, double> diagnostics;
};

// How a law's force depends on the condensed linear residual of its DOFs (DLFT predicts its
// force from it): f_row(r) += row_sign(r)·W·Σ_i c_i·(A x − b)_{dof i}, with A x − b the
// condensed linear part's rows. Hill's method replaces those rows by the full model's
// (s-dependent) rows of the same DOFs, which equal them wherever the other rows hold.
struct LinearResidualDependence {
  Eigen::MatrixXd weights;                    // W, NumCoefficients square
  std::vector<std::pair<int, double>> terms;  // (index into Dofs(), c_i)
  std::vector<std::pair<int, double>> rows;   // (index into Dofs(), row_sign)
};

// A stick piece [begin, end] of a hysteretic law, anchored at the turning point where the last
// slip ended (θ in rad, unwrapped: anchor ≤ begin < end ≤ anchor + 2π).
struct MemoryPiece {
  double anchor = 0.0;
  double begin = 0.0;
  double end = 0.0;
};

// The memory of a hysteretic law's linearisation (Jenkins, DLFT friction's slider). On a stick
// piece the force perturbation is k(δu(t) − δu(t_a)); for Hill's perturbation e^{st}p(θ) the
// anchor's term carries the factor e^{−s(t − t_a)}, which LinearizeForStability takes as 1
// (exact for s = 0: folds and branch points). Hill's method restores it (analysis/hill.h).
struct LinearizationMemory {
  std::vector<MemoryPiece> pieces;
  double stiffness = 0.0;  // k (N/m)
  // δu = Σ c_i δx_{Dofs()[i]}: (index into Dofs(), c_i).
  std::vector<std::pair<int, double>> terms;
  // And Σ d_i (A x − b)_{Dofs()[i]} of the condensed linear rows, for a law driven by its
  // predicted force (DLFT's z = u − (A x − b)/ε): (index into Dofs(), d_i, m/N). Hill's method
  // takes the full model's s-dependent rows instead (see LinearResidualDependence).
  std::vector<std::pair<int, double>> residual_terms;
  // The force acts as +row_sign·f on Dofs()[i]: (index into Dofs(), row_sign).
  std::vector<std::pair<int, double>> rows;
};

// A nonlinear law of the harmonic-balance problem (the extension point, like Ceres's
// CostFunction). It adds its force to the equations of its DOFs and, if it has unknowns of
// its own (e.g. friction-force coefficients), the equations that close them.
class Nonlinearity {
 public:
  virtual ~Nonlinearity() = default;

  // The case-file type, e.g. "cubic_spring".
  virtual std::string type() const = 0;

  // Model DOFs the law acts on; the condensation keeps them.
  virtual std::vector<int> Dofs() const = 0;

  // Compliance (m/N) of a massless obstacle behind each of Dofs(), 0 for none; empty means
  // none at all. The system then works in relative coordinates x − x_obs at those DOFs
  // (Condensation::SetObstacleCompliance), so the law sees relative displacements.
  virtual std::vector<double> ObstacleCompliance() const { return {}; }

  // Called once by the system that owns the law, when its context is final: a law resolves
  // here what depends only on the system (DLFT's default ε from the static stiffness).
  virtual void Bind(const NonlinearityContext& /*ctx*/) {}

  // Number of own unknowns (placed at ctx.own_offset) for a harmonic set.
  virtual int NumOwnUnknowns(const HarmonicSet& /*set*/) const { return 0; }

  // Adds the law's contributions at (y, ω) to `residual` (size of y) and, when non-null, to
  // ∂residual/∂y (`jacobian`, square) and ∂residual/∂ω (`d_omega`). Residual rows of the
  // displacement equations are in force units; the law adds +f_nl there.
  virtual void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                        Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                        Eigen::VectorXd* d_omega) const = 0;

  // Hill's method (analysis/hill.h) linearises the law for a perturbation e^{st}p(θ) of the
  // periodic solution y, whose velocity is (s + ωD)p. Adds ∂residual/∂y of the law as a law of
  // the state (x, ẋ = ωDx) to `jacobian` and ∂residual/∂(velocity coefficients of its DOFs),
  // placed in the columns of those DOFs, to `velocity_jacobian` (both square, size of y).
  // Default: Evaluate's Jacobian and no velocity dependence, right for laws of the
  // displacement alone.
  virtual void LinearizeForStability(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                     double omega, Eigen::MatrixXd* jacobian,
                                     Eigen::MatrixXd* velocity_jacobian) const {
    (void)velocity_jacobian;
    Eigen::VectorXd scratch = Eigen::VectorXd::Zero(y.size());
    Evaluate(ctx, y, omega, scratch, jacobian, nullptr);
  }

  // The part of the law's force that LinearizeForStability leaves out because it comes from
  // the condensed linear residual (see LinearResidualDependence). Default: none.
  virtual std::optional<LinearResidualDependence> LinearResidualPart(
      const NonlinearityContext& /*ctx*/, const Eigen::VectorXd& /*y*/, double /*omega*/) const {
    return std::nullopt;
  }

  // The memory LinearizeForStability leaves out (see LinearizationMemory). Default: none.
  virtual std::optional<LinearizationMemory> Memory(const NonlinearityContext& /*ctx*/,
                                                    const Eigen::VectorXd& /*y*/,
                                                    double /*omega*/) const {
    return std::nullopt;
  }

  // Whether the own unknowns are signals in the HarmonicSet layout (blocks of
  // NumCoefficients), which a start from fewer harmonics may re-express; false for samples.
  virtual bool OwnUnknownsAreCoefficients() const { return true; }

  // Whether the continuation engine should scale the own unknowns with the displacements
  // (they are in metres) rather than as a group of their own.
  virtual bool OwnUnknownsScaleLikeDisplacements() const { return false; }

  // Whether Evaluate writes into the displacement rows' displacement columns of the Jacobian
  // (∂f_law/∂x). A law that enters the equations of motion only through its own unknowns
  // (a friction force) returns false, which leaves that block the linear part's: block
  // diagonal per harmonic, so the engine eliminates it (HarmonicSystem::EliminationBlocks).
  virtual bool WritesDisplacementBlock() const { return true; }

  // Throws std::invalid_argument naming the case field if Newton-based continuation cannot
  // follow the law with this harmonic set (e.g. a sampled complementarity that needs a square
  // Fourier matrix). Default: it can.
  virtual void CheckForContinuation(const HarmonicSet& /*set*/) const {}

  // A starting value of the own unknowns given the displacements in y (default zeros).
  virtual void InitialOwnUnknowns(const NonlinearityContext& /*ctx*/, const Eigen::VectorXd& /*y*/,
                                  double /*omega*/, Eigen::Ref<Eigen::VectorXd> own) const {
    own.setZero();
  }

  // The law's own time signals at solution y, sampled by `fine` (same harmonics as
  // ctx.harmonic_set(), any number of samples). Default: none.
  virtual std::vector<LawSignal> Signals(const NonlinearityContext& /*ctx*/,
                                         const Eigen::VectorXd& /*y*/, double /*omega*/,
                                         const FourierTransform& /*fine*/) const {
    return {};
  }

  // Signals on the law's own N_t samples (ctx.fourier's grid) as the law computed them,
  // before truncation to the harmonic bandwidth (e.g. DLFT's corrected contact force).
  virtual std::vector<LawSignal> RawSamples(const NonlinearityContext& /*ctx*/,
                                            const Eigen::VectorXd& /*y*/, double /*omega*/) const {
    return {};
  }

  // The typed facts analyses use (phases, contact extremes). Default: none.
  virtual LawSummary Summarize(const NonlinearityContext& /*ctx*/, const Eigen::VectorXd& /*y*/,
                               double /*omega*/, const FourierTransform& /*fine*/) const {
    return {};
  }

  // Scalar diagnostics of the solution for output (e.g. stick phases per period).
  virtual std::map<std::string, double> Diagnostics(const NonlinearityContext& /*ctx*/,
                                                    const Eigen::VectorXd& /*y*/, double /*omega*/,
                                                    const FourierTransform& /*fine*/) const {
    return {};
  }

  // Both of the above, as every accepted point reports them; a law whose two share their work
  // (its signals on the fine grid) overrides this to do it once.
  virtual LawReport Report(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                           const FourierTransform& fine) const {
    return {Summarize(ctx, y, omega, fine), Diagnostics(ctx, y, omega, fine)};
  }
};

}  // namespace nfrc
