#pragma once

#include <Eigen/Dense>
#include <array>
#include <cassert>
#include <vector>

namespace nfrc {

// How a plotted coordinate is drawn: deviations count in its own unit over the largest
// |value| of the branch so far (linear), or in its logarithm (log: 1e-3 is 0.1 %).
enum class PlotScale { kLinear, kLog };

// The curve as the user plots a branch: a few coordinates of a point (e.g. an amplitude or
// an energy) drawn against λ, one scale each. Given to Continue with
// ContinuationOptions::plot_tolerance, it sizes the steps so that every chord stays that
// close to the curve in each (λ, coordinate) plane.
class PlotCurve {
 public:
  virtual ~PlotCurve() = default;
  // One scale per coordinate; at least one.
  virtual std::vector<PlotScale> Scales() const = 0;
  // The coordinates at (y, λ), as many as Scales(); log-scale values must be > 0.
  virtual Eigen::VectorXd Coordinates(const Eigen::VectorXd& y, double lambda) = 0;
};

// Whether every entry is finite, as the engine tests an output: x·0 is 0 for finite x and
// NaN for ±∞ or NaN, summed in eight partial sums (Eigen's allFinite exits early entry by
// entry, and one running sum waits on each addition: 4–6 % of the N_φ = 160 friction curve).
inline bool AllFinite(const Eigen::Ref<const Eigen::MatrixXd>& m) {
  assert(m.cols() <= 1 || m.outerStride() == m.rows());  // read as one run of m.size()
  const double* x = m.data();
  const Eigen::Index n = m.size();
  std::array<double, 8> partial{};
  Eigen::Index i = 0;
  for (; i + 8 <= n; i += 8) {
    for (size_t k = 0; k < 8; ++k) partial[k] += x[i + static_cast<Eigen::Index>(k)] * 0.0;
  }
  double sum = 0.0;
  for (; i < n; ++i) sum += x[i] * 0.0;
  for (const double p : partial) sum += p;
  return sum == 0.0;
}

// An equation R(y, λ) = 0 to be followed in the parameter λ. The engine knows nothing
// else about it. Jacobians are dense: the problems continued here are condensed ones.
class ContinuationProblem {
 public:
  virtual ~ContinuationProblem() = default;

  virtual int NumUnknowns() const = 0;

  // Fills R(y, λ) and, for non-null arguments, ∂R/∂y and ∂R/∂λ, each sized n by the caller:
  // every entry is the problem's to write (∂R/∂y arrives with unspecified contents, so that
  // a large one is not zeroed twice). Returns false when the problem cannot be evaluated
  // there (e.g. a singular linear part): the engine treats it as a failed step, never as a
  // converged point.
  virtual bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                        Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) = 0;

  // True when Evaluate itself returns false wherever an output it filled is not finite (e.g.
  // by AllFinite below), so that the engine does not pass over ∂R/∂y again (321² entries at
  // N_φ = 160, 3 % of the friction curve). Default false: the engine checks every output.
  virtual bool ChecksFiniteness() const { return false; }

  // Scale group of each unknown: unknowns of one group share one physical unit and one
  // scale (e.g. displacement coefficients vs force coefficients). Default: one group.
  virtual std::vector<int> ScaleGroups() const { return std::vector<int>(NumUnknowns(), 0); }

  // Weight of each unknown in the tangent-turn test that limits the step (default: empty,
  // all 1). Unknowns that jump at every kink of a nonsmooth branch without shaping the curve
  // (the top harmonics of a friction force) can be weighed down, so that the step follows
  // the curvature of the smooth pieces instead of shrinking at each kink.
  virtual Eigen::VectorXd StepWeights() const { return {}; }

  // Groups of unknowns whose rows and columns of ∂R/∂y are block diagonal among themselves
  // (a group couples with no other group, only with itself and the other unknowns), each
  // small: the engine then solves its linear systems by eliminating them, per-group LUs and
  // one dense LU of the Schur complement on the rest. E.g. the harmonics of a condensed
  // linear part where the laws enter only through their own unknowns (friction forces).
  // Default: none (one dense LU of everything).
  virtual std::vector<std::vector<int>> EliminationBlocks() const { return {}; }

  // Estimated rounding noise of ‖R(y, λ)‖ (units of R): the floor below which no Newton
  // step can push the residual while λ moves, e.g. the rounding of a condensed operator of
  // a fine mesh, which changes with every λ. Default 0: no noise beyond eps·‖R's terms‖.
  // Asked for only when a corrector stalls above its residual tolerance.
  virtual double ResidualNoise(const Eigen::VectorXd& /*y*/, double /*lambda*/) { return 0.0; }
};

}  // namespace nfrc
