// libFuzzer target of the case reader: bytes -> ParseJsonText -> the case parser, the field
// paths and the whole of a manifest (its base a fixed case), and a sweep's record (sweep.json,
// against the plan its own parameters make). The only
// exception a case file may raise is nfrc::InputError; any other exception, a crash, a leak,
// a timeout or a sanitizer report is a finding. Built with -DNFRC_FUZZ=ON (tools/fuzz/fuzz.cmake),
// run by tools/fuzz/run_fuzz.sh.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "tools/case_file.h"
#include "tools/case_manifest.h"
#include "tools/json_input.h"
#include "tools/sweep.h"

namespace {

// The case parser under test: the one call to adapt when it is renamed or moves.
void ParseTheCase(const nlohmann::json& source, const std::string& base_dir) {
  nfrc::ParseCase(source, base_dir);
}

// The field paths of a manifest's variants ("set": {path: value}) applied to the document
// itself: the path parser and ApplyFieldChange (ParseManifest would read its base file).
void ApplyManifestChanges(const nlohmann::json& source) {
  if (!nfrc::IsManifest(source) || !source.contains("variants")) return;
  const nlohmann::json& variants = source.at("variants");
  if (!variants.is_array()) return;
  for (const nlohmann::json& variant : variants) {
    if (!variant.is_object() || !variant.contains("set") || !variant.at("set").is_object())
      continue;
    nlohmann::json changed = source;
    for (const auto& [path, value] : variant.at("set").items()) {
      nfrc::ApplyFieldChange(&changed, {path, value}, "fuzz.json");
      nfrc::FieldAt(changed, path);
    }
  }
}

// Keys of "model" whose string value is a Matrix Market path (tools/model_reader.cc).
constexpr const char* kMatrixKeys[] = {"M", "K", "C"};

// Directory relative matrix paths resolve against: empty, so a fuzzed case finds no file.
// run_fuzz.sh passes one in NFRC_FUZZ_BASE_DIR; otherwise one is made and removed at exit.
class BaseDir {
 public:
  BaseDir() {
    if (const char* given = std::getenv("NFRC_FUZZ_BASE_DIR")) {
      path_ = given;
      return;
    }
    std::string pattern = (std::filesystem::temp_directory_path() / "nfrc_fuzz_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) std::abort();
    path_ = pattern;
    owned_ = true;
  }
  BaseDir(const BaseDir&) = delete;
  BaseDir& operator=(const BaseDir&) = delete;
  ~BaseDir() {
    std::error_code ignored;
    if (owned_) std::filesystem::remove(path_, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  bool owned_ = false;
};

// The case's "model" object, or nullptr: what the two filters below look at.
const nlohmann::json* ModelOf(const nlohmann::json& source) {
  if (!source.is_object() || !source.contains("model")) return nullptr;
  const nlohmann::json& model = source.at("model");
  return model.is_object() ? &model : nullptr;
}

// True if a matrix path of the model leaves the base directory (absolute, or with a ".."
// component): such inputs are skipped, so that fuzzing never reads a file of the machine.
bool NamesFileOutsideBaseDir(const nlohmann::json& model) {
  for (const char* key : kMatrixKeys) {
    if (!model.contains(key) || !model.at(key).is_string()) continue;
    const std::filesystem::path path(model.at(key).get<std::string>());
    if (path.is_absolute()) return true;
    for (const auto& part : path) {
      if (part == "..") return true;
    }
  }
  return false;
}

// A generated model's size is linear algebra the input asks for, not parsing: modal damping
// takes every mode (cubic) and a reduction solves an eigenproblem on the whole model. Built
// for fuzzing (-O1, ASan, UBSan, Eigen's assertions), the two rods of tools/fuzz/regressions/
// (1 000 elements with modal damping, 300 reduced onto every mode) each outlast the fuzzer's
// 10 s limit when this cap is raised, so valid work would be reported as a hang; every
// run_fuzz.sh run tries them first. Larger rods are skipped; the readers' own size limits
// (kMaxModalDofs, kMaxReductionModes, CheckProblemSize) are tested in tests/tools. Inline
// matrices need no cap: -max_len bounds them to about 45 x 45.
constexpr double kMaxFuzzedRodElements = 100;

bool AsksForALargeModel(const nlohmann::json& model) {
  if (!model.contains("elements")) return false;
  const nlohmann::json& elements = model.at("elements");
  return elements.is_number() && elements.get<double>() > kMaxFuzzedRodElements;
}

// The base a fuzzed manifest's members change: the Duffing case of cases/duffing_h1.json.
constexpr const char* kManifestBase = R"({"model": {"type": "matrices", "M": [[1]],
  "C": [[0.05]], "K": [[1]], "forcing": [{"dof": 0, "cos": 0.18}]},
  "nonlinearities": [{"type": "cubic_spring", "dof": 0, "coefficient": 0.1}],
  "harmonics": {"max": 1, "odd_only": true, "samples": 16},
  "continuation": {"omega_start": 0.5, "omega_end": 1.6, "step": 0.01},
  "output": {"dofs": [0]}})";

// The manifest as `nfrc sweep MANIFEST` reads it, its base the fixed case above, and its first
// member built and read as a case.
void ParseTheManifest(const nlohmann::json& source, const std::string& base_dir) {
  if (!nfrc::IsManifest(source)) return;
  const nfrc::CaseManifest manifest =
      nfrc::ParseManifest(source, base_dir + "/fuzz.json",
                          [](const std::string&) { return nlohmann::json::parse(kManifestBase); });
  if (manifest.variants.empty()) return;
  const nlohmann::json member = nfrc::VariantSource(manifest, 0);
  const nlohmann::json* model = ModelOf(member);
  if (model != nullptr && (NamesFileOutsideBaseDir(*model) || AsksForALargeModel(*model))) return;
  ParseTheCase(member, base_dir);
}

// A sweep's record against the plan of its own "parameters" (when they make one): what a resume
// reads of DIR/sweep.json, every field of every run.
void ParseTheSweepRecord(const nlohmann::json& source) {
  if (!source.is_object() || !source.contains("runs") || !source.contains("parameters")) return;
  const nlohmann::json& axes = source.at("parameters");
  if (!axes.is_array()) return;
  nfrc::SweepGrid grid;
  for (const nlohmann::json& axis : axes) {
    if (!axis.is_object() || !axis.contains("path") || !axis.at("path").is_string() ||
        !axis.contains("values") || !axis.at("values").is_array()) {
      return;
    }
    std::vector<double> values;
    for (const nlohmann::json& value : axis.at("values")) {
      if (!value.is_number()) return;
      values.push_back(value.get<double>());
    }
    grid.emplace_back(axis.at("path").get<std::string>(), std::move(values));
  }
  nfrc::CheckGrid(grid);  // a shape the plan can hold (InputError otherwise)
  nfrc::ParseSweepRecord(source, nfrc::SweepPlan(grid), "fuzz.json");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const BaseDir base_dir;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const nlohmann::json source = nfrc::ParseJsonText(text, "fuzz.json");
    const nlohmann::json* model = ModelOf(source);
    if (model != nullptr && (NamesFileOutsideBaseDir(*model) || AsksForALargeModel(*model))) {
      return 0;
    }
    ApplyManifestChanges(source);
    try {
      ParseTheManifest(source, base_dir.path());
    } catch (const nfrc::InputError&) {
      // A bad manifest is named; the same bytes as a case and a record are tried below.
    }
    try {
      ParseTheSweepRecord(source);
    } catch (const nfrc::InputError&) {
    }
    ParseTheCase(source, base_dir.path());
  } catch (const nfrc::InputError&) {
    // Rejected input with a message: the expected outcome for most inputs.
  }
  return 0;
}
