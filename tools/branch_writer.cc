#include "tools/branch_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <numbers>
#include <stdexcept>

#include "continuation/fixed_lambda.h"
#include "tools/output_files.h"
#include "tools/version.h"

namespace nfrc {
namespace {

nlohmann::json OptionsToJson(const Case& the_case) {
  const ContinuationOptions& o = the_case.continuation;
  if (the_case.method == "lemke_stepping") {
    return {{"method", the_case.method},
            {"omega_start", o.lambda_start},
            {"omega_end", o.lambda_end},
            {"points", the_case.stepping.points},
            {"track_contact", the_case.stepping.track_contact}};
  }
  return {{"method", the_case.method},
          {"omega_start", o.lambda_start},
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

BranchWriter::BranchWriter(std::string dir, const Case& the_case, HarmonicSystem& system,
                           bool solve_signals)
    : dir_(std::move(dir)),
      case_(the_case),
      system_(system),
      analyzer_(system, the_case.output_dofs),
      solve_signals_(solve_signals) {
  std::error_code error;
  std::filesystem::create_directories(dir_, error);
  if (error)
    throw std::runtime_error(dir_ + ": cannot create output directory: " + error.message());
  csv_.open(dir_ + "/branch.csv");
  if (!csv_) throw std::runtime_error(dir_ + "/branch.csv: cannot open for writing");
  csv_ << "index,omega,step,newton_iterations,residual_norm,tangent_omega,energy";
  for (const std::string& name : case_.output_names) csv_ << ",max_abs_" << name;
  for (const std::string& name : case_.output_names) csv_ << ",h1_" << name;
  csv_ << "\n" << std::flush;
  csv_ << std::setprecision(12);

  const HarmonicSet& set = case_.harmonics;
  document_ = {{"program", "nfrc"},
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
               {"options", OptionsToJson(case_)},
               {"points", nlohmann::json::array()},
               {"folds", nlohmann::json::array()},
               {"signals", nlohmann::json::array()},
               {"summary", {{"termination", "running"}, {"message", "run in progress"}}}};
  WriteJson();
}

nlohmann::json BranchWriter::Measure(const Eigen::VectorXd& y, double omega) {
  const PointMeasures m = analyzer_.Measure(y, omega);
  nlohmann::json entry = {{"energy", m.energy},
                          {"max_abs", m.max_abs},
                          {"min", m.min},
                          {"max", m.max},
                          {"h1", m.h1},
                          {"amplitudes", m.amplitudes},
                          {"laws", LawDiagnostics(y, omega)}};
  AddContactExtremes(entry);
  return entry;
}

void BranchWriter::AnnotateLastPoint(const nlohmann::json& extra) {
  document_["points"].back().update(extra);
}

bool BranchWriter::OnPoint(const BranchPoint& point, int index) {
  nlohmann::json entry = {{"index", index},
                          {"omega", point.lambda},
                          {"step", point.step},
                          {"newton_iterations", point.newton_iterations},
                          {"residual_norm", point.residual_norm},
                          {"tangent_omega", point.tangent_lambda}};
  const nlohmann::json measures = Measure(point.y, point.lambda);
  entry.update(measures);
  const double energy = measures["energy"].get<double>();
  const std::vector<double> max_abs = measures["max_abs"];
  const std::vector<double> h1 = measures["h1"];
  document_["points"].push_back(std::move(entry));
  csv_ << index << ',' << point.lambda << ',' << point.step << ',' << point.newton_iterations << ','
       << point.residual_norm << ',' << point.tangent_lambda << ',' << energy;
  for (double v : max_abs) csv_ << ',' << v;
  for (double v : h1) csv_ << ',' << v;
  csv_ << '\n' << std::flush;

  for (double omega : solve_signals_ ? case_.signals_at : std::vector<double>{}) {
    const BranchPoint* previous = previous_ ? &*previous_ : nullptr;
    if (const auto solved = SolveAtCrossing(system_, previous, point, omega, case_.continuation)) {
      WriteSignals(omega, solved->y, point.lambda == omega ? index : index - 1, solved->converged,
                   solved->message);
    }
  }
  previous_ = point;
  // Large documents are rewritten less often, so that writing stays a small share of the run.
  const auto interval =
      std::max<std::chrono::steady_clock::duration>(kJsonInterval, 10 * last_json_duration_);
  if (std::chrono::steady_clock::now() - last_json_write_ > interval) WriteJson();
  return true;
}

nlohmann::json BranchWriter::LawDiagnostics(const Eigen::VectorXd& y, double omega) {
  nlohmann::json laws = nlohmann::json::array();
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    laws.push_back(system_.laws()[i]->Diagnostics(system_.context(static_cast<int>(i)), y, omega,
                                                  analyzer_.fine()));
  }
  return laws;
}

const nlohmann::json& BranchWriter::WriteSignals(double omega, const Eigen::VectorXd& y,
                                                 int after_point, bool converged,
                                                 const std::string& note) {
  const int number = num_signals_++;
  const std::string name = "signals_" + std::to_string(number) + ".csv";
  const FourierTransform& fine = analyzer_.fine();
  std::vector<std::string> columns = {"theta", "t"};
  std::vector<Eigen::VectorXd> data = {Angles(fine.harmonic_set().num_samples())};
  data.push_back(data[0] / omega);
  const Eigen::MatrixXd& d = system_.fourier().DerivativeMatrix();
  std::vector<Eigen::VectorXd> coefficients;
  for (size_t i = 0; i < case_.output_dofs.size(); ++i) {
    coefficients.push_back(system_.DofCoefficients(y, omega, case_.output_dofs[i]));
    columns.push_back("x_" + case_.output_names[i]);
    data.push_back(fine.ToTime(coefficients.back()).col(0));
    columns.push_back("v_" + case_.output_names[i]);
    data.push_back(fine.ToTime(omega * (d * coefficients.back())).col(0));
  }
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const auto& law = system_.laws()[i];
    for (LawSignal& signal : law->Signals(system_.context(static_cast<int>(i)), y, omega, fine)) {
      columns.push_back("law" + std::to_string(i) + "_" + signal.name);
      data.push_back(std::move(signal.samples));
    }
  }
  WriteCsv(dir_ + "/" + name, columns, data);

  // The laws' own samples (N_t, before truncation), when they have any.
  std::string samples_name;
  const FourierTransform& coarse = system_.fourier();
  std::vector<std::string> raw_columns = {"theta", "t"};
  std::vector<Eigen::VectorXd> raw = {Angles(coarse.harmonic_set().num_samples())};
  raw.push_back(raw[0] / omega);
  for (size_t i = 0; i < case_.output_dofs.size(); ++i) {
    raw_columns.push_back("x_" + case_.output_names[i]);
    raw.push_back(coarse.ToTime(coefficients[i]).col(0));
  }
  const size_t num_fixed = raw.size();
  for (size_t i = 0; i < system_.laws().size(); ++i) {
    const auto& law = system_.laws()[i];
    for (LawSignal& signal : law->RawSamples(system_.context(static_cast<int>(i)), y, omega)) {
      raw_columns.push_back("law" + std::to_string(i) + "_" + signal.name);
      raw.push_back(std::move(signal.samples));
    }
  }
  if (raw.size() > num_fixed) {
    samples_name = "samples_" + std::to_string(number) + ".csv";
    WriteCsv(dir_ + "/" + samples_name, raw_columns, raw);
  }

  nlohmann::json entry = {{"omega", omega},
                          {"file", name},
                          {"after_point", after_point},
                          {"converged", converged},
                          {"note", note}};
  entry.update(Measure(y, omega));
  entry.erase("amplitudes");
  if (!samples_name.empty()) entry["samples_file"] = samples_name;
  document_["signals"].push_back(std::move(entry));
  WriteJson();
  return document_["signals"].back();
}

void BranchWriter::AddContactExtremes(nlohmann::json& entry) {
  double min_gap = INFINITY;
  double min_force = INFINITY;
  for (const nlohmann::json& law : entry["laws"]) {
    if (law.contains("min_gap")) min_gap = std::min(min_gap, law["min_gap"].get<double>());
    if (law.contains("min_force")) min_force = std::min(min_force, law["min_force"].get<double>());
  }
  if (std::isfinite(min_gap)) entry["min_gap"] = min_gap;
  if (std::isfinite(min_force)) entry["min_force"] = min_force;
}

void BranchWriter::OnFold(const Fold& fold) {
  const PointMeasures m = analyzer_.Measure(fold.y, fold.lambda);
  document_["folds"].push_back({{"omega", fold.lambda},
                                {"energy", m.energy},
                                {"max_abs", m.max_abs},
                                {"min", m.min},
                                {"max", m.max},
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
  const auto start = std::chrono::steady_clock::now();
  WriteJsonAtomically(dir_ + "/branch.json", document_);
  last_json_write_ = std::chrono::steady_clock::now();
  last_json_duration_ = last_json_write_ - start;
}

}  // namespace nfrc
