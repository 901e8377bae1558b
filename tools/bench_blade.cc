#include "tools/bench_blade.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "tools/bench_common.h"
#include "tools/case_file.h"

namespace nfrc::bench {

bool BladeMatrices() {
  const std::string dir = std::string(NFRC_SOURCE_DIR) + "/cases/blade";
  if (std::filesystem::exists(dir + "/K.mtx") && std::filesystem::exists(dir + "/M.mtx")) {
    return true;
  }
  const auto start = Clock::now();
  const std::string command = "/usr/bin/python3 " + dir + "/make_blade.py";
  if (std::system(command.c_str()) != 0) {
    std::printf("blade: %s failed; skipped\n", command.c_str());
    return false;
  }
  std::printf("blade: matrices generated in %.1f s\n", Seconds(start));
  return true;
}

void BenchBlade(int repeats, double lu_unit) {
  const std::string dir = std::string(NFRC_SOURCE_DIR) + "/cases/blade";
  if (!BladeMatrices()) return;
  const auto load_start = Clock::now();
  const Case the_case = LoadCase(dir + "/blade.json");
  const double load = Seconds(load_start);
  const ReductionReport& r = *the_case.reduction;
  const double read = load - r.time_s - r.check_time_s;
  std::printf("blade: %d DOFs -> %d boundary + %d modes\n", r.full_dofs, r.boundary_dofs, r.modes);
  std::printf("  read K, M + case   %.0f ms = %.0f LU(320)\n", 1e3 * read, read / lu_unit);
  std::printf(
      "  reduction          %.0f ms = %.0f LU(320) (factor + constraint modes %.0f ms,"
      " fixed-interface modes %.0f ms)\n",
      1e3 * r.time_s, r.time_s / lu_unit, 1e3 * r.factor_s, 1e3 * r.modes_s);
  std::printf("  eigenvalue check   %.0f ms = %.0f LU(320) (%zu frequencies, worst error %.1e)\n",
              1e3 * r.check_time_s, r.check_time_s / lu_unit, r.eigenfrequencies.size(),
              std::accumulate(r.eigenfrequencies.begin(), r.eigenfrequencies.end(), 0.0,
                              [](double worst, const EigenfrequencyCheck& c) {
                                return std::max(worst, std::abs(c.relative_error));
                              }));
  std::vector<double> times;
  const Branch branch = TimeTraces(the_case, repeats, &times);
  const auto& s = branch.summary;
  const int fallbacks = static_cast<int>(
      std::count_if(s.history.begin(), s.history.end(), [](const StepRecord& step) {
        return step.note.find("natural-parameter") != std::string::npos;
      }));
  const double t = Median(times);
  const int corners = static_cast<int>(std::count_if(branch.folds.begin(), branch.folds.end(),
                                                     [](const Fold& f) { return f.corner; }));
  std::printf(
      "  NFRC               %.0f ms = %.0f LU(320) (median of %d): %s, %d points, %d folds"
      " (%d corners), %d natural-parameter steps\n",
      1e3 * t, t / lu_unit, repeats, ToString(s.reason), s.num_points, s.num_folds, corners,
      fallbacks);
  std::printf("  per step           %.2f ms = %.2f LU(320); Newton/point %.2f\n",
              1e3 * t / std::max(1, s.num_points - 1), t / std::max(1, s.num_points - 1) / lu_unit,
              static_cast<double>(s.total_newton_iterations) / s.num_points);
  std::printf("  peak memory        %.0f MB (process so far)\n", PeakMemoryMb());
}

}  // namespace nfrc::bench
