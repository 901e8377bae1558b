#include "tools/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <string_view>
#include <thread>
#include <utility>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/input_fields.h"
#include "tools/json_input.h"
#include "tools/output_files.h"
#include "tools/rewrite_schedule.h"
#include "tools/run_case.h"

namespace nfrc {
namespace {

// The run's values by path (a variant's changes, for a manifest).
nlohmann::json RunValues(const SweepRun& run, const SweepPlan& plan) {
  nlohmann::json values = nlohmann::json::object();
  if (!plan.is_grid()) {
    for (const FieldChange& change : plan.Changes(static_cast<size_t>(run.index))) {
      values[change.path] = change.value;
    }
    return values;
  }
  const SweepGrid& grid = plan.grid();
  for (size_t i = 0; i < grid.size() && i < run.values.size(); ++i) {
    values[grid[i].path] = run.values[i];
  }
  return values;
}

nlohmann::json RunJson(const SweepRun& run, const SweepPlan& plan) {
  nlohmann::json json = {{"index", run.index},
                         {"values", RunValues(run, plan)},
                         {"dir", run.dir},
                         {"status", run.status},
                         {"termination", run.termination},
                         {"message", run.message},
                         {"points", run.points},
                         {"folds", run.folds},
                         {"bifurcations", run.bifurcations},
                         {"peaks", run.peaks},
                         {"seconds", run.seconds}};
  if (!run.name.empty()) json["name"] = run.name;
  return json;
}

// The largest max |x| of each output and energy on the branch, with their ω.
std::map<std::string, double> Peaks(const TraceResult& trace, const Case& the_case) {
  std::map<std::string, double> peaks;
  auto keep = [&](const std::string& name, double value, double omega) {
    const auto found = peaks.find(name);
    if (found == peaks.end() || value > found->second) {
      peaks[name] = value;
      peaks["omega_at_" + name] = omega;
    }
  };
  for (const TracePoint& point : trace.points) {
    const double omega = point.point.lambda * the_case.period_multiple;
    const PointMeasures& response = point.measures.response;
    for (size_t i = 0; i < response.max_abs.size() && i < the_case.output_names.size(); ++i) {
      keep("max_abs_" + the_case.output_names[i], response.max_abs[i], omega);
    }
    keep("energy", response.energy, omega);
  }
  return peaks;
}

constexpr const char* kStatuses[] = {"complete", "failed", "interrupted", "pending"};

// A run as sweep.json or run.json records it (`where` names it in messages: "runs[3]"), every
// field of its type; InputError naming the field otherwise. Unknown fields are left alone
// (a newer nfrc may add some).
SweepRun RunFromJson(const nlohmann::json& json, const SweepPlan& plan, const std::string& where) {
  InputFields fields(json, where);
  const int index = fields.RequiredInt("index");
  if (index < 0 || static_cast<size_t>(index) >= plan.size()) {
    fields.Fail("index", "run " + std::to_string(index) + " is not one of this sweep's " +
                             std::to_string(plan.size()) + " runs");
  }
  SweepRun record = PendingRun(plan, static_cast<size_t>(index));
  record.dir = fields.OptionalString("dir", record.dir);
  record.status = fields.OptionalString("status", "pending");
  if (std::find(std::begin(kStatuses), std::end(kStatuses), record.status) == std::end(kStatuses)) {
    fields.Fail("status",
                "\"" + record.status + "\" is not complete, failed, interrupted or pending");
  }
  record.termination = fields.OptionalString("termination", "");
  record.message = fields.OptionalString("message", "");
  record.points = fields.OptionalInt("points", 0);
  record.folds = fields.OptionalInt("folds", 0);
  record.bifurcations = fields.OptionalInt("bifurcations", 0);
  record.seconds = fields.OptionalNumber("seconds", 0.0);
  if (fields.Has("peaks")) {
    InputFields peaks(fields.RequiredObject("peaks"), where + ".peaks");
    for (const auto& [name, value] : json.at("peaks").items()) {
      record.peaks[name] = peaks.RequiredNumber(name);
    }
  }
  return record;
}

// The JSON of a sweep's file; InputError naming --out and the file if it is not one.
nlohmann::json ReadRecordFile(const std::string& path) {
  try {
    return ReadJsonFile(path, kSweepRecordKind);
  } catch (const InputError& error) {
    throw InputError(std::string("--out: ") + error.what());
  }
}

// sweep.json's "parameters": [{"path", "values"}], one per axis in grid order.
nlohmann::json AxesJson(const SweepGrid& grid) {
  nlohmann::json axes = nlohmann::json::array();
  for (const SweepAxis& axis : grid) axes.push_back({{"path", axis.path}, {"values", axis.values}});
  return axes;
}

std::string RunDir(const SweepJob& job, const SweepRun& run) { return job.out_dir + "/" + run.dir; }

// Why complete run `run` of an earlier sweep cannot be kept, "" if it can: its folder must be
// its own (DIR/<index>) and hold a complete run.json of the same run and case, branch.json
// and branch.csv.
std::string NotKept(const SweepJob& job, const SweepRun& run) {
  const std::string own = std::to_string(run.index);
  if (run.dir != own) return "its record names the folder \"" + run.dir + "\", not " + own;
  const std::string dir = RunDir(job, run);
  const std::string path = dir + "/run.json";
  if (!std::filesystem::is_regular_file(path)) return "its folder has no run.json";
  nlohmann::json json;
  try {
    json = ReadJsonFile(path, kSweepRecordKind);
    const SweepRun record = RunFromJson(json, job.plan, "run");
    if (record.index != run.index) return "its run.json is run " + std::to_string(record.index);
    if (record.status != "complete") return "its run.json says " + record.status;
  } catch (const InputError& error) {
    return std::string("its run.json is not a run record (") + error.what() + ")";
  }
  if (!json.contains("case_fingerprint") || json["case_fingerprint"] != job.fingerprint) {
    return "its run.json is of another case";
  }
  for (const char* name : {"branch.json", "branch.csv"}) {
    if (!std::filesystem::is_regular_file(dir + "/" + name)) {
      return std::string("its folder has no ") + name;
    }
  }
  return "";
}

// The runs an earlier sweep.json in the job's directory leaves complete and kept (`resumed`),
// and why each other complete record is not (run index, reason); InputError naming --out if
// it is not a record of this sweep of this case.
struct PreviousRuns {
  std::vector<SweepRun> kept;
  std::vector<std::pair<int, std::string>> refused;
  std::string note;  // about the record as a whole
};

PreviousRuns Previous(const SweepJob& job) {
  PreviousRuns previous;
  const std::string path = job.out_dir + "/sweep.json";
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, error))) return previous;
  SweepRecord record = ParseSweepRecord(ReadRecordFile(path), job.plan, path);
  if (!record.fingerprint) {
    previous.note = path +
                    " records no case fingerprint (an earlier nfrc wrote it): every run "
                    "is traced again";
    return previous;
  }
  if (*record.fingerprint != job.fingerprint) {
    throw InputError("--out: " + path +
                     " holds this sweep of another case (the case file, or a file it names, "
                     "changed since: case fingerprint " +
                     *record.fingerprint + ", now " + job.fingerprint +
                     "): give another --out, or remove the directory to start over");
  }
  for (SweepRun& run : record.runs) {
    if (run.status != "complete") continue;
    const std::string why = NotKept(job, run);
    if (!why.empty()) {
      previous.refused.emplace_back(run.index, why);
      continue;
    }
    run.resumed = true;
    previous.kept.push_back(std::move(run));
  }
  return previous;
}

// FNV-1a, 64 bits: a fingerprint, not a defence against forgery.
constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

void Hash(std::string_view bytes, std::uint64_t* hash) {
  for (const char c : bytes) {
    *hash ^= static_cast<unsigned char>(c);
    *hash *= kFnvPrime;
  }
}

// Hashes every regular file a string of `node` names (relative to base_dir), with its name.
void HashNamedFiles(const nlohmann::json& node, const std::string& base_dir, std::uint64_t* hash) {
  if (node.is_structured()) {
    for (const nlohmann::json& child : node) HashNamedFiles(child, base_dir, hash);
    return;
  }
  if (!node.is_string()) return;
  const std::string& name = node.get_ref<const std::string&>();
  if (name.empty()) return;
  const std::filesystem::path path = std::filesystem::path(name).is_absolute()
                                         ? std::filesystem::path(name)
                                         : std::filesystem::path(base_dir) / name;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return;
  std::ifstream in(path, std::ios::binary);
  Hash(name, hash);
  std::vector<char> chunk(1 << 16);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    Hash(std::string_view(chunk.data(), static_cast<size_t>(in.gcount())), hash);
  }
}

}  // namespace

SweepPlan::SweepPlan(SweepGrid grid) : grid_(std::move(grid)) {
  record_ = {{"parameters", AxesJson(grid_)}};
}

SweepPlan::SweepPlan(CaseManifest manifest) : manifest_(std::move(manifest)) {
  nlohmann::json variants = nlohmann::json::array();
  for (const CaseVariant& variant : manifest_->variants) {
    nlohmann::json set = nlohmann::json::object();
    for (const FieldChange& change : variant.changes) set[change.path] = change.value;
    variants.push_back({{"name", variant.name}, {"set", set}});
  }
  record_ = {{"manifest", manifest_->path}, {"variants", variants}};
}

size_t SweepPlan::size() const { return manifest_ ? manifest_->variants.size() : GridSize(grid_); }

std::vector<FieldChange> SweepPlan::Changes(size_t index) const {
  if (manifest_) return manifest_->variants.at(index).changes;
  const std::vector<double> point = GridPoint(grid_, index);
  std::vector<FieldChange> changes;
  for (size_t i = 0; i < grid_.size(); ++i)
    changes.push_back({grid_[i].path, NumberJson(point[i])});
  return changes;
}

std::string SweepPlan::Label(size_t index) const {
  if (manifest_) return manifest_->variants.at(index).name;
  const std::vector<double> point = GridPoint(grid_, index);
  std::string label;
  for (size_t i = 0; i < grid_.size(); ++i) {
    std::ostringstream value;
    value << point[i];
    label += (i == 0 ? "" : ", ") + grid_[i].path + "=" + value.str();
  }
  return label;
}

CaseFile CaseForRun(const CaseFile& file, const SweepPlan& plan, size_t index) {
  CaseFile run;
  run.base_dir = file.base_dir;
  if (const CaseManifest* manifest = plan.manifest()) {
    run.source = VariantSource(*manifest, index);
  } else {
    run.source = file.source;
    for (const FieldChange& change : plan.Changes(index)) {
      ApplyFieldChange(&run.source, change, "--parameter");
    }
  }
  const SweepGrid& grid = plan.grid();
  const bool typed = plan.is_grid() && std::all_of(grid.begin(), grid.end(), [&](const auto& axis) {
                       return CaseParameter::Accepts(axis.path, file.the_case);
                     });
  // A field of a law or a forcing term is set in the typed case: a model that was reduced
  // (Craig-Bampton) is not reduced again for each run.
  run.the_case = typed ? CaseAtGridPoint(file.the_case, grid, GridPoint(grid, index))
                       : ParseCase(run.source, file.base_dir);
  run.the_case.path = file.the_case.path;
  return run;
}

void CheckGridPaths(const CaseFile& file, const SweepGrid& grid) {
  for (const SweepAxis& axis : grid) {
    if (CaseParameter::Accepts(axis.path, file.the_case)) continue;
    if (!FieldAt(file.source, axis.path).is_number()) {
      throw InputError("--parameter: \"" + axis.path + "\" names no number in the case file (" +
                       file.the_case.path + ")");
    }
  }
}

void CheckGrid(const SweepGrid& grid) {
  if (grid.empty()) throw InputError("--parameter: no parameter to sweep");
  double runs = 1.0;  // a double: the product of a few large axes must not wrap around
  for (size_t i = 0; i < grid.size(); ++i) {
    const std::string& path = grid[i].path;
    for (size_t j = 0; j < i; ++j) {
      if (grid[j].path == path) {
        throw InputError("--parameter: " + path + " is swept twice");
      }
    }
    if (grid[i].values.empty()) throw InputError("--values: no values to sweep for " + path);
    runs *= static_cast<double>(grid[i].values.size());
  }
  if (runs > static_cast<double>(kMaxSweepRuns)) {
    throw InputError("--values: the grid has " + std::to_string(static_cast<long long>(runs)) +
                     " runs, more than " + std::to_string(kMaxSweepRuns));
  }
}

size_t GridSize(const SweepGrid& grid) {
  if (grid.empty()) return 0;
  size_t size = 1;
  for (const SweepAxis& axis : grid) size *= axis.values.size();
  return size;
}

std::vector<double> GridPoint(const SweepGrid& grid, size_t index) {
  std::vector<double> point(grid.size());
  // Row-major: peel the fastest (last) axis off first.
  for (size_t i = grid.size(); i-- > 0;) {
    const size_t size = grid[i].values.size();
    point[i] = grid[i].values[index % size];
    index /= size;
  }
  return point;
}

Case CaseAtGridPoint(const Case& the_case, const SweepGrid& grid,
                     const std::vector<double>& point) {
  Case changed = the_case;
  for (size_t i = 0; i < grid.size(); ++i)
    CaseParameter(grid[i].path, the_case).Set(&changed, point[i]);
  changed.Validate();
  return changed;
}

SweepRun PendingRun(const SweepPlan& plan, size_t index) {
  SweepRun run;
  run.index = static_cast<int>(index);
  if (plan.is_grid()) {
    run.values = GridPoint(plan.grid(), index);
  } else {
    run.name = plan.Label(index);
  }
  run.dir = std::to_string(index);
  return run;
}

SweepRecord ParseSweepRecord(const nlohmann::json& old, const SweepPlan& plan,
                             const std::string& path) {
  const std::string named = "--out: " + path;
  if (!old.is_object()) throw InputError(named + ": expected an object (a sweep record)");
  // A record written before grids has only the one-parameter "parameter" and "values".
  nlohmann::json identity = nlohmann::json::object();
  if (old.contains("manifest")) {
    identity["manifest"] = old["manifest"];
    identity["variants"] = old.value("variants", nlohmann::json());
  } else if (old.contains("parameters")) {
    identity["parameters"] = old["parameters"];
  } else {
    identity["parameters"] =
        nlohmann::json::array({{{"path", old.value("parameter", nlohmann::json())},
                                {"values", old.value("values", nlohmann::json())}}});
  }
  if (identity != plan.Record()) {
    throw InputError(named + " holds another sweep (parameters or values differ)");
  }
  SweepRecord record;
  if (old.contains("case_fingerprint")) {
    const nlohmann::json& fingerprint = old["case_fingerprint"];
    if (!fingerprint.is_string()) throw InputError(named + ": case_fingerprint: expected a string");
    record.fingerprint = fingerprint.get<std::string>();
  }
  if (!old.contains("runs")) return record;
  const nlohmann::json& runs = old["runs"];
  if (!runs.is_array()) throw InputError(named + ": runs: expected a list of runs");
  for (size_t k = 0; k < runs.size(); ++k) {
    try {
      record.runs.push_back(RunFromJson(runs[k], plan, "runs[" + std::to_string(k) + "]"));
    } catch (const InputError& bad) {
      throw InputError(named + ": " + bad.what());
    }
  }
  return record;
}

std::string CaseFingerprint(const CaseFile& file) {
  std::uint64_t hash = kFnvOffset;
  Hash(file.source.dump(), &hash);
  HashNamedFiles(file.source, file.base_dir, &hash);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::vector<SweepRun> PlanSweep(const SweepJob& job, std::vector<std::string>* notes) {
  const SweepPlan& plan = job.plan;
  if (plan.is_grid()) CheckGrid(plan.grid());
  for (const SweepAxis& axis : plan.grid()) {
    for (double value : axis.values) {
      if (!std::isfinite(value)) {
        throw InputError("--values: every value must be finite (" + axis.path + ")");
      }
    }
  }
  std::filesystem::create_directories(job.out_dir);
  std::vector<SweepRun> runs;
  runs.reserve(plan.size());
  for (size_t k = 0; k < plan.size(); ++k) runs.push_back(PendingRun(plan, k));
  PreviousRuns previous = Previous(job);
  if (notes != nullptr && !previous.note.empty()) notes->push_back(previous.note);
  // Without a fingerprint nothing in the directory is known to be this case's.
  const bool trusted = previous.note.empty();
  for (SweepRun& kept : previous.kept) {
    runs[static_cast<size_t>(kept.index)] = std::move(kept);
  }
  // A run that finished after sweep.json was last written (it is rewritten on a schedule, and
  // a killed sweep writes no last one) has its complete run.json, of this case.
  for (SweepRun& run : runs) {
    if (!trusted) break;
    if (run.resumed || !std::filesystem::exists(RunDir(job, run) + "/run.json")) continue;
    std::optional<SweepRun> record;
    try {
      record = ReadRunRecord(job, run);
    } catch (const InputError&) {
      continue;  // traced again: its run.json is rewritten
    }
    if (record && record->status == "complete" && NotKept(job, *record).empty()) {
      run = *record;
      run.resumed = true;
    }
  }
  for (const auto& [index, why] : previous.refused) {
    if (notes == nullptr) break;
    const bool kept = runs[static_cast<size_t>(index)].resumed;
    notes->push_back("run " + std::to_string(index) + ": its record in sweep.json not used (" +
                     why + "): " + (kept ? "kept from its own folder's run.json" : "traced again"));
  }
  return runs;
}

SweepRun TraceSweepRun(const SweepJob& job, SweepRun run, const std::atomic<bool>* stop,
                       int threads) {
  const std::string dir = RunDir(job, run);
  std::filesystem::remove(dir + "/run.json");
  const auto start = std::chrono::steady_clock::now();
  try {
    const CaseFile at_run = CaseForRun(job.file, job.plan, static_cast<size_t>(run.index));
    const Case& the_case = at_run.the_case;
    TraceResult trace;
    RunCase(the_case, dir, nullptr, stop, at_run.source, &trace, threads);
    const ContinuationSummary& summary = trace.branch.summary;
    run.termination = ToString(summary.reason);
    run.message = summary.message;
    run.points = static_cast<int>(trace.points.size());
    run.folds = static_cast<int>(trace.folds.size());
    run.bifurcations = static_cast<int>(trace.bifurcations.size());
    run.peaks = Peaks(trace, the_case);
    const bool stopped = stop != nullptr && stop->load();
    const bool complete = summary.success() || summary.reason == TerminationReason::kMaxPoints;
    run.status = stopped ? "interrupted" : complete ? "complete" : "failed";
  } catch (const InputError& error) {
    run.status = "failed";
    run.message = error.what();
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::filesystem::create_directories(dir);
  nlohmann::json record = RunJson(run, job.plan);
  record["case_fingerprint"] = job.fingerprint;
  WriteJsonAtomically(dir + "/run.json", record);
  return run;
}

std::optional<SweepRun> ReadRunRecord(const SweepJob& job, const SweepRun& run) {
  const std::string path = RunDir(job, run) + "/run.json";
  if (!std::filesystem::exists(path)) return std::nullopt;
  try {
    return RunFromJson(ReadJsonFile(path, kSweepRecordKind), job.plan, "run");
  } catch (const InputError& error) {
    throw InputError(path + ": " + error.what());
  }
}

void WriteSweepRecord(const SweepJob& job, const std::vector<SweepRun>& runs) {
  const SweepPlan& plan = job.plan;
  nlohmann::json document = nlohmann::json::object();
  // One parameter: the fields readers of sweeps before grids know, kept.
  if (plan.is_grid() && plan.grid().size() == 1) {
    document["parameter"] = plan.grid()[0].path;
    document["values"] = plan.grid()[0].values;
  }
  document.update(plan.Record());
  document["case_fingerprint"] = job.fingerprint;
  nlohmann::json& list = document["runs"] = nlohmann::json::array();
  for (const SweepRun& run : runs) list.push_back(RunJson(run, plan));
  WriteJsonAtomically(job.out_dir + "/sweep.json", document);
}

void PrintRun(std::ostream* progress, const SweepPlan& plan, const SweepRun& run) {
  if (progress == nullptr) return;
  *progress << "nfrc: run " << run.index << " (" << plan.Label(static_cast<size_t>(run.index))
            << "): " << run.status << ", " << run.points << " points, " << run.seconds << " s"
            << (run.message.empty() ? "" : ": ") << run.message << "\n";
}

SweepResult RunSweep(const CaseFile& file, const CaseParameter& parameter,
                     const std::vector<double>& values, const std::string& out_dir,
                     const SweepOptions& options) {
  return RunSweep(file, SweepGrid{{parameter, values}}, out_dir, options);
}

SweepResult RunSweep(const CaseFile& file, const SweepGrid& grid, const std::string& out_dir,
                     const SweepOptions& options) {
  CheckGridPaths(file, grid);
  return RunSweep(file, SweepPlan(grid), out_dir, options);
}

SweepResult RunSweep(const CaseFile& file, const SweepPlan& plan, const std::string& out_dir,
                     const SweepOptions& options) {
  if (options.jobs < 1) throw InputError("--jobs: must be at least 1");
  const SweepJob job{file, plan, out_dir, CaseFingerprint(file)};
  SweepResult result;
  result.runs = PlanSweep(job, &result.notes);
  std::vector<SweepRun>& runs = result.runs;
  if (options.progress != nullptr) {
    for (const std::string& note : result.notes) *options.progress << "nfrc: " << note << "\n";
  }
  WriteSweepRecord(job, runs);
  RewriteSchedule schedule(kSweepRecordInterval);
  std::vector<size_t> todo;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].resumed) todo.push_back(k);
  }
  std::mutex mutex;  // guards runs, the record file, its schedule and progress
  std::atomic<size_t> next{0};
  // An I/O error or a broken invariant in one thread ends the sweep: no new runs start, and it
  // is rethrown here once the running ones have finished.
  std::atomic<bool> aborted{false};
  const int hill_threads = options.jobs > 1 ? 0 : -1;  // TraceOptions::threads of each branch
  std::exception_ptr first_error;
  auto worker = [&] {
    for (size_t i = next++; i < todo.size() && !aborted.load(); i = next++) {
      if (options.stop != nullptr && options.stop->load()) return;
      try {
        const SweepRun run = TraceSweepRun(job, runs[todo[i]], options.stop, hill_threads);
        const std::lock_guard<std::mutex> lock(mutex);
        runs[todo[i]] = run;
        // Every run is on disk in its run.json: sweep.json follows on the schedule.
        if (schedule.Due(true)) schedule.Timed([&] { WriteSweepRecord(job, runs); });
        PrintRun(options.progress, plan, run);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        aborted = true;
      }
    }
  };
  std::vector<std::thread> threads;
  const int extra = std::min<int>(options.jobs, static_cast<int>(todo.size())) - 1;
  for (int t = 0; t < extra; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();
  WriteSweepRecord(job, runs);
  result.record_writes = schedule.writes() + 2;  // and the first and last
  if (first_error) std::rethrow_exception(first_error);
  return result;
}

}  // namespace nfrc
