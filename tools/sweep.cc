#include "tools/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>
#include <utility>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/output_files.h"
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

SweepRun RunFromJson(const nlohmann::json& run, const SweepPlan& plan) {
  const int index = run.value("index", -1);
  if (index < 0 || static_cast<size_t>(index) >= plan.size()) {
    throw InputError("--out: a sweep record names run " + std::to_string(index) +
                     ", which this sweep does not have");
  }
  SweepRun record = PendingRun(plan, static_cast<size_t>(index));
  record.dir = run.value("dir", record.dir);
  record.status = run.value("status", "pending");
  record.termination = run.value("termination", "");
  record.message = run.value("message", "");
  record.points = run.value("points", 0);
  record.folds = run.value("folds", 0);
  record.bifurcations = run.value("bifurcations", 0);
  record.peaks = run.value("peaks", std::map<std::string, double>{});
  record.seconds = run.value("seconds", 0.0);
  return record;
}

nlohmann::json ReadJson(const std::string& path) {
  try {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InputError("--out: " + path + " is not a sweep record (" + error.what() + ")");
  }
}

// sweep.json's "parameters": [{"path", "values"}], one per axis in grid order.
nlohmann::json AxesJson(const SweepGrid& grid) {
  nlohmann::json axes = nlohmann::json::array();
  for (const SweepAxis& axis : grid) axes.push_back({{"path", axis.path}, {"values", axis.values}});
  return axes;
}

// Runs from an earlier sweep.json of the same sweep, complete ones only. A record written
// before grids has only the one-parameter "parameter" and "values".
std::vector<SweepRun> Previous(const std::string& path, const SweepPlan& plan) {
  std::vector<SweepRun> kept;
  if (!std::filesystem::exists(path)) return kept;
  const nlohmann::json old = ReadJson(path);
  nlohmann::json identity = nlohmann::json::object();
  if (old.is_object() && old.contains("manifest")) {
    identity["manifest"] = old["manifest"];
    identity["variants"] = old.value("variants", nlohmann::json());
  } else if (old.is_object() && old.contains("parameters")) {
    identity["parameters"] = old["parameters"];
  } else if (old.is_object()) {
    identity["parameters"] =
        nlohmann::json::array({{{"path", old.value("parameter", "")},
                                {"values", old.value("values", std::vector<double>{})}}});
  }
  if (identity != plan.Record()) {
    throw InputError("--out: " + path + " holds another sweep (parameters or values differ)");
  }
  for (const nlohmann::json& run : old.value("runs", nlohmann::json::array())) {
    if (run.value("status", "") != "complete") continue;
    SweepRun record = RunFromJson(run, plan);
    record.resumed = true;
    kept.push_back(std::move(record));
  }
  return kept;
}

}  // namespace

SweepPlan::SweepPlan(SweepGrid grid) : grid_(std::move(grid)) {}

SweepPlan::SweepPlan(CaseManifest manifest) : manifest_(std::move(manifest)) {}

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

nlohmann::json SweepPlan::Record() const {
  if (!manifest_) return {{"parameters", AxesJson(grid_)}};
  nlohmann::json variants = nlohmann::json::array();
  for (const CaseVariant& variant : manifest_->variants) {
    nlohmann::json set = nlohmann::json::object();
    for (const FieldChange& change : variant.changes) set[change.path] = change.value;
    variants.push_back({{"name", variant.name}, {"set", set}});
  }
  return {{"manifest", manifest_->path}, {"variants", variants}};
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

std::vector<SweepRun> PlanSweep(const SweepPlan& plan, const std::string& out_dir) {
  if (plan.is_grid()) CheckGrid(plan.grid());
  for (const SweepAxis& axis : plan.grid()) {
    for (double value : axis.values) {
      if (!std::isfinite(value)) {
        throw InputError("--values: every value must be finite (" + axis.path + ")");
      }
    }
  }
  std::filesystem::create_directories(out_dir);
  std::vector<SweepRun> runs;
  for (size_t k = 0; k < plan.size(); ++k) runs.push_back(PendingRun(plan, k));
  for (SweepRun& kept : Previous(out_dir + "/sweep.json", plan)) {
    runs[static_cast<size_t>(kept.index)] = std::move(kept);
  }
  return runs;
}

SweepRun TraceSweepRun(const CaseFile& file, const SweepPlan& plan, SweepRun run,
                       const std::string& out_dir, const std::atomic<bool>* stop, int threads) {
  const std::string dir = out_dir + "/" + run.dir;
  std::filesystem::remove(dir + "/run.json");
  const auto start = std::chrono::steady_clock::now();
  try {
    const CaseFile at_run = CaseForRun(file, plan, static_cast<size_t>(run.index));
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
  WriteJsonAtomically(dir + "/run.json", RunJson(run, plan));
  return run;
}

std::optional<SweepRun> ReadRunRecord(const std::string& out_dir, const SweepRun& run,
                                      const SweepPlan& plan) {
  const std::string path = out_dir + "/" + run.dir + "/run.json";
  if (!std::filesystem::exists(path)) return std::nullopt;
  return RunFromJson(ReadJson(path), plan);
}

void WriteSweepRecord(const std::string& out_dir, const SweepPlan& plan,
                      const std::vector<SweepRun>& runs) {
  nlohmann::json document = nlohmann::json::object();
  // One parameter: the fields readers of sweeps before grids know, kept.
  if (plan.is_grid() && plan.grid().size() == 1) {
    document["parameter"] = plan.grid()[0].path;
    document["values"] = plan.grid()[0].values;
  }
  document.update(plan.Record());
  document["runs"] = nlohmann::json::array();
  for (const SweepRun& run : runs) document["runs"].push_back(RunJson(run, plan));
  WriteJsonAtomically(out_dir + "/sweep.json", document);
}

void PrintRun(std::ostream* progress, const SweepPlan& plan, const SweepRun& run) {
  if (progress == nullptr) return;
  *progress << "nfrc: run " << run.index << " (" << plan.Label(static_cast<size_t>(run.index))
            << "): " << run.status << ", " << run.points << " points, " << run.seconds << " s"
            << (run.message.empty() ? "" : ": ") << run.message << "\n";
}

std::vector<SweepRun> RunSweep(const CaseFile& file, const CaseParameter& parameter,
                               const std::vector<double>& values, const std::string& out_dir,
                               const SweepOptions& options) {
  return RunSweep(file, SweepGrid{{parameter, values}}, out_dir, options);
}

std::vector<SweepRun> RunSweep(const CaseFile& file, const SweepGrid& grid,
                               const std::string& out_dir, const SweepOptions& options) {
  CheckGridPaths(file, grid);
  return RunSweep(file, SweepPlan(grid), out_dir, options);
}

std::vector<SweepRun> RunSweep(const CaseFile& file, const SweepPlan& plan,
                               const std::string& out_dir, const SweepOptions& options) {
  if (options.jobs < 1) throw InputError("--jobs: must be at least 1");
  std::vector<SweepRun> runs = PlanSweep(plan, out_dir);
  WriteSweepRecord(out_dir, plan, runs);
  std::vector<size_t> todo;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].resumed) todo.push_back(k);
  }
  std::mutex mutex;  // guards runs, the record file and progress
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
        const SweepRun run =
            TraceSweepRun(file, plan, runs[todo[i]], out_dir, options.stop, hill_threads);
        const std::lock_guard<std::mutex> lock(mutex);
        runs[todo[i]] = run;
        WriteSweepRecord(out_dir, plan, runs);
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
  if (first_error) std::rethrow_exception(first_error);
  return runs;
}

}  // namespace nfrc
