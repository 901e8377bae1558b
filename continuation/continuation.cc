#include "continuation/continuation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "continuation/augmented_system.h"
#include "continuation/closure.h"
#include "continuation/corrector.h"
#include "continuation/evaluator.h"
#include "continuation/fold_locator.h"
#include "continuation/plot_control.h"
#include "continuation/progress.h"
#include "continuation/scaling.h"
#include "continuation/step_control.h"
#include "continuation/tangent.h"

namespace nfrc {
namespace {

// Step attempts allowed per requested point: a hard guard against step-control cycles,
// far above what the min_step rule lets a healthy run use (≈ log(max/min)/log(1/decrease)).
constexpr int kMaxAttemptsPerPoint = 50;

// A turn above max_tangent_angle that a retry with at most kKinkStepRatio of the step still
// shows at kKinkAngleRatio or more of its size is a kink of a nonsmooth branch (a smooth
// turn would have shrunk in proportion to the step).
constexpr double kKinkStepRatio = 0.6;
constexpr double kKinkAngleRatio = 0.75;

// Natural-parameter fallback: not where the tangent is this close to a fold (|τ_λ| small),
// and only for a solution within this many step lengths of the last point.
constexpr double kMinNaturalTangent = 1e-3;
constexpr double kNaturalReach = 10.0;

// Enough digits to locate a stall or a bound in a message, as in the progress lines.
constexpr int kMessageDigits = 8;

std::string Number(double value) {
  std::ostringstream text;
  text << std::setprecision(kMessageDigits) << value;
  return text.str();
}

// The λ extent a plot of the run spans: the distance from start to end, or the range.
double PlotSpan(const ContinuationOptions& options) {
  const double span = std::abs(options.lambda_end - options.lambda_start);
  if (span > 0.0) return span;
  const double range = options.UpperBound() - options.LowerBound();
  return range > 0.0 ? range : 1.0;
}

// The Newton iterations a correction counts for the step control: one more where it was
// accepted on its contraction, so that target_newton_iterations paces steps as it did when
// every correction took its confirming iteration (the saved solve is economy, not a sign
// that a longer step would converge as well).
int PacedIterations(const CorrectorResult& corrected) {
  return corrected.iterations + (corrected.error_estimate >= 0.0 ? 1 : 0);
}

std::string Describe(const std::string& name, double value) { return name + '=' + Number(value); }

// r: ‖R(0, λ_start)‖, the size of the excitation, against which residuals are judged. A
// problem without one (R(0, λ_start) = 0, e.g. unforced) falls back to
// max(1, ‖R(y_guess, λ_start)‖), which is not unit-invariant but keeps the test meaningful.
double ResidualScale(Evaluator& evaluator, const Eigen::VectorXd& y_guess, double lambda) {
  Eigen::VectorXd residual;
  if (evaluator.Residual(Eigen::VectorXd::Zero(y_guess.size()), lambda, &residual)) {
    const double norm = residual.norm();
    if (norm > 0.0 && std::isfinite(norm)) return norm;
  }
  if (evaluator.Residual(y_guess, lambda, &residual) && std::isfinite(residual.norm())) {
    return std::max(1.0, residual.norm());
  }
  return 1.0;
}

// Groups still zero everywhere get the scale s_λ·|dy/dλ| = s_λ·|R_y⁻¹R_λ|: the change of y
// over the λ range, in y's own unit; those that do not move with λ either get the scale that
// balances their Jacobian columns against the others'.
void SeedZeroGroups(const Linearization& linearization, Scaling* scaling) {
  if (!scaling->HasZeroGroup()) return;
  // Partial pivoting: a full-pivoting LU of thousands of unknowns took seconds (unblocked).
  Eigen::VectorXd dy_dlambda;
  if (SolveRegular(linearization.jacobian_y, linearization.jacobian_lambda, &dy_dlambda)) {
    scaling->SeedZeroGroups(scaling->lambda_scale() * dy_dlambda);
  }
  if (scaling->HasZeroGroup()) scaling->SeedZeroGroupsFromColumns(linearization.jacobian_y);
}

class Continuer {
 public:
  Continuer(ContinuationProblem& problem, const ContinuationOptions& options,
            ContinuationObserver* observer, PlotCurve* plot)
      : evaluator_(problem),
        options_(options),
        observer_(observer),
        groups_(problem.ScaleGroups()),
        scaling_(groups_, LambdaScale(options), options.scale_floor),
        controller_(options),
        progress_(options.progress, options.lambda_name),
        lambda_min_(options.LowerBound()),
        lambda_max_(options.UpperBound()) {
    if (static_cast<int>(groups_.size()) != evaluator_.num_unknowns()) {
      throw std::invalid_argument("ContinuationProblem: ScaleGroups() size != NumUnknowns()");
    }
    const Eigen::VectorXd weights = problem.StepWeights();
    if (weights.size() != 0) {
      if (weights.size() != evaluator_.num_unknowns() || (weights.array() < 0.0).any()) {
        throw std::invalid_argument(
            "ContinuationProblem: StepWeights() size != NumUnknowns() or a weight < 0");
      }
      turn_weights_.resize(weights.size() + 1);
      turn_weights_ << weights, 1.0;
    }
    if (options.plot_tolerance > 0.0) {
      if (plot == nullptr) {
        throw std::invalid_argument("plot_tolerance: set, but no plotted curve was given");
      }
      plot_.emplace(*plot, PlotSpan(options), options.plot_tolerance);
    }
    settings_.max_iterations = options.max_newton_iterations;
    settings_.update_tolerance = options.newton_tolerance;
    settings_.residual_tolerance = options.residual_tolerance;
    settings_.line_search = options.line_search;
    settings_.stop = options.stop;
  }

  Branch Run(const Eigen::VectorXd& y_guess) {
    const auto start_time = std::chrono::steady_clock::now();
    if (Start(y_guess)) Follow();
    ContinuationSummary& summary = branch_.summary;
    summary.num_points = static_cast<int>(branch_.points.size());
    summary.num_folds = static_cast<int>(branch_.folds.size());
    for (const StepRecord& record : summary.history) {
      ++(record.accepted ? summary.num_accepted_steps : summary.num_rejected_steps);
    }
    summary.total_newton_iterations = newton_iterations_;
    if (noise_floor_steps_ > 0) {
      summary.notes.push_back(std::to_string(noise_floor_steps_) +
                              " steps converged at the residual's rounding floor (above "
                              "residual_tolerance, within " +
                              Number(kNoiseFactor) + " times the problem's estimate)");
    }
    if (reoriented_steps_ > 0) {
      summary.notes.push_back(
          std::to_string(reoriented_steps_) +
          " steps past a corner turning the branch by more than 90 degrees: the orientation "
          "index (the sign of det[R_u; tangent]) reversed the tangent the previous one oriented "
          "(the step then retried shorter or accepted as a kink)");
    }
    if (plot_gaps_ > 0) {
      summary.notes.push_back(std::to_string(plot_gaps_) +
                              " steps sized by the tangent's turn: the problem gave no usable "
                              "plot coordinates there");
    }
    summary.num_evaluations = evaluator_.num_evaluations();
    summary.wall_time_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
    progress_.Finish(summary);
    return std::move(branch_);
  }

 private:
  int n() const { return evaluator_.num_unknowns(); }
  bool Stopped() const { return options_.stop != nullptr && options_.stop->load(); }

  void Finish(TerminationReason reason, std::string message) {
    if (finished_) return;
    finished_ = true;
    branch_.summary.reason = reason;
    branch_.summary.message = std::move(message);
  }

  bool Start(const Eigen::VectorXd& y_guess) {
    if (y_guess.size() != n()) {
      throw std::invalid_argument("Continue: y_guess size differs from NumUnknowns()");
    }
    const double lambda = options_.lambda_start;
    settings_.residual_scale = ResidualScale(evaluator_, y_guess, lambda);
    Eigen::VectorXd u_guess(n() + 1);
    u_guess << y_guess, lambda;

    // The start Newton measures its updates against y_guess's magnitude: no branch yet.
    Scaling guess_scaling = scaling_;
    guess_scaling.Include(y_guess);
    Linearization at_guess;
    if (guess_scaling.HasZeroGroup() && evaluator_.Linearize(u_guess, &at_guess)) {
      SeedZeroGroups(at_guess, &guess_scaling);
    }
    NewtonSettings start_settings = settings_;
    start_settings.max_iterations = options_.max_start_iterations;
    CorrectorResult start =
        CorrectAtFixedLambda(evaluator_, guess_scaling, start_settings, u_guess);
    newton_iterations_ += start.iterations;
    if (!start.converged && start_settings.line_search) {
      // Semismooth Newton converges locally where a line search on ‖R‖ can stall at a kink
      // (seen on friction at N_φ = 640 from the lower-harmonic start): one undamped retry,
      // which gives up if ‖R‖ grows a hundredfold.
      NewtonSettings undamped = start_settings;
      undamped.line_search = false;
      CorrectorResult retry = CorrectAtFixedLambda(evaluator_, guess_scaling, undamped, u_guess);
      newton_iterations_ += retry.iterations;
      if (retry.converged) {
        retry.failure = start.failure;
        retry.iterations += start.iterations;
        start = std::move(retry);
        branch_.summary.notes.push_back("start: Newton with line search failed (" + start.failure +
                                        "), converged undamped");
        if (options_.progress != nullptr)
          *options_.progress << branch_.summary.notes.back() << '\n';
      } else {
        start.failure += "; undamped: " + retry.failure;
      }
    }
    if (!start.converged && Stopped()) {
      Finish(TerminationReason::kStoppedByObserver, "interrupted before the first point");
      return false;
    }
    if (!start.converged) {
      Finish(TerminationReason::kStartFailed,
             "Newton at " + Describe(options_.lambda_name, lambda) + " from y_guess failed: " +
                 start.failure + " (" + Describe("residual", start.residual_norm) + ")");
      return false;
    }

    scaling_.Include(start.u.head(n()));
    SeedZeroGroups(start.linearization, &scaling_);
    Eigen::VectorXd tangent_scaled;
    const double direction = options_.lambda_end > options_.lambda_start ? 1.0 : -1.0;
    int orientation = 0;
    if (!InitialTangent(start.linearization, scaling_, settings_.residual_scale, direction,
                        &tangent_scaled, &orientation)) {
      Finish(TerminationReason::kStartFailed,
             "no unique tangent at the starting point (rank of [R_y, R_lambda] below n)");
      return false;
    }
    BranchPoint point;
    point.newton_iterations = start.iterations;
    point.residual_norm = start.residual_norm;
    AddPoint(point, start.u, tangent_scaled, orientation);
    closure_.emplace(u_, tangent_);
    if (!finished_ && options_.max_points <= 1) {
      Finish(TerminationReason::kMaxPoints, "max_points (1) reached at the first point");
    }
    return true;
  }

  void Follow() {
    double step = options_.initial_step;
    const long max_attempts = static_cast<long>(kMaxAttemptsPerPoint) * options_.max_points;
    for (long attempts = 0; !finished_; ++attempts) {
      if (Stopped()) {
        Finish(TerminationReason::kStoppedByObserver,
               "interrupted after point " + std::to_string(branch_.points.size() - 1) + " (" +
                   Describe(options_.lambda_name, u_(n())) + ")");
        return;
      }
      if (attempts >= max_attempts) {
        Finish(TerminationReason::kStalled, "gave up after " + std::to_string(attempts) +
                                                " step attempts at " +
                                                Describe(options_.lambda_name, u_(n())));
        return;
      }
      if (std::optional<double> next = Attempt(step)) {
        step = *next;
        continue;
      }
      if (std::optional<double> retry = controller_.AfterFailure(step)) {
        step = *retry;
        continue;
      }
      Finish(TerminationReason::kStalled, "stalled at " + Describe(options_.lambda_name, u_(n())) +
                                              " (" + Describe("step", step) + " failed, min_step " +
                                              Number(options_.min_step) + "): " + last_failure_);
    }
  }

  // One predictor-corrector step of scaled arclength h; the next step on success.
  std::optional<double> Attempt(double h) {
    StepRecord record;
    record.step = h;
    const Eigen::VectorXd tangent_scaled = scaling_.UnitScaled(tangent_);
    const Eigen::VectorXd u_pred = u_ + h * scaling_.FromScaled(tangent_scaled);
    CorrectorResult corrected =
        CorrectOnArclength(evaluator_, scaling_, settings_, u_pred, tangent_scaled);
    newton_iterations_ += corrected.iterations;
    record.newton_iterations = corrected.iterations;
    if (!corrected.converged) {
      if (std::optional<double> next = NaturalStep(h, tangent_scaled, record)) return next;
      return Reject(std::move(record), corrected.failure);
    }
    NoteNoiseFloor(corrected, record);

    Eigen::VectorXd new_tangent;
    int orientation = 0;
    // From the corrector's last factorisation where its refinement converges, else afresh.
    const double r = settings_.residual_scale;
    const bool tangent_found = (corrected.last_step != nullptr &&
                                NextTangent(*corrected.last_step, corrected.linearization, scaling_,
                                            r, tangent_scaled, &new_tangent, &orientation)) ||
                               NextTangent(corrected.linearization, scaling_, r, tangent_scaled,
                                           &new_tangent, &orientation);
    if (!tangent_found) return Reject(std::move(record), "no tangent at the corrected point");
    double angle = TurnAngle(tangent_scaled, new_tangent);
    // Past a corner of a nonsmooth branch the rule τᵀτ_prev > 0 can point the new tangent back
    // along the branch (where the motion turns by more than 90° at a sharp super-harmonic peak
    // of a stiff stick law: ω goes on, the amplitude turns back), which was then reported as a
    // fold and the branch retraced to lambda_start. The orientation index, invariant across
    // corners, decides at such turns; on smooth turns the two rules agree (they differ only at
    // branch points, where the tangent turns little).
    const bool reoriented = angle > options_.max_tangent_angle &&
                            OrientationReversed(corrected, new_tangent, &orientation);
    if (reoriented) {
      new_tangent = -new_tangent;
      orientation = -orientation;
      angle = TurnAngle(tangent_scaled, new_tangent);
      ++reoriented_steps_;
    }
    const double angle_limit = plot_ ? options_.max_plot_turn_angle : options_.max_tangent_angle;
    if (angle > angle_limit) {
      // On a smooth branch the turn shrinks with the step; on a nonsmooth one (a sample of a
      // piecewise law switching branch) the tangent jumps by the same angle however short
      // the step: such a kink is accepted once a halved step no longer reduces the turn.
      const bool kink = angle_rejection_.has_value() &&
                        h <= kKinkStepRatio * angle_rejection_->step &&
                        angle >= kKinkAngleRatio * angle_rejection_->angle;
      if (!kink) {
        angle_rejection_ = AngleRejection{h, angle};
        return Reject(std::move(record),
                      "tangent turned by " + Number(angle) + " rad, above " +
                          (plot_ ? "max_plot_turn_angle" : "max_tangent_angle") +
                          (reoriented ? " (oriented by the orientation index)" : ""));
      }
      record.note = "kink: tangent jumped by " + Number(angle) + " rad";
      if (reoriented) record.note += ", oriented by the orientation index";
    }
    PlotVerdict plotted =
        PlotCheck(corrected.u, new_tangent, h, angle > options_.max_tangent_angle);
    if (!plotted.within) {
      return Reject(std::move(record), "chord departs from the plotted curve by " +
                                           Number(*plotted.chord_error) + ", above plot_tolerance");
    }
    angle_rejection_.reset();
    // A kink's turn says nothing about the curvature ahead: it does not shrink the next step.
    const double smooth_angle = angle > angle_limit ? 0.0 : angle;
    const bool fold_crossed = options_.detect_folds && new_tangent(n()) * tangent_scaled(n()) < 0;
    const double lambda = corrected.u(n());
    if (lambda <= lambda_min_ || lambda >= lambda_max_) {
      if (fold_crossed) return Reject(std::move(record), "fold and lambda bound in one step");
      return Land(std::move(record), corrected.u, tangent_scaled);
    }
    if (fold_crossed) {
      FoldBracket bracket{u_,          tangent_scaled,   tangent_scaled(n()),
                          corrected.u, new_tangent(n()), h};
      RecordFold(bracket);
    }

    BranchPoint point;
    point.step = h;
    point.newton_iterations = corrected.iterations;
    point.residual_norm = corrected.residual_norm;
    const std::optional<double> chord_error = plotted.chord_error;
    Accept(std::move(record), point, corrected.u, new_tangent, orientation,
           std::move(plotted.sample));
    if (chord_error)
      return controller_.AfterPlottedSuccess(h, PacedIterations(corrected), *chord_error);
    return controller_.AfterSuccess(h, PacedIterations(corrected), smooth_angle);
  }

  // Whether the orientation index at the corrected point with `new_tangent` (`*after`, from
  // NextTangent's factorisation; computed here if undecided there) differs from the last
  // point's with its tangent (kept from its own tangent's factorisation; where that was
  // undecided, a start at a fold, from the Jacobian evaluated there again). Asked for only at
  // large turns. Undecided (a singular bordered matrix) counts as not reversed.
  bool OrientationReversed(const CorrectorResult& corrected, const Eigen::VectorXd& new_tangent,
                           int* after) {
    const double r = settings_.residual_scale;
    if (*after == 0) *after = OrientationIndex(corrected.linearization, scaling_, r, new_tangent);
    if (orientation_ == 0) {
      Linearization last;
      if (!evaluator_.Linearize(u_, &last)) return false;
      orientation_ = OrientationIndex(last, scaling_, r, scaling_.UnitScaled(tangent_));
    }
    return orientation_ != 0 && *after != 0 && orientation_ != *after;
  }

  // Fallback after a failed corrector: where a nonsmooth branch turns by more than 90° (in
  // the scaled norm) at a kink, no arclength hyperplane beyond the kink meets it, yet the
  // branch is still a graph over λ. Steps at fixed λ by the λ-extent of the arclength step,
  // accepted only if the solution lies within kNaturalReach·h of the last point (so that it
  // cannot jump to another branch), and orients the new tangent along the secant.
  std::optional<double> NaturalStep(double h, const Eigen::VectorXd& tangent_scaled,
                                    StepRecord& record) {
    const double t_lambda = tangent_scaled(n());
    if (std::abs(t_lambda) < kMinNaturalTangent) return std::nullopt;  // near a fold
    const double lambda = u_(n()) + h * t_lambda * scaling_.lambda_scale();
    if (lambda <= lambda_min_ || lambda >= lambda_max_) return std::nullopt;
    Eigen::VectorXd guess = u_;
    guess(n()) = lambda;
    CorrectorResult solved = CorrectAtFixedLambda(evaluator_, scaling_, settings_, guess);
    newton_iterations_ += solved.iterations;
    record.newton_iterations += solved.iterations;
    if (!solved.converged || scaling_.Norm(solved.u - u_) > kNaturalReach * h) {
      return std::nullopt;
    }
    NoteNoiseFloor(solved, record);
    const Eigen::VectorXd secant = scaling_.ToScaled(solved.u - u_).normalized();
    Eigen::VectorXd new_tangent;
    int orientation = 0;
    if (!NextTangent(solved.linearization, scaling_, settings_.residual_scale, secant, &new_tangent,
                     &orientation) ||
        new_tangent(n()) * t_lambda <= 0.0) {
      return std::nullopt;
    }
    PlotVerdict plotted =
        PlotCheck(solved.u, new_tangent, scaling_.Norm(solved.u - u_),
                  TurnAngle(tangent_scaled, new_tangent) > options_.max_tangent_angle);
    if (!plotted.within) return std::nullopt;
    BranchPoint point;
    point.step = scaling_.Norm(solved.u - u_);
    point.newton_iterations = solved.iterations;
    point.residual_norm = solved.residual_norm;
    record.note = "natural-parameter step after a failed arclength corrector";
    record.fixed_lambda = true;
    angle_rejection_.reset();
    const std::optional<double> chord_error = plotted.chord_error;
    Accept(std::move(record), point, solved.u, new_tangent, orientation, std::move(plotted.sample));
    if (chord_error)
      return controller_.AfterPlottedSuccess(h, PacedIterations(solved), *chord_error);
    return controller_.AfterSuccess(h, PacedIterations(solved), 0.0);
  }

  // With plot_tolerance: the sample at u and the chord's distance from the plotted curve
  // between the last point and u (unit scaled tangent `tangent`, h apart), across a corner if
  // the state's tangent turned by more than max_tangent_angle. Without a usable sample the
  // step counts as a gap (sized by the tangent's turn).
  struct PlotVerdict {
    std::optional<PlotChordControl::Sample> sample;  // taken along `tangent`, current scaling
    std::optional<double> chord_error;
    bool within = true;  // chord_error (if any) within plot_tolerance
  };
  PlotVerdict PlotCheck(const Eigen::VectorXd& u, const Eigen::VectorXd& tangent, double h,
                        bool corner) {
    PlotVerdict verdict;
    if (!plot_) return verdict;
    verdict.sample = plot_->At(u, scaling_.FromScaled(tangent));
    if (verdict.sample && plot_sample_) {
      verdict.chord_error = plot_->ChordError(*plot_sample_, *verdict.sample, h, corner);
      verdict.within = *verdict.chord_error <= plot_->tolerance();
    } else {
      ++plot_gaps_;
    }
    return verdict;
  }

  // A correction accepted at the residual's rounding floor, above residual_tolerance: said in
  // the step's record and counted for the summary's notes.
  void NoteNoiseFloor(const CorrectorResult& corrected, StepRecord& record) {
    if (!corrected.at_noise_floor) return;
    ++noise_floor_steps_;
    record.note =
        "converged at the residual's rounding floor: |R| = " + Number(corrected.residual_norm) +
        ", floor " + Number(corrected.noise_floor);
  }

  // Angle between two unit scaled tangents, in the problem's step weights when it has them
  // (a weighted tangent that vanishes, e.g. a step moving only unweighted unknowns, falls
  // back to the plain angle).
  double TurnAngle(const Eigen::VectorXd& from, const Eigen::VectorXd& to) const {
    double cosine = from.dot(to);
    if (turn_weights_.size() != 0) {
      const Eigen::VectorXd a = from.cwiseProduct(turn_weights_);
      const Eigen::VectorXd b = to.cwiseProduct(turn_weights_);
      const double norms = a.norm() * b.norm();
      if (norms > 0.0) cosine = a.dot(b) / norms;
    }
    return std::acos(std::clamp(cosine, -1.0, 1.0));
  }

  // Records an accepted step and its point, then checks the stop rules.
  void Accept(StepRecord record, const BranchPoint& point, const Eigen::VectorXd& u,
              const Eigen::VectorXd& tangent_scaled, int orientation,
              std::optional<PlotChordControl::Sample> plot_sample) {
    const Eigen::VectorXd u_previous = u_;
    record.accepted = true;
    branch_.summary.history.push_back(std::move(record));
    AddPoint(point, u, tangent_scaled, orientation, std::move(plot_sample));
    if (!finished_ && closure_->Closes(scaling_, u_previous, u_, tangent_)) {
      Finish(
          TerminationReason::kClosedCurve,
          "returned to the first point after " + std::to_string(branch_.points.size()) + " points");
    }
    if (!finished_ && static_cast<int>(branch_.points.size()) >= options_.max_points) {
      Finish(TerminationReason::kMaxPoints, "max_points (" + std::to_string(options_.max_points) +
                                                ") reached at " +
                                                Describe(options_.lambda_name, u_(n())));
    }
  }

  // The step left [λ_min, λ_max] at `u_outside`: solves at λ = bound from the chord's
  // interpolation so that the branch ends exactly on the bound.
  std::optional<double> Land(StepRecord record, const Eigen::VectorXd& u_outside,
                             const Eigen::VectorXd& tangent_scaled) {
    const double step = record.step;
    const double bound = u_outside(n()) <= lambda_min_ ? lambda_min_ : lambda_max_;
    const double span = u_outside(n()) - u_(n());
    const double fraction = span != 0.0 ? (bound - u_(n())) / span : 1.0;
    Eigen::VectorXd guess = u_ + fraction * (u_outside - u_);
    guess(n()) = bound;
    CorrectorResult landed = CorrectAtFixedLambda(evaluator_, scaling_, settings_, guess);
    newton_iterations_ += landed.iterations;
    record.newton_iterations += landed.iterations;
    Eigen::VectorXd tangent;
    int orientation = 0;
    if (!landed.converged) {
      return Reject(std::move(record), "landing on the lambda bound failed: " + landed.failure);
    }
    if (!NextTangent(landed.linearization, scaling_, settings_.residual_scale, tangent_scaled,
                     &tangent, &orientation)) {
      return Reject(std::move(record), "no tangent at the lambda bound");
    }
    BranchPoint point;
    point.step = scaling_.Norm(landed.u - u_);
    point.newton_iterations = record.newton_iterations;
    point.residual_norm = landed.residual_norm;
    record.accepted = true;
    branch_.summary.history.push_back(std::move(record));
    AddPoint(point, landed.u, tangent, orientation);
    Finish(TerminationReason::kReachedLambdaBound,
           "reached " + Describe(options_.lambda_name, bound));
    return step;
  }

  std::optional<double> Reject(StepRecord record, std::string note) {
    record.accepted = false;
    record.note = note;
    branch_.summary.history.push_back(std::move(record));
    last_failure_ = std::move(note);
    return std::nullopt;
  }

  void RecordFold(const FoldBracket& bracket) {
    FoldSearchResult search = LocateFold(evaluator_, scaling_, settings_, bracket,
                                         options_.fold_tolerance, options_.max_fold_iterations);
    newton_iterations_ += search.newton_iterations;
    search.fold.after_point = static_cast<int>(branch_.points.size()) - 1;
    branch_.folds.push_back(std::move(search.fold));
    progress_.FoldFound(static_cast<int>(branch_.folds.size()), branch_.folds.back());
    if (observer_ != nullptr) observer_->OnFold(branch_.folds.back());
  }

  // Appends a converged point; `tangent_scaled` is its unit tangent in the current scaling,
  // renormalised after the scaling has taken the point in. `plot_sample`: the step's plot
  // sample at u along that tangent, if it took one (else it is taken here).
  void AddPoint(BranchPoint point, const Eigen::VectorXd& u, const Eigen::VectorXd& tangent_scaled,
                int orientation,
                std::optional<PlotChordControl::Sample> plot_sample = std::nullopt) {
    const Eigen::VectorXd direction = scaling_.FromScaled(tangent_scaled);
    const Eigen::VectorXd scales_before = scaling_.scales();
    orientation_ = orientation;
    scaling_.Include(u.head(n()));
    tangent_ = direction / scaling_.Norm(direction);
    u_ = u;
    point.lambda = u(n());
    point.y = u.head(n());
    point.tangent_y = tangent_.head(n());
    point.tangent_lambda = tangent_(n());
    if (plot_) {
      // The step's sample is per unit arclength in the scaling before this point: reused
      // while the point leaves the scaling as it was (most steps), else taken again.
      if (plot_sample && scaling_.scales() == scales_before) {
        plot_sample_ = std::move(plot_sample);
      } else {
        plot_sample_ = plot_->At(u_, tangent_);
      }
      if (plot_sample_) plot_->Include(*plot_sample_);
    }
    const int index = static_cast<int>(branch_.points.size());
    branch_.points.push_back(point);
    progress_.Point(index, branch_.points.back());
    if (observer_ != nullptr && !observer_->OnPoint(branch_.points.back(), index)) {
      Finish(TerminationReason::kStoppedByObserver,
             StoppedByObserverMessage(index, options_.lambda_name, point.lambda));
    }
  }

  Evaluator evaluator_;
  const ContinuationOptions& options_;
  ContinuationObserver* observer_;
  std::vector<int> groups_;
  Eigen::VectorXd turn_weights_;  // StepWeights() and 1 for λ; empty = unweighted
  Scaling scaling_;
  StepController controller_;
  ProgressReporter progress_;
  const double lambda_min_;
  const double lambda_max_;
  NewtonSettings settings_;

  Branch branch_;
  Eigen::VectorXd u_;        // last accepted point (y, λ)
  Eigen::VectorXd tangent_;  // its tangent direction, unit in the current scaling
  std::optional<ClosureDetector> closure_;
  std::optional<PlotChordControl> plot_;                 // with plot_tolerance > 0
  std::optional<PlotChordControl::Sample> plot_sample_;  // at u_, if the problem gave one
  int plot_gaps_ = 0;  // accepted steps without a chord error (no usable plot sample)
  // The last step rejected for its tangent turn, to tell a kink from a too-long step.
  struct AngleRejection {
    double step;
    double angle;
  };
  std::optional<AngleRejection> angle_rejection_;
  // The orientation index of (u_, tangent_), known from the factorisation that gave the
  // tangent (OrientationIndex: invariant under the scaling's changes); 0 when undecided.
  int orientation_ = 0;
  bool finished_ = false;
  int newton_iterations_ = 0;
  int noise_floor_steps_ = 0;
  int reoriented_steps_ = 0;  // step attempts whose tangent the orientation index reversed
  std::string last_failure_;
};

}  // namespace

Branch Continue(ContinuationProblem& problem, const Eigen::VectorXd& y_guess,
                const ContinuationOptions& options, ContinuationObserver* observer,
                PlotCurve* plot) {
  options.Validate();
  return Continuer(problem, options, observer, plot).Run(y_guess);
}

}  // namespace nfrc
