#include "tools/validate.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <numbers>
#include <ostream>
#include <sstream>

#include "continuation/fixed_lambda.h"
#include "nonlinearities/phase_count.h"
#include "tools/output_files.h"
#include "analysis/point_measures.h"
#include "analysis/solution_report.h"
#include "tools/run_case.h"
#include "validation/make_integrator.h"
#include "validation/period_measures.h"

namespace nfrc {
namespace {

// One HBM solution at a requested ω (a crossing of the traced branch).
struct HbmSolution {
  Eigen::VectorXd y;
  int after_point = 0;  // index of the branch point that ends the crossed segment
  PointMeasures measures;
  std::vector<std::string> phase_names;
  std::vector<int> phase_counts;
  std::vector<double> phase_fractions;
  std::string label;  // "lower", "upper", ... by energy among the crossings
};

double Relative(double value, double reference) {
  return std::abs(value - reference) / std::max(std::abs(reference), 1e-300);
}

// Stick phases from a law's diagnostics, contact phases from its raw force samples (the force
// before truncation is exactly zero while open, so every run of positive samples counts).
void HbmPhases(HarmonicSystem& system, const PointAnalyzer& analyzer, HbmSolution* s,
               double omega) {
  for (size_t i = 0; i < system.laws().size(); ++i) {
    const auto& law = *system.laws()[i];
    const NonlinearityContext& ctx = system.context(static_cast<int>(i));
    const auto diagnostics = law.Diagnostics(ctx, s->y, omega, analyzer.fine());
    if (const auto it = diagnostics.find("stick_phases"); it != diagnostics.end()) {
      s->phase_names.push_back("stick");
      s->phase_counts.push_back(static_cast<int>(it->second));
      s->phase_fractions.push_back(diagnostics.at("stick_fraction"));
      continue;
    }
    for (const LawSignal& signal : law.RawSamples(ctx, s->y, omega)) {
      if (signal.name != "force_raw") continue;
      std::vector<bool> flags(signal.samples.size());
      for (Eigen::Index j = 0; j < signal.samples.size(); ++j) flags[j] = signal.samples(j) > 0;
      const PhaseCount count = CountPhases(flags, 0.0);
      s->phase_names.push_back("contact");
      s->phase_counts.push_back(count.count);
      s->phase_fractions.push_back(count.fraction);
    }
  }
}

// Every solution of the branch at exactly ω, labelled by energy.
std::vector<HbmSolution> SolveCrossings(HarmonicSystem& system, const Branch& branch, double omega,
                                        const ContinuationOptions& options,
                                        PointAnalyzer& analyzer) {
  std::vector<HbmSolution> solutions;
  for (size_t i = 0; i < branch.points.size(); ++i) {
    const BranchPoint* previous = i > 0 ? &branch.points[i - 1] : nullptr;
    const auto solved = SolveAtCrossing(system, previous, branch.points[i], omega, options);
    if (!solved || !solved->converged) continue;
    HbmSolution s;
    s.y = solved->y;
    s.after_point = static_cast<int>(i);
    s.measures = analyzer.Measure(s.y, omega);
    HbmPhases(system, analyzer, &s, omega);
    solutions.push_back(std::move(s));
  }
  std::vector<int> order(solutions.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return solutions[a].measures.energy < solutions[b].measures.energy;
  });
  static const char* kNames3[] = {"lower", "middle", "upper"};
  for (size_t rank = 0; rank < order.size(); ++rank) {
    std::string label;
    if (order.size() == 1) {
      label = "only";
    } else if (order.size() == 2) {
      label = rank == 0 ? "lower" : "upper";
    } else if (order.size() == 3) {
      label = kNames3[rank];
    } else {
      label = "solution " + std::to_string(rank + 1) + " of " + std::to_string(order.size()) +
              " by energy";
    }
    solutions[order[rank]].label = label;
  }
  return solutions;
}

// x(0) and ẋ(0) of every model DOF of an HBM solution.
InitialState StateAtZero(HarmonicSystem& system, const Eigen::VectorXd& y, double omega) {
  const Eigen::MatrixXd x = system.AllDofCoefficients(y, omega);  // DOF × coefficient
  const FourierTransform& fourier = system.fourier();
  const Eigen::MatrixXd xt = x.transpose();
  const Eigen::MatrixXd vt = omega * fourier.DerivativeMatrix() * xt;
  InitialState start;
  start.x = fourier.ToTime(xt).row(0).transpose();
  start.v = fourier.ToTime(vt).row(0).transpose();
  return start;
}

nlohmann::json PhasesJson(const std::vector<std::string>& names, const std::vector<int>& counts,
                          const std::vector<double>& fractions) {
  nlohmann::json phases = nlohmann::json::array();
  for (size_t i = 0; i < names.size(); ++i) {
    phases.push_back({{"phase", names[i]}, {"count", counts[i]}, {"fraction", fractions[i]}});
  }
  return phases;
}

nlohmann::json HbmJson(const HbmSolution& s) {
  return {{"branch", s.label},
          {"after_point", s.after_point},
          {"energy", s.measures.energy},
          {"max_abs", s.measures.max_abs},
          {"h1", s.measures.h1},
          {"phases", PhasesJson(s.phase_names, s.phase_counts, s.phase_fractions)}};
}

// Distance used to say which HBM solution a transient landed on: relative differences of the
// first-harmonic amplitudes and of the energy.
double Distance(const PeriodMeasures& t, const HbmSolution& s) {
  double d = Relative(t.energy, s.measures.energy);
  for (size_t i = 0; i < t.h1.size(); ++i) d += Relative(t.h1[i], s.measures.h1[i]);
  return d;
}

struct SignalsOnGrid {
  std::vector<std::string> columns;
  std::vector<Eigen::VectorXd> data;
};

// The HBM solution and the transient's recorded period on the transient's grid
// (θ = 2πi/N from a period boundary, where the excitation phase is a multiple of 2π).
SignalsOnGrid OverlaySignals(const Case& the_case, HarmonicSystem& system, const HbmSolution& s,
                             const PeriodRecord& record, double omega, std::vector<double>* rms) {
  const int n = static_cast<int>(record.t.size());
  const HarmonicSet& set = system.harmonic_set();
  const FourierTransform grid(HarmonicSet(set.max_harmonic(), set.odd_only(), n));
  SignalsOnGrid out;
  out.columns = {"theta", "t"};
  out.data = {Angles(n)};
  out.data.push_back(out.data[0] / omega);
  const Eigen::MatrixXd& d = system.fourier().DerivativeMatrix();
  for (size_t i = 0; i < the_case.output_dofs.size(); ++i) {
    const int dof = the_case.output_dofs[i];
    const std::string& name = the_case.output_names[i];
    const Eigen::VectorXd c = system.DofCoefficients(s.y, omega, dof);
    const Eigen::VectorXd hbm = grid.ToTime(c).col(0);
    const Eigen::VectorXd transient = record.x.row(dof).transpose();
    rms->push_back(std::sqrt((hbm - transient).squaredNorm() / n) /
                   std::max(std::sqrt(hbm.squaredNorm() / n), 1e-300));
    out.columns.insert(out.columns.end(), {"hbm_x_" + name, "transient_x_" + name, "hbm_v_" + name,
                                           "transient_v_" + name});
    out.data.push_back(hbm);
    out.data.push_back(transient);
    out.data.push_back(grid.ToTime(omega * (d * c)).col(0));
    out.data.push_back(record.v.row(dof).transpose());
  }
  for (size_t i = 0; i < system.laws().size(); ++i) {
    for (LawSignal& signal :
         system.laws()[i]->Signals(system.context(static_cast<int>(i)), s.y, omega, grid)) {
      out.columns.push_back("hbm_law" + std::to_string(i) + "_" + signal.name);
      out.data.push_back(std::move(signal.samples));
    }
  }
  for (size_t j = 0; j < record.law_signals.size(); ++j) {
    for (const auto& [name, samples] : record.law_signals[j]) {
      out.columns.push_back("transient_law" + std::to_string(j) + "_" + name);
      out.data.push_back(samples);
    }
  }
  return out;
}

nlohmann::json TransientJson(const TransientResult& r, const PeriodMeasures& m) {
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
      {"period_multiple", r.period_multiple},
      {"last_period_difference", r.period_differences.empty() ? 0.0 : r.period_differences.back()}};
  if (r.last_period.t.size() > 0) {
    j["energy"] = m.energy;
    j["max_abs"] = m.max_abs;
    j["h1"] = m.h1;
    j["phases"] = PhasesJson(m.phase_names, m.phase_counts, m.phase_fractions);
    j["energy_balance"] = {{"work_input", r.last_period.work_input},
                           {"work_damping", r.last_period.work_damping},
                           {"work_laws", r.last_period.work_laws},
                           {"energy_change", r.last_period.energy_change},
                           {"relative_defect", m.energy_balance_defect}};
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

nlohmann::json RunChirps(const Case& the_case, const ChirpSettings& chirp,
                         TransientIntegrator& integrator, const std::string& out_dir,
                         std::ostream* progress) {
  nlohmann::json result = nlohmann::json::object();
  const double mean_omega = 0.5 * (chirp.omega_start + chirp.omega_end);
  const double duration = chirp.cycles * 2.0 * std::numbers::pi / mean_omega;
  for (const bool up : {true, false}) {
    if ((up && !chirp.up) || (!up && !chirp.down)) continue;
    const std::string name = up ? "up" : "down";
    const double w1 = up ? chirp.omega_start : chirp.omega_end;
    const double w2 = up ? chirp.omega_end : chirp.omega_start;
    if (progress != nullptr) {
      *progress << "nfrc validate: chirp " << name << " " << w1 << " -> " << w2 << " over "
                << duration << " time units\n";
    }
    const ChirpResult r = integrator.RunChirp(
        Excitation::Chirp(the_case.model.forcing, w1, w2, duration), chirp.samples_per_cycle);
    std::vector<std::string> columns = {"omega", "t_start", "t_end", "energy"};
    std::vector<Eigen::VectorXd> data(4, Eigen::VectorXd(r.cycles.size()));
    for (const std::string& n : the_case.output_names) columns.push_back("max_abs_" + n);
    data.resize(columns.size(), Eigen::VectorXd(r.cycles.size()));
    for (size_t k = 0; k < r.cycles.size(); ++k) {
      const ChirpCycle& c = r.cycles[k];
      data[0](k) = c.omega;
      data[1](k) = c.t_start;
      data[2](k) = c.t_end;
      data[3](k) = c.mean_energy;
      for (size_t i = 0; i < the_case.output_dofs.size(); ++i) {
        data[4 + i](k) = c.max_abs(the_case.output_dofs[i]);
      }
    }
    const std::string file = "chirp_" + name + ".csv";
    // A chirp has no steady state: kPeriodic only says that it ran to its end.
    const std::string status =
        r.status == TransientStatus::kPeriodic ? "completed" : ToString(r.status);
    if (!r.cycles.empty()) WriteCsv(out_dir + "/" + file, columns, data);
    result[name] = {{"status", status},
                    {"message", r.message},
                    {"method", r.method},
                    {"omega_start", w1},
                    {"omega_end", w2},
                    {"duration", duration},
                    {"sweep_rate", (w2 - w1) / duration},
                    {"integration_time", r.wall_seconds},
                    {"cycles", r.cycles.size()},
                    {"steps", r.steps},
                    {"events", r.events},
                    {"file", r.cycles.empty() ? "" : file}};
    if (progress != nullptr) {
      *progress << "nfrc validate: chirp " << name << ": " << status << ", " << r.cycles.size()
                << " cycles, " << r.wall_seconds << " s\n";
    }
  }
  return result;
}

}  // namespace

nlohmann::json RunValidation(const Case& the_case, const ValidationSettings& settings,
                             const std::string& out_dir, std::ostream* progress,
                             std::ostream* table, const std::atomic<bool>* stop,
                             const nlohmann::json& source) {
  std::filesystem::create_directories(out_dir);
  the_case.Validate();
  // One case, three uses: the time-domain laws, the traced branch, the crossing solves.
  TransientModel transient_model = MakeTransientModel(the_case.model, the_case.laws);
  const std::unique_ptr<TransientIntegrator> integrator =
      MakeTransientIntegrator(transient_model, settings.transient);
  const int n = settings.transient.samples_per_period;
  if (n < 2 * the_case.harmonics.max_harmonic() + 1) {
    throw InputError("validation.transient.samples_per_period: " + std::to_string(n) +
                     " cannot resolve harmonic " +
                     std::to_string(the_case.harmonics.max_harmonic()) + " (needs at least " +
                     std::to_string(2 * the_case.harmonics.max_harmonic() + 1) + ")");
  }

  if (the_case.method != Method::kArclength) {
    throw InputError(
        "continuation.method: validate needs the arclength branch (Newton "
        "solves at each omega), not \"" +
        std::string(ToString(the_case.method)) + "\"");
  }
  const Branch branch = RunCase(the_case, out_dir + "/hbm", progress, stop, source);

  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  PointAnalyzer analyzer(*system, the_case.output_dofs);

  nlohmann::json document = {
      {"case", the_case.path},
      {"branch", "hbm/branch.json"},
      {"branch_summary",
       {{"points", branch.points.size()},
        {"folds", branch.folds.size()},
        {"reason", ToString(branch.summary.reason)}}},
      {"output_dofs", the_case.output_names},
      {"start", settings.start == ValidationSettings::Start::kHbm ? "hbm" : "rest"},
      {"transient_options",
       {{"relative_tolerance", settings.transient.relative_tolerance},
        {"steady_tolerance", settings.transient.steady_tolerance},
        {"max_periods", settings.transient.max_periods},
        {"samples_per_period", n}}},
      {"points", nlohmann::json::array()}};
  const std::string json_path = out_dir + "/validation.json";
  WriteJsonAtomically(json_path, document);

  if (table != nullptr) {
    *table << std::left << std::setw(10) << "omega" << std::setw(8) << "branch" << std::setw(8)
           << "start" << std::setw(13) << "status" << std::setw(13) << "h1 HBM" << std::setw(13)
           << "h1 transient" << std::setw(10) << "rel diff" << std::setw(13) << "E HBM"
           << std::setw(13) << "E transient" << std::setw(10) << "rel diff" << std::setw(8)
           << "phases" << std::setw(8) << "time s"
           << "\n";
  }
  int signals = 0;
  for (double omega : settings.omegas) {
    if (stop != nullptr && stop->load()) break;
    std::vector<HbmSolution> solutions =
        SolveCrossings(*system, branch, omega, the_case.continuation, analyzer);
    nlohmann::json entry = {{"omega", omega},
                            {"hbm_solutions", nlohmann::json::array()},
                            {"transients", nlohmann::json::array()}};
    for (const HbmSolution& s : solutions) entry["hbm_solutions"].push_back(HbmJson(s));
    if (progress != nullptr) {
      *progress << "nfrc validate: omega " << omega << ": " << solutions.size()
                << " HBM solution(s)\n";
    }
    std::vector<int> starts;  // HBM solution index per transient, −1 from rest
    if (settings.start == ValidationSettings::Start::kHbm && !solutions.empty()) {
      for (size_t i = 0; i < solutions.size(); ++i) starts.push_back(static_cast<int>(i));
    } else {
      starts.push_back(-1);
    }
    int primary = -1;
    for (int from : starts) {
      if (stop != nullptr && stop->load()) break;
      InitialState start;
      if (from >= 0) {
        start = StateAtZero(*system, solutions[from].y, omega);
      } else {
        start.x = Eigen::VectorXd::Zero(the_case.model.model.num_dofs());
        start.v = start.x;
      }
      const TransientResult r = integrator->RunToSteadyState(omega, start);
      const bool recorded = r.last_period.t.size() > 0;
      const PeriodMeasures m =
          recorded ? MeasurePeriod(r.last_period, the_case.output_dofs) : PeriodMeasures{};
      nlohmann::json tj = TransientJson(r, m);
      tj["start"] = from >= 0 ? "hbm " + solutions[from].label : "rest";
      int match = -1;
      if (r.periodic() && !solutions.empty()) {
        double best = INFINITY;
        for (size_t i = 0; i < solutions.size(); ++i) {
          const double d = Distance(m, solutions[i]);
          if (d < best) {
            best = d;
            match = static_cast<int>(i);
          }
        }
        const HbmSolution& s = solutions[match];
        std::vector<double> h1, max_abs, rms;
        for (size_t i = 0; i < m.h1.size(); ++i) {
          h1.push_back(Relative(m.h1[i], s.measures.h1[i]));
          max_abs.push_back(Relative(m.max_abs[i], s.measures.max_abs[i]));
        }
        const SignalsOnGrid overlay =
            OverlaySignals(the_case, *system, s, r.last_period, omega, &rms);
        const std::string file = "signals_" + std::to_string(signals++) + ".csv";
        WriteCsv(out_dir + "/" + file, overlay.columns, overlay.data);
        tj["matches"] = s.label;
        tj["matches_solution"] = match;
        tj["stayed"] = from < 0 || from == match;
        tj["differences"] = {{"h1", h1},
                             {"max_abs", max_abs},
                             {"energy", Relative(m.energy, s.measures.energy)},
                             {"rms", rms},
                             {"same_phase_counts", m.phase_counts == s.phase_counts}};
        tj["signals"] = file;
        if (primary < 0 && (from < 0 || from == match)) {
          primary = static_cast<int>(entry["transients"].size());
          entry["hbm"] = HbmJson(s);
        }
      }
      if (table != nullptr) {
        const bool compared = match >= 0;
        *table << std::left << std::setw(10) << Fixed(omega, 6) << std::setw(8)
               << (compared ? solutions[match].label : "-") << std::setw(8)
               << (from >= 0 ? solutions[from].label : "rest") << std::setw(13)
               << ToString(r.status) << std::setw(13)
               << (compared ? Fixed(solutions[match].measures.h1[0], 6) : "-") << std::setw(13)
               << (recorded ? Fixed(m.h1[0], 6) : "-") << std::setw(10)
               << (compared ? Fixed(tj["differences"]["h1"][0].get<double>(), 2) : "-")
               << std::setw(13) << (compared ? Fixed(solutions[match].measures.energy, 6) : "-")
               << std::setw(13) << (recorded ? Fixed(m.energy, 6) : "-") << std::setw(10)
               << (compared ? Fixed(tj["differences"]["energy"].get<double>(), 2) : "-")
               << std::setw(8)
               << (compared
                       ? PhaseText(solutions[match].phase_counts) + ":" + PhaseText(m.phase_counts)
                       : "-")
               << std::setw(8) << Fixed(r.wall_seconds, 3) << "\n";
      }
      if (progress != nullptr) {
        *progress << "nfrc validate: omega " << omega << ", start "
                  << (from >= 0 ? solutions[from].label : "rest") << ": " << ToString(r.status)
                  << " after " << r.periods << " periods, " << r.wall_seconds << " s"
                  << (r.message.empty() ? "" : " (" + r.message + ")") << "\n";
      }
      entry["transients"].push_back(std::move(tj));
    }
    if (primary < 0 && !entry["transients"].empty()) primary = 0;
    if (primary >= 0) {
      entry["transient"] = entry["transients"][primary];
      if (!entry.contains("hbm") && entry["transient"].contains("matches_solution")) {
        entry["hbm"] = entry["hbm_solutions"][entry["transient"]["matches_solution"].get<int>()];
      }
    }
    document["points"].push_back(std::move(entry));
    WriteJsonAtomically(json_path, document);
  }
  if (settings.chirp.enabled && !(stop != nullptr && stop->load())) {
    document["chirp"] = RunChirps(the_case, settings.chirp, *integrator, out_dir, progress);
    WriteJsonAtomically(json_path, document);
  }
  return document;
}

bool ValidationComplete(const nlohmann::json& document) {
  for (const auto& point : document.at("points")) {
    if (point.at("hbm_solutions").empty()) return false;
    for (const auto& t : point.at("transients")) {
      if (t.at("status") == "failed") return false;
    }
  }
  if (document.contains("chirp")) {
    for (const auto& [direction, sweep] : document.at("chirp").items()) {
      if (sweep.at("status") == "failed") return false;
    }
  }
  return true;
}

}  // namespace nfrc
