#pragma once

#include <atomic>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/case.h"
#include "analysis/refinement.h"
#include "tools/branch_writer.h"

namespace nfrc {

// Writes an ε-refinement (RefineEpsilon) to a directory as it is found:
// - DIR/branch.json and branch.csv: the branch up to ω (BranchWriter, its summary final as
//   soon as the branch ends), with each step's signals in branch.json's "signals";
// - DIR/signals_<i>.csv and samples_<i>.csv: the time signals of step i;
// - DIR/lcp/: the LCP-HBM reference as a one-signal branch.json, signals_0.csv, samples_0.csv;
// - DIR/refinement.json, rewritten atomically as it grows (at the start, after the LCP-HBM
//   reference and after each step, so that a run killed part-way keeps its steps): omega,
//   status ("running", then "complete", "incomplete" or "interrupted"); per step epsilon,
//   converged, newton_iterations, residual_norm, message, max_abs, h1, min_gap, min_force,
//   laws, the files and distance_to_lcp; "lcp" (status, pivots, complementarity_gap, min_gap,
//   max_abs, h1, min_force, files); "message" when steps are missing. It only writes: it never
//   solves.
class RefinementWriter : public RefinementObserver {
 public:
  // Creates `dir` if needed; throws std::runtime_error if it cannot write there. `source` is
  // the case as written (recorded in branch.json; null for a case built in memory).
  RefinementWriter(std::string dir, const Case& the_case, double omega, nlohmann::json source);

  // The observer of the branch up to ω (RefinementRunOptions::branch).
  TraceObserver* branch_observer() { return &branch_; }

  void OnBranchEnd(const ContinuationSummary& summary) override;
  void OnLcpReference(const LcpReference& reference) override;
  void OnStep(const RefinementStep& step) override;

  // Writes the final DIR/refinement.json for the finished (or interrupted) refinement;
  // `complete`: every step asked for was solved.
  void Finish(const RefinementResult& result, bool complete);

  const nlohmann::json& document() const { return document_; }

 private:
  void Write();

  std::string dir_;
  const Case& case_;
  BranchWriter branch_;
  nlohmann::json document_;
};

// `nfrc refine`: checks the input, then RefineEpsilon with a RefinementWriter on `out_dir`.
// `stop` (may be null) is polled after every branch point and before every step, so an
// interrupt keeps what was found and still writes refinement.json. Throws InputError for bad
// input (before anything is written) and std::runtime_error for I/O.
RefinementResult RunRefinement(const Case& the_case, const RefinementOptions& options,
                               const std::string& out_dir, std::ostream* progress,
                               const std::atomic<bool>* stop = nullptr,
                               const nlohmann::json& source = nullptr);

}  // namespace nfrc
