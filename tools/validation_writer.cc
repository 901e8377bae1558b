#include "tools/validation_writer.h"

#include <complex>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "tools/branch_writer.h"
#include "tools/output_files.h"

namespace nfrc {
namespace {

nlohmann::json PhaseJson(const std::string& name, int count, double fraction) {
  return {{"phase", name}, {"count", count}, {"fraction", fraction}};
}

// The integrator's counters (SUNDIALS IDA's; the explicit scheme fills steps and events).
nlohmann::json StatisticsJson(const TransientStatistics& s) {
  return {{"steps", s.steps},
          {"residual_evaluations", s.residual_evaluations},
          {"jacobian_evaluations", s.jacobian_evaluations},
          {"nonlinear_iterations", s.nonlinear_iterations},
          {"nonlinear_convergence_failures", s.nonlinear_convergence_failures},
          {"error_test_failures", s.error_test_failures},
          {"events", s.events}};
}

nlohmann::json TransientJson(const TransientRun& run, const std::string& signals_file) {
  const TransientResult& r = run.result;
  const PeriodMeasures& m = run.measures;
  nlohmann::json j = {
      {"status", ToString(r.status)},
      {"periodic", r.periodic()},
      {"message", r.message},
      {"method", r.method},
      {"integration_time", r.wall_seconds},
      {"periods", r.periods},
      {"t_end", r.t_end},
      {"steps", r.steps},
      {"events", r.events},
      {"statistics", StatisticsJson(r.statistics)},
      {"period_multiple", r.period_multiple},
      {"last_period_difference", r.period_differences.empty() ? 0.0 : r.period_differences.back()},
      {"start", run.start}};
  if (run.recorded) {
    j["energy"] = m.energy;
    j["max_abs"] = m.max_abs;
    j["h1"] = m.h1;
    nlohmann::json phases = nlohmann::json::array();
    for (size_t i = 0; i < m.phase_names.size(); ++i) {
      phases.push_back(PhaseJson(m.phase_names[i], m.phase_counts[i], m.phase_fractions[i]));
    }
    j["phases"] = std::move(phases);
    j["energy_balance"] = {{"work_input", r.last_period.work_input},
                           {"work_damping", r.last_period.work_damping},
                           {"work_laws", r.last_period.work_laws},
                           {"energy_change", r.last_period.energy_change},
                           {"relative_defect", m.energy_balance_defect}};
  }
  if (const auto& c = run.comparison) {
    j["matches"] = c->label;
    j["matches_solution"] = c->solution;
    j["stayed"] = c->stayed;
    j["differences"] = {{"h1", c->h1},
                        {"max_abs", c->max_abs},
                        {"energy", c->energy},
                        {"rms", c->rms},
                        {"same_phase_counts", c->same_phase_counts}};
    j["signals"] = signals_file;
  }
  return j;
}

// The transient monodromy of one HBM solution: multipliers as [re, im], by decreasing |μ|.
nlohmann::json MonodromyJson(const MonodromyResult& m) {
  return {{"ok", m.ok},
          {"message", m.message},
          {"multipliers", ComplexListToJson(m.multipliers)},
          {"max_modulus", m.max_modulus()},
          {"closure", m.closure},
          {"state_own", m.state_own},
          {"integrations", m.integrations},
          {"wall_seconds", m.wall_seconds}};
}

// Hill's multipliers of one HBM solution (the branch points' "floquet" record) and their
// distance to the transient ones.
nlohmann::json HillJson(const SolutionStability& stability) {
  const FloquetResult& hill = stability.hill;
  nlohmann::json j = FloquetToJson(hill);
  j["stable"] = hill.stable();
  j["message"] = hill.message;
  j["seconds"] = hill.seconds;
  if (stability.multiplier_difference) {
    j["difference_to_monodromy"] = *stability.multiplier_difference;
    j["max_modulus_difference"] = *stability.max_modulus_difference;
  }
  return j;
}

std::string Fixed(double value, int precision) {
  std::ostringstream out;
  out << std::setprecision(precision) << value;
  return out.str();
}

std::string PhaseText(const std::vector<int>& counts) {
  std::string text;
  for (int c : counts) {
    if (!text.empty()) text += '/';
    text += std::to_string(c);
  }
  return text.empty() ? "-" : text;
}

void WriteTableHeader(std::ostream& table) {
  table << std::left << std::setw(10) << "omega" << std::setw(8) << "branch" << std::setw(8)
        << "start" << std::setw(13) << "status" << std::setw(13) << "h1 HBM" << std::setw(13)
        << "h1 transient" << std::setw(10) << "rel diff" << std::setw(13) << "E HBM"
        << std::setw(13) << "E transient" << std::setw(10) << "rel diff" << std::setw(8) << "phases"
        << std::setw(8) << "time s"
        << "\n";
}

// A line per transient: the matched HBM solution (or "-"), how it started and the
// differences of the first output DOF's first harmonic and of the energy.
void WriteTableRow(std::ostream& table, const ValidationPoint& point, const TransientRun& run) {
  const std::optional<TransientComparison>& c = run.comparison;
  const CrossingSolution* s = c ? &point.solutions[c->solution] : nullptr;
  const PointMeasures* hbm = s != nullptr ? &s->signals.measures.response : nullptr;
  const PeriodMeasures& m = run.measures;
  const TransientResult& r = run.result;
  std::vector<int> hbm_counts;
  if (s != nullptr) {
    for (const PhaseSummary& phase : s->phases) hbm_counts.push_back(phase.count);
  }
  table << std::left << std::setw(10) << Fixed(point.omega, 6) << std::setw(8)
        << (s != nullptr ? s->label : "-") << std::setw(8)
        << (run.start_solution >= 0 ? point.solutions[run.start_solution].label : "rest")
        << std::setw(13) << ToString(r.status) << std::setw(13)
        << (hbm != nullptr ? Fixed(hbm->h1[0], 6) : "-") << std::setw(13)
        << (run.recorded ? Fixed(m.h1[0], 6) : "-") << std::setw(10)
        << (c ? Fixed(c->h1[0], 2) : "-") << std::setw(13)
        << (hbm != nullptr ? Fixed(hbm->energy, 6) : "-") << std::setw(13)
        << (run.recorded ? Fixed(m.energy, 6) : "-") << std::setw(10)
        << (c ? Fixed(c->energy, 2) : "-") << std::setw(8)
        << (c ? PhaseText(hbm_counts) + ":" + PhaseText(m.phase_counts) : "-") << std::setw(8)
        << Fixed(r.wall_seconds, 3) << "\n";
}

}  // namespace

nlohmann::json CrossingToJson(const CrossingSolution& s) {
  const PointMeasures& m = s.signals.measures.response;
  nlohmann::json phases = nlohmann::json::array();
  for (const PhaseSummary& phase : s.phases) {
    phases.push_back(PhaseJson(phase.name, phase.count, phase.fraction));
  }
  return {{"branch", s.label},  {"after_point", s.after_point},
          {"energy", m.energy}, {"max_abs", m.max_abs},
          {"h1", m.h1},         {"phases", phases}};
}

ValidationWriter::ValidationWriter(std::string dir, const Case& the_case,
                                   const ValidationSettings& settings, nlohmann::json source,
                                   std::ostream* table)
    : dir_(std::move(dir)),
      case_(the_case),
      settings_(settings),
      source_(std::move(source)),
      table_(table) {}

TraceObserver* ValidationWriter::OnTraceStart() {
  std::error_code error;
  std::filesystem::create_directories(dir_, error);
  if (error) {
    throw OutputError(dir_ + ": cannot create output directory: " + error.message());
  }
  branch_writer_ = std::make_unique<BranchWriter>(dir_ + "/hbm", case_, source_);
  return branch_writer_.get();
}

void ValidationWriter::OnBranch(const TraceResult& trace) {
  if (branch_writer_ != nullptr) branch_writer_->Finish(trace.branch.summary);
  const Branch& branch = trace.branch;
  const TransientOptions& transient = settings_.transient;
  document_ = {{"case", case_.path},
               {"branch", "hbm/branch.json"},
               {"branch_summary",
                {{"points", branch.points.size()},
                 {"folds", branch.folds.size()},
                 {"reason", ToString(branch.summary.reason)}}},
               {"output_dofs", case_.output_names},
               {"start", settings_.start == ValidationSettings::Start::kHbm ? "hbm" : "rest"},
               {"transient_options",
                {{"relative_tolerance", transient.relative_tolerance},
                 {"steady_tolerance", transient.steady_tolerance},
                 {"max_periods", transient.max_periods},
                 {"samples_per_period", transient.samples_per_period}}},
               {"monodromy_options",
                {{"enabled", settings_.monodromy.enabled},
                 {"relative_step", settings_.monodromy.relative_step},
                 {"scale", settings_.monodromy.scale}}},
               {"status", "running"},
               {"interrupted", false},
               {"points", nlohmann::json::array()}};
  WriteJson();
  if (table_ != nullptr) WriteTableHeader(*table_);
}

void ValidationWriter::OnEnd(const ValidationResult& result) {
  if (document_.is_null()) return;  // the trace itself failed: no validation.json was begun
  document_["status"] = result.interrupted ? "interrupted"
                        : result.complete  ? "complete"
                                           : "incomplete";
  document_["interrupted"] = result.interrupted;
  WriteJson();
}

void ValidationWriter::OnTransient(const ValidationPoint& point) {
  const TransientRun& run = point.transients.back();
  std::string file;
  if (run.comparison) {
    file = "signals_" + std::to_string(num_signals_++) + ".csv";
    WriteCsv(dir_ + "/" + file, run.comparison->overlay.names, run.comparison->overlay.columns);
  }
  point_files_.push_back(file);
  if (table_ != nullptr) WriteTableRow(*table_, point, run);
}

void ValidationWriter::OnPoint(const ValidationPoint& point) {
  nlohmann::json entry = {{"omega", point.omega},
                          {"hbm_solutions", nlohmann::json::array()},
                          {"transients", nlohmann::json::array()}};
  for (size_t i = 0; i < point.solutions.size(); ++i) {
    nlohmann::json solution = CrossingToJson(point.solutions[i]);
    if (i < point.stability.size()) {
      const SolutionStability& stability = point.stability[i];
      if (stability.monodromy) solution["monodromy"] = MonodromyJson(*stability.monodromy);
      if (stability.hill.computed) solution["hill"] = HillJson(stability);
    }
    entry["hbm_solutions"].push_back(std::move(solution));
  }
  for (size_t i = 0; i < point.transients.size(); ++i) {
    entry["transients"].push_back(TransientJson(point.transients[i], point_files_.at(i)));
  }
  point_files_.clear();
  if (point.primary >= 0) {
    entry["transient"] = entry["transients"][point.primary];
    if (const auto& c = point.transients[point.primary].comparison) {
      entry["hbm"] = entry["hbm_solutions"][c->solution];
    }
  }
  document_["points"].push_back(std::move(entry));
  WriteJson();
}

void ValidationWriter::OnChirp(const ChirpRun& run) {
  const ChirpResult& r = run.result;
  std::vector<std::string> columns = {"omega", "t_start", "t_end", "energy"};
  for (const std::string& n : case_.output_names) columns.push_back("max_abs_" + n);
  std::vector<Eigen::VectorXd> data(columns.size(), Eigen::VectorXd(r.cycles.size()));
  for (size_t k = 0; k < r.cycles.size(); ++k) {
    const ChirpCycle& c = r.cycles[k];
    data[0](k) = c.omega;
    data[1](k) = c.t_start;
    data[2](k) = c.t_end;
    data[3](k) = c.mean_energy;
    for (size_t i = 0; i < case_.output_dofs.size(); ++i) {
      data[4 + i](k) = c.max_abs(case_.output_dofs[i]);
    }
  }
  const std::string file = "chirp_" + run.direction + ".csv";
  if (!r.cycles.empty()) WriteCsv(dir_ + "/" + file, columns, data);
  document_["chirp"][run.direction] = {{"status", ChirpStatusName(r.status)},
                                       {"message", r.message},
                                       {"method", r.method},
                                       {"omega_start", run.omega_start},
                                       {"omega_end", run.omega_end},
                                       {"duration", run.duration},
                                       {"sweep_rate", run.sweep_rate},
                                       {"integration_time", r.wall_seconds},
                                       {"cycles", r.cycles.size()},
                                       {"steps", r.steps},
                                       {"events", r.events},
                                       {"statistics", StatisticsJson(r.statistics)},
                                       {"file", r.cycles.empty() ? "" : file}};
  WriteJson();
}

void ValidationWriter::WriteJson() const {
  WriteJsonAtomically(dir_ + "/validation.json", document_);
}

}  // namespace nfrc
