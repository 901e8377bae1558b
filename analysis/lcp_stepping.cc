#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <string>

#include "analysis/lcp_hbm.h"
#include "analysis/trace.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// The stepping grid: `points` even steps plus the signals_at frequencies inside the range,
// ordered from omega_start to omega_end.
std::vector<double> Grid(const Case& the_case) {
  const double start = the_case.continuation.lambda_start;
  const double end = the_case.continuation.lambda_end;
  const int points = the_case.stepping.points;
  std::vector<double> grid;
  for (int i = 0; i < points; ++i) grid.push_back(start + (end - start) * i / (points - 1));
  for (double omega : the_case.signals_at) {
    if (omega >= std::min(start, end) && omega <= std::max(start, end)) grid.push_back(omega);
  }
  if (end > start) {
    std::sort(grid.begin(), grid.end());
  } else {
    std::sort(grid.begin(), grid.end(), std::greater<double>());
  }
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  return grid;
}

LemkeRecord Record(const LcpHbm::Solution& s) {
  LemkeRecord r;
  r.status = s.lemke.status;
  r.pivots = s.lemke.pivots;
  r.trivial = s.lemke.trivial;
  r.warm_started = s.lemke.warm_started;
  r.complementarity = s.lemke.complementarity;
  r.feasibility = s.lemke.feasibility;
  r.complementarity_gap = s.complementarity_gap;
  return r;
}

bool HasContact(const LcpHbm::Solution& s) { return s.lambda.maxCoeff() > 0.0; }

}  // namespace

TraceResult StepLcp(const Case& the_case, const TraceOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::ostream* progress = options.progress;
  const std::atomic<bool>* stop = options.stop;
  TraceObserver* observer = options.observer;
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  LcpHbm lcp(*system, the_case.laws);
  SolutionReporter reporter(*system, the_case.output_dofs, the_case.output_names);
  TraceResult result;
  result.num_unknowns = system->NumUnknowns();
  if (observer != nullptr) observer->OnStart(result.num_unknowns);
  const std::vector<double> grid = Grid(the_case);
  if (progress != nullptr) {
    *progress << "nfrc: LCP-HBM stepping, " << lcp.num_samples() << " complementarity pairs ("
              << the_case.harmonics.num_harmonics() << " harmonics, "
              << the_case.harmonics.num_samples() << " samples), " << grid.size() << " frequencies "
              << grid.front() << " -> " << grid.back() << "\n";
  }
  Branch& branch = result.branch;
  ContinuationSummary& summary = branch.summary;
  std::vector<int> contact_basis;  // Lemke basis of the last solution with contact
  int failures = 0;
  int coexisting = 0;
  for (double omega : grid) {
    if (stop != nullptr && stop->load()) {
      summary.reason = TerminationReason::kStoppedByObserver;
      break;
    }
    StepRecord record;
    LemkeOptions cold_options;
    cold_options.stop = stop;
    LcpHbm::Solution cold;
    try {
      cold = lcp.Solve(omega, cold_options);
    } catch (const InputError& error) {
      // The frequency comes from the case's range: name the end it lies nearer to.
      const ContinuationOptions& range = the_case.continuation;
      const bool near_start =
          std::abs(omega - range.lambda_start) <= std::abs(omega - range.lambda_end);
      throw InputError(std::string("continuation.") + (near_start ? "omega_start" : "omega_end") +
                       ": " + error.what());
    }
    if (cold.lemke.status == LemkeStatus::kInterrupted) continue;  // ended at the loop's top
    record.newton_iterations = cold.lemke.pivots;
    if (!cold.lemke.ok()) {
      ++failures;
      record.note = "omega " + std::to_string(omega) + ": Lemke " + ToString(cold.lemke.status) +
                    ": " + cold.lemke.message;
      summary.history.push_back(record);
      ++summary.num_rejected_steps;
      if (progress != nullptr) *progress << "nfrc: " << record.note << "\n";
      continue;
    }
    TracePoint record_point;
    record_point.lemke = Record(cold);
    std::optional<LcpHbm::Solution> warm;
    if (HasContact(cold)) {
      contact_basis = cold.lemke.basic_z;
    } else if (the_case.stepping.track_contact && !contact_basis.empty()) {
      LemkeOptions options;
      options.warm_basis = contact_basis;
      options.stop = stop;
      warm = lcp.Solve(omega, options);
      if (warm->lemke.ok() && HasContact(*warm)) {
        contact_basis = warm->lemke.basic_z;
        record_point.coexisting_contact = true;
        ++coexisting;
      } else {
        contact_basis.clear();
        warm.reset();
      }
    }
    BranchPoint point;
    point.lambda = omega;
    point.y = cold.y;
    point.tangent_y = Eigen::VectorXd::Zero(cold.y.size());
    point.residual_norm = cold.lemke.equation_residual;
    const int index = static_cast<int>(branch.points.size());
    record_point.index = index;
    record_point.point = point;
    record_point.measures = reporter.Measure(point.y, omega);
    if (warm)
      record_point.contact_branch =
          ContactBranchRecord{reporter.Measure(warm->y, omega), Record(*warm)};
    result.points.push_back(std::move(record_point));
    if (observer != nullptr) observer->OnPoint(result.points.back());
    if (options.solve_signals && std::find(the_case.signals_at.begin(), the_case.signals_at.end(),
                                           omega) != the_case.signals_at.end()) {
      auto add_signals = [&](const Eigen::VectorXd& y, const char* note) {
        SolutionSignals signals = reporter.Signals(y, omega);
        signals.after_point = index;
        signals.note = note;
        result.signals.push_back(std::move(signals));
        if (observer != nullptr) observer->OnSignals(result.signals.back());
      };
      add_signals(cold.y, "LCP-HBM (Lemke, cold start)");
      if (warm) add_signals(warm->y, "coexisting contact solution");
    }
    branch.points.push_back(std::move(point));
    record.accepted = true;
    summary.history.push_back(record);
    ++summary.num_accepted_steps;
    summary.total_newton_iterations += cold.lemke.pivots;
    if (progress != nullptr) {
      *progress << "nfrc: point " << index << " omega=" << omega << " pivots=" << cold.lemke.pivots
                << (HasContact(cold) ? " contact" : " trivial")
                << (warm ? " (coexisting contact found by warm start)" : "") << "\n";
    }
  }
  if (summary.reason != TerminationReason::kStoppedByObserver) {
    summary.reason = TerminationReason::kReachedLambdaBound;
  }
  summary.num_points = static_cast<int>(branch.points.size());
  summary.wall_time_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  summary.message = "LCP-HBM stepping: " + std::to_string(summary.num_points) + " of " +
                    std::to_string(grid.size()) + " frequencies solved, " +
                    std::to_string(failures) + " without a Lemke solution, " +
                    std::to_string(coexisting) + " trivial with a coexisting contact solution";
  if (summary.reason == TerminationReason::kStoppedByObserver) {
    summary.message += " (interrupted by a signal)";
  }
  return result;
}

}  // namespace nfrc
