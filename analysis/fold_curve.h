#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/case_parameter.h"
#include "continuation/branch.h"

namespace nfrc {

struct FoldCurve;

struct FoldCurvePoint;

// Receives each point of a fold curve as it is found and each curve as soon as it ends (a
// writer keeps what was found on disk). `curve` numbers the curves from 0 in result order.
class FoldCurveObserver {
 public:
  virtual ~FoldCurveObserver() = default;
  virtual void OnPoint(int /*curve*/, const FoldCurvePoint& /*point*/) {}
  virtual void OnCurve(const FoldCurve& curve) = 0;
};

// Two-parameter continuation of the folds of a case's branch: each fold is followed in
// (parameter, ω) towards `to`.
struct FoldCurveOptions {
  double to = 0.0;  // value of the parameter the curves are followed towards
  // Scaled arclength caps of the fold-curve steps (the engine's; the case's continuation
  // options give every other setting).
  double initial_step = 0.01;
  double max_step = 0.1;
  int max_points = 2000;  // per curve
  std::ostream* progress = nullptr;
  const std::atomic<bool>* stop = nullptr;  // raised: each curve stops after its point
  // Called after every point of the branch and of the curves; false stops as `stop` does
  // (Python checks its signals here). Empty: not called.
  std::function<bool()> poll;
  FoldCurveObserver* observer = nullptr;

  // Sets max_step and lowers initial_step to it if it exceeds it.
  void SetMaxStep(double step) {
    max_step = step;
    initial_step = std::min(initial_step, step);
  }

  // Throws InputError naming "to", "initial_step", "max_step" or "max_points".
  void Validate(double from) const;
};

// One point of a fold curve: a fold of the branch at this parameter value.
struct FoldCurvePoint {
  double parameter = 0.0;
  double omega = 0.0;           // rad per time unit
  Eigen::VectorXd y;            // the HarmonicSystem's unknowns at the fold
  std::vector<double> max_abs;  // per output DOF (PointMeasures)
  double energy = 0.0;          // PointMeasures::energy
  int newton_iterations = 0;
};

// Where the fold curve turns back in the parameter. A cusp (two folds meet and vanish) when
// ω turns back too; otherwise the curve only turns in the parameter.
struct FoldCurveTurn {
  double parameter = 0.0;
  double omega = 0.0;
  int after_point = 0;
  bool cusp = false;
};

struct FoldCurve {
  int start_fold = 0;                  // index in the traced branch's folds
  double start_omega = 0.0;            // the fold's ω on that branch
  std::vector<FoldCurvePoint> points;  // in order along the curve
  std::vector<FoldCurveTurn> turns;
  ContinuationSummary summary;  // the engine's (termination, counts, timings)
};

struct FoldCurveResult {
  std::string parameter;  // the path
  double from = 0.0;      // its value in the case
  double to = 0.0;
  int branch_folds = 0;  // folds found on the case's branch
  // One per fold that does not lie on an earlier curve (a curve through a cusp passes both
  // folds it joins).
  std::vector<FoldCurve> curves;
  std::vector<std::string> notes;
};

// Traces the case's branch, then follows each of its folds in (parameter, ω). The fold is
// posed as the minimally augmented system R(y, ω; p) = 0, g(y, ω; p) = 0, where g is the last
// entry of the solution of [[R_y, b], [cᵀ, 0]] (v, g) = (0, 1) (b, c: left and right null
// vectors at the last point), regular at a simple fold and through a cusp. ∂R/∂p by central
// differences of systems built at p ± δ; g's gradient by −wᵀ(∂R_y/∂z)v as differences of
// Jacobians along v. Throws InputError for bad input (the case, the parameter, the options).
FoldCurveResult TraceFoldCurves(const Case& the_case, const CaseParameter& parameter,
                                const FoldCurveOptions& options);

}  // namespace nfrc
