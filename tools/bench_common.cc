#include "tools/bench_common.h"

#include <sys/resource.h>

#include <algorithm>

#include "analysis/trace.h"

namespace nfrc::bench {

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

double PeakMemoryMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports ru_maxrss in KiB
}

Branch TimeTraces(const Case& the_case, int repeats, std::vector<double>* times) {
  Branch branch;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    const auto start = Clock::now();
    auto system = BuildSystem(the_case);
    const Eigen::VectorXd guess = StartingGuess(the_case, *system, nullptr);
    branch = Trace(*system, the_case.continuation, nullptr, &guess, the_case.Plot());
    times->push_back(Seconds(start));
  }
  return branch;
}

}  // namespace nfrc::bench
