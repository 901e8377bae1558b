#include "tools/bench_acceptance.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/curve_accuracy.h"
#include "analysis/harmonic_system.h"
#include "analysis/point_measures.h"
#include "analysis/trace.h"
#include "tools/bench_common.h"
#include "tools/case_file.h"

namespace nfrc::bench {
namespace {

// What the curve's accuracy is judged on: the papers plot the friction curves' energy on a
// log axis and the contact curves' max |x| of the output DOFs.
enum class Plotted { kLogEnergy, kMaxAbs };

struct AcceptanceCase {
  const char* file;  // under cases/
  Plotted plotted;
  double budget_lu;  // the budget in LU(320); 0 = "unchanged or faster"
};

// One run of a case in its child: its wall time and the calibration just before it (s).
struct Timing {
  double seconds = 0.0;
  double lu_unit = 0.0;
  int points = 0;
  double accuracy = -1.0;  // against a tenth of the step; negative where not measured
};

// Round r of `perturb` scales the first forcing term by 1 + r·kPerturbation (two ulps a
// round): the same curve to rounding, traced afresh. Near grazing and sample switches the
// step sequence depends on the last bits: NLvib's penalty curve took 320–390 points over six
// such copies at one commit, which one run cannot tell from a change of the code.
constexpr double kPerturbation = 4.4e-16;

PlottedCurve Curve(const TraceResult& trace, Plotted plotted) {
  PlottedCurve curve;
  curve.log_scale = plotted == Plotted::kLogEnergy;
  for (const TracePoint& p : trace.points) {
    curve.omega.push_back(p.point.lambda);
    const PointMeasures& m = p.measures.response;
    const std::vector<double> values =
        plotted == Plotted::kLogEnergy ? std::vector<double>{m.energy} : m.max_abs;
    curve.measures.resize(values.size());
    for (size_t j = 0; j < values.size(); ++j) curve.measures[j].push_back(values[j]);
  }
  return curve;
}

// The reference of the accuracy figure: the same case with a tenth of the default maximum
// step (or of the case's, if smaller; first step no longer than it), steps sized by the
// tangent's turn (plot_tolerance off: the reference does not rest on the step control it
// judges), stability off (it does not change the curve).
double Accuracy(Case the_case, const TraceResult& trace, Plotted plotted) {
  ContinuationOptions& options = the_case.continuation;
  options.max_step = std::min(options.max_step, ContinuationOptions().max_step) / 10.0;
  options.initial_step = std::min(options.initial_step, options.max_step);
  options.min_step = std::min(options.min_step, 0.1 * options.initial_step);
  options.max_points *= 20;
  options.plot_tolerance = 0.0;
  the_case.stability.enabled = false;
  const TraceResult reference = TraceCase(the_case);
  return CurveDeviation(Curve(reference, plotted), Curve(trace, plotted));
}

Timing RunCase(const AcceptanceCase& c, double lu_unit, bool accuracy, int perturbation,
               const AcceptanceOptions& settings) {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + c.file);
  the_case.stability.enabled = settings.stability;
  if (settings.newton_target > 0) {
    the_case.continuation.target_newton_iterations = settings.newton_target;
  }
  if (perturbation > 0 && !the_case.model.forcing.empty()) {
    ForcingTerm& term = the_case.model.forcing.front();
    term.cos *= 1.0 + perturbation * kPerturbation;
    term.sin *= 1.0 + perturbation * kPerturbation;
    std::printf("(forcing x (1 + %d x %.1e)) ", perturbation, kPerturbation);
  }
  TraceOptions options;
  options.threads = settings.threads;
  const auto start = Clock::now();
  const TraceResult trace = TraceCase(the_case, options);
  const double seconds = Seconds(start);
  const ContinuationSummary& s = trace.branch.summary;
  std::printf("%s: %s, %zu points, %d unknowns, %d Newton, %zu bifurcations\n", c.file,
              ToString(s.reason), trace.points.size(), trace.num_unknowns,
              s.total_newton_iterations, trace.bifurcations.size());
  std::printf("  wall time %.1f ms = %.1f LU(320)", 1e3 * seconds, seconds / lu_unit);
  if (c.budget_lu > 0.0) std::printf("  (budget %.0f LU(320))", c.budget_lu);
  std::printf("\n");
  // The localisations' work: folds by the engine, other crossings by Newton + Hill each.
  int corners = 0, fold_iterations = 0, crossings = 0, jumps = 0, crossing_iterations = 0;
  for (const TraceFold& f : trace.folds) {
    corners += f.fold.corner ? 1 : 0;
    fold_iterations += f.fold.iterations;
  }
  for (const Bifurcation& b : trace.bifurcations) {
    if (b.type == BifurcationType::kFold) continue;
    ++crossings;
    jumps += b.discontinuous ? 1 : 0;
    crossing_iterations += b.iterations;
  }
  std::printf("  folds %zu (%d corners) in %d iterations; other crossings %d (%d jumps) in %d\n",
              trace.folds.size(), corners, fold_iterations, crossings, jumps, crossing_iterations);
  // The corrector's detours: steps at fixed ω after a failed arclength corrector (their
  // iterations include the failed one's) and rejected steps, against all of the trace's.
  int fixed = 0, fixed_iterations = 0, rejected = 0, rejected_iterations = 0;
  for (const StepRecord& r : s.history) {
    if (r.fixed_lambda) {
      ++fixed;
      fixed_iterations += r.newton_iterations;
    } else if (!r.accepted) {
      ++rejected;
      rejected_iterations += r.newton_iterations;
    }
  }
  const double total = std::max(s.total_newton_iterations, 1);
  std::printf(
      "  corrector: %d evaluations; %d steps at fixed omega after a failed arclength corrector "
      "in %d iterations (%.1f %%), %d rejected steps in %d (%.1f %%)\n",
      s.num_evaluations, fixed, fixed_iterations, 100.0 * fixed_iterations / total, rejected,
      rejected_iterations, 100.0 * rejected_iterations / total);
  Timing timing{seconds, lu_unit, static_cast<int>(trace.points.size())};
  if (accuracy) {
    timing.accuracy = Accuracy(the_case, trace, c.plotted);
    std::printf("  accuracy %.2e against a tenth of the step\n", timing.accuracy);
  }
  std::fflush(stdout);
  return timing;
}

// One friction point at N_φ = 640 (harmonics 1, 3, …, 1279: 1 280 coefficients per signal,
// 2 560 unknowns with the friction force): the start
// solve at ω = 0.75 of the two-DOF oscillator, N = 10.
Timing RunFineFrictionPoint(double lu_unit, const AcceptanceOptions& settings) {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/friction/point_e.json");
  the_case.harmonics = HarmonicSet(1279, true);
  the_case.continuation.lambda_start = 0.75;
  the_case.continuation.max_points = 1;
  the_case.stability.enabled = settings.stability;
  TraceOptions options;
  options.threads = settings.threads;
  const auto start = Clock::now();
  const TraceResult trace = TraceCase(the_case, options);
  const double seconds = Seconds(start);
  std::printf("friction point at N_phi = 640, omega = 0.75: %s, %d unknowns, %d Newton\n",
              ToString(trace.branch.summary.reason), trace.num_unknowns,
              trace.branch.summary.total_newton_iterations);
  std::printf("  wall time %.1f ms = %.1f LU(320)  (budget 200 LU(320))\n", 1e3 * seconds,
              seconds / lu_unit);
  std::fflush(stdout);
  return {seconds, lu_unit};
}

double Calibrate(const std::function<double()>& lu_unit) {
  const double seconds = lu_unit();
  std::printf("[LU(320) = %.3f ms] ", 1e3 * seconds);
  return seconds;
}

// Runs `body` (which returns a Timing) in a child, prints the child's peak resident memory
// and returns the Timing (through a pipe), or nothing if the child failed.
template <typename Body>
std::optional<Timing> InChild(Body body) {
  std::fflush(stdout);
  int channel[2];
  if (pipe(channel) != 0) {
    std::printf("  (could not open a pipe to a child process)\n");
    return std::nullopt;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(channel[0]);
    const Timing timing = body();
    std::fflush(stdout);
    const bool sent = write(channel[1], &timing, sizeof timing) == sizeof timing;
    _exit(sent ? 0 : 1);
  }
  close(channel[1]);
  Timing timing;
  const bool received = pid > 0 && read(channel[0], &timing, sizeof timing) == sizeof timing;
  close(channel[0]);
  int status = 0;
  rusage usage{};
  if (pid < 0 || wait4(pid, &status, 0, &usage) != pid) {
    std::printf("  (could not run in a child process)\n");
    return std::nullopt;
  }
  const bool exited = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!exited) std::printf("  (child failed)\n");
  std::printf("  peak memory %.1f MB\n", usage.ru_maxrss / 1024.0);  // ru_maxrss is in KiB
  if (!exited || !received) return std::nullopt;
  return timing;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The summary of repeated runs of one case: fastest and median ms, and the same in LU(320)
// as each run's time over its own child's calibration (a slow phase of the shared machine
// slows both alike).
void PrintRuns(const std::string& name, const std::vector<Timing>& runs, double budget_lu) {
  if (runs.empty()) {
    std::printf("  %-34s no run completed\n", name.c_str());
    return;
  }
  std::vector<double> ms, units, points;
  for (const Timing& t : runs) {
    ms.push_back(1e3 * t.seconds);
    units.push_back(t.seconds / t.lu_unit);
    points.push_back(t.points);
  }
  std::printf("  %-34s %zu runs: %9.1f / %9.1f ms, %8.1f / %8.1f LU(320)", name.c_str(),
              runs.size(), *std::min_element(ms.begin(), ms.end()), Median(ms),
              *std::min_element(units.begin(), units.end()), Median(units));
  if (budget_lu > 0.0) std::printf("  (budget %.0f)", budget_lu);
  const auto [fewest, most] = std::minmax_element(points.begin(), points.end());
  if (*fewest != *most) {
    std::printf("  points %.0f / %.0f / %.0f", *fewest, Median(points), *most);
  }
  std::vector<double> accuracies;
  for (const Timing& t : runs) {
    if (t.accuracy >= 0.0) accuracies.push_back(t.accuracy);
  }
  if (accuracies.size() > 1) {
    const auto [best, worst] = std::minmax_element(accuracies.begin(), accuracies.end());
    std::printf("  accuracy %.2e / %.2e / %.2e", *best, Median(accuracies), *worst);
  }
  std::printf("\n");
}

// The Fig. 7 curve (N = 10) traced with own-unknown step weight `weight`, as the plotted
// ln E curve; its wall time (s), Newton iterations and points through the pointers.
PlottedCurve TraceWithWeight(const Case& the_case, double weight, double* seconds, int* newton) {
  const auto start = Clock::now();
  auto system = BuildSystem(the_case);
  system->set_own_step_weight(weight);
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, nullptr);
  const Branch branch = Trace(*system, the_case.continuation, nullptr, &guess, the_case.Plot());
  *seconds = Seconds(start);
  *newton = branch.summary.total_newton_iterations;
  PointAnalyzer analyzer(*system, the_case.output_dofs);
  PlottedCurve curve;
  curve.log_scale = true;
  curve.measures.resize(1);
  for (const BranchPoint& p : branch.points) {
    curve.omega.push_back(p.lambda);
    curve.measures[0].push_back(analyzer.Measure(p.y, p.lambda).energy);
  }
  return curve;
}

}  // namespace

void BenchStepWeights(double lu_unit) {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json");
  Case fine = the_case;
  ContinuationOptions& options = fine.continuation;
  options.max_step /= 10.0;
  options.initial_step = std::min(options.initial_step, options.max_step);
  options.max_points *= 20;
  double seconds = 0.0;
  int newton = 0;
  // The reference with full weight: the most conservative steps, a tenth as long.
  const PlottedCurve reference = TraceWithWeight(fine, 1.0, &seconds, &newton);
  std::printf(
      "friction/frc_n10.json, step weight of the friction force (stability off; "
      "reference: %zu points at a tenth of the step)\n",
      reference.omega.size());
  for (const double weight : {1.0, 0.3, 0.1, 0.0}) {
    const PlottedCurve curve = TraceWithWeight(the_case, weight, &seconds, &newton);
    std::printf("  weight %.1f: %zu points, %d Newton, %.1f ms = %.1f LU(320), accuracy %.2e\n",
                weight, curve.omega.size(), newton, 1e3 * seconds, seconds / lu_unit,
                CurveDeviation(reference, curve));
  }
}

namespace {

// The cases with their budgets; the N_φ = 640 point (kFinePoint) runs after them.
const std::vector<AcceptanceCase>& AcceptanceCases() {
  static const std::vector<AcceptanceCase> cases = {
      {"duffing.json", Plotted::kMaxAbs, 0.0},
      {"friction/one_dof_coulomb.json", Plotted::kMaxAbs, 4.0},
      {"contact/nlvib.json#penalty", Plotted::kMaxAbs, 30.0},
      {"friction/fig7.json#n8", Plotted::kLogEnergy, 40.0},
      {"friction/frc_n10.json", Plotted::kLogEnergy, 40.0},
      {"friction/fig7.json#n10_5", Plotted::kLogEnergy, 40.0},
      {"friction/fig7.json#n11", Plotted::kLogEnergy, 40.0},
      {"rod/rigid_nh20.json", Plotted::kMaxAbs, 60.0},
      {"friction/point_e.json", Plotted::kLogEnergy, 700.0},
  };
  return cases;
}
constexpr const char* kFinePoint = "friction point at N_phi = 640";

// Whether `word` of AcceptanceOptions::only selects the case `name`.
bool Selects(const std::string& word, const std::string& name) {
  return name.find(word) != std::string::npos;
}

}  // namespace

std::vector<std::string> AcceptanceCaseNames() {
  std::vector<std::string> names;
  for (const AcceptanceCase& c : AcceptanceCases()) names.emplace_back(c.file);
  names.emplace_back(kFinePoint);
  return names;
}

void CheckAcceptanceSelection(const std::vector<std::string>& only) {
  const std::vector<std::string> names = AcceptanceCaseNames();
  for (const std::string& word : only) {
    if (std::none_of(names.begin(), names.end(),
                     [&](const std::string& name) { return Selects(word, name); })) {
      throw std::invalid_argument("case=" + word + " names no case of section 9");
    }
  }
}

void BenchAcceptance(const std::function<double()>& lu_unit, const AcceptanceOptions& options) {
  const auto selected = [&](const std::string& name) {
    return options.only.empty() ||
           std::any_of(options.only.begin(), options.only.end(),
                       [&](const std::string& word) { return Selects(word, name); });
  };
  CheckAcceptanceSelection(options.only);
  const std::vector<AcceptanceCase>& cases = AcceptanceCases();
  // Rounds of every case in turn, so that a slow phase of the machine spreads over the cases.
  std::vector<std::vector<Timing>> timings(cases.size() + 1);
  const auto keep = [](std::optional<Timing> timing, std::vector<Timing>* into) {
    if (timing) into->push_back(*timing);
  };
  if (options.stability) {
    std::printf("Hill's analyses on %d threads beside the trace (threads=%d)\n",
                HillThreads(options.threads), options.threads);
  } else {
    std::printf("stability off: the trace alone, not the budgets' measure\n");
  }
  if (options.newton_target > 0)
    std::printf("every case with target_newton_iterations %d\n", options.newton_target);
  for (int round = 0; round < options.runs; ++round) {
    if (options.runs > 1) std::printf("round %d of %d\n", round + 1, options.runs);
    // The reference traces cost more: once, or on every perturbed copy (the spread).
    const bool with_accuracy = options.accuracy && (round == 0 || options.perturb);
    for (size_t i = 0; i < cases.size(); ++i) {
      if (!selected(cases[i].file)) continue;
      const int perturbation = options.perturb ? round : 0;
      keep(InChild([&] {
             return RunCase(cases[i], Calibrate(lu_unit), with_accuracy, perturbation, options);
           }),
           &timings[i]);
    }
    if (selected(kFinePoint)) {
      keep(InChild([&] { return RunFineFrictionPoint(Calibrate(lu_unit), options); }),
           &timings[cases.size()]);
    }
  }
  if (options.runs <= 1) return;
  std::printf(
      "over %d rounds: fastest / median wall time, and each run's time over its own "
      "calibration, fastest / median\n",
      options.runs);
  for (size_t i = 0; i < cases.size(); ++i) {
    if (selected(cases[i].file)) PrintRuns(cases[i].file, timings[i], cases[i].budget_lu);
  }
  if (selected(kFinePoint)) PrintRuns(kFinePoint, timings[cases.size()], 200.0);
}

}  // namespace nfrc::bench
