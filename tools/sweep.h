#pragma once

#include <atomic>
#include <iosfwd>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "analysis/case_parameter.h"
#include "tools/case_file.h"

namespace nfrc {

// One branch of a sweep, as DIR/sweep.json records it.
struct SweepRun {
  int index = 0;
  double value = 0.0;  // of the swept parameter
  std::string dir;     // relative to the sweep's directory
  // "complete" (the branch reached the end of its range), "failed" (bad input at this value,
  // or a numerical failure: `message` says which), "interrupted" or "pending".
  std::string status = "pending";
  std::string termination;  // the engine's reason, when the branch was traced
  std::string message;
  int points = 0, folds = 0, bifurcations = 0;
  // max_abs_<output> and energy: their largest value on the branch, and omega_at_<name>.
  std::map<std::string, double> peaks;
  double seconds = 0.0;
  bool resumed = false;  // kept from an earlier run of the same sweep, not traced again
};

struct SweepOptions {
  int jobs = 1;                             // branches traced at once, each in its own thread
  std::ostream* progress = nullptr;         // a line per finished branch
  const std::atomic<bool>* stop = nullptr;  // raised: running branches stop after their point
};

// `nfrc sweep`: one branch per value of the parameter, each traced and written as `nfrc run`
// does into DIR/<k>/, and DIR/sweep.json (parameter, values, runs) rewritten atomically as
// runs finish (and each run in DIR/<k>/run.json). A run that fails is a status, never the end of
// the sweep. If DIR/sweep.json already holds this sweep (same parameter and values), its complete
// runs are kept and the others traced again (resume); a different sweep there is an InputError
// naming --out.
std::vector<SweepRun> RunSweep(const CaseFile& file, const CaseParameter& parameter,
                               const std::vector<double>& values, const std::string& out_dir,
                               const SweepOptions& options);

// The pieces RunSweep is made of, for other ways of distributing runs (MPI ranks):
// - PlanSweep: the runs of the sweep in `out_dir` (created): complete runs of an earlier
//   DIR/sweep.json of the same sweep kept (`resumed`), the others pending; InputError naming
//   --values or --out as RunSweep.
// - TraceSweepRun: traces one run into DIR/<dir>/ and records it in DIR/<dir>/run.json.
// - ReadRunRecord: that record, if the run has one.
// - WriteSweepRecord: DIR/sweep.json for these runs; PrintRun: the progress line of a run.
std::vector<SweepRun> PlanSweep(const CaseParameter& parameter, const std::vector<double>& values,
                                const std::string& out_dir);
SweepRun TraceSweepRun(const CaseFile& file, const CaseParameter& parameter, SweepRun run,
                       const std::string& out_dir, const std::atomic<bool>* stop);
std::optional<SweepRun> ReadRunRecord(const std::string& out_dir, const SweepRun& run,
                                      const std::vector<double>& values);
void WriteSweepRecord(const std::string& out_dir, const CaseParameter& parameter,
                      const std::vector<double>& values, const std::vector<SweepRun>& runs);
void PrintRun(std::ostream* progress, const CaseParameter& parameter, const SweepRun& run);

// The case-file JSON with the field at `path` (a CaseParameter path) set to `value`.
nlohmann::json WithField(nlohmann::json source, const std::string& path, double value);

}  // namespace nfrc
