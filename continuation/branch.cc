#include "continuation/branch.h"

#include <algorithm>
#include <cassert>
#include <sstream>

namespace nfrc {

std::string StoppedByObserverMessage(int index, const std::string& lambda_name, double lambda) {
  std::ostringstream message;
  message.precision(8);  // as the engine's other messages
  message << "stopped by the observer at point " << index << " (" << lambda_name << "=" << lambda
          << ")";
  return message.str();
}

void StopBranchAfter(int last, const std::string& lambda_name, Branch* branch) {
  assert(last >= 0 && last < static_cast<int>(branch->points.size()));
  branch->points.resize(static_cast<size_t>(last) + 1);
  std::erase_if(branch->folds, [&](const Fold& fold) { return fold.after_point >= last; });
  ContinuationSummary& summary = branch->summary;
  summary.num_points = static_cast<int>(branch->points.size());
  summary.num_folds = static_cast<int>(branch->folds.size());
  summary.reason = TerminationReason::kStoppedByObserver;
  summary.message = StoppedByObserverMessage(last, lambda_name, branch->points.back().lambda);
}

const char* ToString(TerminationReason reason) {
  switch (reason) {
    case TerminationReason::kReachedLambdaBound:
      return "reached_lambda_bound";
    case TerminationReason::kClosedCurve:
      return "closed_curve";
    case TerminationReason::kMaxPoints:
      return "max_points";
    case TerminationReason::kStalled:
      return "stalled";
    case TerminationReason::kStartFailed:
      return "start_failed";
    case TerminationReason::kStoppedByObserver:
      return "stopped_by_observer";
  }
  return "unknown";
}

}  // namespace nfrc
