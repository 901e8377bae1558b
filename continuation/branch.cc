#include "continuation/branch.h"

namespace nfrc {

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
