// The nfrc command line program: `nfrc run CASE.json --out DIR`, `nfrc refine ...`,
// `nfrc validate ...` and `nfrc plot DIR`.
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "tools/case_file.h"
#include "tools/refinement_writer.h"
#include "tools/run_case.h"
#include "tools/validate.h"
#include "tools/version.h"

namespace {

// Exit codes: documented in the README.
constexpr int kExitOk = 0;
constexpr int kExitInputError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitRunIncomplete = 3;
constexpr int kExitIoError = 4;

std::atomic<bool> g_stop{false};

void OnSignal(int) { g_stop.store(true); }

constexpr const char* kUsage =
    "usage:\n"
    "  nfrc run CASE.json --out DIR   trace the frequency response of a case\n"
    "  nfrc refine CASE.json --omega W --out DIR [--epsilon0 E] [--factor F] [--steps N]\n"
    "              [--epsilons E1,E2,...]\n"
    "                                 DLFT epsilon refinement at W (default: from the\n"
    "                                 case's epsilon, factor 2, 15 steps), warm-started\n"
    "  nfrc validate CASE.json --out DIR [--omega W1,W2,...] [--start hbm|rest] [--no-chirp]\n"
    "              [--no-plot]\n"
    "                                 integrate the model in time to steady state at each W\n"
    "                                 and compare with the HBM branch (DIR/validation.json)\n"
    "  nfrc plot DIR                  draw DIR/branch.json to DIR/frc.png and DIR/frc.svg\n"
    "  nfrc --version\n";

int Run(const std::vector<std::string>& args) {
  std::string case_path;
  std::string out_dir;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && i + 1 < args.size()) {
      out_dir = args[++i];
    } else if (!args[i].empty() && args[i][0] == '-') {
      std::cerr << "nfrc run: unknown option " << args[i] << "\n" << kUsage;
      return kExitUsage;
    } else if (case_path.empty()) {
      case_path = args[i];
    } else {
      std::cerr << "nfrc run: more than one case file given\n" << kUsage;
      return kExitUsage;
    }
  }
  if (case_path.empty() || out_dir.empty()) {
    std::cerr << "nfrc run: needs a case file and --out DIR\n" << kUsage;
    return kExitUsage;
  }
  const nfrc::CaseFile file = nfrc::ReadCaseFile(case_path);
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  const nfrc::Branch branch =
      nfrc::RunCase(file.the_case, out_dir, &std::cerr, &g_stop, file.source);
  const auto& summary = branch.summary;
  std::cerr << "nfrc: " << nfrc::ToString(summary.reason) << ": " << summary.message << "\n"
            << "nfrc: " << summary.num_points << " points, " << summary.num_folds
            << " folds, wrote " << out_dir << "/branch.json and branch.csv\n";
  const bool complete = summary.success() || summary.reason == nfrc::TerminationReason::kMaxPoints;
  return complete ? kExitOk : kExitRunIncomplete;
}

// Parses a number of option `name`; throws InputError naming it.
double NumberOption(const std::string& name, const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw nfrc::InputError(name + ": not a number: \"" + text + "\"");
}

int Refine(const std::vector<std::string>& args) {
  std::string case_path;
  std::string out_dir;
  std::optional<double> omega;
  std::optional<double> epsilon0;
  double factor = 2.0;
  int steps = 15;
  std::vector<double> list;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--out" && has_value) {
      out_dir = args[++i];
    } else if (arg == "--omega" && has_value) {
      omega = NumberOption("--omega", args[++i]);
    } else if (arg == "--epsilon0" && has_value) {
      epsilon0 = NumberOption("--epsilon0", args[++i]);
    } else if (arg == "--factor" && has_value) {
      factor = NumberOption("--factor", args[++i]);
    } else if (arg == "--steps" && has_value) {
      steps = static_cast<int>(NumberOption("--steps", args[++i]));
    } else if (arg == "--epsilons" && has_value) {
      std::stringstream items(args[++i]);
      for (std::string item; std::getline(items, item, ',');) {
        list.push_back(NumberOption("--epsilons", item));
      }
    } else if (!arg.empty() && arg[0] == '-') {
      std::cerr << "nfrc refine: unknown option or missing value: " << arg << "\n" << kUsage;
      return kExitUsage;
    } else if (case_path.empty()) {
      case_path = arg;
    } else {
      std::cerr << "nfrc refine: more than one case file given\n" << kUsage;
      return kExitUsage;
    }
  }
  if (case_path.empty() || out_dir.empty() || !omega) {
    std::cerr << "nfrc refine: needs a case file, --omega and --out DIR\n" << kUsage;
    return kExitUsage;
  }
  const nfrc::CaseFile file = nfrc::ReadCaseFile(case_path);
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
    if (!epsilon0) {
      std::cerr << "nfrc refine: give --epsilon0 or --epsilons (the case sets no epsilon)\n";
      return kExitUsage;
    }
    options.epsilons = nfrc::GeometricEpsilons(*epsilon0, factor, steps);
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  const nfrc::RefinementResult result =
      nfrc::RunRefinement(the_case, options, out_dir, &std::cerr, &g_stop, file.source);
  const auto& done = result.steps;
  const bool complete = !result.interrupted && done.size() == options.epsilons.size() &&
                        (done.empty() || done.back().converged);
  if (!result.message.empty()) std::cerr << "nfrc: " << result.message << "\n";
  std::cerr << "nfrc: " << done.size() << " of " << options.epsilons.size()
            << " refinement steps, wrote " << out_dir << "/refinement.json\n";
  return complete ? kExitOk : kExitRunIncomplete;
}

// Runs tools/<script> with the arguments under the system Python; its exit status.
int RunPythonScript(const std::string& script, const std::vector<std::string>& args) {
  const std::string path = std::string(NFRC_TOOLS_DIR) + "/" + script;
  // Debian's python3-matplotlib lives with the system interpreter.
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string command = python + " '" + path + "'";
  for (const std::string& arg : args) command += " '" + arg + "'";
  return std::system(command.c_str());
}

int Plot(const std::vector<std::string>& args) {
  if (args.empty()) {
    std::cerr << "nfrc plot: needs an output directory\n" << kUsage;
    return kExitUsage;
  }
  return RunPythonScript("plot_frc.py", args) == 0 ? kExitOk : kExitIoError;
}

int Validate(const std::vector<std::string>& args) {
  std::string case_path;
  std::string out_dir;
  std::vector<double> omegas;
  std::string start;
  bool chirp = true;
  bool plot = true;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--out" && has_value) {
      out_dir = args[++i];
    } else if (arg == "--omega" && has_value) {
      std::stringstream items(args[++i]);
      for (std::string item; std::getline(items, item, ',');) {
        omegas.push_back(NumberOption("--omega", item));
        if (!(omegas.back() > 0.0)) throw nfrc::InputError("--omega: frequencies must be positive");
      }
    } else if (arg == "--start" && has_value) {
      start = args[++i];
    } else if (arg == "--no-chirp") {
      chirp = false;
    } else if (arg == "--no-plot") {
      plot = false;
    } else if (!arg.empty() && arg[0] == '-') {
      std::cerr << "nfrc validate: unknown option or missing value: " << arg << "\n" << kUsage;
      return kExitUsage;
    } else if (case_path.empty()) {
      case_path = arg;
    } else {
      std::cerr << "nfrc validate: more than one case file given\n" << kUsage;
      return kExitUsage;
    }
  }
  if (case_path.empty() || out_dir.empty()) {
    std::cerr << "nfrc validate: needs a case file and --out DIR\n" << kUsage;
    return kExitUsage;
  }
  const nfrc::CaseFile file = nfrc::ReadCaseFile(case_path);
  const nfrc::Case& the_case = file.the_case;
  nfrc::ValidationSettings settings = the_case.validation;
  if (!omegas.empty()) settings.omegas = omegas;
  if (start == "rest") {
    settings.start = nfrc::ValidationSettings::Start::kRest;
  } else if (start == "hbm") {
    settings.start = nfrc::ValidationSettings::Start::kHbm;
  } else if (!start.empty()) {
    throw nfrc::InputError("--start: expected hbm or rest, got \"" + start + "\"");
  }
  if (!chirp) settings.chirp.enabled = false;
  if (settings.omegas.empty() && !settings.chirp.enabled) {
    throw nfrc::InputError(
        "--omega: no frequencies to validate (give --omega or the case's "
        "validation.omega)");
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  const nfrc::ValidationResult result =
      nfrc::RunValidation(the_case, settings, out_dir, &std::cerr, &std::cout, &g_stop, file.source);
  std::cerr << "nfrc: wrote " << out_dir << "/validation.json\n";
  int status = result.complete && !g_stop.load() ? kExitOk : kExitRunIncomplete;
  if (plot && RunPythonScript("plot_validation.py", {out_dir}) != 0) {
    std::cerr << "nfrc validate: plotting failed\n";
    if (status == kExitOk) status = kExitIoError;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
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
  try {
    if (command == "run") return Run(args);
    if (command == "refine") return Refine(args);
    if (command == "plot") return Plot(args);
    if (command == "validate") return Validate(args);
    std::cerr << "nfrc: unknown command \"" << command << "\"\n" << kUsage;
    return kExitUsage;
  } catch (const nfrc::InputError& error) {
    std::cerr << "nfrc: error: " << error.what() << "\n";
    return kExitInputError;
  } catch (const std::invalid_argument& error) {
    std::cerr << "nfrc: error: " << error.what() << "\n";
    return kExitInputError;
  } catch (const std::exception& error) {
    std::cerr << "nfrc: error: " << error.what() << "\n";
    return kExitIoError;
  }
}
