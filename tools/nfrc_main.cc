// The nfrc command line program: `nfrc run CASE.json --out DIR`, `nfrc refine ...`,
// `nfrc validate ...` and `nfrc plot DIR`: readers → analysis → writers, and the exit codes.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/case_parameter.h"
#include "analysis/event_curve.h"
#include "analysis/fold_curve.h"
#include "core/errors.h"
#include "tools/allocator.h"
#include "tools/case_file.h"
#include "tools/case_manifest.h"
#include "tools/command_line.h"
#include "tools/event_curve_writer.h"
#include "tools/fold_curve_writer.h"
#include "tools/json_input.h"
#include "tools/output_files.h"
#include "tools/refinement_writer.h"
#include "tools/run_case.h"
#include "tools/stop_signal.h"
#include "tools/sweep.h"
#include "tools/sweep_ranks.h"
#include "tools/validate.h"
#include "tools/version.h"

namespace {

// Exit codes: documented in the README.
constexpr int kExitOk = 0;
constexpr int kExitInputError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitRunIncomplete = 3;
constexpr int kExitIoError = 4;
constexpr int kExitInternalError = 5;

constexpr const char* kUsage =
    "usage:\n"
    "  nfrc run CASE.json --out DIR [--threads N]\n"
    "                                 trace the frequency response of a case, its stability\n"
    "                                 analysed on N threads beside the trace (default: one\n"
    "                                 per further core; 0: on the tracing thread only)\n"
    "  nfrc refine CASE.json --omega W --out DIR [--epsilon0 E] [--factor F] [--steps N]\n"
    "              [--epsilons E1,E2,...]\n"
    "                                 DLFT epsilon refinement at W (default: from the\n"
    "                                 case's epsilon, factor 2, 15 steps), warm-started\n"
    "  nfrc validate CASE.json --out DIR [--omega W1,W2,...] [--start hbm|rest] [--no-chirp]\n"
    "              [--no-plot]\n"
    "                                 integrate the model in time to steady state at each W\n"
    "                                 and compare with the HBM branch (DIR/validation.json)\n"
    "  nfrc fold-curve CASE.json --parameter PATH --to VALUE --out DIR [--max-step S]\n"
    "                                 follow each fold of the branch in (PATH, omega), e.g.\n"
    "                                 PATH model.forcing[0].cos or nonlinearities[0].gap\n"
    "                                 (DIR/fold_curve.json)\n"
    "  nfrc fold-curve CASE.json --kind peak|neimark_sacker --parameter PATH --to VALUE\n"
    "              --out DIR [--measure energy|h1:OUT|max_abs:OUT] [--near W] [--at P1,P2,...]\n"
    "              [--max-step F]\n"
    "                                 follow each maximum of the measure along omega in PATH\n"
    "                                 (steps at most F |VALUE - from|, landing on each Pi)\n"
    "                                 (DIR/peak_curve.json); neimark_sacker: each\n"
    "                                 Neimark-Sacker point, --measure only reported\n"
    "                                 (DIR/neimark_sacker_curve.json)\n"
    "  nfrc sweep CASE.json --parameter PATH (--values V1,V2,... | --range FROM:TO:COUNT)\n"
    "              [--parameter PATH2 (--values ... | --range ...) ...] --out DIR [--jobs N]\n"
    "                                 one branch per value (several --parameter: per point of\n"
    "                                 their grid, the last varying fastest) in DIR/<k>/,\n"
    "                                 DIR/sweep.json rewritten as runs finish; resumes a sweep\n"
    "                                 in DIR. PATH: any numeric field of the case file.\n"
    "                                 With --jobs above 1 each branch's stability runs on\n"
    "                                 its own thread\n"
    "  nfrc sweep MANIFEST.json --out DIR [--jobs N]\n"
    "                                 one branch per variant of a manifest (a base case and its\n"
    "                                 variants; run one as MANIFEST.json#NAME)\n"
    "  nfrc plot DIR [DIR ...] [--measure max_abs|min|max|h1|energy] [--logy] [--output BASE]\n"
    "              [--labels A,B] [--xlim MIN,MAX] [--title TEXT]\n"
    "                                 draw DIR/branch.json to DIR/frc.png and DIR/frc.svg\n"
    "  nfrc --version\n";

// The one case file of a command that needs one, and --out.
struct CaseAndOut {
  std::string case_path;
  std::string out_dir;
};

CaseAndOut RequireCaseAndOut(const nfrc::CommandLine& line) {
  if (line.positionals().size() > 1) throw line.Error("more than one case file given");
  const std::optional<std::string> out = line.Value("--out");
  if (line.positionals().empty() || !out) throw line.Error("needs a case file and --out DIR");
  if (out->empty()) throw line.Error("--out: empty directory name");
  return {line.positionals()[0], *out};
}

// A library field the command line sets, and the option that sets it ("to" is --to).
struct OptionField {
  std::string_view field;
  std::string_view option;
};

// Runs `study` on the case read from `case_path`. An InputError it raises names either a field
// the command line set (listed in `options`: re-raised naming the option, "to: ..." as
// "--to: ...") or a field of the case file (re-raised naming the file, unless it already does
// or names an option).
template <typename Study>
auto Naming(const std::string& case_path, std::initializer_list<OptionField> options, Study study) {
  try {
    return study();
  } catch (const nfrc::InputError& error) {
    const std::string message = error.what();
    for (const OptionField& named : options) {
      const std::string field = std::string(named.field) + ":";
      if (message.rfind(field, 0) == 0) {
        throw nfrc::InputError(std::string(named.option) + message.substr(named.field.size()));
      }
    }
    if (message.rfind(case_path, 0) == 0 || message.rfind("--", 0) == 0) throw;
    throw nfrc::InputError(case_path + ": " + message);
  }
}

// The lock on --out DIR, refused where DIR is a run folder of a sweep (it holds the run.json
// the sweep resumes from: writing another run there would replace one the sweep counts as its
// own).
nfrc::OutputDirectoryLock LockOutput(const std::string& out_dir) {
  if (std::filesystem::exists(std::filesystem::path(out_dir) / "run.json")) {
    throw nfrc::InputError("--out: " + out_dir +
                           " is a run folder of a sweep (it holds run.json): write elsewhere, or "
                           "remove it first");
  }
  return nfrc::OutputDirectoryLock(out_dir);
}

int Run(const std::vector<std::string>& args, const nfrc::StopSignal& stop) {
  const nfrc::CommandLine line(
      "run", args, {nfrc::OptionSpec::Value("--out"), nfrc::OptionSpec::Value("--threads")});
  const CaseAndOut io = RequireCaseAndOut(line);
  const int threads = line.Int("--threads", -1, nfrc::kMaxThreads).value_or(-1);
  const nfrc::CaseFile file = nfrc::ReadCaseFile(io.case_path);
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  stop.set_immediate(false);
  const nfrc::Branch branch = Naming(io.case_path, {}, [&] {
    return nfrc::RunCase(file.the_case, io.out_dir, &std::cerr, &stop.flag(), file.source, nullptr,
                         threads);
  });
  const auto& summary = branch.summary;
  std::cerr << "nfrc: " << nfrc::ToString(summary.reason) << ": " << summary.message << "\n"
            << "nfrc: " << summary.num_points << " points, " << summary.num_folds
            << " folds, wrote " << io.out_dir << "/branch.json and branch.csv\n";
  const bool complete = summary.success() || summary.reason == nfrc::TerminationReason::kMaxPoints;
  return complete && !stop.requested() ? kExitOk : kExitRunIncomplete;
}

int Refine(const std::vector<std::string>& args, const nfrc::StopSignal& stop) {
  using nfrc::NumberDomain;
  using nfrc::OptionSpec;
  const nfrc::CommandLine line("refine", args,
                               {OptionSpec::Value("--out"), OptionSpec::Value("--omega"),
                                OptionSpec::Value("--epsilon0"), OptionSpec::Value("--factor"),
                                OptionSpec::Value("--steps"), OptionSpec::Value("--epsilons")});
  const CaseAndOut io = RequireCaseAndOut(line);
  const std::optional<double> omega = line.Number("--omega", NumberDomain::kPositive);
  if (!omega) throw line.Error("needs --omega W (rad per time unit)");
  std::optional<double> epsilon0 = line.Number("--epsilon0", NumberDomain::kPositive);
  const double factor = line.Number("--factor", NumberDomain::kPositive).value_or(2.0);
  if (!(factor > 1.0)) throw line.Error("--factor: must be > 1");
  // 60 doublings take ε over 18 orders of magnitude: more is not a refinement.
  const int steps = line.Int("--steps", 0, 60).value_or(15);
  const std::vector<double> list = line.NumberList("--epsilons", NumberDomain::kPositive);

  const nfrc::CaseFile file = nfrc::ReadCaseFile(io.case_path);
  const nfrc::Case& the_case = file.the_case;
  nfrc::RefinementOptions options;
  options.omega = *omega;
  if (!list.empty()) {
    options.epsilons = list;
  } else {
    if (!epsilon0) {
      for (const nfrc::LawSpec& law : the_case.laws) {
        const auto* dlft = std::get_if<nfrc::DlftContactSpec>(&law);
        if (dlft != nullptr && dlft->contact.epsilon > 0.0) epsilon0 = dlft->contact.epsilon;
      }
    }
    if (!epsilon0) throw line.Error("give --epsilon0 or --epsilons (the case sets no epsilon)");
    options.epsilons = nfrc::GeometricEpsilons(*epsilon0, factor, steps);
  }
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  stop.set_immediate(false);
  const nfrc::RefinementResult result =
      Naming(io.case_path,
             {{"omega", "--omega"}, {"epsilons", "--epsilons"}, {"factor", "--factor"}}, [&] {
               return nfrc::RunRefinement(the_case, options, io.out_dir, &std::cerr, &stop.flag(),
                                          file.source);
             });
  const auto& done = result.steps;
  const bool complete = result.Complete(options);
  if (!result.message.empty()) std::cerr << "nfrc: " << result.message << "\n";
  std::cerr << "nfrc: " << done.size() << " of " << options.epsilons.size()
            << " refinement steps, wrote " << io.out_dir << "/refinement.json\n";
  return complete ? kExitOk : kExitRunIncomplete;
}

// An InputError about a peak-curve option, re-raised naming the command-line option that set it
// ("stations: ..." becomes "--at: ...").
[[noreturn]] void RethrowAsOption(const nfrc::CommandLine& line, const nfrc::InputError& error) {
  static const std::pair<const char*, const char*> kOptions[] = {
      {"stations", "--at"},           {"near", "--near"},
      {"measure", "--measure"},       {"max_step", "--max-step"},
      {"initial_step", "--max-step"}, {"min_step", "--max-step"}};
  const std::string message = error.what();
  for (const auto& [field, option] : kOptions) {
    if (message.rfind(std::string(field) + ":", 0) == 0) {
      throw line.Error(option + message.substr(std::string(field).size()));
    }
  }
  throw error;
}

// A study's "status" in its JSON file.
std::string StudyStatus(bool complete, const nfrc::StopSignal& stop) {
  return stop.requested() ? "interrupted" : complete ? "complete" : "incomplete";
}

// `nfrc fold-curve --kind peak|neimark_sacker`.
int EventCurve(const nfrc::CommandLine& line, const CaseAndOut& io, const std::string& path,
               double to, const std::string& kind, const nfrc::StopSignal& stop) {
  using nfrc::NumberDomain;
  const nfrc::CaseFile file = nfrc::ReadCaseFile(io.case_path);
  const nfrc::Case& the_case = file.the_case;
  const nfrc::CaseParameter parameter = Naming(io.case_path, {{"parameter", "--parameter"}},
                                               [&] { return nfrc::CaseParameter(path, the_case); });
  nfrc::EventCurveOptions options;
  options.to = to;
  try {
    options.measure = nfrc::ParsePeakMeasure(line.Value("--measure").value_or("energy"), the_case);
  } catch (const nfrc::InputError& error) {
    RethrowAsOption(line, error);
  }
  if (const auto near = line.Number("--near", NumberDomain::kPositive)) options.near = *near;
  options.stations = line.NumberList("--at");
  if (const auto max_step = line.Number("--max-step", NumberDomain::kPositive)) {
    options.SetMaxStep(*max_step);
  }
  const double from = parameter.Get(the_case);
  Naming(io.case_path, {{"to", "--to"}}, [&] {
    try {
      options.Validate(from);
    } catch (const nfrc::InputError& error) {
      RethrowAsOption(line, error);  // the peak curve's own options: a usage error
    }
  });
  options.progress = &std::cerr;
  options.stop = &stop.flag();
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  stop.set_immediate(false);
  const std::string file_name = kind + "_curve.json";
  nfrc::EventCurveWriter writer(io.out_dir + "/" + file_name, parameter.path(), from, to,
                                options.measure.name, file.source);
  options.observer = &writer;
  const nfrc::EventCurveResult result = Naming(io.case_path, {{"to", "--to"}}, [&] {
    return kind == "peak" ? nfrc::TracePeakCurves(the_case, parameter, options)
                          : nfrc::TraceNeimarkSackerCurves(the_case, parameter, options);
  });
  bool complete = !result.curves.empty();
  for (const std::string& note : result.notes) std::cerr << "nfrc: " << note << "\n";
  for (size_t i = 0; i < result.curves.size(); ++i) {
    const nfrc::EventCurve& curve = result.curves[i];
    std::cerr << "nfrc: " << kind << " " << i << " (omega=" << curve.start_omega
              << "): " << nfrc::ToString(curve.end) << ", " << curve.points.size() << " points, "
              << curve.solves << " solves" << (curve.message.empty() ? "" : ": " + curve.message)
              << "\n";
    complete = complete && curve.end == nfrc::EventCurveEnd::kReachedTo;
  }
  writer.Finish(result, StudyStatus(complete, stop));
  std::cerr << "nfrc: wrote " << io.out_dir << "/" << file_name << "\n";
  return complete && !stop.requested() ? kExitOk : kExitRunIncomplete;
}

int FoldCurve(const std::vector<std::string>& args, const nfrc::StopSignal& stop) {
  using nfrc::NumberDomain;
  using nfrc::OptionSpec;
  const nfrc::CommandLine line(
      "fold-curve", args,
      {OptionSpec::Value("--out"), OptionSpec::Value("--parameter"), OptionSpec::Value("--to"),
       OptionSpec::Value("--max-step"), OptionSpec::Value("--kind"), OptionSpec::Value("--measure"),
       OptionSpec::Value("--near"), OptionSpec::Value("--at")});
  const CaseAndOut io = RequireCaseAndOut(line);
  const std::optional<std::string> path = line.Value("--parameter");
  const std::optional<double> to = line.Number("--to");
  if (!path || !to) throw line.Error("needs --parameter PATH and --to VALUE");
  const std::string kind =
      line.Choice("--kind", {"fold", "peak", "neimark_sacker"}).value_or("fold");
  if (kind != "fold") return EventCurve(line, io, *path, *to, kind, stop);
  for (const char* option : {"--measure", "--near", "--at"}) {
    if (line.Value(option)) {
      throw line.Error(std::string(option) + " needs --kind peak or neimark_sacker");
    }
  }
  const nfrc::CaseFile file = nfrc::ReadCaseFile(io.case_path);
  const nfrc::Case& the_case = file.the_case;
  const nfrc::CaseParameter parameter = Naming(io.case_path, {{"parameter", "--parameter"}}, [&] {
    return nfrc::CaseParameter(*path, the_case);
  });
  nfrc::FoldCurveOptions options;
  options.to = *to;
  if (const auto max_step = line.Number("--max-step", NumberDomain::kPositive)) {
    options.SetMaxStep(*max_step);
  }
  const double from = parameter.Get(the_case);
  Naming(io.case_path, {{"to", "--to"}, {"max_step", "--max-step"}},
         [&] { options.Validate(from); });
  options.progress = &std::cerr;
  options.stop = &stop.flag();
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  stop.set_immediate(false);
  nfrc::FoldCurveWriter writer(io.out_dir, the_case, parameter.path(), from, *to, file.source);
  options.observer = &writer;
  const nfrc::FoldCurveResult result = Naming(io.case_path, {{"to", "--to"}}, [&] {
    return nfrc::TraceFoldCurves(the_case, parameter, options);
  });
  bool complete = !result.curves.empty();
  for (const std::string& note : result.notes) std::cerr << "nfrc: " << note << "\n";
  for (const nfrc::FoldCurve& curve : result.curves) {
    std::cerr << "nfrc: fold " << curve.start_fold << ": " << nfrc::ToString(curve.summary.reason)
              << ", " << curve.points.size() << " points, " << curve.turns.size()
              << " turns: " << curve.summary.message << "\n";
    complete = complete && curve.summary.success();
  }
  writer.Finish(result, StudyStatus(complete, stop));
  std::cerr << "nfrc: wrote " << io.out_dir << "/fold_curve.json\n";
  return complete && !stop.requested() ? kExitOk : kExitRunIncomplete;
}

// The sweep's last line and exit code: 0 when every run is complete.
int ReportSweep(const std::vector<nfrc::SweepRun>& runs, const std::string& out_dir,
                const nfrc::StopSignal& stop) {
  int complete = 0, resumed = 0;
  for (const nfrc::SweepRun& run : runs) {
    complete += run.status == "complete";
    resumed += run.resumed;
  }
  std::cerr << "nfrc: " << complete << " of " << runs.size() << " runs complete (" << resumed
            << " kept from an earlier run), wrote " << out_dir << "/sweep.json\n";
  return complete == static_cast<int>(runs.size()) && !stop.requested() ? kExitOk
                                                                        : kExitRunIncomplete;
}

// The parameters of `nfrc sweep`, each with the --values or --range given after it (before the
// next --parameter). With one --parameter the order does not matter, as before grids.
struct SweepAxisArgs {
  std::string path;
  std::vector<double> values;
};

std::vector<SweepAxisArgs> SweepAxes(const nfrc::CommandLine& line) {
  std::vector<std::string> paths;
  for (const nfrc::GivenOption& option : line.options()) {
    if (option.name != "--parameter") continue;
    if (std::find(paths.begin(), paths.end(), option.value) != paths.end()) {
      throw line.Error("--parameter " + option.value + ": given more than once");
    }
    paths.push_back(option.value);
  }
  if (paths.empty()) throw line.Error("needs --parameter PATH");
  std::vector<std::vector<nfrc::GivenOption>> lists(paths.size());
  size_t axis = 0;  // the --parameter the next value list belongs to, plus one
  for (const nfrc::GivenOption& option : line.options()) {
    if (option.name == "--parameter") ++axis;
    if (option.name != "--values" && option.name != "--range") continue;
    if (paths.size() > 1 && axis == 0) {
      throw line.Error(option.name + ": give it after the --parameter PATH it is for");
    }
    lists[paths.size() == 1 ? 0 : axis - 1].push_back(option);
  }
  std::vector<SweepAxisArgs> axes;
  double runs = 1.0;  // a double: the product of a few large axes must not wrap around
  for (size_t i = 0; i < paths.size(); ++i) {
    const std::string named = "--parameter " + paths[i] + ": ";
    if (lists[i].empty()) {
      throw line.Error(named + "needs --values V1,V2,... or --range FROM:TO:COUNT after it");
    }
    if (lists[i].size() > 1) {
      throw line.Error(named + "give one of --values or --range, not " + lists[i][0].name +
                       " and " + lists[i][1].name);
    }
    const nfrc::GivenOption& list = lists[i][0];
    axes.push_back({paths[i], list.name == "--range"
                                  ? line.ParseRange(list.name, list.value,
                                                    static_cast<int>(nfrc::kMaxSweepRuns))
                                  : line.ParseNumberList(list.name, list.value)});
    runs *= static_cast<double>(axes.back().values.size());
  }
  if (runs > static_cast<double>(nfrc::kMaxSweepRuns)) {
    throw line.Error("--parameter: the grid has " + std::to_string(static_cast<long long>(runs)) +
                     " runs, more than " + std::to_string(nfrc::kMaxSweepRuns));
  }
  return axes;
}

int Sweep(const std::vector<std::string>& args, const nfrc::StopSignal& stop) {
  using nfrc::OptionSpec;
  const nfrc::CommandLine line("sweep", args,
                               {OptionSpec::Value("--out"), OptionSpec::Repeated("--parameter"),
                                OptionSpec::Repeated("--values"), OptionSpec::Repeated("--range"),
                                OptionSpec::Value("--jobs")});
  const CaseAndOut io = RequireCaseAndOut(line);
  // Two cores here; a few hundred threads is more than any machine this runs on has.
  const int jobs = line.Int("--jobs", 1, 256).value_or(1);
  // A manifest without --parameter: one run per variant, of its base case.
  std::optional<nfrc::CaseManifest> manifest;
  const bool axes_given =
      std::any_of(line.options().begin(), line.options().end(), [](const auto& option) {
        return option.name == "--parameter" || option.name == "--values" ||
               option.name == "--range";
      });
  if (!axes_given && io.case_path.find('#') == std::string::npos) {
    const nlohmann::json document = nfrc::ReadJsonFile(io.case_path);
    if (nfrc::IsManifest(document)) manifest = nfrc::ParseManifest(document, io.case_path);
  }
  const nfrc::CaseFile file = nfrc::ReadCaseFile(manifest ? manifest->base_path : io.case_path);
  std::optional<nfrc::SweepPlan> plan;
  if (manifest) {
    plan.emplace(std::move(*manifest));
  } else {
    nfrc::SweepGrid grid;
    for (const SweepAxisArgs& axis : SweepAxes(line)) grid.emplace_back(axis.path, axis.values);
    nfrc::CheckGridPaths(file, grid);
    plan.emplace(std::move(grid));
  }
  if (nfrc::LaunchedRanks() > 1) {
    if (jobs != 1) {
      throw line.Error(
          "--jobs: under mpirun each rank traces one branch at a time (start more "
          "ranks instead)");
    }
    const nfrc::RankSession session;
    stop.set_immediate(false);
    const std::vector<nfrc::SweepRun> runs =
        nfrc::RunSweepOnRanks(session, file, *plan, io.out_dir, &std::cerr, &stop.flag());
    if (session.rank() != 0) return kExitOk;  // rank 0 reports for all
    return ReportSweep(runs, io.out_dir, stop);
  }
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  nfrc::SweepOptions options;
  options.jobs = jobs;
  options.progress = &std::cerr;
  options.stop = &stop.flag();
  stop.set_immediate(false);
  return ReportSweep(nfrc::RunSweep(file, *plan, io.out_dir, options).runs, io.out_dir, stop);
}

// Runs tools/<script> with the arguments under the system Python; its exit status.
int RunPythonScript(const std::string& script, const std::vector<std::string>& args) {
  const std::string path = std::string(NFRC_TOOLS_DIR) + "/" + script;
  // Debian's python3-matplotlib lives with the system interpreter.
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string command = python + " '" + path + "'";
  for (const std::string& arg : args) {
    // Single quotes protect everything but a single quote, which closes, escapes and reopens.
    std::string quoted;
    for (char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    command += " '" + quoted + "'";
  }
  return std::system(command.c_str());
}

int Plot(const std::vector<std::string>& args) {
  using nfrc::OptionSpec;
  const nfrc::CommandLine line(
      "plot", args,
      {OptionSpec::Value("--measure"), OptionSpec::Flag("--logy"), OptionSpec::Value("--output"),
       OptionSpec::Value("--labels"), OptionSpec::Value("--xlim"), OptionSpec::Value("--title")});
  if (line.positionals().empty()) throw line.Error("needs an output directory");
  std::vector<std::string> script_args = line.positionals();
  if (const auto measure = line.Choice("--measure", {"max_abs", "min", "max", "h1", "energy"})) {
    script_args.insert(script_args.end(), {"--measure", *measure});
  }
  if (line.Flag("--logy")) script_args.push_back("--logy");
  for (const char* option : {"--output", "--labels", "--title"}) {
    if (const auto value = line.Value(option))
      script_args.insert(script_args.end(), {option, *value});
  }
  if (const auto xlim = line.Value("--xlim")) {
    const std::vector<double> range = line.NumberList("--xlim");
    if (range.size() != 2 || !(range[0] < range[1])) throw line.Error("--xlim: expected MIN,MAX");
    script_args.insert(script_args.end(), {"--xlim", *xlim});
  }
  for (const std::string& dir : line.positionals()) {
    if (!std::filesystem::is_regular_file(dir + "/branch.json")) {
      throw nfrc::InputError(dir + "/branch.json: no branch to plot (run nfrc run first)");
    }
  }
  return RunPythonScript("plot_frc.py", script_args) == 0 ? kExitOk : kExitIoError;
}

int Validate(const std::vector<std::string>& args, const nfrc::StopSignal& stop) {
  using nfrc::NumberDomain;
  using nfrc::OptionSpec;
  const nfrc::CommandLine line(
      "validate", args,
      {OptionSpec::Value("--out"), OptionSpec::Value("--omega"), OptionSpec::Value("--start"),
       OptionSpec::Flag("--no-chirp"), OptionSpec::Flag("--no-plot")});
  const CaseAndOut io = RequireCaseAndOut(line);
  const std::vector<double> omegas = line.NumberList("--omega", NumberDomain::kPositive);
  const std::optional<std::string> start = line.Choice("--start", {"hbm", "rest"});

  const nfrc::CaseFile file = nfrc::ReadCaseFile(io.case_path);
  const nfrc::Case& the_case = file.the_case;
  nfrc::ValidationSettings settings = the_case.validation;
  if (!omegas.empty()) settings.omegas = omegas;
  if (start) {
    settings.start = *start == "rest" ? nfrc::ValidationSettings::Start::kRest
                                      : nfrc::ValidationSettings::Start::kHbm;
  }
  if (line.Flag("--no-chirp")) settings.chirp.enabled = false;
  if (settings.omegas.empty() && !settings.chirp.enabled) {
    throw nfrc::InputError(
        "--omega: no frequencies to validate (give --omega or the case's "
        "validation.omega)");
  }
  const nfrc::OutputDirectoryLock lock = LockOutput(io.out_dir);
  stop.set_immediate(false);
  const nfrc::ValidationResult result = Naming(io.case_path, {}, [&] {
    return nfrc::RunValidation(the_case, settings, io.out_dir, &std::cerr, &std::cout, &stop.flag(),
                               file.source);
  });
  std::cerr << "nfrc: wrote " << io.out_dir << "/validation.json\n";
  int status = result.complete && !stop.requested() ? kExitOk : kExitRunIncomplete;
  if (!line.Flag("--no-plot") && RunPythonScript("plot_validation.py", {io.out_dir}) != 0) {
    std::cerr << "nfrc validate: plotting failed\n";
    if (status == kExitOk) status = kExitIoError;
  }
  return status;
}

int Dispatch(const std::string& command, const std::vector<std::string>& args) {
  if (command == "plot") return Plot(args);
  if (command != "run" && command != "refine" && command != "validate" && command != "fold-curve" &&
      command != "sweep") {
    std::cerr << "nfrc: unknown command \"" << command << "\"\n" << kUsage;
    return kExitUsage;
  }
  // SIGINT, SIGTERM and SIGHUP stop a run after its current point (or Newton iteration); what
  // was found stays on disk with a final summary. A second SIGINT quits at once, and so does
  // any stop signal while a command still reads its case (nothing is computed yet).
  const nfrc::StopSignal stop;
  stop.set_immediate(true);
  if (command == "run") return Run(args, stop);
  if (command == "refine") return Refine(args, stop);
  if (command == "fold-curve") return FoldCurve(args, stop);
  if (command == "sweep") return Sweep(args, stop);
  return Validate(args, stop);
}

}  // namespace

int main(int argc, char** argv) {
  nfrc::KeepFreedMemoryMapped();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? kExitUsage : kExitOk;
  }
  if (args[0] == "--version") {
    std::cout << "nfrc " << nfrc::kNfrcVersion << "\n";
    return kExitOk;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  // The three tiers: bad input (1, 2), a failed write (4); numerical failures are statuses
  // (3) returned above; anything else is a broken invariant (5), said as such.
  try {
    return Dispatch(command, args);
  } catch (const nfrc::UsageError& error) {
    std::cerr << error.what() << "\n" << kUsage;
    return kExitUsage;
  } catch (const nfrc::InputError& error) {
    std::cerr << "nfrc: error: " << error.what() << "\n";
    return kExitInputError;
  } catch (const nfrc::OutputDirectoryInUse& error) {
    // Nothing failed on disk: the command named a directory another run holds.
    std::cerr << "nfrc: error: " << error.what() << "\n";
    return kExitInputError;
  } catch (const nfrc::OutputError& error) {
    std::cerr << "nfrc: I/O error: " << error.what() << "\n";
    return kExitIoError;
  } catch (const std::bad_alloc&) {
    std::cerr << "nfrc: internal error: out of memory (the case passed nfrc's size estimate; "
                 "please report it with the case)\n";
    return kExitInternalError;
  } catch (const std::exception& error) {
    std::cerr << "nfrc: internal error: " << error.what() << "\n";
    return kExitInternalError;
  }
}
