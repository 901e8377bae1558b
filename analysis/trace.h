#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/harmonic_system.h"
#include "analysis/solution_report.h"
#include "analysis/stability.h"
#include "continuation/continuation.h"
#include "core/lemke.h"
#include "models/model_check.h"

namespace nfrc {

// What Lemke reported for one LCP-HBM solution (Lemke stepping).
struct LemkeRecord {
  LemkeStatus status = LemkeStatus::kSolution;
  int pivots = 0;
  bool trivial = false;
  bool warm_started = false;
  double complementarity = 0.0;
  double feasibility = 0.0;
  double complementarity_gap = 0.0;  // m, max |min(g, λ/w)|
};

// A coexisting contact solution found by a warm start where the cold solve was trivial.
struct ContactBranchRecord {
  SolutionMeasures measures;
  LemkeRecord lemke;
};

// One point of a traced branch with what is reported about it.
struct TracePoint {
  int index = 0;
  BranchPoint point;
  SolutionMeasures measures;
  std::optional<LemkeRecord> lemke;  // Lemke stepping only
  bool coexisting_contact = false;   // Lemke stepping: a warm start found one
  std::optional<ContactBranchRecord> contact_branch;
  FloquetResult floquet;  // Hill's method; computed = false when stability is off
};

// A fold with the response measures at it.
struct TraceFold {
  Fold fold;
  PointMeasures measures;
};

// Receives a trace's results as they are found (a writer, a progress display). Called on
// the tracing thread; returning false from OnPoint stops the trace (points kept).
class TraceObserver {
 public:
  virtual ~TraceObserver() = default;
  // Before the first point, once the system is built.
  virtual void OnStart(int /*num_unknowns*/) {}
  virtual bool OnPoint(const TracePoint& /*point*/) { return true; }
  virtual void OnFold(const TraceFold& /*fold*/) {}
  virtual void OnBifurcation(const Bifurcation& /*bifurcation*/) {}
  virtual void OnSignals(const SolutionSignals& /*signals*/) {}
};

// Whether a study (fold or peak curves) goes on: a stop flag (a signal handler's) and a poll
// callback (Python checks its signals there), both optional. Once stopped it stays stopped. As
// a TraceObserver it stops the study's branch trace too.
class StopCheck : public TraceObserver {
 public:
  StopCheck(const std::atomic<bool>* stop, std::function<bool()> poll)
      : stop_(stop), poll_(std::move(poll)) {}
  // Polls; false once the flag was raised or the callback returned false.
  bool Continue() {
    if (!stopped_ && ((stop_ != nullptr && stop_->load()) || (poll_ && !poll_()))) {
      stopped_ = true;
    }
    return !stopped_;
  }
  bool stopped() const { return stopped_; }
  bool OnPoint(const TracePoint& /*point*/) override { return Continue(); }

 private:
  const std::atomic<bool>* stop_;
  std::function<bool()> poll_;
  bool stopped_ = false;
};

struct TraceOptions {
  std::ostream* progress = nullptr;         // progress lines; null = quiet
  const std::atomic<bool>* stop = nullptr;  // polled after every point
  TraceObserver* observer = nullptr;        // results as they come
  bool solve_signals = true;                // resolve the case's signals_at crossings
  // A solution (or close guess) at continuation.lambda_start to start from, instead of the
  // linear guess and the harmonic ladder (branch switching); null: none.
  const Eigen::VectorXd* start = nullptr;
  // Threads that run Hill's analyses beside the tracing one, which runs them too while it
  // waits for them (analysis/stability_pipeline.h): -1 (default) one per further hardware thread,
  // 0 none. The results are the same, bit for bit, whatever the count.
  int threads = -1;
  // The linear model's check (CheckLinearModel), where the caller made it before writing
  // anything (a model it refuses leaves no files); null: TraceCase makes it. Its warnings
  // go to the progress stream and the summary's notes.
  const ModelCheck* model_check = nullptr;
  // Throws InputError("threads: ...") for a count outside [-1, kMaxThreads].
  void Validate() const;
};

// More Hill threads than this is a typo, not a machine.
constexpr int kMaxThreads = 256;

// The worker count of TraceOptions::threads: `requested`, or for -1 the hardware threads but one.
int HillThreads(int requested);

// A traced branch and everything reported along it.
struct TraceResult {
  Branch branch;  // points, folds and the summary (termination reason, message, counts)
  std::vector<TracePoint> points;
  std::vector<TraceFold> folds;
  std::vector<Bifurcation> bifurcations;  // in branch order
  // Between pairs of Neimark–Sacker points (QuasiPeriodicWindows in analysis/bifurcation.h).
  std::vector<QuasiPeriodicWindow> quasi_periodic_windows;
  std::vector<SolutionSignals> signals;
  int num_unknowns = 0;
};

// Traces the branch of a case (the arclength engine, or Lemke stepping for
// continuation.method "lemke_stepping"), with the starting point of StartingGuess, and
// resolves the signals_at crossings. Throws InputError for bad input; numerical failure is
// the summary's termination reason.
TraceResult TraceCase(const Case& the_case, const TraceOptions& options = {});

// Traces the branch of `system` from `guess` (default: the linear guess) at
// options.lambda_start; with options.plot_tolerance > 0 the steps follow `plot` (usually
// Case::Plot(); std::invalid_argument if it plots nothing).
Branch Trace(HarmonicSystem& system, const ContinuationOptions& options,
             ContinuationObserver* observer = nullptr, const Eigen::VectorXd* guess = nullptr,
             const PlotSpec& plot = {});

// Above this many unknowns StartingGuess tries the harmonic ladder before the linear guess.
// From the linear guess a nonsmooth law takes tens of Newton iterations, from the rung below
// (a third of the harmonics, an iteration ~1/27 of the cost) a few: point E at N_φ = 160
// (320 unknowns) 40 from the linear guess against 17 at H = 53 and 4 at H = 159; the
// N_φ = 640 point's rung at H = 425 (852 unknowns) 38 against 13 + 7 + 11 (`nfrc run`
// prints each rung's). Below ~200 unknowns the start is a few ms either way.
constexpr int kLadderFirstUnknowns = 200;

// A starting point at lambda_start for a case: Newton from the linear guess or, when that
// fails, (1) the stiffness homotopy of the_case.start (laws with a stiffness: solved softer,
// then stiffened rung by rung, warm-started), then (2) the start of the same case with about a
// third of the harmonics (recursively, each rung trying both) re-expressed in the full set and
// corrected (undamped, then damped): the harmonic ladder. Systems of more than kLadderFirstUnknowns
// go down the ladder before trying the linear guess. Returns the linear guess if all of it
// fails (the engine then reports the failed start). A raised `stop` skips the remaining rungs
// (the engine then stops after its first point). What was done beyond the linear guess (the
// homotopy's rungs and outcome, the ladder) is appended to `notes` ("start: ..."), which
// TraceCase puts first in the summary's notes.
Eigen::VectorXd StartingGuess(const Case& the_case, HarmonicSystem& system, std::ostream* progress,
                              const std::atomic<bool>* stop = nullptr,
                              std::vector<std::string>* notes = nullptr);

// Lemke stepping (continuation.method "lemke_stepping"): LCP-HBM at `stepping.points`
// evenly spaced ω plus the signals_at frequencies.
TraceResult StepLcp(const Case& the_case, const TraceOptions& options = {});

// The branch a study in a second parameter starts from: the case traced without its signals
// and, unless `stability`, without Hill's method; `check` can stop it (points kept).
TraceResult TraceStudyBranch(const Case& the_case, bool stability, std::ostream* progress,
                             StopCheck* check);

}  // namespace nfrc
