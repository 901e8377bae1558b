#include "tools/run_case.h"

#include "analysis/branch_switching.h"
#include "analysis/trace.h"
#include "tools/branch_writer.h"

namespace nfrc {

Branch RunCase(const Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop, const nlohmann::json& source) {
  the_case.Validate();
  BranchWriter writer(out_dir, the_case, source);
  TraceOptions options;
  options.progress = progress;
  options.stop = stop;
  options.observer = &writer;
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
  return std::move(result.branch);
}

}  // namespace nfrc
