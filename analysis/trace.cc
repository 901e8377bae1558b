#include "analysis/trace.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include "analysis/bifurcation.h"
#include "analysis/stability_pipeline.h"
#include "continuation/fixed_lambda.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// Measures every point, resolves the signals_at crossings of each new segment, analyses each
// point's stability (StabilityPipeline: on threads of its own and this one) and forwards the typed
// results to the caller's observer in branch order; stops the engine when `stop` is raised or
// the observer refuses a point. The observer hears of a point once its analysis is done, up to
// a chain of points per thread after the engine found it.
class TraceRecorder : public ContinuationObserver {
 public:
  TraceRecorder(const Case& the_case, HarmonicSystem& system, const TraceOptions& options,
                TraceResult* result)
      : case_(the_case),
        system_(system),
        options_(options),
        reporter_(system, the_case.output_dofs, the_case.output_names),
        monitor_(system, the_case.stability, the_case.continuation),
        result_(result) {
    if (the_case.stability.enabled) {
      stability_ = std::make_unique<StabilityPipeline>(the_case, monitor_, reporter_,
                                                       HillThreads(options.threads));
    }
  }

  bool OnPoint(const BranchPoint& point, int index) override {
    // Filled in place: a TracePoint copied with its empty optionals trips GCC 12's
    // -Wmaybe-uninitialized.
    TracePoint& record = std::get<TracePoint>(events_.emplace_back(std::in_place_type<TracePoint>));
    record.index = index;
    record.point = point;
    if (stability_) {  // which measures the point beside its analysis
      const bool fold_before = last_fold_ && last_fold_->after_point == index - 1;
      stability_->Submit(index, point, fold_before ? &*last_fold_ : nullptr);
    } else {
      record.measures = reporter_.Measure(point.y, point.lambda);
    }
    ++pending_points_;
    if (options_.solve_signals) {
      for (double omega : case_.signals_at) {
        const BranchPoint* previous = previous_ ? &*previous_ : nullptr;
        if (const auto solved =
                SolveAtCrossing(system_, previous, point, omega, case_.continuation)) {
          SolutionSignals signals = reporter_.Signals(solved->y, omega);
          signals.after_point = point.lambda == omega ? index : index - 1;
          signals.converged = solved->converged;
          signals.note = solved->message;
          events_.emplace_back(std::move(signals));
        }
      }
    }
    previous_ = point;
    // With workers, enough queued points for every thread to have a chain of its own.
    Deliver(stability_ && stability_->threads() > 0
                ? StabilityPipeline::kChainPoints * (stability_->threads() + 1)
                : 0);
    const bool stopped = options_.stop != nullptr && options_.stop->load();
    return !refused_at_ && !stopped;
  }

  void OnFold(const Fold& fold) override {
    last_fold_ = fold;
    events_.emplace_back(TraceFold{fold, reporter_.analyzer().Measure(fold.y, fold.lambda)});
  }

  // Delivers what is still queued once the engine has returned (waits for the workers).
  void Finish() { Deliver(0); }

  // The last point the observer was given, if it refused it (the engine went on meanwhile).
  std::optional<int> refused_at() const { return refused_at_; }

 private:
  using Event = std::variant<TracePoint, TraceFold, SolutionSignals>;

  // Forwards queued events in order while their point's analysis is done, and waits for the
  // oldest while more than `max_pending` points are queued. After a refused point only its
  // own signals follow; the rest is dropped.
  void Deliver(int max_pending) {
    while (!events_.empty()) {
      Event& event = events_.front();
      if (refused_at_ && !std::holds_alternative<SolutionSignals>(event)) {
        events_.clear();
        pending_points_ = 0;
        return;
      }
      if (auto* point = std::get_if<TracePoint>(&event)) {
        std::optional<Bifurcation> bifurcation;
        if (stability_) {
          if (pending_points_ <= max_pending && !stability_->Ready(point->index)) return;
          PointStability stability = stability_->Take(point->index);
          point->floquet = std::move(stability.floquet);
          point->measures = std::move(stability.measures);
          bifurcation = std::move(stability.bifurcation_before);
        }
        --pending_points_;
        result_->points.push_back(std::move(*point));
        const TracePoint& record = result_->points.back();
        if (bifurcation) Report(std::move(*bifurcation), record.index);
        if (options_.observer != nullptr && !options_.observer->OnPoint(record)) {
          refused_at_ = record.index;
        }
      } else if (auto* fold = std::get_if<TraceFold>(&event)) {
        result_->folds.push_back(std::move(*fold));
        if (options_.observer != nullptr) options_.observer->OnFold(result_->folds.back());
      } else {
        result_->signals.push_back(std::move(std::get<SolutionSignals>(event)));
        if (options_.observer != nullptr) options_.observer->OnSignals(result_->signals.back());
      }
      events_.pop_front();
    }
  }

  // A bifurcation found between point `index` and the one before.
  void Report(Bifurcation found, int index) {
    found.after_point = index - 1;
    found.measures = reporter_.analyzer().Measure(found.y, found.omega);
    if (options_.progress != nullptr) {
      const double m = case_.period_multiple;  // λ = ω/m
      *options_.progress << "nfrc: " << ToString(found.type) << " at omega = " << m * found.omega
                         << " (+/- " << m * found.omega_accuracy << ")\n";
    }
    result_->bifurcations.push_back(std::move(found));
    if (options_.observer != nullptr)
      options_.observer->OnBifurcation(result_->bifurcations.back());
  }

  const Case& case_;
  HarmonicSystem& system_;
  const TraceOptions& options_;
  SolutionReporter reporter_;
  // The analyses and localisations the tracing thread runs itself.
  StabilityMonitor monitor_;
  TraceResult* result_;
  std::unique_ptr<StabilityPipeline> stability_;  // with stability on
  std::optional<Fold> last_fold_;                 // the engine's latest
  std::deque<Event> events_;  // found by the engine, not yet given to the observer
  int pending_points_ = 0;    // points among events_
  std::optional<int> refused_at_;
  std::optional<BranchPoint> previous_;
};

// The rung below H on the harmonic ladder: about H/3, odd if the set is odd-only.
int CoarserMaxHarmonic(const HarmonicSet& set) {
  int coarse = std::max(1, set.max_harmonic() / 3);
  if (set.odd_only() && coarse % 2 == 0) --coarse;
  return std::max(1, coarse);
}

// A stiffness scale this close to 1 is 1 (products of the homotopy's ratios round).
constexpr double kScaleRounding = 1e-9;

std::string Number(double value) {
  std::ostringstream text;
  text << std::setprecision(6) << value;
  return text.str();
}

// The stiffness homotopy of StartOptions at omega_start, the last rung solved on `system` (the
// case's own), the rungs down from `from` (null: each rung's linear guess). Empty if no law
// has a stiffness, the option is off, no rung down converges, or a rung up fails at the
// smallest ratio; the outcome goes to `notes`.
std::optional<Eigen::VectorXd> StiffnessHomotopy(const Case& the_case, HarmonicSystem& system,
                                                 const Eigen::VectorXd* from,
                                                 std::ostream* progress,
                                                 const std::atomic<bool>* stop,
                                                 std::vector<std::string>* notes) {
  const StartOptions& start = the_case.start;
  if (!start.homotopy) return std::nullopt;
  std::vector<std::pair<size_t, double>> stiff;  // law index, the case's stiffness (N/m)
  for (size_t i = 0; i < the_case.laws.size(); ++i) {
    if (const auto k = LawStiffness(the_case.laws[i], the_case.model.model))
      stiff.push_back({i, *k});
  }
  if (stiff.empty()) return std::nullopt;
  auto note = [&](const std::string& text) {
    if (progress != nullptr) *progress << "nfrc: " << text << "\n";
    if (notes != nullptr) notes->push_back("start: " + text);
  };
  auto stopped = [&] { return stop != nullptr && stop->load(); };
  ContinuationOptions options = the_case.continuation;
  options.stop = stop;
  const double omega = options.lambda_start;
  // Solves the case with its stiffnesses times `scale` from `guess` (the linear guess if null):
  // damped, then undamped (semismooth Newton's local convergence where the line search stalls).
  int iterations = 0;
  auto solve = [&](double scale, const Eigen::VectorXd* guess) -> std::optional<Eigen::VectorXd> {
    std::unique_ptr<HarmonicSystem> scaled_system;
    HarmonicSystem* target = &system;
    if (scale != 1.0) {
      Case scaled = the_case;
      for (const auto& [i, k] : stiff) SetLawStiffness(scaled.laws[i], k * scale);
      scaled_system = BuildSystem(scaled);
      target = scaled_system.get();
    }
    const Eigen::VectorXd initial = guess != nullptr ? *guess : target->InitialGuess(omega);
    FixedLambdaSolution solved = SolveAtFixedLambda(*target, initial, omega, initial, options);
    iterations += solved.iterations;
    if (!solved.converged && options.line_search) {
      ContinuationOptions undamped = options;
      undamped.line_search = false;
      solved = SolveAtFixedLambda(*target, initial, omega, initial, undamped);
      iterations += solved.iterations;
    }
    if (progress != nullptr) {
      *progress << "nfrc: stiffness homotopy: " << Number(scale)
                << " times the laws' stiffness: " << (solved.converged ? "converged" : "failed")
                << " (" << iterations << " Newton iterations so far)\n";
    }
    if (!solved.converged) return std::nullopt;
    return solved.y;
  };

  // Down: the stiffest rung that Newton from the linear guess solves.
  double scale = 1.0;
  std::optional<Eigen::VectorXd> y;
  for (int rung = 1; rung <= start.homotopy_rungs && !y; ++rung) {
    if (stopped()) return std::nullopt;
    scale /= start.homotopy_factor;
    y = solve(scale, from);
  }
  const std::string origin =
      from != nullptr ? "the coarser harmonics' solution" : "the linear guess";
  if (!y) {
    note("stiffness homotopy: no start from " + origin + " down to " + Number(scale) +
         " times the laws' stiffness (" + std::to_string(iterations) + " Newton iterations)");
    return std::nullopt;
  }
  const double softest = scale;
  // Up, warm-started, to the case's stiffness: from the secant through the last two rungs in
  // log(stiffness) once there are two (the solution moves smoothly with the stiffness).
  double ratio = start.homotopy_factor;
  int rungs = 0;
  std::optional<Eigen::VectorXd> y_before;
  double scale_before = 0.0;
  while (scale < 1.0) {
    if (stopped()) return std::nullopt;
    // The last rung lands on the case's stiffness exactly (not a rounding below it).
    const double next = scale * ratio >= 1.0 - kScaleRounding ? 1.0 : scale * ratio;
    Eigen::VectorXd guess = *y;
    if (y_before) {
      guess += (*y - *y_before) * (std::log(next / scale) / std::log(scale / scale_before));
    }
    const int before = iterations;
    if (std::optional<Eigen::VectorXd> solved = solve(next, &guess)) {
      y_before = std::move(y);
      scale_before = scale;
      y = std::move(solved);
      scale = next;
      ++rungs;
      // An easy rung lets the next one go further (back up to the factor).
      if (iterations - before <= 2 * options.target_newton_iterations) {
        ratio = std::min(start.homotopy_factor, ratio * ratio);
      }
    } else {
      ratio = std::sqrt(ratio);
      if (ratio < kMinHomotopyRatio) {
        note("stiffness homotopy: failed at " + Number(next) + " times the laws' stiffness, from " +
             Number(scale) + " (" + std::to_string(iterations) + " Newton iterations)");
        return std::nullopt;
      }
    }
  }
  note("stiffness homotopy: started from " + origin + " at " + Number(softest) +
       " times the laws' stiffness, " + std::to_string(rungs) + (rungs == 1 ? " rung" : " rungs") +
       " up to the case's (" + std::to_string(iterations) + " Newton iterations)");
  return y;
}

}  // namespace

Branch Trace(HarmonicSystem& system, const ContinuationOptions& options,
             ContinuationObserver* observer, const Eigen::VectorXd* guess, const PlotSpec& plot) {
  for (size_t i = 0; i < system.laws().size(); ++i) {
    try {
      system.laws()[i]->CheckForContinuation(system.harmonic_set());
    } catch (const std::invalid_argument& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "] (" + system.laws()[i]->type() +
                       "): " + error.what());
    }
  }
  const Eigen::VectorXd start =
      guess != nullptr ? *guess : system.InitialGuess(options.lambda_start);
  std::optional<MeasureCurve> curve;
  if (options.plot_tolerance > 0.0) curve.emplace(system, plot);
  Branch branch = Continue(system, start, options, observer, curve ? &*curve : nullptr);
  if (!branch.summary.success() && !system.last_error().empty()) {
    branch.summary.message += " (last evaluation error: " + system.last_error() + ")";
  }
  return branch;
}

Eigen::VectorXd StartingGuess(const Case& the_case, HarmonicSystem& system, std::ostream* progress,
                              const std::atomic<bool>* stop, std::vector<std::string>* notes) {
  ContinuationOptions options = the_case.continuation;
  options.stop = stop;
  const double omega = options.lambda_start;
  const Eigen::VectorXd linear = system.InitialGuess(omega);
  if (stop != nullptr && stop->load()) return linear;
  const HarmonicSet& set = system.harmonic_set();
  const int coarse_h = CoarserMaxHarmonic(set);
  bool ladder = coarse_h < set.max_harmonic();
  const int block = set.NumCoefficients();
  for (const auto& law : system.laws()) {
    // Only own unknowns that are coefficient signals can move between harmonic sets.
    if (!law->OwnUnknownsAreCoefficients() || law->NumOwnUnknowns(set) % block != 0) {
      ladder = false;
    }
  }
  const bool ladder_first = ladder && system.NumUnknowns() > kLadderFirstUnknowns;
  // A converged start's cost on the progress stream: every rung of a ladder reports its own.
  const auto started = [&](const FixedLambdaSolution& solved, int iterations,
                           const std::string& from) {
    if (progress != nullptr) {
      *progress << "nfrc: start at H=" << set.max_harmonic() << ": " << iterations
                << " Newton iterations from " << from << "\n";
    }
    return solved.y;
  };
  if (!ladder_first) {
    const FixedLambdaSolution solved = SolveAtFixedLambda(system, linear, omega, linear, options);
    if (solved.converged) return started(solved, solved.iterations, "the linear guess");
    if (progress != nullptr) {
      *progress << "nfrc: no start from the linear guess with H=" << set.max_harmonic() << "\n";
    }
    if (const auto homotopy = StiffnessHomotopy(the_case, system, nullptr, progress, stop, notes)) {
      return *homotopy;
    }
    if (!ladder || (stop != nullptr && stop->load())) return linear;
  }
  if (progress != nullptr) {
    if (ladder_first) *progress << "nfrc: large system with H=" << set.max_harmonic() << "; ";
    *progress << (ladder_first ? "" : "nfrc: ") << "starting from H=" << coarse_h << "\n";
  }
  if (notes != nullptr) {
    notes->push_back("start: harmonic ladder from H=" + std::to_string(coarse_h) +
                     " to H=" + std::to_string(set.max_harmonic()));
  }
  // The same case with fewer harmonics (the default sampling of that set).
  Case coarse_case = the_case;
  coarse_case.harmonics = HarmonicSet(coarse_h, set.odd_only());
  std::unique_ptr<HarmonicSystem> coarse_system = BuildSystem(coarse_case);
  const Eigen::VectorXd coarse = StartingGuess(coarse_case, *coarse_system, progress, stop, notes);
  if (stop != nullptr && stop->load()) return linear;
  const Eigen::VectorXd padded = ChangeHarmonicSet(coarse, coarse_system->harmonic_set(), set);
  // The re-expressed coarse solution lies in semismooth Newton's local region, where a line
  // search on ‖R‖ can stall at a kink (at N_φ = 640 it stopped at ‖R‖ = 2e-4 of its start
  // after 13 iterations): undamped first, damped if that diverges.
  ContinuationOptions undamped = options;
  undamped.line_search = false;
  FixedLambdaSolution solved = SolveAtFixedLambda(system, padded, omega, padded, undamped);
  int iterations = solved.iterations;
  if (!solved.converged && options.line_search) {
    solved = SolveAtFixedLambda(system, padded, omega, padded, options);
    iterations += solved.iterations;
  }
  if (solved.converged) return started(solved, iterations, "H=" + std::to_string(coarse_h));
  // The coarse solution of a stiff law can lie outside Newton's region at the full harmonics
  // (DLFT friction at ε = 1e4, N_φ = 60): softer, it lies inside.
  if (const auto homotopy = StiffnessHomotopy(the_case, system, &padded, progress, stop, notes)) {
    return *homotopy;
  }
  // Padded failed both ways; at a large system the linear guess has not been tried yet.
  if (ladder_first) {
    solved = SolveAtFixedLambda(system, linear, omega, linear, options);
    if (solved.converged) return started(solved, solved.iterations, "the linear guess");
  }
  return linear;
}

int HillThreads(int requested) {
  if (requested >= 0) return requested;
  // The tracing thread runs analyses too while it waits for them.
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(cores - 1, 0, kMaxThreads);
}

void TraceOptions::Validate() const {
  if (threads < -1 || threads > kMaxThreads) {
    throw InputError("threads: must be -1 (one per core), 0 (none) or up to " +
                     std::to_string(kMaxThreads) + ", got " + std::to_string(threads));
  }
}

namespace {

// TraceCase for the arclength method.
TraceResult TraceArclength(const Case& the_case, const TraceOptions& options) {
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  TraceResult result;
  result.num_unknowns = system->NumUnknowns();
  if (options.observer != nullptr) options.observer->OnStart(result.num_unknowns);
  TraceRecorder recorder(the_case, *system, options, &result);
  ContinuationOptions continuation = the_case.continuation;
  continuation.progress = options.progress;
  continuation.stop = options.stop;
  if (options.progress != nullptr) {
    *options.progress << "nfrc: " << system->NumUnknowns() << " unknowns ("
                      << the_case.harmonics.num_harmonics() << " harmonics, "
                      << the_case.harmonics.num_samples() << " samples), omega "
                      << continuation.lambda_start << " -> " << continuation.lambda_end << "\n";
  }
  std::vector<std::string> start_notes;
  const Eigen::VectorXd guess =
      options.start != nullptr
          ? *options.start
          : StartingGuess(the_case, *system, options.progress, options.stop, &start_notes);
  result.branch = Trace(*system, continuation, &recorder, &guess, the_case.Plot());
  recorder.Finish();
  if (const std::optional<int> last = recorder.refused_at();
      last && *last + 1 < static_cast<int>(result.branch.points.size())) {
    // The engine went past the refused point while its analysis was pending.
    StopBranchAfter(*last, continuation.lambda_name, &result.branch);
  }
  std::vector<std::string>& notes = result.branch.summary.notes;
  notes.insert(notes.begin(), start_notes.begin(), start_notes.end());
  result.quasi_periodic_windows = QuasiPeriodicWindows(result.bifurcations, result.points);
  if (options.stop != nullptr && options.stop->load()) {
    result.branch.summary.message += " (interrupted by a signal)";
  }
  return result;
}

}  // namespace

TraceResult TraceCase(const Case& the_case, const TraceOptions& options) {
  the_case.Validate();
  options.Validate();
  const ModelCheck model_check = options.model_check != nullptr
                                     ? *options.model_check
                                     : CheckLinearModel(the_case.model.model);
  for (const std::string& warning : model_check.warnings) {
    if (options.progress != nullptr) *options.progress << "nfrc: warning: " << warning << "\n";
  }
  TraceResult result = the_case.method == Method::kLemkeStepping
                           ? StepLcp(the_case, options)
                           : TraceArclength(the_case, options);
  std::vector<std::string>& notes = result.branch.summary.notes;
  notes.insert(notes.begin(), model_check.warnings.begin(), model_check.warnings.end());
  return result;
}

TraceResult TraceStudyBranch(const Case& the_case, bool stability, std::ostream* progress,
                             StopCheck* check) {
  Case branch_case = the_case;
  branch_case.stability.enabled = branch_case.stability.enabled && stability;
  TraceOptions options;
  options.progress = progress;
  options.solve_signals = false;
  options.observer = check;
  return TraceCase(branch_case, options);
}

}  // namespace nfrc
