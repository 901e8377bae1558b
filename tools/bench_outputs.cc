#include "tools/bench_outputs.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/trace.h"
#include "tools/bench_common.h"
#include "tools/branch_writer.h"
#include "tools/case_file.h"

namespace nfrc::bench {

void BenchOutputs(int repeats, int threads, double lu_unit) {
  // The cases with many folds and bifurcations (each once rewrote the whole branch.json), and
  // two friction curves with none.
  const std::vector<std::string> names = {"contact/nlvib.json#penalty", "contact/nlvib.json#dlft",
                                          "rod/rigid_nh20.json", "friction/frc_n10.json",
                                          "friction/point_e.json"};
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("nfrc_bench_outputs_" + std::to_string(getpid())))
          .string();
  std::printf(
      "the trace alone and with its files written (BranchWriter), %d times each, "
      "alternating, Hill on %d threads beside (threads=%d)\n",
      repeats, HillThreads(threads), threads);
  for (const std::string& name : names) {
    const Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
    TraceOptions options;
    options.threads = threads;
    std::vector<double> alone, written;
    int writes = 0, points = 0, folds = 0, bifurcations = 0;
    for (int r = 0; r < repeats; ++r) {
      auto start = Clock::now();
      const TraceResult trace = TraceCase(the_case, options);
      alone.push_back(Seconds(start));
      points = trace.branch.summary.num_points;
      folds = trace.branch.summary.num_folds;
      bifurcations = static_cast<int>(trace.bifurcations.size());
      std::filesystem::remove_all(dir);
      start = Clock::now();
      BranchWriter writer(dir, the_case, nullptr);
      TraceOptions with_writer = options;
      with_writer.observer = &writer;
      const TraceResult traced = TraceCase(the_case, with_writer);
      writer.SetWindows(traced.quasi_periodic_windows);
      writer.Finish(traced.branch.summary);
      written.push_back(Seconds(start));
      writes = writer.json_writes();
    }
    std::filesystem::remove_all(dir);
    const double fastest_alone = *std::min_element(alone.begin(), alone.end());
    const double fastest_written = *std::min_element(written.begin(), written.end());
    std::printf("%s: %d points, %d folds, %d bifurcations, branch.json written %d times\n",
                name.c_str(), points, folds, bifurcations, writes);
    std::printf("  trace alone    %8.1f / %8.1f ms = %7.1f LU(320) (fastest / median)\n",
                1e3 * fastest_alone, 1e3 * Median(alone), fastest_alone / lu_unit);
    std::printf(
        "  files written  %8.1f / %8.1f ms = %7.1f LU(320), the writer %+.0f %% (fastest)\n",
        1e3 * fastest_written, 1e3 * Median(written), fastest_written / lu_unit,
        1e2 * (fastest_written / fastest_alone - 1.0));
  }
}

}  // namespace nfrc::bench
