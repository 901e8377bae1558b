#pragma once

#include <iosfwd>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/validate.h"
#include "analysis/validation_settings.h"
#include "tools/branch_writer.h"

namespace nfrc {

// Writes what a validation (ValidateCase) finds as it finds it: the HBM branch to DIR/hbm/
// (BranchWriter), DIR/signals_<k>.csv per transient compared with an HBM solution (both on
// the transient's grid), DIR/chirp_<up|down>.csv, and DIR/validation.json, rewritten after
// every ω and chirp so a run that stops keeps what was done (an interrupted transient with
// what it integrated), with its "status" and "interrupted" at the end; and a line per
// transient to
// `table`. It only writes: it never solves. Files are created only once the input has passed
// ValidateCase's checks (OnTraceStart).
class ValidationWriter : public ValidationObserver {
 public:
  // `source` is the case as written (recorded in hbm/branch.json; null for a case built in
  // memory); `table` may be null. `the_case` and `settings` must outlive the writer. Throws
  // std::runtime_error (from the callbacks) if it cannot write in `dir`.
  ValidationWriter(std::string dir, const Case& the_case, const ValidationSettings& settings,
                   nlohmann::json source, std::ostream* table);

  TraceObserver* OnTraceStart() override;
  void OnBranch(const TraceResult& trace) override;
  void OnTransient(const ValidationPoint& point) override;
  void OnPoint(const ValidationPoint& point) override;
  void OnChirp(const ChirpRun& chirp) override;
  // The final "status" ("complete", "incomplete" or "interrupted"; "running" before) and
  // "interrupted".
  void OnEnd(const ValidationResult& result) override;

  // validation.json as last written.
  const nlohmann::json& document() const { return document_; }

 private:
  void WriteJson() const;

  std::string dir_;
  const Case& case_;
  const ValidationSettings& settings_;
  nlohmann::json source_;
  std::ostream* table_;
  std::unique_ptr<BranchWriter> branch_writer_;
  nlohmann::json document_;
  std::vector<std::string> point_files_;  // signals file per transient of the current ω
  int num_signals_ = 0;
};

// The JSON record of an HBM crossing solution as validation.json holds it: branch (the
// label), after_point, energy, max_abs, h1 and phases.
nlohmann::json CrossingToJson(const CrossingSolution& solution);

}  // namespace nfrc
