#include "nonlinearities/phase_count.h"

#include <algorithm>
#include <cmath>

namespace nfrc {
namespace {

struct Run {
  bool value;
  int length;
};

// Cyclic runs of `flags`, starting at a run boundary (flags holds both values).
std::vector<Run> CyclicRuns(const std::vector<bool>& flags) {
  const int n = static_cast<int>(flags.size());
  int start = 0;
  while (flags[start] == flags[(start + n - 1) % n]) ++start;
  std::vector<Run> runs;
  for (int i = 0; i < n; ++i) {
    const bool value = flags[(start + i) % n];
    if (runs.empty() || runs.back().value != value) {
      runs.push_back({value, 1});
    } else {
      ++runs.back().length;
    }
  }
  return runs;
}

// Flips every run of `value` shorter than min_length, then merges equal neighbours.
std::vector<Run> DropShort(std::vector<Run> runs, bool value, int min_length) {
  for (Run& run : runs) {
    if (run.value == value && run.length < min_length) run.value = !value;
  }
  std::vector<Run> merged;
  for (const Run& run : runs) {
    if (!merged.empty() && merged.back().value == run.value) {
      merged.back().length += run.length;
    } else {
      merged.push_back(run);
    }
  }
  if (merged.size() > 1 && merged.front().value == merged.back().value) {
    merged.front().length += merged.back().length;
    merged.pop_back();
  }
  return merged;
}

}  // namespace

PhaseCount CountPhases(const std::vector<bool>& flags, double min_fraction) {
  PhaseCount result;
  if (flags.empty()) return result;
  const int n = static_cast<int>(flags.size());
  const auto on = static_cast<int>(std::count(flags.begin(), flags.end(), true));
  if (on == 0 || on == n) {
    result.count = on == n ? 1 : 0;
    result.fraction = on == n ? 1.0 : 0.0;
    return result;
  }
  const int min_length = std::max(1, static_cast<int>(std::ceil(min_fraction * n)));
  std::vector<Run> runs = DropShort(CyclicRuns(flags), true, min_length);
  runs = DropShort(std::move(runs), false, min_length);
  int covered = 0;
  for (const Run& run : runs) {
    if (run.value) {
      ++result.count;
      covered += run.length;
    }
  }
  result.fraction = static_cast<double>(covered) / n;
  if (result.fraction == 1.0) result.count = 1;
  return result;
}

}  // namespace nfrc
