#pragma once

#include <chrono>
#include <vector>

#include "analysis/case.h"
#include "continuation/branch.h"

namespace nfrc::bench {

using Clock = std::chrono::steady_clock;

// Wall time since `since` (s).
double Seconds(Clock::time_point since);

// Median of a non-empty sample.
double Median(std::vector<double> values);

// Peak resident memory of the process so far (MB).
double PeakMemoryMb();

// Builds the system and traces the case `repeats` times (the linear-guess start included),
// appending each wall time (s); returns the last branch.
Branch TimeTraces(const Case& the_case, int repeats, std::vector<double>* times);

}  // namespace nfrc::bench
