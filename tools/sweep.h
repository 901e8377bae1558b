#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/case_parameter.h"
#include "tools/case_file.h"
#include "tools/case_manifest.h"

namespace nfrc {

// One parameter of a sweep and the values it takes, in order. The path names a numeric field
// of the case file: a CaseParameter path, or any other ("harmonics.max", "model.M[1][1]",
// "model.damping.modal_ratio"), which is set in the case's JSON and the case read again.
struct SweepAxis {
  SweepAxis(std::string path_in, std::vector<double> values_in)
      : path(std::move(path_in)), values(std::move(values_in)) {}
  SweepAxis(const CaseParameter& parameter, std::vector<double> values_in)
      : SweepAxis(parameter.path(), std::move(values_in)) {}
  std::string path;
  std::vector<double> values;
};

// The parameters of a sweep: one run per point of the Cartesian product of their values, in
// row-major order (the last parameter varies fastest): with two parameters of n0 and n1
// values, run k is at (values0[k / n1], values1[k % n1]). One axis is a plain sweep.
using SweepGrid = std::vector<SweepAxis>;

// Runs a sweep may have: more branches than this is not a sweep one machine finishes (and a
// typo such as COUNT 1000 on three axes is caught before anything is written).
inline constexpr size_t kMaxSweepRuns = 100000;

// InputError unless the grid has a shape that can be swept: at least one parameter, no path
// twice (naming --parameter), values on every axis and at most kMaxSweepRuns runs (naming
// --values). Values the case refuses are left to each run.
void CheckGrid(const SweepGrid& grid);
// The number of runs (the product of the axes' sizes); GridPoint: run `index`'s value of
// each axis, in the grid's order.
size_t GridSize(const SweepGrid& grid);
std::vector<double> GridPoint(const SweepGrid& grid, size_t index);
// A copy of `the_case` with every axis' field at `point` (one value per axis), validated once
// all are set (so that fields checked together are never seen half-changed). Every path must
// be a CaseParameter path (InputError naming "parameter" otherwise).
Case CaseAtGridPoint(const Case& the_case, const SweepGrid& grid, const std::vector<double>& point);

// The runs of a sweep: the points of a grid, or the variants of a manifest (one run each, in
// the manifest's order; the case file of the sweep is then the manifest's base).
class SweepPlan {
 public:
  explicit SweepPlan(SweepGrid grid);
  explicit SweepPlan(CaseManifest manifest);

  size_t size() const;
  bool is_grid() const { return !manifest_.has_value(); }
  const CaseManifest* manifest() const { return manifest_ ? &*manifest_ : nullptr; }
  const SweepGrid& grid() const { return grid_; }
  // Run `index`'s changes to the case file, in order.
  std::vector<FieldChange> Changes(size_t index) const;
  // Run `index` for people: "path=value, ..." or the variant's name.
  std::string Label(size_t index) const;
  // What sweep.json records of the plan ("parameters", or "manifest" and "variants"): a sweep
  // resumes only into a directory that holds the same. Built once.
  const nlohmann::json& Record() const { return record_; }

 private:
  SweepGrid grid_;
  std::optional<CaseManifest> manifest_;
  nlohmann::json record_;
};
// One branch of a sweep, as DIR/sweep.json records it.
struct SweepRun {
  int index = 0;
  std::vector<double> values;  // of the swept parameters, one per axis of a grid
  std::string name;            // a manifest's variant
  std::string dir;             // relative to the sweep's directory
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

// sweep.json's RewriteSchedule interval: a finished run is urgent, so this bounds only the
// duration rule's spacing from below when writes are quick.
inline constexpr std::chrono::milliseconds kSweepRecordInterval{1000};

struct SweepOptions {
  // Branches traced at once, each in its own thread. Above 1 each branch analyses its
  // stability on its own thread (TraceOptions::threads 0): the jobs already share the cores.
  int jobs = 1;
  std::ostream* progress = nullptr;         // a line per finished branch, and resume notes
  const std::atomic<bool>* stop = nullptr;  // raised: running branches stop after their point
};

// `nfrc sweep`: one branch per grid point (or per variant of a manifest), each traced and written
// as `nfrc run` does into DIR/<k>/ (k the run's index in grid order) and recorded in
// DIR/<k>/run.json as it finishes, and DIR/sweep.json (parameters, values, case fingerprint,
// runs) rewritten atomically as runs finish, on a RewriteSchedule (so that a sweep of 10⁵ runs
// spends a bounded share of its time rewriting it), and at the end. A run that fails is a
// status, never the end of the sweep. If DIR/sweep.json already holds this sweep (same
// parameters and values, same case fingerprint), its complete runs whose folders are their own
// are kept and the others traced again (resume, PlanSweep); a different sweep or case there is
// an InputError naming --out. sweep.json has "parameters": [{"path", "values"}] and, for one
// parameter only, the "parameter" and "values" of that axis as well.
// What a sweep did: its runs in plan order, what the resume said (PlanSweep's notes), and how
// often DIR/sweep.json was written (at the start, on the schedule and at the end).
struct SweepResult {
  std::vector<SweepRun> runs;
  std::vector<std::string> notes;
  int record_writes = 0;
};
SweepResult RunSweep(const CaseFile& file, const SweepPlan& plan, const std::string& out_dir,
                     const SweepOptions& options);
SweepResult RunSweep(const CaseFile& file, const SweepGrid& grid, const std::string& out_dir,
                     const SweepOptions& options);
// One parameter: RunSweep of the grid {{parameter, values}}.
SweepResult RunSweep(const CaseFile& file, const CaseParameter& parameter,
                     const std::vector<double>& values, const std::string& out_dir,
                     const SweepOptions& options);

// A fingerprint of a case file as a sweep resolves it: its JSON and the bytes of every file
// a string in it names (Matrix Market matrices, relative to base_dir), so that a sweep never
// resumes over the runs of a case that was edited since (16 hex digits, FNV-1a).
std::string CaseFingerprint(const CaseFile& file);

// What a sweep.json (`record`, as read from `path`) holds for `plan`: its case fingerprint
// (none in a record an earlier nfrc wrote) and its runs, each field checked for its type.
// InputError naming --out, the file and the field where it is not a record of `plan`.
struct SweepRecord {
  std::optional<std::string> fingerprint;
  std::vector<SweepRun> runs;
};
SweepRecord ParseSweepRecord(const nlohmann::json& record, const SweepPlan& plan,
                             const std::string& path);

// One sweep as its pieces see it: the case file (a manifest's base), the plan, the sweep's
// directory and the case's fingerprint, which DIR/sweep.json and every run.json record.
struct SweepJob {
  const CaseFile& file;
  const SweepPlan& plan;
  std::string out_dir;
  std::string fingerprint;  // CaseFingerprint(file)
};

// The pieces RunSweep is made of, for other ways of distributing runs (MPI ranks):
// - PlanSweep: the runs of the sweep in job.out_dir (created), pending, or `resumed` where an
//   earlier run of the same sweep left one complete: its folder DIR/<index> holds a run.json
//   of that run and case, branch.json and branch.csv (a complete run.json there counts even
//   where sweep.json, rewritten on a schedule, had not caught up). InputError as CheckGrid,
//   for a value that is not finite (naming --values), and naming --out for a directory that
//   holds another sweep, a sweep of another case, or a sweep.json that is not a sweep record
//   (with the field). A kept record whose folder is not its own is traced again, said in
//   `notes` (one line per run, for the progress stream; null: not said).
// - PendingRun: run `index` of the plan, not yet traced.
// - TraceSweepRun: traces one run into DIR/<dir>/ and records it in DIR/<dir>/run.json, with
//   `threads` for Hill's analyses (TraceOptions::threads).
// - ReadRunRecord: that record, if the run has one (InputError naming the file and field if it
//   is not a run record).
// - WriteSweepRecord: DIR/sweep.json for these runs; PrintRun: the progress line of a run.
// - CaseForRun: run `index`'s case and its case-file JSON (InputError if the run's values do
//   not make a case).
std::vector<SweepRun> PlanSweep(const SweepJob& job, std::vector<std::string>* notes);
SweepRun PendingRun(const SweepPlan& plan, size_t index);
SweepRun TraceSweepRun(const SweepJob& job, SweepRun run, const std::atomic<bool>* stop,
                       int threads);
std::optional<SweepRun> ReadRunRecord(const SweepJob& job, const SweepRun& run);
void WriteSweepRecord(const SweepJob& job, const std::vector<SweepRun>& runs);
void PrintRun(std::ostream* progress, const SweepPlan& plan, const SweepRun& run);
CaseFile CaseForRun(const CaseFile& file, const SweepPlan& plan, size_t index);

// InputError naming --parameter unless every axis of the grid names a numeric field of the
// case file (a CaseParameter path, or a number in its JSON).
void CheckGridPaths(const CaseFile& file, const SweepGrid& grid);

}  // namespace nfrc
