#include "analysis/stability.h"

#include <cmath>
#include <string>

#include "core/errors.h"
#include "models/craig_bampton.h"

namespace nfrc {

void StabilityOptions::Validate() const {
  if (!(unstable_tolerance >= 0.0) || !std::isfinite(unstable_tolerance)) {
    throw InputError("stability.unstable_tolerance: must be a finite number >= 0");
  }
  if (!(bifurcation_tolerance > 0.0) || !(bifurcation_tolerance < 1.0)) {
    throw InputError("stability.bifurcation_tolerance: must be in (0, 1)");
  }
  if (!(jump_tolerance > 0.0) || !(jump_tolerance < 1.0)) {
    throw InputError("stability.jump_tolerance: must be in (0, 1)");
  }
  if (max_bifurcation_iterations < 1) {
    throw InputError("stability.max_bifurcation_iterations: must be at least 1");
  }
  if (hill_modes < -1 || hill_modes > kMaxReductionModes) {
    throw InputError("stability.hill_modes: must be -1 (the whole model) or between 0 and " +
                     std::to_string(kMaxReductionModes) + ", got " + std::to_string(hill_modes));
  }
}

const char* ToString(BifurcationType type) {
  switch (type) {
    case BifurcationType::kFold:
      return "fold";
    case BifurcationType::kBranchPoint:
      return "branch_point";
    case BifurcationType::kPeriodDoubling:
      return "period_doubling";
    case BifurcationType::kNeimarkSacker:
      return "neimark_sacker";
  }
  return "unknown";
}

}  // namespace nfrc
