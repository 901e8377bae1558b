#include "tools/branch_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <numbers>
#include <stdexcept>

#include "tools/output_files.h"
#include "tools/version.h"

namespace nfrc {
namespace {

nlohmann::json OptionsToJson(const Case& the_case) {
  const ContinuationOptions& o = the_case.continuation;
  if (the_case.method == Method::kLemkeStepping) {
    return {{"method", ToString(the_case.method)},
            {"omega_start", o.lambda_start},
            {"omega_end", o.lambda_end},
            {"points", the_case.stepping.points},
            {"track_contact", the_case.stepping.track_contact}};
  }
  return {{"method", ToString(the_case.method)},
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
          {"line_search", o.line_search},
          {"start_homotopy", the_case.start.homotopy},
          {"start_homotopy_factor", the_case.start.homotopy_factor},
          {"start_homotopy_rungs", the_case.start.homotopy_rungs}};
}

}  // namespace

nlohmann::json ReductionToJson(const ReductionReport& report) {
  nlohmann::json frequencies = nlohmann::json::array();
  for (const EigenfrequencyCheck& check : report.eigenfrequencies) {
    frequencies.push_back({{"full", check.full},
                           {"reduced", check.reduced},
                           {"relative_error", check.relative_error}});
  }
  return {{"type", "craig_bampton"},
          {"full_dofs", report.full_dofs},
          {"boundary_dofs", report.boundary_dofs},
          {"modes", report.modes},
          {"time_s", report.time_s},
          {"factor_s", report.factor_s},
          {"modes_s", report.modes_s},
          {"check_time_s", report.check_time_s},
          {"fixed_interface_frequencies", report.fixed_interface_frequencies},
          {"eigenfrequencies", frequencies}};
}

namespace {

nlohmann::json LemkeToJson(const LemkeRecord& r) {
  return {{"status", ToString(r.status)},
          {"pivots", r.pivots},
          {"trivial", r.trivial},
          {"warm_started", r.warm_started},
          {"complementarity", r.complementarity},
          {"feasibility", r.feasibility},
          {"complementarity_gap", r.complementarity_gap}};
}

nlohmann::json StabilityOptionsToJson(const StabilityOptions& o) {
  return {{"enabled", o.enabled},
          {"unstable_tolerance", o.unstable_tolerance},
          {"bifurcation_tolerance", o.bifurcation_tolerance},
          {"max_bifurcation_iterations", o.max_bifurcation_iterations},
          {"jump_tolerance", o.jump_tolerance},
          {"hill_modes", o.hill_modes}};
}

// The CSV's stability columns: empty when not computed, so that a reader tells "not
// analysed" from "unstable".
void WriteStabilityColumns(CsvStream& csv, const FloquetResult& floquet) {
  if (!floquet.computed) {
    csv << ",,,";
    return;
  }
  csv << ',' << (floquet.stable() ? 1 : 0) << ',' << floquet.max_modulus << ','
      << floquet.num_unstable;
}

}  // namespace

nlohmann::json ComplexListToJson(const std::vector<std::complex<double>>& values) {
  nlohmann::json list = nlohmann::json::array();
  for (const std::complex<double>& value : values) list.push_back({value.real(), value.imag()});
  return list;
}

nlohmann::json FloquetToJson(const FloquetResult& floquet) {
  if (!floquet.computed) return nullptr;
  return {{"max_modulus", floquet.max_modulus},
          {"unstable", floquet.num_unstable},
          {"method", floquet.method},
          {"multipliers", ComplexListToJson(floquet.multipliers)}};
}

nlohmann::json BifurcationToJson(const Bifurcation& bifurcation, double factor) {
  const PointMeasures& m = bifurcation.measures;
  return {{"type", ToString(bifurcation.type)},
          {"omega", factor * bifurcation.omega},
          {"omega_accuracy", factor * bifurcation.omega_accuracy},
          {"converged", bifurcation.converged},
          {"iterations", bifurcation.iterations},
          {"after_point", bifurcation.after_point},
          {"crossing_multipliers", ComplexListToJson(bifurcation.crossing_multipliers)},
          {"discontinuous", bifurcation.discontinuous},
          {"energy", m.energy},
          {"max_abs", m.max_abs},
          {"min", m.min},
          {"max", m.max},
          {"h1", m.h1}};
}

nlohmann::json MeasuresToJson(const SolutionMeasures& measures) {
  const PointMeasures& m = measures.response;
  nlohmann::json laws = nlohmann::json::array();
  for (const auto& law : measures.laws) laws.push_back(law);
  nlohmann::json entry = {
      {"energy", m.energy}, {"max_abs", m.max_abs},       {"min", m.min}, {"max", m.max},
      {"h1", m.h1},         {"amplitudes", m.amplitudes}, {"laws", laws}};
  if (measures.min_gap) entry["min_gap"] = *measures.min_gap;
  if (measures.min_force) entry["min_force"] = *measures.min_force;
  return entry;
}

void WriteSignalTable(const std::string& path, const SignalTable& table) {
  WriteCsv(path, table.names, table.columns);
}

nlohmann::json SummaryToJson(const ContinuationSummary& summary) {
  nlohmann::json history = nlohmann::json::array();
  for (const StepRecord& step : summary.history) {
    history.push_back({{"step", step.step},
                       {"newton_iterations", step.newton_iterations},
                       {"accepted", step.accepted},
                       {"fixed_lambda", step.fixed_lambda},
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
          {"notes", summary.notes},
          {"history", history}};
}

BranchWriter::BranchWriter(std::string dir, const Case& the_case, nlohmann::json source)
    : dir_(std::move(dir)), case_(the_case), omega_factor_(the_case.period_multiple) {
  std::error_code error;
  std::filesystem::create_directories(dir_, error);
  if (error) throw OutputError(dir_ + ": cannot create output directory: " + error.message());
  csv_.Open(dir_ + "/branch.csv");
  csv_ << "index,omega,step,newton_iterations,residual_norm,tangent_omega,energy";
  for (const std::string& name : case_.output_names) csv_ << ",max_abs_" << name;
  for (const std::string& name : case_.output_names) csv_ << ",h1_" << name;
  // Appended last so that readers of the older columns by position keep working.
  csv_ << ",stable,max_multiplier,unstable\n";
  csv_.Flush();

  const HarmonicSet& set = case_.harmonics;
  document_ = {{"program", "nfrc"},
               {"version", kNfrcVersion},
               {"case_file", case_.path},
               {"case", std::move(source)},
               {"harmonics",
                {{"max", set.max_harmonic()},
                 {"odd_only", set.odd_only()},
                 {"samples", set.num_samples()},
                 {"list", set.harmonics()}}},
               {"output_dofs", case_.output_names},
               {"period_multiple", case_.period_multiple},
               {"unknowns", 0},
               {"options", OptionsToJson(case_)},
               {"stability", StabilityOptionsToJson(case_.stability)},
               {"points", nlohmann::json::array()},
               {"folds", nlohmann::json::array()},
               {"bifurcations", nlohmann::json::array()},
               {"signals", nlohmann::json::array()},
               {"summary", {{"termination", "running"}, {"message", "run in progress"}}}};
  if (case_.reduction) document_["reduction"] = ReductionToJson(*case_.reduction);
  WriteJson();
}

void BranchWriter::OnStart(int num_unknowns) {
  document_["unknowns"] = num_unknowns;
  WriteJson();
}

bool BranchWriter::OnPoint(const TracePoint& record) {
  const BranchPoint& point = record.point;
  nlohmann::json entry = {{"index", record.index},
                          {"omega", omega_factor_ * point.lambda},
                          {"step", point.step},
                          {"newton_iterations", point.newton_iterations},
                          {"residual_norm", point.residual_norm},
                          {"tangent_omega", point.tangent_lambda}};
  entry.update(MeasuresToJson(record.measures));
  // null, not false, when not analysed: "unknown" must not read as "unstable".
  entry["stable"] = record.floquet.computed ? nlohmann::json(record.floquet.stable()) : nullptr;
  entry["floquet"] = FloquetToJson(record.floquet);
  if (record.lemke) {
    nlohmann::json info = LemkeToJson(*record.lemke);
    info["coexisting_contact"] = record.coexisting_contact;
    if (record.contact_branch) {
      nlohmann::json contact = MeasuresToJson(record.contact_branch->measures);
      contact["lcp"] = LemkeToJson(record.contact_branch->lemke);
      info["contact_branch"] = std::move(contact);
    }
    entry["lcp"] = std::move(info);
  }
  document_["points"].push_back(std::move(entry));
  const PointMeasures& m = record.measures.response;
  csv_ << record.index << ',' << omega_factor_ * point.lambda << ',' << point.step << ','
       << point.newton_iterations << ',' << point.residual_norm << ',' << point.tangent_lambda
       << ',' << m.energy;
  for (double v : m.max_abs) csv_ << ',' << v;
  for (double v : m.h1) csv_ << ',' << v;
  WriteStabilityColumns(csv_, record.floquet);
  csv_ << '\n';
  csv_.Flush();
  WriteJsonIfDue();
  return true;
}

void BranchWriter::OnSignals(const SolutionSignals& signals) {
  const int number = num_signals_++;
  const std::string name = "signals_" + std::to_string(number) + ".csv";
  WriteSignalTable(dir_ + "/" + name, signals.fine);
  std::string samples_name;
  if (!signals.samples.columns.empty()) {
    samples_name = "samples_" + std::to_string(number) + ".csv";
    WriteSignalTable(dir_ + "/" + samples_name, signals.samples);
  }
  nlohmann::json entry = {{"omega", omega_factor_ * signals.omega},
                          {"file", name},
                          {"after_point", signals.after_point},
                          {"converged", signals.converged},
                          {"note", signals.note}};
  entry.update(MeasuresToJson(signals.measures));
  entry.erase("amplitudes");
  if (!samples_name.empty()) entry["samples_file"] = samples_name;
  document_["signals"].push_back(std::move(entry));
  WriteJson();
}

void BranchWriter::SetWindows(const std::vector<QuasiPeriodicWindow>& windows) {
  nlohmann::json list = nlohmann::json::array();
  for (const QuasiPeriodicWindow& w : windows) {
    list.push_back({{"omega_from", omega_factor_ * w.omega_from},
                    {"omega_to", omega_factor_ * w.omega_to},
                    {"first_point", w.first_point},
                    {"last_point", w.last_point},
                    {"closed", w.closed}});
  }
  document_["quasi_periodic_windows"] = std::move(list);
}

void BranchWriter::OnFold(const TraceFold& record) {
  const Fold& fold = record.fold;
  const PointMeasures& m = record.measures;
  document_["folds"].push_back({{"omega", omega_factor_ * fold.lambda},
                                {"energy", m.energy},
                                {"max_abs", m.max_abs},
                                {"min", m.min},
                                {"max", m.max},
                                {"h1", m.h1},
                                {"after_point", fold.after_point},
                                {"omega_accuracy", omega_factor_ * fold.lambda_accuracy},
                                {"tangent_omega", fold.tangent_lambda},
                                {"iterations", fold.iterations},
                                {"converged", fold.converged},
                                {"corner", fold.corner}});
  unwritten_event_ = true;
  WriteJsonIfDue();
}

void BranchWriter::OnBifurcation(const Bifurcation& bifurcation) {
  document_["bifurcations"].push_back(BifurcationToJson(bifurcation, omega_factor_));
  unwritten_event_ = true;
  WriteJsonIfDue();
}

void BranchWriter::Finish(const ContinuationSummary& summary) {
  document_["summary"] = SummaryToJson(summary);
  WriteJson();
  csv_.Close();
}

void BranchWriter::WriteJsonIfDue() {
  if (schedule_.Due(unwritten_event_)) WriteJson();
}

void BranchWriter::WriteJson() {
  schedule_.Timed([&] { WriteJsonAtomically(dir_ + "/branch.json", document_); });
  unwritten_event_ = false;
}

}  // namespace nfrc
