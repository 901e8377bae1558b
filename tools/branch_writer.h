#pragma once

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "continuation/continuation.h"
#include "tools/case_file.h"
#include "tools/harmonic_system.h"
#include "tools/point_measures.h"

namespace nfrc {

// Streams a branch to DIR/branch.csv (a line per point, flushed) and DIR/branch.json
// (rewritten atomically at most every kJsonInterval, or ten times the last write's duration
// if longer, at every fold and at the end), so a run that stops
// part-way leaves every point computed so far on disk.
class BranchWriter : public ContinuationObserver {
 public:
  static constexpr std::chrono::milliseconds kJsonInterval{2000};

  // Creates `dir` if needed; throws std::runtime_error if it cannot write there. With
  // `solve_signals` false, OnPoint does not solve for the case's signals_at frequencies by
  // Newton (for drivers that are not Newton-based and call WriteSignals themselves).
  BranchWriter(std::string dir, const Case& the_case, HarmonicSystem& system,
               bool solve_signals = true);

  bool OnPoint(const BranchPoint& point, int index) override;
  // Also writes the time signals at every requested ω the segment from the previous point
  // crosses (solved at exactly that ω) to DIR/signals_<n>.csv.
  void OnFold(const Fold& fold) override;

  // Merges `extra` into the last point's record (e.g. a driver's per-point solver data).
  void AnnotateLastPoint(const nlohmann::json& extra);

  // Measures of solution y at ω as the point records hold them: energy, max_abs, min, max,
  // h1, laws (diagnostics) and, for contact cases, min_gap and min_force.
  nlohmann::json Measure(const Eigen::VectorXd& y, double omega);

  // Writes the final branch.json with the summary.
  void Finish(const ContinuationSummary& summary);

  // Writes the time signals of solution y at ω to DIR/signals_<n>.csv (fine grid) and, if
  // the laws have raw samples, DIR/samples_<n>.csv (N_t grid), and records them in
  // branch.json's "signals" with `note`. Returns that record.
  const nlohmann::json& WriteSignals(double omega, const Eigen::VectorXd& y, int after_point,
                                     bool converged, const std::string& note);

  const nlohmann::json& document() const { return document_; }

 private:
  void WriteJson();
  nlohmann::json LawDiagnostics(const Eigen::VectorXd& y, double omega);
  // Contact cases: the smallest min_gap and min_force over the laws, at the entry's top level.
  static void AddContactExtremes(nlohmann::json& entry);

  std::string dir_;
  const Case& case_;
  HarmonicSystem& system_;
  PointAnalyzer analyzer_;
  std::ofstream csv_;
  nlohmann::json document_;
  std::chrono::steady_clock::time_point last_json_write_;
  std::chrono::steady_clock::duration last_json_duration_{};
  std::optional<BranchPoint> previous_;
  int num_signals_ = 0;
  bool solve_signals_;
};

// nlohmann::json summary of a continuation run.
nlohmann::json SummaryToJson(const ContinuationSummary& summary);

}  // namespace nfrc
