#include "tools/branch_writer.h"

#include <filesystem>
#include <iomanip>
#include <stdexcept>

#include "tools/version.h"

namespace nfrc {
namespace {

nlohmann::json OptionsToJson(const ContinuationOptions& o) {
  return {{"omega_start", o.lambda_start},
          {"omega_end", o.lambda_end},
          {"step", o.initial_step},
          {"min_step", o.min_step},
          {"max_step", o.max_step},
          {"max_points", o.max_points},
          {"max_newton_iterations", o.max_newton_iterations},
          {"target_newton_iterations", o.target_newton_iterations},
          {"newton_tolerance", o.newton_tolerance},
          {"residual_tolerance", o.residual_tolerance},
          {"max_tangent_angle", o.max_tangent_angle},
          {"detect_folds", o.detect_folds},
          {"fold_tolerance", o.fold_tolerance},
          {"line_search", o.line_search}};
}

}  // namespace

nlohmann::json SummaryToJson(const ContinuationSummary& summary) {
  nlohmann::json history = nlohmann::json::array();
  for (const StepRecord& step : summary.history) {
    history.push_back({{"step", step.step},
                       {"newton_iterations", step.newton_iterations},
                       {"accepted", step.accepted},
                       {"note", step.note}});
  }
  return {{"termination", ToString(summary.reason)},
          {"success", summary.success()},
          {"message", summary.message},
          {"points", summary.num_points},
          {"folds", summary.num_folds},
          {"accepted_steps", summary.num_accepted_steps},
          {"rejected_steps", summary.num_rejected_steps},
          {"newton_iterations", summary.total_newton_iterations},
          {"evaluations", summary.num_evaluations},
          {"wall_time_s", summary.wall_time_seconds},
          {"history", history}};
}

BranchWriter::BranchWriter(std::string dir, const Case& the_case, HarmonicSystem& system)
    : dir_(std::move(dir)),
      case_(the_case),
      system_(system),
      analyzer_(system, the_case.output_dofs) {
  std::error_code error;
  std::filesystem::create_directories(dir_, error);
  if (error) throw std::runtime_error(dir_ + ": cannot create output directory: " + error.message());
  csv_.open(dir_ + "/branch.csv");
  if (!csv_) throw std::runtime_error(dir_ + "/branch.csv: cannot open for writing");
  csv_ << "index,omega,step,newton_iterations,residual_norm,tangent_omega";
  for (const std::string& name : case_.output_names) csv_ << ",max_abs_" << name;
  for (const std::string& name : case_.output_names) csv_ << ",h1_" << name;
  csv_ << "\n" << std::flush;
  csv_ << std::setprecision(12);

  const HarmonicSet& set = case_.harmonics;
  document_ = {
      {"program", "nfrc"},
      {"version", kNfrcVersion},
      {"case_file", case_.path},
      {"case", case_.source},
      {"harmonics",
       {{"max", set.max_harmonic()},
        {"odd_only", set.odd_only()},
        {"samples", set.num_samples()},
        {"list", set.harmonics()}}},
      {"output_dofs", case_.output_names},
      {"unknowns", system_.NumUnknowns()},
      {"options", OptionsToJson(case_.continuation)},
      {"points", nlohmann::json::array()},
      {"folds", nlohmann::json::array()},
      {"summary", {{"termination", "running"}, {"message", "run in progress"}}}};
  WriteJson();
}

bool BranchWriter::OnPoint(const BranchPoint& point, int index) {
  const PointMeasures m = analyzer_.Measure(point.y, point.lambda);
  document_["points"].push_back({{"index", index},
                                 {"omega", point.lambda},
                                 {"step", point.step},
                                 {"newton_iterations", point.newton_iterations},
                                 {"residual_norm", point.residual_norm},
                                 {"tangent_omega", point.tangent_lambda},
                                 {"max_abs", m.max_abs},
                                 {"h1", m.h1},
                                 {"amplitudes", m.amplitudes}});
  csv_ << index << ',' << point.lambda << ',' << point.step << ',' << point.newton_iterations
       << ',' << point.residual_norm << ',' << point.tangent_lambda;
  for (double v : m.max_abs) csv_ << ',' << v;
  for (double v : m.h1) csv_ << ',' << v;
  csv_ << '\n' << std::flush;
  if (std::chrono::steady_clock::now() - last_json_write_ > kJsonInterval) WriteJson();
  return true;
}

void BranchWriter::OnFold(const Fold& fold) {
  const PointMeasures m = analyzer_.Measure(fold.y, fold.lambda);
  document_["folds"].push_back({{"omega", fold.lambda},
                                {"max_abs", m.max_abs},
                                {"h1", m.h1},
                                {"after_point", fold.after_point},
                                {"omega_accuracy", fold.lambda_accuracy},
                                {"tangent_omega", fold.tangent_lambda},
                                {"iterations", fold.iterations},
                                {"converged", fold.converged}});
  WriteJson();
}

void BranchWriter::Finish(const ContinuationSummary& summary) {
  document_["summary"] = SummaryToJson(summary);
  WriteJson();
}

void BranchWriter::WriteJson() {
  const std::string path = dir_ + "/branch.json";
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    if (!out) throw std::runtime_error(temporary + ": cannot open for writing");
    out << document_.dump(1) << "\n";
    if (!out) throw std::runtime_error(temporary + ": write failed");
  }
  std::filesystem::rename(temporary, path);
  last_json_write_ = std::chrono::steady_clock::now();
}

}  // namespace nfrc
