// Hill's analyses beside the trace (StabilityPipeline): the same results, bit for bit, as the
// analyses in turn on the tracing thread, whatever the number of threads; the observer hears of
// every point in order, and a refused point ends the branch there.
#include "analysis/stability_pipeline.h"

#include <doctest/doctest.h>

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "analysis/bifurcation.h"
#include "analysis/solution_report.h"
#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

Case LoadSourceCase(const std::string& name) {
  return LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
}

TraceResult TraceWith(const Case& the_case, int threads, TraceObserver* observer = nullptr,
                      const std::atomic<bool>* stop = nullptr) {
  TraceOptions options;
  options.threads = threads;
  options.observer = observer;
  options.stop = stop;
  return TraceCase(the_case, options);
}

void CheckSameFloquet(const FloquetResult& a, const FloquetResult& b) {
  CHECK(a.computed == b.computed);
  CHECK(a.num_unstable == b.num_unstable);
  CHECK(a.operator_applications == b.operator_applications);
  CHECK(a.exponents == b.exponents);
  CHECK(a.multipliers == b.multipliers);
}

void CheckSameMeasures(const SolutionMeasures& a, const SolutionMeasures& b) {
  CHECK(a.response.max_abs == b.response.max_abs);
  CHECK(a.response.min == b.response.min);
  CHECK(a.response.max == b.response.max);
  CHECK(a.response.h1 == b.response.h1);
  CHECK(a.response.amplitudes == b.response.amplitudes);
  CHECK(a.response.energy == b.response.energy);
  CHECK(a.laws == b.laws);
  CHECK(a.min_gap == b.min_gap);
  CHECK(a.min_force == b.min_force);
}

void CheckSameTrace(const TraceResult& in_turn, const TraceResult& beside) {
  REQUIRE(beside.points.size() == in_turn.points.size());
  for (size_t i = 0; i < in_turn.points.size(); ++i) {
    CAPTURE(i);
    CHECK(beside.points[i].index == static_cast<int>(i));
    CHECK(beside.points[i].point.lambda == in_turn.points[i].point.lambda);
    CHECK(beside.points[i].point.y == in_turn.points[i].point.y);
    CheckSameFloquet(in_turn.points[i].floquet, beside.points[i].floquet);
    CheckSameMeasures(in_turn.points[i].measures, beside.points[i].measures);
  }
  REQUIRE(beside.folds.size() == in_turn.folds.size());
  REQUIRE(beside.bifurcations.size() == in_turn.bifurcations.size());
  for (size_t i = 0; i < in_turn.bifurcations.size(); ++i) {
    CAPTURE(i);
    const Bifurcation& a = in_turn.bifurcations[i];
    const Bifurcation& b = beside.bifurcations[i];
    CHECK(a.type == b.type);
    CHECK(a.after_point == b.after_point);
    CHECK(a.omega == b.omega);
    CHECK(a.omega_accuracy == b.omega_accuracy);
    CHECK(a.iterations == b.iterations);
    CHECK(a.discontinuous == b.discontinuous);
    CHECK(a.crossing_multipliers == b.crossing_multipliers);
  }
  CHECK(beside.quasi_periodic_windows.size() == in_turn.quasi_periodic_windows.size());
}

TEST_CASE("stability pipeline: any number of threads gives the analyses in turn, bit for bit") {
  // Duffing: two folds; NLvib's penalty spring: dozens of Neimark-Sacker crossings, most of
  // them jumps, localised between points while the trace goes on. Three workers on this
  // two-core machine interleave their chains differently from run to run.
  for (const char* name : {"duffing.json", "contact/nlvib.json#penalty"}) {
    CAPTURE(name);
    const Case the_case = LoadSourceCase(name);
    REQUIRE(the_case.stability.enabled);
    const TraceResult in_turn = TraceWith(the_case, 0);
    REQUIRE(in_turn.branch.summary.success());
    REQUIRE(in_turn.bifurcations.size() >= 2);
    for (const int threads : {1, 3}) {
      CAPTURE(threads);
      CheckSameTrace(in_turn, TraceWith(the_case, threads));
    }
  }
}

TEST_CASE("stability pipeline: each point's multipliers are its chain's, analysed in turn") {
  // The reference is StabilityMonitor alone on a system of its own: each chain of
  // kChainPoints points from a cold start, Arnoldi warm-started from point to point; each
  // change of stability localised by Between from the two points' results; each point's
  // measures by a SolutionReporter on that system.
  const Case the_case = LoadSourceCase("contact/nlvib.json#penalty");
  const TraceResult trace = TraceWith(the_case, 2);
  REQUIRE(trace.points.size() > 3 * StabilityPipeline::kChainPoints);
  auto system = BuildSystem(the_case);
  StabilityMonitor monitor(*system, the_case.stability, the_case.continuation);
  SolutionReporter reporter(*system, the_case.output_dofs, the_case.output_names);
  Eigen::VectorXd warm_start;
  for (const TracePoint& p : trace.points) {
    CAPTURE(p.index);
    if (p.index % StabilityPipeline::kChainPoints == 0) warm_start.resize(0);
    CheckSameFloquet(monitor.Analyze(p.point.y, p.point.lambda, &warm_start), p.floquet);
    CheckSameMeasures(reporter.Measure(p.point.y, p.point.lambda), p.measures);
  }
  REQUIRE(!trace.bifurcations.empty());
  for (const Bifurcation& b : trace.bifurcations) {
    CAPTURE(b.after_point);
    const TracePoint& before = trace.points[static_cast<size_t>(b.after_point)];
    const TracePoint& after = trace.points[static_cast<size_t>(b.after_point) + 1];
    const Fold* fold = nullptr;
    for (const TraceFold& f : trace.folds) {
      if (f.fold.after_point == b.after_point) fold = &f.fold;
    }
    const std::optional<Bifurcation> again =
        monitor.Between(before.point, before.floquet, after.point, after.floquet, fold);
    REQUIRE(again);
    CHECK(again->type == b.type);
    CHECK(again->omega == b.omega);
    CHECK(again->crossing_multipliers == b.crossing_multipliers);
  }
}

// Records what it hears; refuses point `refuse_at` (-1: none) and raises `stop` at `stop_at`.
class Recording : public TraceObserver {
 public:
  int refuse_at = -1;
  int stop_at = -1;
  std::atomic<bool> stop{false};
  std::vector<int> points;
  int bifurcations = 0;
  bool OnPoint(const TracePoint& point) override {
    points.push_back(point.index);
    if (point.index == stop_at) stop = true;
    return point.index != refuse_at;
  }
  void OnBifurcation(const Bifurcation& /*bifurcation*/) override { ++bifurcations; }
};

TEST_CASE("stability pipeline: a point the observer refuses ends the branch there") {
  const Case the_case = LoadSourceCase("duffing.json");
  const TraceResult whole = TraceWith(the_case, 0);
  REQUIRE(whole.folds.size() == 2);
  // Past the first fold and its bifurcation, well before the second.
  const int last = whole.folds[0].fold.after_point + 3;
  REQUIRE(last < whole.folds[1].fold.after_point);
  for (const int threads : {0, 2}) {
    CAPTURE(threads);
    Recording observer;
    observer.refuse_at = last;
    const TraceResult trace = TraceWith(the_case, threads, &observer);
    std::vector<int> expected;
    for (int i = 0; i <= last; ++i) expected.push_back(i);
    CHECK(observer.points == expected);
    REQUIRE(trace.points.size() == static_cast<size_t>(last) + 1);
    CHECK(trace.branch.points.size() == trace.points.size());
    const ContinuationSummary& summary = trace.branch.summary;
    CHECK(summary.reason == TerminationReason::kStoppedByObserver);
    CHECK(summary.num_points == last + 1);
    CHECK(summary.message.find("at point " + std::to_string(last) + " ") != std::string::npos);
    REQUIRE(trace.folds.size() == 1);
    CHECK(trace.branch.folds.size() == 1);
    CHECK(summary.num_folds == 1);
    REQUIRE(trace.bifurcations.size() == 1);
    CHECK(observer.bifurcations == 1);
    CHECK(trace.bifurcations[0].omega == whole.bifurcations[0].omega);
  }
}

TEST_CASE("stability pipeline: a raised stop flag keeps every point found, analysed") {
  const Case the_case = LoadSourceCase("contact/nlvib.json#penalty");
  Recording observer;
  observer.stop_at = 20;
  const TraceResult trace = TraceWith(the_case, 2, &observer, &observer.stop);
  REQUIRE(trace.points.size() > 20);
  CHECK(trace.points.size() == trace.branch.points.size());
  CHECK(observer.points.size() == trace.points.size());
  for (const TracePoint& p : trace.points) CHECK(p.floquet.computed);
}

TEST_CASE("stability pipeline: a one-point trace and the thread count's bounds") {
  Case the_case = LoadSourceCase("duffing.json");
  the_case.continuation.max_points = 1;
  const TraceResult one = TraceWith(the_case, 3);
  REQUIRE(one.points.size() == 1);
  CHECK(one.points[0].floquet.computed);
  for (const int threads : {-2, kMaxThreads + 1}) {
    CAPTURE(threads);
    CHECK_THROWS_WITH_AS(TraceWith(the_case, threads), doctest::Contains("threads:"), InputError);
  }
  CHECK(HillThreads(0) == 0);
  CHECK(HillThreads(5) == 5);
  CHECK(HillThreads(-1) >= 0);
}

}  // namespace
}  // namespace nfrc
