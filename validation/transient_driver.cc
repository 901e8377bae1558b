#include "validation/transient_driver.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

#include "core/errors.h"
#include "validation/steady_state.h"

namespace nfrc {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The quadratures grow with time; restarting them this often (in periods or chirp cycles)
// keeps them of the order of one period's increment, for IDA's error test on them and for the
// round-off of the differences taken here.
constexpr int kQuadratureResetPeriods = 32;
// Newton iterations for the time of a chirp cycle's end (converges in a few).
constexpr int kPhaseNewtonIterations = 50;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// max_seconds after `start`; beyond 1e9 s (about 30 years) the limit is that.
Clock::time_point Deadline(Clock::time_point start, double max_seconds) {
  return start + std::chrono::duration_cast<Clock::duration>(
                     std::chrono::duration<double>(std::min(max_seconds, 1e9)));
}

// A start value per DOF (zeros if none given).
Eigen::VectorXd StartValues(const Eigen::VectorXd& values, int n, const std::string& field) {
  if (values.size() == 0) return Eigen::VectorXd::Zero(n);
  if (values.size() != n) throw InputError(field + ": needs one value per DOF");
  return values;
}

// z = (x, v/ω): displacements and velocities in one unit (m), for the steady-state rule.
Eigen::VectorXd PhaseState(const Eigen::Ref<const Eigen::VectorXd>& x,
                           const Eigen::Ref<const Eigen::VectorXd>& v, double omega) {
  Eigen::VectorXd z(x.size() + v.size());
  z << x, v / omega;
  return z;
}

double MaxAbs(const Eigen::VectorXd& z) { return z.size() > 0 ? z.cwiseAbs().maxCoeff() : 0.0; }

// Time at which the chirp's phase reaches `target` (rad), by Newton from `guess` (s): φ is
// increasing and convex or concave, so Newton converges monotonically.
double PhaseTime(const Excitation& chirp, double target, double guess) {
  double t = guess;
  for (int i = 0; i < kPhaseNewtonIterations; ++i) {
    const double step = (chirp.Phase(t) - target) / chirp.InstantaneousOmega(t);
    t -= step;
    if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(t))) break;
  }
  return t;
}

}  // namespace

TransientDriver::TransientDriver(const TransientModel& model, TransientOptions options,
                                 std::unique_ptr<TransientStepper> stepper)
    : model_(model), options_(std::move(options)), stepper_(std::move(stepper)) {
  options_.Validate();
}

TransientDriver::~TransientDriver() = default;

double TransientDriver::Energy() const {
  const auto x = stepper_->x();
  const auto v = stepper_->v();
  return 0.5 * v.dot(model_.model.mass * v) + 0.5 * x.dot(model_.model.stiffness * x);
}

bool TransientDriver::Advance(double t, std::string* failure) {
  const StepOutcome outcome = stepper_->AdvanceTo(t);
  if (outcome == StepOutcome::kFailed) {
    *failure = stepper_->message();
    return false;
  }
  if (outcome == StepOutcome::kOutOfTime || Clock::now() > deadline_) {
    std::ostringstream out;
    out << "wall-clock limit of " << options_.max_seconds << " s reached at t = " << stepper_->t();
    *failure = out.str();
    return false;
  }
  return true;
}

bool TransientDriver::RecordPeriod(int p, double omega, PeriodRecord* record, double* scale,
                                   std::string* failure) {
  const int n = model_.num_dofs();
  const int samples = options_.samples_per_period;
  const double period = kTwoPi / omega;
  const double t0 = (p - 1) * period;
  const double t_end = p * period;
  if (!stepper_->BeginSegment(t_end)) {
    *failure = stepper_->message();
    return false;
  }
  const StepperQuadratures q0 = stepper_->Quadratures();
  const double energy0 = Energy();
  record->t0 = t0;
  record->period = period;
  record->t.resize(samples);
  record->x.resize(n, samples);
  record->v.resize(n, samples);
  record->law_signals.clear();
  *scale = 0.0;
  for (int i = 0; i < samples; ++i) {
    record->t(i) = t0 + i * period / samples;
    if (i > 0 && !Advance(record->t(i), failure)) return false;
    record->x.col(i) = stepper_->x();
    record->v.col(i) = stepper_->v();
    *scale = std::max(*scale, MaxAbs(PhaseState(stepper_->x(), stepper_->v(), omega)));
    const LawSignalValues signals = stepper_->Signals();
    if (i == 0) {
      record->law_signals.resize(signals.size());
      for (size_t l = 0; l < signals.size(); ++l) {
        for (const auto& [name, value] : signals[l]) {
          record->law_signals[l].emplace_back(name, Eigen::VectorXd::Zero(samples));
        }
      }
    }
    for (size_t l = 0; l < signals.size() && l < record->law_signals.size(); ++l) {
      auto& stored = record->law_signals[l];
      for (size_t k = 0; k < signals[l].size() && k < stored.size(); ++k) {
        stored[k].second(i) = signals[l][k].second;
      }
    }
  }
  if (!Advance(t_end, failure)) return false;
  *scale = std::max(*scale, MaxAbs(PhaseState(stepper_->x(), stepper_->v(), omega)));
  const StepperQuadratures q = stepper_->Quadratures();
  record->mean_energy = (q.energy - q0.energy) / period;
  record->work_input = q.work_input - q0.work_input;
  record->work_damping = q.work_damping - q0.work_damping;
  record->work_laws = q.work_laws - q0.work_laws;
  record->energy_change = Energy() - energy0;
  record->phases = stepper_->PhaseLogs();
  return true;
}

Excitation TransientDriver::HarmonicExcitation(double omega) const {
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw InputError("validation.omega: must be finite and > 0");
  }
  return Excitation::Harmonic(model_.forcing, omega);
}

StepperStart TransientDriver::StartFrom(const Excitation& excitation, const InitialState& start,
                                        Clock::time_point clock_start) {
  const int n = model_.num_dofs();
  StepperStart begin;
  begin.excitation = &excitation;
  begin.x = StartValues(start.x, n, "validation.initial_state.x");
  begin.v = StartValues(start.v, n, "validation.initial_state.v");
  begin.own = start.own;
  begin.samples_per_cycle = options_.samples_per_period;
  deadline_ = Deadline(clock_start, options_.max_seconds);
  begin.deadline = deadline_;
  return begin;
}

TransientResult TransientDriver::RunToSteadyState(double omega, const InitialState& start) {
  const Excitation excitation = HarmonicExcitation(omega);
  const Clock::time_point clock_start = Clock::now();
  const StepperStart begin = StartFrom(excitation, start, clock_start);

  TransientResult result;
  result.method = stepper_->method();
  result.omega = omega;
  auto finish = [&](TransientStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.statistics = stepper_->Statistics();
    result.steps = result.statistics.steps;
    result.events = result.statistics.events;
    result.t_end = stepper_->t();
    result.wall_seconds = Seconds(clock_start);
    return std::move(result);
  };
  if (!stepper_->Start(begin)) return finish(TransientStatus::kFailed, stepper_->message());

  SteadyStateMonitor monitor(options_);
  monitor.Start(PhaseState(stepper_->x(), stepper_->v(), omega));
  std::string failure;
  PeriodRecord record;  // the period being integrated; its storage is reused
  for (int p = 1; p <= options_.max_periods; ++p) {
    if (stop_requested()) {
      return finish(TransientStatus::kInterrupted,
                    "interrupted after " + std::to_string(p - 1) + " periods");
    }
    if (p > 1 && (p - 1) % kQuadratureResetPeriods == 0 && !stepper_->ResetQuadratures()) {
      return finish(TransientStatus::kFailed, stepper_->message());
    }
    double scale = 0.0;
    if (!RecordPeriod(p, omega, &record, &scale, &failure)) {
      return finish(TransientStatus::kFailed, failure);
    }
    std::swap(result.last_period, record);
    result.periods = p;
    result.period_differences.push_back(
        monitor.EndPeriod(PhaseState(stepper_->x(), stepper_->v(), omega), scale));
    if (monitor.Steady()) return finish(TransientStatus::kPeriodic, "");
  }
  result.period_multiple = monitor.PeriodMultiple();
  std::string message =
      "no T-periodic steady state within " + std::to_string(options_.max_periods) + " periods";
  if (result.period_multiple > 0) {
    message += " (" + std::to_string(result.period_multiple) + "T-periodic)";
  }
  return finish(TransientStatus::kNotPeriodic, message);
}

bool TransientDriver::IntegratePeriods(double omega, const InitialState& start, int periods,
                                       InitialState* end, std::string* message) {
  const Excitation excitation = HarmonicExcitation(omega);
  if (periods < 1) throw InputError("IntegratePeriods: periods must be >= 1");
  // The same start as RunToSteadyState's (the explicit scheme's resolution included), so
  // that the period map is the one the steady-state runs integrate.
  const StepperStart begin = StartFrom(excitation, start, Clock::now());
  if (!stepper_->Start(begin)) {
    *message = stepper_->message();
    return false;
  }
  const double period = kTwoPi / omega;
  for (int p = 1; p <= periods; ++p) {
    if (stop_requested()) {
      *message = "interrupted";
      return false;
    }
    if (p > 1 && (p - 1) % kQuadratureResetPeriods == 0 && !stepper_->ResetQuadratures()) {
      *message = stepper_->message();
      return false;
    }
    // One segment per period, as RunToSteadyState (IDA stops exactly at its end); no samples
    // in between: IDA only interpolates at them, so the steps are the same.
    if (!stepper_->BeginSegment(p * period)) {
      *message = stepper_->message();
      return false;
    }
    if (!Advance(p * period, message)) return false;
  }
  end->x = stepper_->x();
  end->v = stepper_->v();
  end->own = stepper_->own();
  return true;
}

ChirpResult TransientDriver::RunChirp(const Excitation& chirp, int samples_per_cycle) {
  if (!chirp.chirp || !(chirp.duration > 0.0) || !(chirp.omega > 0.0) || !(chirp.omega_end > 0.0)) {
    throw InputError("validation.chirp: needs omega_start, omega_end and duration > 0");
  }
  if (samples_per_cycle < 1) throw InputError("validation.chirp.samples_per_cycle: must be >= 1");
  const int n = model_.num_dofs();
  StepperStart begin;
  begin.excitation = &chirp;
  begin.x = Eigen::VectorXd::Zero(n);
  begin.v = Eigen::VectorXd::Zero(n);
  begin.samples_per_cycle = samples_per_cycle;
  const Clock::time_point clock_start = Clock::now();
  deadline_ = Deadline(clock_start, options_.max_seconds);
  begin.deadline = deadline_;

  ChirpResult result;
  result.method = stepper_->method();
  auto finish = [&](TransientStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.statistics = stepper_->Statistics();
    result.steps = result.statistics.steps;
    result.events = result.statistics.events;
    result.wall_seconds = Seconds(clock_start);
    return std::move(result);
  };
  if (!stepper_->Start(begin)) return finish(TransientStatus::kFailed, stepper_->message());

  std::string failure;
  double t_start = 0.0;
  for (int k = 1;; ++k) {
    // Cycle k ends where φ = 2πk; only whole cycles within the duration are recorded.
    const double t_end =
        PhaseTime(chirp, kTwoPi * k, t_start + kTwoPi / chirp.InstantaneousOmega(t_start));
    if (t_end > chirp.duration) break;
    if (stop_requested()) {
      return finish(TransientStatus::kInterrupted,
                    "interrupted after " + std::to_string(k - 1) + " cycles");
    }
    if (!stepper_->BeginSegment(t_end)) {
      return finish(TransientStatus::kFailed, stepper_->message());
    }
    const double energy0 = stepper_->Quadratures().energy;
    ChirpCycle cycle;
    cycle.t_start = t_start;
    cycle.t_end = t_end;
    cycle.max_abs = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < samples_per_cycle; ++i) {
      const double t = t_start + i * (t_end - t_start) / samples_per_cycle;
      if (i > 0 && !Advance(t, &failure)) return finish(TransientStatus::kFailed, failure);
      cycle.max_abs = cycle.max_abs.cwiseMax(stepper_->x().cwiseAbs());
    }
    if (!Advance(t_end, &failure)) return finish(TransientStatus::kFailed, failure);
    cycle.mean_energy = (stepper_->Quadratures().energy - energy0) / (t_end - t_start);
    cycle.omega = kTwoPi / (t_end - t_start);  // (φ(t_end) − φ(t_start)) / Δt
    result.cycles.push_back(std::move(cycle));
    t_start = t_end;
    if (k % kQuadratureResetPeriods == 0 && !stepper_->ResetQuadratures()) {
      return finish(TransientStatus::kFailed, stepper_->message());
    }
  }
  // The rest of the duration, short of a whole cycle, is integrated but not recorded.
  if (!stepper_->BeginSegment(chirp.duration)) {
    return finish(TransientStatus::kFailed, stepper_->message());
  }
  if (!Advance(chirp.duration, &failure)) return finish(TransientStatus::kFailed, failure);
  return finish(TransientStatus::kPeriodic, "");
}

}  // namespace nfrc
