#include "tools/run_case.h"

#include <algorithm>
#include <ostream>

#include "continuation/fixed_lambda.h"
#include "tools/input_fields.h"
#include "tools/branch_writer.h"
#include "tools/lcp_stepping.h"

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
             ContinuationObserver* observer, const Eigen::VectorXd* guess) {
  for (size_t i = 0; i < system.laws().size(); ++i) {
    try {
      system.laws()[i]->CheckForContinuation(system.harmonic_set());
    } catch (const std::invalid_argument& error) {
      throw InputError("nonlinearities[" + std::to_string(i) + "] (" + system.laws()[i]->type() +
                       "): " + error.what());
    }
  }
  const Eigen::VectorXd start =
      guess != nullptr ? *guess : system.InitialGuess(options.lambda_start);
  Branch branch = Continue(system, start, options, observer);
  if (!branch.summary.success() && !system.last_error().empty()) {
    branch.summary.message += " (last evaluation error: " + system.last_error() + ")";
  }
  return branch;
}

namespace {

// The rung below H on the harmonic ladder: about H/3, odd if the set is odd-only.
int CoarserMaxHarmonic(const HarmonicSet& set) {
  int coarse = std::max(1, set.max_harmonic() / 3);
  if (set.odd_only() && coarse % 2 == 0) --coarse;
  return std::max(1, coarse);
}

}  // namespace

Eigen::VectorXd StartingGuess(const Case& the_case, HarmonicSystem& system,
                              std::ostream* progress) {
  const ContinuationOptions& options = the_case.continuation;
  const double omega = options.lambda_start;
  const Eigen::VectorXd linear = system.InitialGuess(omega);
  FixedLambdaSolution solved = SolveAtFixedLambda(system, linear, omega, linear, options);
  if (solved.converged) return solved.y;
  const HarmonicSet& set = system.harmonic_set();
  const int coarse_h = CoarserMaxHarmonic(set);
  if (coarse_h >= set.max_harmonic()) return linear;
  const int block = set.NumCoefficients();
  for (const auto& law : system.laws()) {
    // Only own unknowns that are coefficient signals can move between harmonic sets.
    if (!law->OwnUnknownsAreCoefficients() || law->NumOwnUnknowns(set) % block != 0) {
      return linear;
    }
  }
  if (progress != nullptr) {
    *progress << "nfrc: no start from the linear guess with H=" << set.max_harmonic()
              << "; starting from H=" << coarse_h << "\n";
  }
  nlohmann::json source = the_case.source;
  source["harmonics"] = {{"max", coarse_h}, {"odd_only", set.odd_only()}};
  Case coarse_case = ParseCase(source, the_case.base_dir);
  std::unique_ptr<HarmonicSystem> coarse_system = MakeSystem(coarse_case);
  const Eigen::VectorXd coarse = StartingGuess(coarse_case, *coarse_system, progress);
  const Eigen::VectorXd padded = ChangeHarmonicSet(coarse, coarse_system->harmonic_set(), set);
  solved = SolveAtFixedLambda(system, padded, omega, padded, options);
  return solved.converged ? solved.y : linear;
}

Branch RunCase(Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop) {
  if (the_case.method == "lemke_stepping") return RunLcpStepping(the_case, out_dir, progress, stop);
  std::unique_ptr<HarmonicSystem> system = MakeSystem(the_case);
  BranchWriter writer(out_dir, the_case, *system);
  StoppableObserver observer(writer, stop);
  ContinuationOptions options = the_case.continuation;
  options.progress = progress;
  if (progress != nullptr) {
    *progress << "nfrc: " << system->NumUnknowns() << " unknowns ("
              << the_case.harmonics.num_harmonics() << " harmonics, "
              << the_case.harmonics.num_samples() << " samples), omega " << options.lambda_start
              << " -> " << options.lambda_end << "\n";
  }
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, progress);
  Branch branch = Trace(*system, options, &observer, &guess);
  if (stop != nullptr && stop->load()) branch.summary.message += " (interrupted by a signal)";
  writer.Finish(branch.summary);
  return branch;
}

}  // namespace nfrc
