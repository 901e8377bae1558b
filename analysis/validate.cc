#include "analysis/validate.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <ostream>
#include <string>

#include "analysis/bifurcation.h"
#include "core/errors.h"
#include "validation/make_integrator.h"

namespace nfrc {
namespace {

double Relative(double value, double reference) {
  return std::abs(value - reference) / std::max(std::abs(reference), 1e-300);
}

// x(0) and ẋ(0) of every model DOF of an HBM solution and, when a time law has memory, its
// own unknowns at t = 0 from the harmonic law's signal (TimeLaw::OwnSignal; the fine grid's
// first sample is θ = 0): a Jenkins slider starts where the HBM solution has it, not at rest.
InitialState StateAtZero(const TransientModel& model, HarmonicSystem& system,
                         const CrossingSolution& s) {
  const FourierTransform& fourier = system.fourier();
  const Eigen::MatrixXd xt = s.coefficients.transpose();
  const Eigen::MatrixXd vt = s.omega * fourier.DerivativeMatrix() * xt;
  InitialState start;
  start.x = fourier.ToTime(xt).row(0).transpose();
  start.v = fourier.ToTime(vt).row(0).transpose();
  int num_own = 0;
  for (const auto& law : model.laws) num_own += law->NumOwn();
  Eigen::VectorXd own = Eigen::VectorXd::Zero(num_own);
  bool carried = false;
  int offset = 0;
  for (size_t l = 0; l < model.laws.size(); ++l) {
    for (int k = 0; k < model.laws[l]->NumOwn(); ++k, ++offset) {
      const std::string signal = model.laws[l]->OwnSignal(k);
      if (signal.empty()) continue;
      const std::string column = "law" + std::to_string(model.law_sources[l]) + "_" + signal;
      const std::vector<std::string>& names = s.signals.fine.names;
      const auto found = std::find(names.begin(), names.end(), column);
      assert(found != names.end() && "a time law's OwnSignal names a signal of its harmonic law");
      own(offset) = s.signals.fine.columns[static_cast<size_t>(found - names.begin())](0);
      carried = true;
    }
  }
  if (carried) start.own = std::move(own);
  return start;
}

// Distance used to say which HBM solution a transient landed on: relative differences of the
// first-harmonic amplitudes and of the energy.
double Distance(const PeriodMeasures& t, const CrossingSolution& s) {
  const PointMeasures& hbm = s.signals.measures.response;
  double d = Relative(t.energy, hbm.energy);
  for (size_t i = 0; i < t.h1.size(); ++i) d += Relative(t.h1[i], hbm.h1[i]);
  return d;
}

// The HBM solution and the transient's recorded period on the transient's grid
// (θ = 2πi/N from a period boundary, where the excitation phase is a multiple of 2π), and
// the RMS differences of x per output DOF.
SignalTable OverlaySignals(const Case& the_case, HarmonicSystem& system, const CrossingSolution& s,
                           const PeriodRecord& record, std::vector<double>* rms) {
  const double omega = s.omega;
  const int n = static_cast<int>(record.t.size());
  const HarmonicSet& set = system.harmonic_set();
  const FourierTransform grid(HarmonicSet(set.max_harmonic(), set.odd_only(), n));
  SignalTable out;
  out.names = {"theta", "t"};
  out.columns = {Angles(n)};
  out.columns.push_back(out.columns[0] / omega);
  const Eigen::MatrixXd& d = system.fourier().DerivativeMatrix();
  for (size_t i = 0; i < the_case.output_dofs.size(); ++i) {
    const int dof = the_case.output_dofs[i];
    const std::string& name = the_case.output_names[i];
    const Eigen::VectorXd c = system.DofCoefficients(s.y, omega, dof);
    const Eigen::VectorXd hbm = grid.ToTime(c).col(0);
    const Eigen::VectorXd transient = record.x.row(dof).transpose();
    rms->push_back(std::sqrt((hbm - transient).squaredNorm() / n) /
                   std::max(std::sqrt(hbm.squaredNorm() / n), 1e-300));
    out.names.insert(out.names.end(), {"hbm_x_" + name, "transient_x_" + name, "hbm_v_" + name,
                                       "transient_v_" + name});
    out.columns.push_back(hbm);
    out.columns.push_back(transient);
    out.columns.push_back(grid.ToTime(omega * (d * c)).col(0));
    out.columns.push_back(record.v.row(dof).transpose());
  }
  for (size_t i = 0; i < system.laws().size(); ++i) {
    for (LawSignal& signal :
         system.laws()[i]->Signals(system.context(static_cast<int>(i)), s.y, omega, grid)) {
      out.names.push_back("hbm_law" + std::to_string(i) + "_" + signal.name);
      out.columns.push_back(std::move(signal.samples));
    }
  }
  for (size_t j = 0; j < record.law_signals.size(); ++j) {
    for (const auto& [name, samples] : record.law_signals[j]) {
      out.names.push_back("transient_law" + std::to_string(j) + "_" + name);
      out.columns.push_back(samples);
    }
  }
  return out;
}

// The nearest solution to a periodic transient and the differences to it.
TransientComparison Compare(const Case& the_case, HarmonicSystem& system,
                            const std::vector<CrossingSolution>& solutions,
                            const TransientRun& run) {
  const PeriodMeasures& m = run.measures;
  TransientComparison c;
  double best = INFINITY;
  for (size_t i = 0; i < solutions.size(); ++i) {
    const double d = Distance(m, solutions[i]);
    if (d < best) {
      best = d;
      c.solution = static_cast<int>(i);
    }
  }
  const CrossingSolution& s = solutions[c.solution];
  const PointMeasures& hbm = s.signals.measures.response;
  c.label = s.label;
  c.stayed = run.start_solution < 0 || run.start_solution == c.solution;
  for (size_t i = 0; i < m.h1.size(); ++i) {
    c.h1.push_back(Relative(m.h1[i], hbm.h1[i]));
    c.max_abs.push_back(Relative(m.max_abs[i], hbm.max_abs[i]));
  }
  c.energy = Relative(m.energy, hbm.energy);
  std::vector<int> hbm_counts;
  for (const PhaseSummary& phase : s.phases) hbm_counts.push_back(phase.count);
  c.same_phase_counts = m.phase_counts == hbm_counts;
  c.overlay = OverlaySignals(the_case, system, s, run.result.last_period, &c.rms);
  return c;
}

// The transients at one ω: from each HBM solution, or from rest (start rest, or no solution).
void RunTransients(const Case& the_case, const TransientModel& model,
                   const ValidationSettings& settings, HarmonicSystem& system,
                   TransientIntegrator& integrator, const ValidationOptions& options,
                   ValidationPoint* point) {
  const double omega = point->omega;
  const std::vector<CrossingSolution>& solutions = point->solutions;
  std::vector<int> starts;  // HBM solution index per transient, −1 from rest
  if (settings.start == ValidationSettings::Start::kHbm && !solutions.empty()) {
    for (size_t i = 0; i < solutions.size(); ++i) starts.push_back(static_cast<int>(i));
  } else {
    starts.push_back(-1);
  }
  for (int from : starts) {
    if (options.stop != nullptr && options.stop->load()) break;
    TransientRun& run = point->transients.emplace_back();
    run.start_solution = from;
    run.start = from >= 0 ? "hbm " + solutions[from].label : "rest";
    InitialState start;
    if (from >= 0) {
      start = StateAtZero(model, system, solutions[from]);
    } else {
      start.x = Eigen::VectorXd::Zero(the_case.model.model.num_dofs());
      start.v = start.x;
    }
    run.result = integrator.RunToSteadyState(omega, start);
    const TransientResult& r = run.result;
    run.recorded = r.last_period.t.size() > 0;
    if (run.recorded) run.measures = MeasurePeriod(r.last_period, the_case.output_dofs);
    if (r.periodic() && !solutions.empty()) {
      run.comparison = Compare(the_case, system, solutions, run);
      if (point->primary < 0 && run.comparison->stayed) {
        point->primary = static_cast<int>(point->transients.size()) - 1;
      }
    }
    if (options.observer != nullptr) options.observer->OnTransient(*point);
    if (options.progress != nullptr) {
      *options.progress << "nfrc validate: omega " << omega << ", start "
                        << (from >= 0 ? solutions[from].label : "rest") << ": "
                        << ToString(r.status) << " after " << r.periods << " periods, "
                        << r.wall_seconds << " s"
                        << (r.message.empty() ? "" : " (" + r.message + ")") << "\n";
    }
  }
  if (point->primary < 0 && !point->transients.empty()) point->primary = 0;
}

// Hill's multipliers of each HBM solution, and how far they are from the transient ones.
void CompareStability(const Case& the_case, HarmonicSystem& system, ValidationPoint* point) {
  if (!the_case.stability.enabled) return;
  StabilityMonitor monitor(system, the_case.stability, the_case.continuation);
  for (size_t i = 0; i < point->solutions.size(); ++i) {
    SolutionStability& stability = point->stability[i];
    stability.hill = monitor.Analyze(point->solutions[i].y, point->omega);
    if (!stability.hill.computed || !stability.monodromy || !stability.monodromy->ok) continue;
    const std::vector<std::complex<double>>& transient = stability.monodromy->multipliers;
    if (transient.empty()) continue;
    double worst = 0.0;
    for (const std::complex<double>& mu : stability.hill.multipliers) {
      if (std::abs(mu) < SolutionStability::kCompared) continue;
      double nearest = std::numeric_limits<double>::infinity();
      for (const std::complex<double>& other : transient) {
        nearest = std::min(nearest, std::abs(mu - other));
      }
      worst = std::max(worst, nearest);
    }
    stability.multiplier_difference = worst;
    stability.max_modulus_difference =
        std::abs(stability.hill.max_modulus - stability.monodromy->max_modulus());
  }
}

// The transient monodromy of each HBM solution at ω, from its state at t = 0.
void RunMonodromies(const TransientModel& model, const ValidationSettings& settings,
                    HarmonicSystem& system, TransientIntegrator& integrator,
                    const ValidationOptions& options, ValidationPoint* point) {
  point->stability.resize(point->solutions.size());
  if (!settings.monodromy.enabled) return;
  for (size_t i = 0; i < point->solutions.size(); ++i) {
    if (options.stop != nullptr && options.stop->load()) break;
    const CrossingSolution& s = point->solutions[i];
    std::optional<MonodromyResult>& slot = point->stability[i].monodromy;
    slot = ComputeMonodromy(integrator, model, point->omega, StateAtZero(model, system, s),
                            settings.monodromy, options.stop);
    const MonodromyResult& m = *slot;
    if (options.progress != nullptr) {
      *options.progress << "nfrc validate: omega " << point->omega << ", solution " << s.label
                        << ": monodromy ";
      if (m.ok) {
        *options.progress << "max |mu| " << m.max_modulus() << " ("
                          << (m.max_modulus() < 1.0 ? "stable" : "unstable") << ")";
      } else {
        *options.progress << "failed (" << m.message << ")";
      }
      *options.progress << ", " << m.integrations << " periods integrated, " << m.wall_seconds
                        << " s\n";
    }
  }
}

void RunChirps(const Case& the_case, const ChirpSettings& chirp, TransientIntegrator& integrator,
               const ValidationOptions& options, std::vector<ChirpRun>* runs) {
  const double mean_omega = 0.5 * (chirp.omega_start + chirp.omega_end);
  const double duration = chirp.cycles * 2.0 * std::numbers::pi / mean_omega;
  for (const bool up : {true, false}) {
    if ((up && !chirp.up) || (!up && !chirp.down)) continue;
    if (options.stop != nullptr && options.stop->load()) break;
    ChirpRun& run = runs->emplace_back();
    run.direction = up ? "up" : "down";
    run.omega_start = up ? chirp.omega_start : chirp.omega_end;
    run.omega_end = up ? chirp.omega_end : chirp.omega_start;
    run.duration = duration;
    run.sweep_rate = (run.omega_end - run.omega_start) / duration;
    if (options.progress != nullptr) {
      *options.progress << "nfrc validate: chirp " << run.direction << " " << run.omega_start
                        << " -> " << run.omega_end << " over " << duration << " time units\n";
    }
    run.result = integrator.RunChirp(
        Excitation::Chirp(the_case.model.forcing, run.omega_start, run.omega_end, duration),
        chirp.samples_per_cycle);
    if (options.observer != nullptr) options.observer->OnChirp(run);
    if (options.progress != nullptr) {
      *options.progress << "nfrc validate: chirp " << run.direction << ": "
                        << ChirpStatusName(run.result.status) << ", " << run.result.cycles.size()
                        << " cycles, " << run.result.wall_seconds << " s\n";
    }
  }
}

bool Complete(const ValidationResult& result) {
  for (const ValidationPoint& point : result.points) {
    if (point.solutions.empty()) return false;
    for (const TransientRun& run : point.transients) {
      if (run.result.status == TransientStatus::kFailed ||
          run.result.status == TransientStatus::kInterrupted) {
        return false;
      }
    }
  }
  for (const ChirpRun& run : result.chirps) {
    if (run.result.status == TransientStatus::kFailed ||
        run.result.status == TransientStatus::kInterrupted) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::string ChirpStatusName(TransientStatus status) {
  return status == TransientStatus::kPeriodic ? "completed" : ToString(status);
}

ValidationResult ValidateCase(const Case& the_case, const ValidationSettings& settings,
                              const ValidationOptions& options) {
  the_case.Validate();
  settings.Validate();
  // One case, three uses: the time-domain laws, the traced branch, the crossing solves.
  TransientModel transient_model = MakeTransientModel(the_case.model, the_case.laws);
  const std::unique_ptr<TransientIntegrator> integrator =
      MakeTransientIntegrator(transient_model, settings.transient);
  integrator->set_stop(options.stop);
  const int n = settings.transient.samples_per_period;
  const int h = the_case.harmonics.max_harmonic();
  if (n < 2 * h + 1) {
    throw InputError("validation.transient.samples_per_period: " + std::to_string(n) +
                     " cannot resolve harmonic " + std::to_string(h) + " (needs at least " +
                     std::to_string(2 * h + 1) + ")");
  }
  if (the_case.method != Method::kArclength) {
    throw InputError(
        "continuation.method: validate needs the arclength branch (Newton "
        "solves at each omega), not \"" +
        std::string(ToString(the_case.method)) + "\"");
  }

  ValidationResult result;
  TraceOptions trace_options;
  trace_options.progress = options.progress;
  trace_options.stop = options.stop;
  if (options.observer != nullptr) trace_options.observer = options.observer->OnTraceStart();
  result.trace = TraceCase(the_case, trace_options);
  if (options.observer != nullptr) options.observer->OnBranch(result.trace);

  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);
  for (double omega : settings.omegas) {
    if (options.stop != nullptr && options.stop->load()) break;
    ValidationPoint& point = result.points.emplace_back();
    point.omega = omega;
    for (CrossingSolution& s : SolveCrossings(the_case, *system, result.trace.branch, omega)) {
      if (s.converged) point.solutions.push_back(std::move(s));
    }
    if (options.progress != nullptr) {
      *options.progress << "nfrc validate: omega " << omega << ": " << point.solutions.size()
                        << " HBM solution(s)\n";
    }
    RunTransients(the_case, transient_model, settings, *system, *integrator, options, &point);
    RunMonodromies(transient_model, settings, *system, *integrator, options, &point);
    CompareStability(the_case, *system, &point);
    if (options.observer != nullptr) options.observer->OnPoint(point);
  }
  if (settings.chirp.enabled && !(options.stop != nullptr && options.stop->load())) {
    RunChirps(the_case, settings.chirp, *integrator, options, &result.chirps);
  }
  result.interrupted = options.stop != nullptr && options.stop->load();
  result.complete = Complete(result) && !result.interrupted;
  if (options.observer != nullptr) options.observer->OnEnd(result);
  return result;
}

}  // namespace nfrc
