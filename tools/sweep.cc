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
#include <thread>
#include <utility>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/output_files.h"
#include "tools/run_case.h"

namespace nfrc {
namespace {

nlohmann::json RunJson(const SweepRun& run, const std::string& parameter) {
  return {{"index", run.index},
          {"values", {{parameter, run.value}}},
          {"dir", run.dir},
          {"status", run.status},
          {"termination", run.termination},
          {"message", run.message},
          {"points", run.points},
          {"folds", run.folds},
          {"bifurcations", run.bifurcations},
          {"peaks", run.peaks},
          {"seconds", run.seconds}};
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

SweepRun RunFromJson(const nlohmann::json& run, const std::vector<double>& values) {
  SweepRun record;
  record.index = run.value("index", -1);
  if (record.index < 0 || record.index >= static_cast<int>(values.size())) {
    throw InputError("--out: a sweep record names run " + std::to_string(record.index) +
                     ", which this sweep does not have");
  }
  record.value = values[static_cast<size_t>(record.index)];
  record.dir = run.value("dir", "");
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

// Runs from an earlier sweep.json of the same sweep, complete ones only.
std::vector<SweepRun> Previous(const std::string& path, const std::string& parameter,
                               const std::vector<double>& values) {
  std::vector<SweepRun> kept;
  if (!std::filesystem::exists(path)) return kept;
  const nlohmann::json old = ReadJson(path);
  if (!old.is_object() || old.value("parameter", "") != parameter ||
      old.value("values", std::vector<double>{}) != values) {
    throw InputError("--out: " + path + " holds another sweep (parameter or values differ)");
  }
  for (const nlohmann::json& run : old.value("runs", nlohmann::json::array())) {
    if (run.value("status", "") != "complete") continue;
    SweepRun record = RunFromJson(run, values);
    record.resumed = true;
    kept.push_back(std::move(record));
  }
  return kept;
}

}  // namespace

nlohmann::json WithField(nlohmann::json source, const std::string& path, double value) {
  nlohmann::json* node = &source;
  size_t start = 0;
  while (start <= path.size()) {
    const size_t dot = path.find('.', start);
    std::string part =
        path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    const size_t bracket = part.find('[');
    if (bracket != std::string::npos) {
      const size_t index = std::stoul(part.substr(bracket + 1));
      node = &(*node)[part.substr(0, bracket)][index];
    } else {
      node = &(*node)[part];
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  *node = value;
  return source;
}

std::vector<SweepRun> PlanSweep(const CaseParameter& parameter, const std::vector<double>& values,
                                const std::string& out_dir) {
  if (values.empty()) throw InputError("--values: no values to sweep");
  for (double value : values) {
    if (!std::isfinite(value)) throw InputError("--values: every value must be finite");
  }
  std::filesystem::create_directories(out_dir);
  std::vector<SweepRun> runs(values.size());
  for (size_t k = 0; k < values.size(); ++k) {
    runs[k].index = static_cast<int>(k);
    runs[k].value = values[k];
    runs[k].dir = std::to_string(k);
  }
  for (SweepRun& kept : Previous(out_dir + "/sweep.json", parameter.path(), values)) {
    runs[static_cast<size_t>(kept.index)] = std::move(kept);
  }
  return runs;
}

SweepRun TraceSweepRun(const CaseFile& file, const CaseParameter& parameter, SweepRun run,
                       const std::string& out_dir, const std::atomic<bool>* stop) {
  const std::string dir = out_dir + "/" + run.dir;
  std::filesystem::remove(dir + "/run.json");
  const auto start = std::chrono::steady_clock::now();
  try {
    const Case the_case = parameter.With(file.the_case, run.value);
    TraceResult trace;
    RunCase(the_case, dir, nullptr, stop, WithField(file.source, parameter.path(), run.value),
            &trace);
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
  WriteJsonAtomically(dir + "/run.json", RunJson(run, parameter.path()));
  return run;
}

std::optional<SweepRun> ReadRunRecord(const std::string& out_dir, const SweepRun& run,
                                      const std::vector<double>& values) {
  const std::string path = out_dir + "/" + run.dir + "/run.json";
  if (!std::filesystem::exists(path)) return std::nullopt;
  return RunFromJson(ReadJson(path), values);
}

void WriteSweepRecord(const std::string& out_dir, const CaseParameter& parameter,
                      const std::vector<double>& values, const std::vector<SweepRun>& runs) {
  nlohmann::json document = {
      {"parameter", parameter.path()}, {"values", values}, {"runs", nlohmann::json::array()}};
  for (const SweepRun& run : runs) document["runs"].push_back(RunJson(run, parameter.path()));
  WriteJsonAtomically(out_dir + "/sweep.json", document);
}

void PrintRun(std::ostream* progress, const CaseParameter& parameter, const SweepRun& run) {
  if (progress == nullptr) return;
  *progress << "nfrc: run " << run.index << " (" << parameter.path() << "=" << run.value
            << "): " << run.status << ", " << run.points << " points, " << run.seconds << " s"
            << (run.message.empty() ? "" : ": ") << run.message << "\n";
}

std::vector<SweepRun> RunSweep(const CaseFile& file, const CaseParameter& parameter,
                               const std::vector<double>& values, const std::string& out_dir,
                               const SweepOptions& options) {
  if (options.jobs < 1) throw InputError("--jobs: must be at least 1");
  std::vector<SweepRun> runs = PlanSweep(parameter, values, out_dir);
  WriteSweepRecord(out_dir, parameter, values, runs);
  std::vector<size_t> todo;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (!runs[k].resumed) todo.push_back(k);
  }
  std::mutex mutex;  // guards runs, the record file and progress
  std::atomic<size_t> next{0};
  // An I/O error or a broken invariant in one thread ends the sweep: no new runs start, and it
  // is rethrown here once the running ones have finished.
  std::atomic<bool> aborted{false};
  std::exception_ptr first_error;
  auto worker = [&] {
    for (size_t i = next++; i < todo.size() && !aborted.load(); i = next++) {
      if (options.stop != nullptr && options.stop->load()) return;
      try {
        const SweepRun run = TraceSweepRun(file, parameter, runs[todo[i]], out_dir, options.stop);
        const std::lock_guard<std::mutex> lock(mutex);
        runs[todo[i]] = run;
        WriteSweepRecord(out_dir, parameter, values, runs);
        PrintRun(options.progress, parameter, run);
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
