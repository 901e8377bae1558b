#include "tools/run_case.h"

#include <cstdio>

#include "analysis/branch_switching.h"
#include "analysis/trace.h"
#include "tools/branch_writer.h"

namespace nfrc {

void PrintReduction(const ReductionReport& report, std::ostream& out) {
  char line[160];
  std::snprintf(line, sizeof line,
                "nfrc: Craig-Bampton: %d DOFs -> %d boundary + %d modes in %.3f s (factor %.3f s, "
                "modes %.3f s; check %.3f s)\n",
                report.full_dofs, report.boundary_dofs, report.modes, report.time_s,
                report.factor_s, report.modes_s, report.check_time_s);
  out << line;
  for (size_t j = 0; j < report.eigenfrequencies.size(); ++j) {
    const EigenfrequencyCheck& c = report.eigenfrequencies[j];
    std::snprintf(line, sizeof line,
                  "nfrc:   mode %zu: full %.6g rad/s, reduced %.6g rad/s, relative error %.2e\n",
                  j + 1, c.full, c.reduced, c.relative_error);
    out << line;
  }
}

Branch RunCase(const Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop, const nlohmann::json& source, TraceResult* trace,
               int threads) {
  the_case.Validate();
  // Before anything is written: a model it refuses leaves no files.
  const ModelCheck model_check = CheckLinearModel(the_case.model.model);
  if (progress != nullptr && the_case.reduction) PrintReduction(*the_case.reduction, *progress);
  BranchWriter writer(out_dir, the_case, source);
  TraceOptions options;
  options.progress = progress;
  options.stop = stop;
  options.observer = &writer;
  options.threads = threads;
  options.model_check = &model_check;
  TraceResult result = TraceCase(the_case, options);
  writer.SetWindows(result.quasi_periodic_windows);
  writer.Finish(result.branch.summary);
  // The period-2 branch of every period doubling and the other branch of every branch point,
  // each in its own directory.
  int number = 0;
  for (const Bifurcation& bifurcation : result.bifurcations) {
    const bool doubling = bifurcation.type == BifurcationType::kPeriodDoubling;
    if (!doubling && bifurcation.type != BifurcationType::kBranchPoint) continue;
    if (stop != nullptr && stop->load()) break;
    const std::string dir =
        out_dir + (doubling ? "/period2_" : "/branch_point_") + std::to_string(++number);
    const Case sub = doubling ? SubharmonicCase(the_case, 2) : the_case;
    BranchWriter sub_writer(dir, sub, source);
    TraceOptions sub_options = options;
    sub_options.observer = &sub_writer;
    const SwitchedBranch switched = FollowBifurcation(the_case, bifurcation, sub_options);
    sub_writer.SetWindows(switched.trace.quasi_periodic_windows);
    sub_writer.Finish(switched.trace.branch.summary);
    if (progress != nullptr) {
      *progress << "nfrc: " << (doubling ? "period-2 branch " : "branch-point branch ") << number
                << ": " << switched.message << ", wrote " << dir << "/branch.json\n";
    }
  }
  if (trace != nullptr) {
    *trace = std::move(result);
    return trace->branch;
  }
  return std::move(result.branch);
}

}  // namespace nfrc
