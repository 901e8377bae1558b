#include "tools/bench_hill_reduction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/trace.h"
#include "tools/bench_blade.h"
#include "tools/bench_common.h"
#include "tools/case_file.h"

namespace nfrc::bench {
namespace {

struct Run {
  TraceResult trace;
  double seconds = 0.0;
  double hill_seconds = 0.0;
};

Run Trace(Case the_case, int modes) {
  the_case.stability.hill_modes = modes;
  TraceOptions in_turn;
  in_turn.threads = 0;  // Hill's whole cost in the wall time, as it is on one core
  Run run;
  const auto start = Clock::now();
  run.trace = TraceCase(the_case, in_turn);
  run.seconds = Seconds(start);
  for (const TracePoint& p : run.trace.points) run.hill_seconds += p.floquet.seconds;
  return run;
}

void Compare(const std::string& name, int modes, const Run& run, const Run& full, double lu_unit) {
  const std::vector<TracePoint>& a = run.trace.points;
  const std::vector<TracePoint>& b = full.trace.points;
  std::printf("  %-6s %8.0f ms = %6.0f LU(320), Hill %5.1f %%, %zu bifurcations",
              modes < 0 ? "whole" : std::to_string(modes).c_str(), 1e3 * run.seconds,
              run.seconds / lu_unit, 100.0 * run.hill_seconds / run.seconds,
              run.trace.bifurcations.size());
  if (modes < 0) {
    std::printf(" (%s: %zu points)\n", name.c_str(), a.size());
    return;
  }
  if (a.size() != b.size()) {
    std::printf("; the trace differs (%zu points against %zu)\n", a.size(), b.size());
    return;
  }
  int verdicts = 0, counts = 0;
  std::vector<double> errors;
  for (size_t i = 0; i < a.size(); ++i) {
    verdicts += a[i].floquet.stable() != b[i].floquet.stable();
    counts += a[i].floquet.num_unstable != b[i].floquet.num_unstable;
    errors.push_back(std::abs(a[i].floquet.max_modulus - b[i].floquet.max_modulus));
  }
  std::printf(
      "; against the whole pencil: %d verdicts and %d unstable counts differ, |d max|mu||"
      " median %.1e, largest %.1e\n",
      verdicts, counts, Median(errors), *std::max_element(errors.begin(), errors.end()));
}

// The case traced with the whole pencil, then with each number of modes.
void Bench(const std::string& name, const Case& the_case, const std::vector<int>& modes,
           double lu_unit) {
  std::printf("Hill on a Craig-Bampton reduction, %s (%d DOFs, %zu laws, their DOFs kept):\n",
              name.c_str(), the_case.model.model.num_dofs(), the_case.laws.size());
  const Run full = Trace(the_case, -1);
  Compare(name, -1, full, full, lu_unit);
  for (int m : modes) Compare(name, m, Trace(the_case, m), full, lu_unit);
}

}  // namespace

void BenchHillReduction(double lu_unit) {
  const std::string cases = std::string(NFRC_SOURCE_DIR) + "/cases/";
  for (const char* name : {"rod/rigid_nh20.json", "rod/flexible_4krod.json"}) {
    const Case the_case = LoadCase(cases + name);
    Bench(name, the_case, {4, 8, 12, the_case.model.model.num_dofs() - 1}, lu_unit);
  }
  if (!BladeMatrices()) return;
  Case blade = LoadCase(cases + "blade/blade.json");
  blade.stability.enabled = true;
  Bench("blade/blade.json", blade, {4, 8, 12}, lu_unit);
}

}  // namespace nfrc::bench
