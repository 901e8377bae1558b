#include "tools/run_case.h"

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
  writer.Finish(result.branch.summary);
  return std::move(result.branch);
}

}  // namespace nfrc
