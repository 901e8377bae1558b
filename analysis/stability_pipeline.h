#pragma once

#include <Eigen/Dense>
#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "analysis/bifurcation.h"
#include "analysis/case.h"
#include "analysis/solution_report.h"
#include "analysis/stability.h"
#include "continuation/branch.h"

namespace nfrc {

// The stability of one point of a branch, the bifurcation between it and the point before,
// and the point's measures.
struct PointStability {
  FloquetResult floquet;
  std::optional<Bifurcation> bifurcation_before;  // its after_point and measures are not set
  SolutionMeasures measures;                      // SolutionReporter::Measure of the point
};

// Hill's analyses of a branch's points, their measures, and the localisation of each change
// of stability between two of them, on threads of their own, so that the trace goes on
// meanwhile (Hill is about half of a friction curve's time and nine tenths of the rod's; the
// measures, a tenth of a friction curve's trace, go with it). The points form chains
// of kChainPoints consecutive ones, each analysed in order with Arnoldi warm-started from the
// one before and the chain's first started cold; any thread may take a chain's next points,
// one thread at a time, and a localisation starts cold too (StabilityMonitor::Between). So
// the results are the same, bit for bit, whatever the number of threads and however the work
// falls between them. Each worker builds its own HarmonicSystem from the case at its first
// analysis (measures taken on it are those taken on the trace's: the same arithmetic); the
// thread that calls Take runs analyses itself while it waits.
class StabilityPipeline {
 public:
  // Points per chain: a cold start costs ~20 % more operator applications than a warm one
  // (38 against 32 on Fig. 7, N = 10), so one in eight costs ~2.5 %.
  static constexpr int kChainPoints = 8;

  // `tracing` analyses and `tracing_reporter` measures on the calling thread (their system is
  // the trace's); they and `the_case` must outlive the pipeline. threads >= 0 workers besides
  // the calling thread.
  StabilityPipeline(const Case& the_case, StabilityMonitor& tracing,
                    SolutionReporter& tracing_reporter, int threads);
  // Discards the work not yet started and joins the threads.
  ~StabilityPipeline();
  StabilityPipeline(const StabilityPipeline&) = delete;
  StabilityPipeline& operator=(const StabilityPipeline&) = delete;

  // Queues the next point of the branch (indices 0, 1, 2, ...) with the fold the engine
  // located between it and the point before, if any (null: none).
  void Submit(int index, const BranchPoint& point, const Fold* fold_before);
  // Whether point `index` and the localisation before it are done.
  bool Ready(int index);
  // Point `index`'s results, handed over; the calling thread runs queued work until they are
  // done. Rethrows what its analysis threw (Analyze itself turns numerical failures into a
  // result with computed = false).
  PointStability Take(int index);

  int threads() const { return static_cast<int>(threads_.size()); }

 private:
  struct Point {
    BranchPoint point;
    std::optional<Fold> fold_before;
    std::optional<FloquetResult> floquet;  // once analysed
    SolutionMeasures measures;             // ... and measured
    std::exception_ptr error;              // what its analysis threw
    bool localising = false;               // a thread took the localisation before it
    bool localised = false;                // ... and finished it (or there is none)
    std::optional<Bifurcation> bifurcation_before;
    bool taken = false;
  };
  // kChainPoints consecutive points; those from `next` on are not analysed yet.
  struct Chain {
    int submitted = 0;
    int next = 0;
    bool busy = false;           // a thread is analysing its points
    Eigen::VectorXd warm_start;  // Arnoldi's start for its next point (empty: cold)
  };
  void Work();
  // Analyses the available points of the lowest chain that has some and is not busy with
  // `monitor`, measures them with `reporter`, and localises what they allow, unlocking
  // `lock` meanwhile; false if there was no such chain.
  bool RunChain(StabilityMonitor& monitor, SolutionReporter& reporter,
                std::unique_lock<std::mutex>& lock);
  // Localises between points index − 1 and index if both are analysed and no thread has.
  void Localise(int index, StabilityMonitor& monitor, std::unique_lock<std::mutex>& lock);
  bool Done(int index) const;
  // The lowest chain that has points to analyse and no thread on it, or chains_.end().
  std::map<int, Chain>::iterator ChainWithWork();
  // Forgets the points no longer needed (taken, and the localisation after them done).
  void Prune(int index);

  const Case& case_;
  StabilityMonitor& tracing_;
  SolutionReporter& tracing_reporter_;
  std::vector<std::thread> threads_;
  int submitted_ = 0;
  std::mutex mutex_;                 // guards everything below
  std::condition_variable changed_;  // a point queued or analysed, a localisation done
  std::map<int, Point> points_;      // until taken and no longer needed by a localisation
  std::map<int, Chain> chains_;      // by index / kChainPoints, until all its points are done
  std::exception_ptr worker_error_;  // a worker could not build its system
  bool stopping_ = false;
};

}  // namespace nfrc
