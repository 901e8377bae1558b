#include "analysis/refinement.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <variant>

#include "analysis/lcp_reference.h"
#include "continuation/fixed_lambda.h"
#include "core/errors.h"

namespace nfrc {
namespace {

std::string Format(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

bool Stopped(const RefinementRunOptions& run) { return run.stop != nullptr && run.stop->load(); }

// Records the branch, forwards it to the run's observer and stops it at the first point at or
// beyond ω, solving exactly there.
class StopAtOmega : public ContinuationObserver {
 public:
  StopAtOmega(HarmonicSystem& system, const Case& the_case, const ContinuationOptions& options,
              double omega, const RefinementRunOptions& run, TraceResult* branch)
      : system_(system),
        reporter_(system, the_case.output_dofs, the_case.output_names),
        options_(options),
        omega_(omega),
        run_(run),
        branch_(branch) {}

  bool OnPoint(const BranchPoint& point, int index) override {
    // Filled in place (see TraceRecorder in trace.cc).
    TracePoint& record = branch_->points.emplace_back();
    record.index = index;
    record.point = point;
    record.measures = reporter_.Measure(point.y, point.lambda);
    const bool go_on = run_.branch == nullptr || run_.branch->OnPoint(record);
    solution_ =
        SolveAtCrossing(system_, previous_ ? &*previous_ : nullptr, point, omega_, options_);
    previous_ = point;
    return go_on && !solution_.has_value() && !Stopped(run_);
  }
  void OnFold(const Fold& fold) override {
    branch_->folds.push_back(TraceFold{fold, reporter_.analyzer().Measure(fold.y, fold.lambda)});
    if (run_.branch != nullptr) run_.branch->OnFold(branch_->folds.back());
  }
  const std::optional<FixedLambdaSolution>& solution() const { return solution_; }

 private:
  HarmonicSystem& system_;
  SolutionReporter reporter_;
  const ContinuationOptions& options_;
  double omega_;
  const RefinementRunOptions& run_;
  TraceResult* branch_;
  std::optional<BranchPoint> previous_;
  std::optional<FixedLambdaSolution> solution_;
};

// Traces the case up to ω into result->branch; the solution at ω if the branch reached it,
// else nullopt with result->message saying why.
std::optional<FixedLambdaSolution> TraceToOmega(const Case& the_case, double omega,
                                                const RefinementRunOptions& run,
                                                RefinementResult* result) {
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  TraceResult& branch = result->branch;
  branch.num_unknowns = system->NumUnknowns();
  if (run.branch != nullptr) run.branch->OnStart(branch.num_unknowns);
  ContinuationOptions options = the_case.continuation;
  options.progress = run.progress;
  options.stop = run.stop;
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, run.progress, run.stop);
  StopAtOmega observer(*system, the_case, options, omega, run, &branch);
  branch.branch = Trace(*system, options, &observer, &guess, the_case.Plot());
  if (Stopped(run)) {
    result->interrupted = true;
    branch.branch.summary.message += " (interrupted by a signal)";
  }
  if (run.observer != nullptr) run.observer->OnBranchEnd(branch.branch.summary);
  if (!observer.solution()) {
    result->message = "the branch did not reach omega: " + branch.branch.summary.message;
  } else if (!observer.solution()->converged) {
    result->message = "no solution at omega: " + observer.solution()->message;
  } else {
    return observer.solution();
  }
  return std::nullopt;
}

// Solves `refined` (the case with this step's ε) at ω from y.
RefinementStep SolveStep(const Case& refined, double epsilon, double omega,
                         const Eigen::VectorXd& y, const LcpReference* reference) {
  std::unique_ptr<HarmonicSystem> system = BuildSystem(refined);
  const FixedLambdaSolution solved = SolveAtFixedLambda(*system, y, omega, y, refined.continuation);
  RefinementStep step;
  step.epsilon = epsilon;
  step.converged = solved.converged;
  step.newton_iterations = solved.iterations;
  step.residual_norm = solved.residual_norm;
  step.message = solved.message;
  SolutionReporter reporter(*system, refined.output_dofs, refined.output_names);
  step.signals = reporter.Signals(solved.y, omega);
  step.signals.after_point = -1;
  step.signals.converged = solved.converged;
  step.signals.note = "epsilon=" + Format(epsilon);
  if (reference != nullptr && reference->ok()) {
    step.distance_to_lcp = DistanceToLcp(refined, *system, solved.y, omega, *reference);
  }
  return step;
}

void ReportStep(std::ostream* progress, const RefinementStep& step) {
  if (progress == nullptr) return;
  const SolutionMeasures& m = step.signals.measures;
  *progress << "refine: epsilon=" << step.epsilon << "  converged=" << step.converged
            << "  newton=" << step.newton_iterations << "  min_gap=" << m.min_gap.value_or(NAN)
            << "  min_force=" << m.min_force.value_or(NAN) << "\n";
}

}  // namespace

void RefinementOptions::Validate(const Case& the_case) const {
  const double lo = std::min(the_case.continuation.lambda_start, the_case.continuation.lambda_end);
  const double hi = std::max(the_case.continuation.lambda_start, the_case.continuation.lambda_end);
  if (!std::isfinite(omega) || omega < lo || omega > hi) {
    throw InputError("omega: must lie in the case's range [" + Format(lo) + ", " + Format(hi) +
                     "], got " + Format(omega));
  }
  if (epsilons.empty()) throw InputError("epsilons: at least one value is needed");
  for (double epsilon : epsilons) {
    if (!(epsilon > 0.0) || !std::isfinite(epsilon)) {
      throw InputError("epsilons: every value must be finite and > 0, got " + Format(epsilon));
    }
  }
  bool any_dlft = false;
  for (const LawSpec& law : the_case.laws) any_dlft |= std::holds_alternative<DlftContactSpec>(law);
  if (!any_dlft) throw InputError("nonlinearities: refinement needs a dlft_contact law");
}

std::vector<double> GeometricEpsilons(double epsilon0, double factor, int steps) {
  if (!(factor > 1.0) || !std::isfinite(factor)) throw InputError("factor: must be > 1");
  if (steps < 0) throw InputError("steps: must be >= 0");
  std::vector<double> epsilons;
  for (int i = 0; i <= steps; ++i) epsilons.push_back(epsilon0 * std::pow(factor, i));
  return epsilons;
}

RefinementResult RefineEpsilon(const Case& the_case, const RefinementOptions& options,
                               const RefinementRunOptions& run) {
  options.Validate(the_case);
  the_case.Validate();
  RefinementResult result;
  result.omega = options.omega;
  const std::optional<FixedLambdaSolution> at_omega =
      TraceToOmega(the_case, options.omega, run, &result);
  if (!at_omega) return result;
  if (const std::optional<Case> limit = LcpLimitCase(the_case)) {
    result.lcp = SolveLcpReference(*limit, options.omega);
    if (run.observer != nullptr) run.observer->OnLcpReference(*result.lcp);
  }
  // The same case with each ε on every DLFT contact; the unknowns keep their layout, so the
  // previous solution warm-starts the next solve.
  Case refined = the_case;
  Eigen::VectorXd y = at_omega->y;
  for (double epsilon : options.epsilons) {
    if (Stopped(run)) {
      result.interrupted = true;
      result.message = "interrupted by a signal after " + std::to_string(result.steps.size()) +
                       " of " + std::to_string(options.epsilons.size()) + " steps";
      break;
    }
    for (LawSpec& law : refined.laws) {
      if (auto* dlft = std::get_if<DlftContactSpec>(&law)) dlft->contact.epsilon = epsilon;
    }
    const RefinementStep& step = result.steps.emplace_back(
        SolveStep(refined, epsilon, options.omega, y, result.lcp ? &*result.lcp : nullptr));
    if (run.observer != nullptr) run.observer->OnStep(step);
    ReportStep(run.progress, step);
    if (!step.converged) break;
    y = step.signals.y;
  }
  return result;
}

bool RefinementResult::Complete(const RefinementOptions& options) const {
  return !interrupted && steps.size() == options.epsilons.size() &&
         (steps.empty() || steps.back().converged);
}

}  // namespace nfrc
