#include "tools/case_file.h"

#include <filesystem>
#include <sstream>

#include "tools/case_manifest.h"
#include "tools/input_fields.h"
#include "tools/json_input.h"
#include "tools/law_reader.h"
#include "tools/model_reader.h"
#include "tools/reduction_reader.h"
#include "tools/validation_reader.h"

namespace nfrc {
namespace {

HarmonicSet ReadHarmonics(const nlohmann::json& spec, int num_dofs) {
  InputFields fields(spec, "harmonics");
  const int max_harmonic = fields.RequiredInt("max");
  const bool odd_only = fields.OptionalBool("odd_only", false);
  const int samples = fields.OptionalInt("samples", 0);
  fields.Finish();
  if (max_harmonic < 1)
    fields.Fail("max", "must be at least 1, got " + std::to_string(max_harmonic));
  // Refuse what cannot fit before the harmonic set and its transforms are allocated (and
  // before 2H + 1 could overflow an int).
  ProblemDimensions dimensions;
  dimensions.num_dofs = num_dofs;
  dimensions.max_harmonic = max_harmonic;
  dimensions.odd_only = odd_only;
  dimensions.samples = samples;
  CheckProblemSize(dimensions);
  const long long least = 2LL * max_harmonic + 1;
  if (fields.Has("samples") && samples < least) {
    fields.Fail("samples", "must be at least 2*max+1 = " + std::to_string(least) + ", got " +
                               std::to_string(samples));
  }
  try {
    return HarmonicSet(max_harmonic, odd_only, samples);
  } catch (const std::invalid_argument& error) {
    throw InputError(std::string("harmonics: ") + error.what());
  }
}

ContinuationOptions ReadContinuation(const nlohmann::json& spec, Case& result) {
  InputFields fields(spec, "continuation");
  ContinuationOptions options;
  options.lambda_start = fields.RequiredNumber("omega_start");
  options.lambda_end = fields.RequiredNumber("omega_end");
  if (options.lambda_start <= 0.0) fields.Fail("omega_start", "must be positive");
  if (options.lambda_end <= 0.0) fields.Fail("omega_end", "must be positive");
  if (options.lambda_end == options.lambda_start) {
    fields.Fail("omega_end", "must differ from omega_start");
  }
  options.lambda_name = "omega";
  const std::string method = fields.OptionalString("method", "arclength");
  if (method == "lemke_stepping") {
    result.method = Method::kLemkeStepping;
    // The arclength settings do not apply; Finish() rejects them.
    result.stepping.points = fields.OptionalInt("points", result.stepping.points);
    if (result.stepping.points < 2) fields.Fail("points", "must be at least 2");
    result.stepping.track_contact =
        fields.OptionalBool("track_contact", result.stepping.track_contact);
    fields.Finish();
    return options;
  }
  if (method != "arclength") {
    fields.Fail("method", "must be \"arclength\" or \"lemke_stepping\", got \"" + method + "\"");
  }
  options.initial_step = fields.OptionalNumber("step", options.initial_step);
  options.min_step = fields.OptionalNumber("min_step", options.min_step);
  options.max_step = fields.OptionalNumber("max_step", options.max_step);
  options.max_points = fields.OptionalInt("max_points", options.max_points);
  options.max_newton_iterations =
      fields.OptionalInt("max_newton_iterations", options.max_newton_iterations);
  options.target_newton_iterations =
      fields.OptionalInt("target_newton_iterations", options.target_newton_iterations);
  options.newton_tolerance = fields.OptionalNumber("newton_tolerance", options.newton_tolerance);
  options.residual_tolerance =
      fields.OptionalNumber("residual_tolerance", options.residual_tolerance);
  options.max_tangent_angle = fields.OptionalNumber("max_tangent_angle", options.max_tangent_angle);
  options.plot_tolerance = fields.OptionalNumber("plot_tolerance", options.plot_tolerance);
  options.max_plot_turn_angle =
      fields.OptionalNumber("max_plot_turn_angle", options.max_plot_turn_angle);
  const std::string plot_measure = fields.OptionalString("plot_measure", "max_abs");
  if (plot_measure == "energy") {
    result.plot_measure = PlotMeasure::kEnergy;
  } else if (plot_measure != "max_abs") {
    fields.Fail("plot_measure", "must be \"max_abs\" or \"energy\", got \"" + plot_measure + "\"");
  }
  options.detect_folds = fields.OptionalBool("detect_folds", options.detect_folds);
  options.fold_tolerance = fields.OptionalNumber("fold_tolerance", options.fold_tolerance);
  options.line_search = fields.OptionalBool("line_search", options.line_search);
  result.start.homotopy = fields.OptionalBool("start_homotopy", result.start.homotopy);
  result.start.homotopy_factor =
      fields.OptionalNumber("start_homotopy_factor", result.start.homotopy_factor);
  result.start.homotopy_rungs =
      fields.OptionalInt("start_homotopy_rungs", result.start.homotopy_rungs);
  fields.Finish();
  ValidateContinuation(options);
  return options;
}

// The "stability" object; the ranges are StabilityOptions::Validate's (run by Case::Validate).
StabilityOptions ReadStability(const nlohmann::json& spec) {
  InputFields fields(spec, "stability");
  StabilityOptions o;
  o.enabled = fields.OptionalBool("enabled", o.enabled);
  o.unstable_tolerance = fields.OptionalNumber("unstable_tolerance", o.unstable_tolerance);
  o.bifurcation_tolerance = fields.OptionalNumber("bifurcation_tolerance", o.bifurcation_tolerance);
  o.max_bifurcation_iterations =
      fields.OptionalInt("max_bifurcation_iterations", o.max_bifurcation_iterations);
  o.jump_tolerance = fields.OptionalNumber("jump_tolerance", o.jump_tolerance);
  o.hill_modes = fields.OptionalInt("hill_modes", o.hill_modes);
  fields.Finish();
  return o;
}

}  // namespace

Case ParseCase(const nlohmann::json& source, const std::string& base_dir) {
  InputFields fields(source, "case");
  Case result;
  result.title = fields.OptionalString("title", "");
  std::optional<ReductionRequest> reduction;
  result.model = BuildModel(fields.RequiredObject("model"), base_dir, &reduction);
  const LinearModel& model = result.model.model;

  result.harmonics = ReadHarmonics(fields.RequiredObject("harmonics"), model.num_dofs());
  for (const ForcingTerm& term : result.model.forcing) {
    const auto& list = result.harmonics.harmonics();
    if (std::find(list.begin(), list.end(), term.harmonic) == list.end()) {
      throw InputError("model.forcing: harmonic " + std::to_string(term.harmonic) +
                       " is not in the harmonic set");
    }
  }

  if (fields.Has("nonlinearities")) {
    const nlohmann::json& list = fields.RequiredValue("nonlinearities");
    if (!list.is_array()) fields.Fail("nonlinearities", "expected a list");
    for (size_t i = 0; i < list.size(); ++i) {
      result.laws.push_back(ReadLaw(list[i], "nonlinearities[" + std::to_string(i) + "]", model));
    }
  }

  result.continuation = ReadContinuation(fields.RequiredObject("continuation"), result);

  InputFields output(fields.RequiredObject("output"), "output");
  const nlohmann::json& dofs = output.RequiredValue("dofs");
  if (!dofs.is_array() || dofs.empty()) output.Fail("dofs", "expected a non-empty list of DOFs");
  for (size_t i = 0; i < dofs.size(); ++i) {
    result.output_dofs.push_back(
        ResolveDof(dofs[i], model, "output.dofs[" + std::to_string(i) + "]"));
    result.output_names.push_back(dofs[i].is_string() ? dofs[i].get<std::string>()
                                                      : std::to_string(dofs[i].get<int>()));
  }
  result.signals_at = output.OptionalNumberList("signals_at");
  const ContinuationOptions& range = result.continuation;
  for (double omega : result.signals_at) {
    if (!(omega > 0.0)) output.Fail("signals_at", "frequencies must be positive");
    // No point of the branch crosses a frequency outside the traced range: it would be
    // dropped without a word.
    if (omega < range.LowerBound() || omega > range.UpperBound()) {
      std::ostringstream text;
      text << omega << " lies outside the traced range [" << range.LowerBound() << ", "
           << range.UpperBound() << "] (continuation.omega_start, omega_end)";
      output.Fail("signals_at", text.str());
    }
  }
  output.Finish();
  if (fields.Has("validation")) {
    result.validation = ReadValidationSettings(fields.RequiredObject("validation"));
  }
  if (fields.Has("stability")) result.stability = ReadStability(fields.RequiredObject("stability"));
  fields.Finish();
  // Last: the boundary DOFs (laws, forcing, outputs) are known and every field was checked
  // against the full model, before the costly part.
  if (reduction) ApplyReduction(result, *reduction);
  result.Validate();
  return result;
}

CaseFile ReadCaseFile(const std::string& path) {
  CaseFile file;
  // FILE#MEMBER names a member of a manifest (a file whose own name has a # is read whole).
  const size_t hash = path.rfind('#');
  const bool member = hash != std::string::npos && !std::filesystem::exists(path);
  const std::string file_path = member ? path.substr(0, hash) : path;
  // Depth, duplicate keys, number range, file type and size are checked while reading.
  nlohmann::json document = ReadJsonFile(file_path);
  if (IsManifest(document)) {
    const CaseManifest manifest = ParseManifest(document, file_path);
    if (!member) {
      throw InputError(file_path + ": manifest: a manifest of " +
                       std::to_string(manifest.variants.size()) + " cases (" +
                       MemberNames(manifest) + "): name one as " + file_path +
                       "#NAME, or run them all with nfrc sweep");
    }
    file.source = VariantSource(manifest, FindVariant(manifest, path.substr(hash + 1)));
    file.base_dir = std::filesystem::path(manifest.base_path).parent_path().string();
  } else {
    if (member) {
      throw InputError(file_path + ": manifest: absent, so \"#" + path.substr(hash + 1) +
                       "\" names nothing (this is a case file, not a manifest)");
    }
    file.source = std::move(document);
    file.base_dir = std::filesystem::absolute(path).parent_path().string();
  }
  try {
    file.the_case = ParseCase(file.source, file.base_dir);
    file.the_case.path = path;
  } catch (const InputError& error) {
    throw InputError(path + ": " + error.what());
  }
  return file;
}

Case LoadCase(const std::string& path) { return ReadCaseFile(path).the_case; }

}  // namespace nfrc
