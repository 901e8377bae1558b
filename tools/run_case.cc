#include "tools/run_case.h"

#include <ostream>

#include "tools/branch_writer.h"

namespace nfrc {
namespace {

// Forwards to the writer and stops the run when `stop` is raised.
class StoppableObserver : public ContinuationObserver {
 public:
  StoppableObserver(BranchWriter& writer, const std::atomic<bool>* stop)
      : writer_(writer), stop_(stop) {}
  bool OnPoint(const BranchPoint& point, int index) override {
    writer_.OnPoint(point, index);
    return stop_ == nullptr || !stop_->load();
  }
  void OnFold(const Fold& fold) override { writer_.OnFold(fold); }

 private:
  BranchWriter& writer_;
  const std::atomic<bool>* stop_;
};

}  // namespace

std::unique_ptr<HarmonicSystem> MakeSystem(Case& the_case) {
  return std::make_unique<HarmonicSystem>(the_case.model, the_case.harmonics,
                                          std::move(the_case.laws), the_case.output_dofs);
}

Branch Trace(HarmonicSystem& system, const ContinuationOptions& options,
             ContinuationObserver* observer) {
  const Eigen::VectorXd guess = system.InitialGuess(options.lambda_start);
  Branch branch = Continue(system, guess, options, observer);
  if (!branch.summary.success() && !system.last_error().empty()) {
    branch.summary.message += " (last evaluation error: " + system.last_error() + ")";
  }
  return branch;
}

Branch RunCase(Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop) {
  std::unique_ptr<HarmonicSystem> system = MakeSystem(the_case);
  BranchWriter writer(out_dir, the_case, *system);
  StoppableObserver observer(writer, stop);
  ContinuationOptions options = the_case.continuation;
  options.progress = progress;
  if (progress != nullptr) {
    *progress << "nfrc: " << system->NumUnknowns() << " unknowns ("
              << the_case.harmonics.num_harmonics() << " harmonics, "
              << the_case.harmonics.num_samples() << " samples), omega "
              << options.lambda_start << " -> " << options.lambda_end << "\n";
  }
  Branch branch = Trace(*system, options, &observer);
  if (stop != nullptr && stop->load()) branch.summary.message += " (interrupted by a signal)";
  writer.Finish(branch.summary);
  return branch;
}

}  // namespace nfrc
