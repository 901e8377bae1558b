#pragma once

#include <chrono>
#include <complex>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/trace.h"
#include "tools/output_files.h"
#include "tools/rewrite_schedule.h"

namespace nfrc {

// Streams a traced branch to DIR/branch.csv (a line per point, flushed) and DIR/branch.json
// (rewritten atomically on a RewriteSchedule of kJsonInterval, a fold or bifurcation being
// urgent, so that a run with many, such as NLvib's 96 over 900 kB, spends about a tenth on
// them instead of a quarter; and at the end), and each solution's time signals to
// DIR/signals_<n>.csv (and samples_<n>.csv), so a run that stops part-way leaves every point
// computed so far on disk. It only writes what the trace computed: it never solves.
class BranchWriter : public TraceObserver {
 public:
  static constexpr std::chrono::milliseconds kJsonInterval{2000};

  // Creates `dir` if needed; throws std::runtime_error if it cannot write there. `source` is
  // the case as written (recorded in branch.json; null for a case built in memory).
  BranchWriter(std::string dir, const Case& the_case, nlohmann::json source);

  void OnStart(int num_unknowns) override;
  bool OnPoint(const TracePoint& point) override;
  void OnFold(const TraceFold& fold) override;
  void OnBifurcation(const Bifurcation& bifurcation) override;
  void OnSignals(const SolutionSignals& signals) override;

  // The branch's quasi-periodic windows (written with the final branch.json).
  void SetWindows(const std::vector<QuasiPeriodicWindow>& windows);
  // Writes the final branch.json with the summary.
  void Finish(const ContinuationSummary& summary);

  const nlohmann::json& document() const { return document_; }
  // How many times branch.json was written (a diagnostic of the write policy).
  int json_writes() const { return schedule_.writes(); }

 private:
  // Writes branch.json if the policy above says it is due.
  void WriteJsonIfDue();
  void WriteJson();

  std::string dir_;
  const Case& case_;
  // ω = m·λ for a case of period m·T (Case::period_multiple), else 1.
  double omega_factor_ = 1.0;
  CsvStream csv_;  // 12 significant digits
  nlohmann::json document_;
  RewriteSchedule schedule_{kJsonInterval};
  bool unwritten_event_ = false;  // a fold or bifurcation not yet in branch.json
  int num_signals_ = 0;
};

// JSON of a Craig–Bampton reduction's report (branch.json "reduction"): sizes, time (s),
// fixed-interface frequencies and the eigenfrequency check (rad/s).
nlohmann::json ReductionToJson(const ReductionReport& report);

// JSON of measures as point records hold them: energy, max_abs, min, max, h1, amplitudes,
// laws (diagnostics) and, for contact cases, min_gap and min_force.
nlohmann::json MeasuresToJson(const SolutionMeasures& measures);

// [[re, im], ...] of complex values (multipliers).
nlohmann::json ComplexListToJson(const std::vector<std::complex<double>>& values);

// A point's "floquet" record: max_modulus, unstable (count), method, multipliers; null when
// not computed.
nlohmann::json FloquetToJson(const FloquetResult& floquet);

// A "bifurcations" entry: type, omega, omega_accuracy, converged, iterations, after_point,
// crossing_multipliers and the response measures as folds record them; ω times `factor`, the
// case's period multiple (its λ is ω/m).
nlohmann::json BifurcationToJson(const Bifurcation& bifurcation, double factor = 1.0);

// nlohmann::json summary of a continuation run.
nlohmann::json SummaryToJson(const ContinuationSummary& summary);

// Writes a signal table as CSV.
void WriteSignalTable(const std::string& path, const SignalTable& table);

}  // namespace nfrc
