#include "analysis/stability_pipeline.h"

#include <algorithm>
#include <cassert>
#include <utility>

#include "analysis/harmonic_system.h"

namespace nfrc {

StabilityPipeline::StabilityPipeline(const Case& the_case, StabilityMonitor& tracing,
                                     SolutionReporter& tracing_reporter, int threads)
    : case_(the_case), tracing_(tracing), tracing_reporter_(tracing_reporter) {
  assert(threads >= 0);
  for (int t = 0; t < threads; ++t) threads_.emplace_back([this] { Work(); });
}

StabilityPipeline::~StabilityPipeline() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void StabilityPipeline::Submit(int index, const BranchPoint& point, const Fold* fold_before) {
  assert(index == submitted_);
  ++submitted_;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    Point& added = points_[index];
    added.point = point;
    if (fold_before != nullptr) added.fold_before = *fold_before;
    added.localised = index == 0;  // nothing before the first point
    ++chains_[index / kChainPoints].submitted;
  }
  changed_.notify_all();
}

bool StabilityPipeline::Done(int index) const {
  const auto found = points_.find(index);
  assert(found != points_.end());
  const Point& p = found->second;
  return p.error != nullptr || (p.floquet && p.localised);
}

bool StabilityPipeline::Ready(int index) {
  const std::lock_guard<std::mutex> lock(mutex_);
  return Done(index);
}

PointStability StabilityPipeline::Take(int index) {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!Done(index)) {
    if (worker_error_) std::rethrow_exception(worker_error_);
    if (!RunChain(tracing_, tracing_reporter_, lock)) changed_.wait(lock);
  }
  Point& p = points_.at(index);
  if (p.error) std::rethrow_exception(p.error);
  // A copy: the localisation after this point may still need its multipliers.
  PointStability result{*p.floquet, std::move(p.bifurcation_before), std::move(p.measures)};
  p.taken = true;
  Prune(index);
  return result;
}

std::map<int, StabilityPipeline::Chain>::iterator StabilityPipeline::ChainWithWork() {
  return std::find_if(chains_.begin(), chains_.end(), [](const auto& entry) {
    return !entry.second.busy && entry.second.next < entry.second.submitted;
  });
}

void StabilityPipeline::Prune(int index) {
  const auto point = points_.find(index);
  const auto next = points_.find(index + 1);
  if (point != points_.end() && point->second.taken && next != points_.end() &&
      next->second.localised) {
    points_.erase(point);
  }
}

bool StabilityPipeline::RunChain(StabilityMonitor& monitor, SolutionReporter& reporter,
                                 std::unique_lock<std::mutex>& lock) {
  const auto found = ChainWithWork();
  if (found == chains_.end()) return false;
  const int id = found->first;
  Chain& chain = found->second;  // std::map: stays valid while other chains come and go
  chain.busy = true;
  while (chain.next < chain.submitted && !stopping_) {
    const int index = id * kChainPoints + chain.next;
    // Read unlocked: a point not yet analysed is neither written nor erased by other threads.
    const BranchPoint& point = points_.at(index).point;
    Eigen::VectorXd warm_start = std::move(chain.warm_start);
    lock.unlock();
    std::optional<FloquetResult> result;
    SolutionMeasures measures;
    std::exception_ptr error;
    try {
      result = monitor.Analyze(point.y, point.lambda, &warm_start);
      measures = reporter.Measure(point.y, point.lambda);
    } catch (...) {
      error = std::current_exception();  // rethrown by Take
    }
    lock.lock();
    chain.warm_start = std::move(warm_start);
    Point& analysed = points_.at(index);
    analysed.floquet = std::move(result);
    analysed.measures = std::move(measures);
    analysed.error = error;
    ++chain.next;
    changed_.notify_all();
    Localise(index, monitor, lock);
    Localise(index + 1, monitor, lock);
  }
  chain.busy = false;
  if (chain.next == kChainPoints) chains_.erase(id);
  changed_.notify_all();
  return true;
}

void StabilityPipeline::Localise(int index, StabilityMonitor& monitor,
                                 std::unique_lock<std::mutex>& lock) {
  const auto b = points_.find(index);
  if (b == points_.end() || b->second.localising || b->second.localised) return;
  const auto a = points_.find(index - 1);
  assert(a != points_.end());  // kept until the localisation after it is done
  const bool analysed_a = a->second.floquet || a->second.error;
  const bool analysed_b = b->second.floquet || b->second.error;
  if (!analysed_a || !analysed_b) return;
  b->second.localising = true;
  if (a->second.error || b->second.error) {
    b->second.localised = true;
    changed_.notify_all();
    return;
  }
  // Read unlocked: analysed points are no longer written, and neither is erased before this
  // localisation is done (Prune).
  const Point& point_a = a->second;
  const Point& point_b = b->second;
  lock.unlock();
  std::optional<Bifurcation> found;
  std::exception_ptr error;
  try {
    found = monitor.Between(point_a.point, *point_a.floquet, point_b.point, *point_b.floquet,
                            point_b.fold_before ? &*point_b.fold_before : nullptr);
  } catch (...) {
    error = std::current_exception();  // rethrown by Take
  }
  lock.lock();
  Point& localised = points_.at(index);
  localised.bifurcation_before = std::move(found);
  if (error) localised.error = error;
  localised.localised = true;
  changed_.notify_all();
  Prune(index - 1);
}

void StabilityPipeline::Work() {
  // Built at the first analysis: a short trace may leave a worker without one.
  std::unique_ptr<HarmonicSystem> system;
  std::optional<StabilityMonitor> monitor;
  std::optional<SolutionReporter> reporter;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || ChainWithWork() != chains_.end(); });
    if (stopping_) return;
    if (!monitor) {
      lock.unlock();
      try {
        system = BuildSystem(case_);
      } catch (...) {
        // The trace built the same system: a failure here is not the input's; Take says so.
        lock.lock();
        worker_error_ = std::current_exception();
        changed_.notify_all();
        return;
      }
      monitor.emplace(*system, case_.stability, case_.continuation);
      reporter.emplace(*system, case_.output_dofs, case_.output_names);
      lock.lock();
      continue;
    }
    RunChain(*monitor, *reporter, lock);
  }
}

}  // namespace nfrc
