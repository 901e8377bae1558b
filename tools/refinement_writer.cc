#include "tools/refinement_writer.h"

#include <optional>

#include "tools/output_files.h"

namespace nfrc {
namespace {

// A field of a signals record, null when absent (min_gap, min_force: contact laws only).
nlohmann::json Field(const nlohmann::json& record, const char* name) {
  return record.contains(name) ? record[name] : nlohmann::json();
}

nlohmann::json DistanceToJson(const LcpDistance& distance) {
  return {{"force_raw", distance.force_raw},
          {"force", distance.force},
          {"gap", distance.gap},
          {"displacement", distance.displacement}};
}

}  // namespace

RefinementWriter::RefinementWriter(std::string dir, const Case& the_case, double omega,
                                   nlohmann::json source)
    : dir_(std::move(dir)),
      case_(the_case),
      branch_(dir_, the_case, std::move(source)),
      document_({{"omega", omega}, {"status", "running"}, {"steps", nlohmann::json::array()}}) {
  Write();
}

void RefinementWriter::Write() { WriteJsonAtomically(dir_ + "/refinement.json", document_); }

void RefinementWriter::OnBranchEnd(const ContinuationSummary& summary) { branch_.Finish(summary); }

void RefinementWriter::OnLcpReference(const LcpReference& reference) {
  // lcp/branch.json describes the case Lemke solved.
  const std::optional<Case> limit = LcpLimitCase(case_);
  BranchWriter writer(dir_ + "/lcp", limit ? *limit : case_, nullptr);
  writer.OnStart(reference.num_unknowns);
  writer.OnSignals(reference.signals);
  const nlohmann::json record = writer.document()["signals"].back();
  ContinuationSummary summary;
  summary.reason = TerminationReason::kReachedLambdaBound;
  summary.message = "LCP-HBM at one frequency: Lemke " + ToString(reference.status);
  writer.Finish(summary);
  document_["lcp"] = {{"status", ToString(reference.status)},
                      {"pivots", reference.pivots},
                      {"complementarity_gap", reference.complementarity_gap},
                      {"min_gap", reference.min_gap},
                      {"max_abs", record["max_abs"]},
                      {"h1", record["h1"]},
                      {"min_force", Field(record, "min_force")},
                      {"signals_file", "lcp/" + record["file"].get<std::string>()},
                      {"samples_file", "lcp/" + record.value("samples_file", std::string())}};
  Write();
}

void RefinementWriter::OnStep(const RefinementStep& step) {
  branch_.OnSignals(step.signals);
  const nlohmann::json& record = branch_.document()["signals"].back();
  nlohmann::json entry = {{"epsilon", step.epsilon},
                          {"converged", step.converged},
                          {"newton_iterations", step.newton_iterations},
                          {"residual_norm", step.residual_norm},
                          {"message", step.message},
                          {"max_abs", record["max_abs"]},
                          {"h1", record["h1"]},
                          {"min_gap", Field(record, "min_gap")},
                          {"min_force", Field(record, "min_force")},
                          {"signals_file", record["file"]},
                          {"samples_file", record.value("samples_file", "")},
                          {"laws", record["laws"]}};
  if (step.distance_to_lcp) entry["distance_to_lcp"] = DistanceToJson(*step.distance_to_lcp);
  document_["steps"].push_back(std::move(entry));
  // A step is a solve of seconds: the small document is rewritten after each.
  Write();
}

void RefinementWriter::Finish(const RefinementResult& result, bool complete) {
  document_["omega"] = result.omega;
  document_["status"] = result.interrupted ? "interrupted" : complete ? "complete" : "incomplete";
  if (!result.message.empty()) document_["message"] = result.message;
  Write();
}

RefinementResult RunRefinement(const Case& the_case, const RefinementOptions& options,
                               const std::string& out_dir, std::ostream* progress,
                               const std::atomic<bool>* stop, const nlohmann::json& source) {
  options.Validate(the_case);
  the_case.Validate();
  RefinementWriter writer(out_dir, the_case, options.omega, source);
  RefinementRunOptions run;
  run.progress = progress;
  run.stop = stop;
  run.branch = writer.branch_observer();
  run.observer = &writer;
  const RefinementResult result = RefineEpsilon(the_case, options, run);
  writer.Finish(result, result.Complete(options));
  return result;
}

}  // namespace nfrc
