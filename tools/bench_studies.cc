#include "tools/bench_studies.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/case_parameter.h"
#include "analysis/event_curve.h"
#include "analysis/fold_curve.h"
#include "tools/case_file.h"
#include "tools/sweep.h"

namespace nfrc::bench {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Case(const std::string& name) {
  return std::string(NFRC_SOURCE_DIR) + "/cases/" + name;
}

void BenchFoldCurve(double lu_unit) {
  const CaseFile file = ReadCaseFile(Case("duffing.json"));
  const CaseParameter forcing("model.forcing[0].cos", file.the_case);
  FoldCurveOptions options;
  options.to = 0.03;
  const auto start = Clock::now();
  const FoldCurveResult result = TraceFoldCurves(file.the_case, forcing, options);
  const double seconds = Seconds(start);
  int points = 0, cusps = 0;
  for (const FoldCurve& curve : result.curves) {
    points += static_cast<int>(curve.points.size());
    cusps += static_cast<int>(std::count_if(curve.turns.begin(), curve.turns.end(),
                                            [](const FoldCurveTurn& t) { return t.cusp; }));
  }
  std::printf(
      "fold curve, duffing.json (H = 7), forcing 0.18 -> 0.03: %zu curve(s), %d points, "
      "%d cusp(s)\n",
      result.curves.size(), points, cusps);
  std::printf("  wall time %.1f ms = %.1f LU(320) (the branch trace included)\n", 1e3 * seconds,
              seconds / lu_unit);
}

using EventTracer = EventCurveResult (*)(const nfrc::Case&, const CaseParameter&,
                                         const EventCurveOptions&);

// Traces a case's event curves in `path` to `to` and prints curves, points, solves and times.
void BenchEventCurves(const char* label, const std::string& case_name, const std::string& path,
                      double to, EventTracer trace, double lu_unit) {
  const CaseFile file = ReadCaseFile(Case(case_name));
  const CaseParameter parameter(path, file.the_case);
  EventCurveOptions options;
  options.to = to;
  const auto start = Clock::now();
  const EventCurveResult result = trace(file.the_case, parameter, options);
  const double seconds = Seconds(start);
  int points = 0, solves = 0;
  for (const EventCurve& curve : result.curves) {
    points += static_cast<int>(curve.points.size());
    solves += curve.solves;
  }
  std::printf("%s, %s, %s %g -> %g: %zu curves, %d points, %d fixed-omega solves\n", label,
              case_name.c_str(), path.c_str(), result.from, to, result.curves.size(), points,
              solves);
  std::printf("  wall time %.1f ms = %.1f LU(320) (the branch trace included); %.2f ms per solve\n",
              1e3 * seconds, seconds / lu_unit, 1e3 * seconds / std::max(solves, 1));
}

struct SweepTiming {
  double wall = 0.0;
  std::vector<SweepRun> runs;
};

SweepTiming TimeSweep(const CaseFile& file, const CaseParameter& parameter,
                      const std::vector<double>& values, int jobs) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("nfrc_bench_sweep_" + std::to_string(jobs));
  std::filesystem::remove_all(dir);
  SweepOptions options;
  options.jobs = jobs;
  const auto start = Clock::now();
  SweepTiming timing;
  timing.runs = RunSweep(file, parameter, values, dir.string(), options).runs;
  timing.wall = Seconds(start);
  std::filesystem::remove_all(dir);
  return timing;
}

void BenchSweep(double lu_unit) {
  const CaseFile file = ReadCaseFile(Case("friction/frc_n10.json"));
  const CaseParameter load("nonlinearities[0].normal_load", file.the_case);
  constexpr int kBranches = 32;
  std::vector<double> values;
  for (int k = 0; k < kBranches; ++k) values.push_back(6.0 + 8.0 * k / (kBranches - 1));
  const SweepTiming serial = TimeSweep(file, load, values, 1);
  const SweepTiming parallel = TimeSweep(file, load, values, 2);
  double shortest = 1e300, longest = 0.0, total = 0.0;
  int complete = 0;
  bool equal = true;
  for (size_t k = 0; k < serial.runs.size(); ++k) {
    const SweepRun& run = serial.runs[k];
    shortest = std::min(shortest, run.seconds);
    longest = std::max(longest, run.seconds);
    total += run.seconds;
    complete += run.status == "complete";
    equal = equal && run.points == parallel.runs[k].points && run.folds == parallel.runs[k].folds &&
            run.peaks == parallel.runs[k].peaks;
  }
  std::printf("sweep, friction/frc_n10.json, normal_load 6 -> 14, %d branches (%d complete)\n",
              kBranches, complete);
  std::printf("  per branch %.0f ms mean = %.0f LU(320) (%.0f to %.0f ms)\n",
              1e3 * total / kBranches, total / kBranches / lu_unit, 1e3 * shortest, 1e3 * longest);
  std::printf("  1 thread  %.2f s = %.0f LU(320)\n", serial.wall, serial.wall / lu_unit);
  std::printf("  2 threads %.2f s = %.0f LU(320): speed-up %.2f, efficiency %.0f %%; results %s\n",
              parallel.wall, parallel.wall / lu_unit, serial.wall / parallel.wall,
              50.0 * serial.wall / parallel.wall, equal ? "equal" : "DIFFER");
}

}  // namespace

void BenchStudies(double lu_unit) {
  BenchFoldCurve(lu_unit);
  // Every energy peak of the Fig. 7 branch at N = 8 followed to N = 12 (the super-harmonic and
  // primary peaks vanish on the way; see the README's studies).
  BenchEventCurves("peak curves (energy)", "friction/fig7.json#n8", "nonlinearities[0].normal_load",
                   12.0, TracePeakCurves, lu_unit);
  // Both Neimark-Sacker points of the NES oscillator (Hill's method at every solve).
  BenchEventCurves("Neimark-Sacker curves", "nes_neimark_sacker.json", "model.forcing[0].cos", 0.01,
                   TraceNeimarkSackerCurves, lu_unit);
  BenchSweep(lu_unit);
}

}  // namespace nfrc::bench
