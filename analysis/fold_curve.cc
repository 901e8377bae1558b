#include "analysis/fold_curve.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <utility>

#include "analysis/parameter_sensitivity.h"
#include "analysis/point_measures.h"
#include "analysis/trace.h"
#include "continuation/continuation.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// Relative step of the central difference along the null vector for ∂R_y/∂z·v:
// h = kDirectionStep·‖y‖/‖v‖, near ε^(1/3) ≈ 6e-6, where truncation (h²) and rounding (ε/h)
// of a central difference balance.
constexpr double kDirectionStep = 1e-5;
// A fold of the branch whose (p, ω) lies within this relative distance of an earlier
// curve's point is on that curve (a curve through a cusp joins two folds).
constexpr double kSameFold = 1e-5;

// R(y, ω; p) = 0 and g(y, ω; p) = 0 in the unknowns (y, ω), continued in p.
class FoldProblem : public ContinuationProblem {
 public:
  FoldProblem(const Case& the_case, const CaseParameter& parameter, double parameter_scale)
      : sensitivity_(the_case, parameter, parameter_scale) {}

  // Sets the borders from the null vectors of R_y at (y, ω; p).
  bool Rebase(const Eigen::VectorXd& y, double omega, double p) {
    Eigen::VectorXd residual;
    Eigen::MatrixXd jacobian;
    if (!System(p).Evaluate(y, omega, &residual, &jacobian, nullptr)) return false;
    if (groups_.empty()) groups_ = System(p).ScaleGroups();
    Eigen::BDCSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const int n = static_cast<int>(y.size());
    b_ = svd.matrixU().col(n - 1);
    c_ = svd.matrixV().col(n - 1);
    return b_.allFinite() && c_.allFinite();
  }

  int NumUnknowns() const override { return NumY() + 1; }

  std::vector<int> ScaleGroups() const override {
    std::vector<int> groups = groups_;
    groups.push_back(*std::max_element(groups.begin(), groups.end()) + 1);  // ω
    return groups;
  }

  bool Evaluate(const Eigen::VectorXd& u, double p, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_u, Eigen::VectorXd* jacobian_p) override {
    const int n = NumY();
    const Eigen::VectorXd y = u.head(n);
    const double omega = u(n);
    HarmonicSystem& system = System(p);
    Eigen::MatrixXd r_y;
    Eigen::VectorXd r, r_omega;
    if (!system.Evaluate(y, omega, &r, &r_y, &r_omega)) return false;
    Eigen::VectorXd v, w;
    double g = 0.0;
    if (!NullVectors(r_y, &v, &w, &g)) return false;
    residual->resize(n + 1);
    residual->head(n) = r;
    (*residual)(n) = g;
    if (jacobian_u == nullptr && jacobian_p == nullptr) return true;

    // ∂g/∂z = −wᵀ(∂R_y/∂z)v = −wᵀ ∂/∂v (∂R/∂z): central differences of the Jacobian along v.
    const double y_size = y.norm() > 0.0 ? y.norm() : 1.0;  // in y's units, not a fixed floor
    const double h = kDirectionStep * y_size / std::max(v.norm(), 1e-300);
    Eigen::MatrixXd plus_y, minus_y;
    Eigen::VectorXd plus_r, minus_r, plus_omega, minus_omega;
    if (!system.Evaluate(y + h * v, omega, &plus_r, &plus_y, &plus_omega) ||
        !system.Evaluate(y - h * v, omega, &minus_r, &minus_y, &minus_omega)) {
      return false;
    }
    if (jacobian_u != nullptr) {
      jacobian_u->resize(n + 1, n + 1);
      jacobian_u->topLeftCorner(n, n) = r_y;
      jacobian_u->topRightCorner(n, 1) = r_omega;
      jacobian_u->bottomLeftCorner(1, n) = -w.transpose() * (plus_y - minus_y) / (2.0 * h);
      (*jacobian_u)(n, n) = -w.dot(plus_omega - minus_omega) / (2.0 * h);
    }
    if (jacobian_p != nullptr) {
      // ∂R/∂p and ∂g/∂p = −wᵀ(∂R_y/∂p)v (ParameterSensitivity: exact where R is affine in p).
      Eigen::VectorXd d_residual;
      Eigen::MatrixXd d_jacobian;
      if (!sensitivity_.Evaluate(p, y, omega, &d_residual, &d_jacobian)) return false;
      jacobian_p->resize(n + 1);
      jacobian_p->head(n) = d_residual;
      (*jacobian_p)(n) = -w.dot(d_jacobian * v);
    }
    return true;
  }

  HarmonicSystem& System(double p) { return sensitivity_.System(p); }

 private:
  int NumY() const { return static_cast<int>(b_.size()); }

  // v, g from [[R_y, b], [cᵀ, 0]] (v, g) = (0, 1), w from the transposed system.
  bool NullVectors(const Eigen::MatrixXd& r_y, Eigen::VectorXd* v, Eigen::VectorXd* w,
                   double* g) const {
    const int n = NumY();
    Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(n + 1, n + 1);
    bordered.topLeftCorner(n, n) = r_y;
    bordered.topRightCorner(n, 1) = b_;
    bordered.bottomLeftCorner(1, n) = c_.transpose();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(bordered);
    const Eigen::VectorXd unit = Eigen::VectorXd::Unit(n + 1, n);
    const Eigen::VectorXd right = lu.solve(unit);
    const Eigen::VectorXd left = lu.transpose().solve(unit);
    if (!right.allFinite() || !left.allFinite()) return false;
    *v = right.head(n);
    *w = left.head(n);
    *g = right(n);
    return true;
  }

  ParameterSensitivity sensitivity_;
  std::vector<int> groups_;  // the HarmonicSystem's scale groups
  Eigen::VectorXd b_, c_;
};

// Re-borders the problem at every accepted point so that [[R_y, b], [cᵀ, 0]] stays well
// conditioned however far the curve goes (g = 0 marks the same folds with any regular border),
// and records the point with its measures in `curve`, passing it on to the observer.
class Rebaser : public ContinuationObserver {
 public:
  Rebaser(FoldProblem& problem, StopCheck& check, const Case& the_case, int index,
          FoldCurveObserver* observer, FoldCurve* curve)
      : problem_(problem),
        check_(check),
        the_case_(the_case),
        index_(index),
        observer_(observer),
        curve_(curve) {}
  bool OnPoint(const BranchPoint& point, int /*index*/) override {
    const int n = static_cast<int>(point.y.size()) - 1;
    FoldCurvePoint& out = curve_->points.emplace_back();
    out.parameter = point.lambda;
    out.omega = point.y(n);
    out.y = point.y.head(n);
    out.newton_iterations = point.newton_iterations;
    PointAnalyzer analyzer(problem_.System(point.lambda), the_case_.output_dofs);
    const PointMeasures measures = analyzer.Measure(out.y, out.omega);
    out.max_abs = measures.max_abs;
    out.energy = measures.energy;
    if (observer_ != nullptr) observer_->OnPoint(index_, out);
    problem_.Rebase(point.y.head(n), point.y(n), point.lambda);
    return check_.Continue();
  }

 private:
  FoldProblem& problem_;
  StopCheck& check_;
  const Case& the_case_;
  int index_;
  FoldCurveObserver* observer_;
  FoldCurve* curve_;
};

bool OnCurve(const FoldCurve& curve, double p, double omega, double p_scale) {
  return std::any_of(curve.points.begin(), curve.points.end(), [&](const FoldCurvePoint& q) {
    return std::abs(q.parameter - p) <= kSameFold * p_scale &&
           std::abs(q.omega - omega) <= kSameFold * std::max(std::abs(omega), 1.0);
  });
}

FoldCurve FollowFold(const Case& the_case, const CaseParameter& parameter,
                     const FoldCurveOptions& options, double from, const Fold& fold, int index,
                     StopCheck& check) {
  const double p_scale = std::max({std::abs(from), std::abs(options.to), 1e-300});
  FoldProblem problem(the_case, parameter, p_scale);
  FoldCurve curve;
  curve.start_omega = fold.lambda;
  if (!problem.Rebase(fold.y, fold.lambda, from)) {
    curve.summary.message = "no null vectors of R_y at the fold";
    return curve;
  }
  ContinuationOptions continuation = the_case.continuation;
  continuation.lambda_start = from;
  continuation.lambda_end = options.to;
  continuation.lambda_min = continuation.lambda_max = std::numeric_limits<double>::quiet_NaN();
  continuation.lambda_scale = 0.0;
  continuation.initial_step = options.initial_step;
  continuation.max_step = options.max_step;
  continuation.min_step = std::min(continuation.min_step, 1e-3 * options.initial_step);
  continuation.max_points = options.max_points;
  continuation.plot_tolerance = 0.0;  // the curve is (p, ω): the tangent's turn sizes steps
  continuation.progress = options.progress;
  continuation.stop = options.stop;
  continuation.lambda_name = parameter.path();
  Eigen::VectorXd start(fold.y.size() + 1);
  start << fold.y, fold.lambda;
  Rebaser rebaser(problem, check, the_case, index, options.observer, &curve);
  const Branch branch = Continue(problem, start, continuation, &rebaser);
  curve.summary = branch.summary;
  const int n = static_cast<int>(fold.y.size());
  for (const Fold& turn : branch.folds) {
    FoldCurveTurn& out = curve.turns.emplace_back();
    out.parameter = turn.lambda;
    out.omega = turn.y(n);
    out.after_point = turn.after_point;
    const size_t a = static_cast<size_t>(turn.after_point);
    if (a + 1 < branch.points.size()) {
      // A cusp: ω turns back where p does (both tangent components change sign).
      out.cusp = branch.points[a].tangent_y(n) * branch.points[a + 1].tangent_y(n) < 0.0;
    }
  }
  return curve;
}

}  // namespace

void FoldCurveOptions::Validate(double from) const {
  CheckStudyTarget(from, to);
  if (!(initial_step > 0.0) || !std::isfinite(initial_step)) {
    throw InputError("initial_step: must be positive");
  }
  if (!(max_step >= initial_step) || !std::isfinite(max_step)) {
    throw InputError("max_step: must be at least initial_step");
  }
  if (max_points < 2) throw InputError("max_points: must be at least 2");
}

FoldCurveResult TraceFoldCurves(const Case& the_case, const CaseParameter& parameter,
                                const FoldCurveOptions& options) {
  the_case.Validate();
  if (the_case.method != Method::kArclength) {
    throw InputError("continuation.method: fold curves need the arclength method");
  }
  FoldCurveResult result;
  result.parameter = parameter.path();
  result.from = parameter.Get(the_case);
  result.to = options.to;
  options.Validate(result.from);
  StopCheck check(options.stop, options.poll);
  // Only the folds are needed: no stability.
  const TraceResult trace = TraceStudyBranch(the_case, false, options.progress, &check);
  result.branch_folds = static_cast<int>(trace.folds.size());
  if (trace.folds.empty()) {
    result.notes.push_back("the case's branch has no fold (" + trace.branch.summary.message + ")");
  }
  const double p_scale = std::max({std::abs(result.from), std::abs(result.to), 1e-300});
  for (size_t i = 0; i < trace.folds.size(); ++i) {
    if (!check.Continue()) break;
    const Fold& fold = trace.folds[i].fold;
    const auto earlier =
        std::find_if(result.curves.begin(), result.curves.end(),
                     [&](const auto& c) { return OnCurve(c, result.from, fold.lambda, p_scale); });
    if (earlier != result.curves.end()) {
      result.notes.push_back("fold " + std::to_string(i) + " lies on the curve from fold " +
                             std::to_string(earlier->start_fold));
      continue;
    }
    if (fold.corner) {
      // R_y has no null vector there: ω turns where a sample of a law switches.
      result.notes.push_back("fold " + std::to_string(i) +
                             " at omega=" + std::to_string(fold.lambda) +
                             " is a corner of the nonsmooth branch, where no fold curve starts "
                             "(follow it by nfrc sweep)");
      continue;
    }
    if (options.progress != nullptr) {
      *options.progress << "nfrc: fold " << i << " at omega=" << fold.lambda << ": following "
                        << parameter.path() << " from " << result.from << " to " << options.to
                        << "\n";
    }
    FoldCurve curve = FollowFold(the_case, parameter, options, result.from, fold,
                                 static_cast<int>(result.curves.size()), check);
    curve.start_fold = static_cast<int>(i);
    result.curves.push_back(std::move(curve));
    if (options.observer != nullptr) options.observer->OnCurve(result.curves.back());
  }
  return result;
}

}  // namespace nfrc
