#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <string>
#include <vector>

#include "validation/excitation.h"

namespace nfrc {

// Options of a transient run to periodic steady state. Field names are the case file's
// "validation.transient" keys.
struct TransientOptions {
  enum class LinearSolver { kAuto, kDense, kKlu };

  // IDA relative tolerance; about 100× tighter than the accuracy wanted on amplitudes.
  double relative_tolerance = 1e-10;
  // Absolute tolerance as a fraction of the state's scale (the linear response amplitude at
  // ω for x, ω times it for v): atol = relative_tolerance × absolute_scale_factor × scale.
  double absolute_scale_factor = 1e-3;
  // Steady state, one rule for every integrator (validation/steady_state.h). With the state
  // z = (x, v/ω) (m, and m per radian of excitation phase: both in displacement units) at the
  // period boundaries t_p = pT, period p's difference is
  //   d_p = max_i |z_i(t_p) − z_i(t_{p−1})| / max over the recorded period of max_i |z_i|,
  // the denominator taken over the period's samples and its end state (d_p = 0 if that is
  // 0). A difference counts when it is strictly below steady_tolerance; the run is T-periodic
  // at the first period p ≥ min_periods that ends `steady_periods` consecutive counting
  // periods. Only when max_periods is reached without it are kT-periodic orbits looked for,
  // k = 2..max_period_multiple, by the same rule: the smallest k for which each of the last
  // `steady_periods` boundary states differs from the one k periods before it by strictly
  // less than steady_tolerance × the largest max|z| of the k periods between them.
  double steady_tolerance = 1e-7;
  int steady_periods = 2;
  int min_periods = 4;            // periods integrated before steady state may be declared
  int max_periods = 20000;        // then the run stops and reports "not periodic"
  double max_seconds = 600;       // wall-clock limit per run (s); reported as a failure
  int samples_per_period = 1024;  // uniform samples of the recorded period
  // When not T-periodic: the largest k for which a kT-periodic orbit is looked for.
  int max_period_multiple = 8;
  // IDA's largest step as a fraction of the period (so no event is stepped over).
  double max_step_fraction = 1.0 / 16;
  // Dense linear algebra up to kDenseLimit unknowns, KLU beyond (kAuto).
  LinearSolver linear_solver = LinearSolver::kAuto;
  static constexpr int kDenseLimit = 64;
  // Explicit scheme (rigid contacts): time step as a fraction of the stability limit 2/ω_max;
  // rounded down so that a whole number of steps makes one period.
  double explicit_step_fraction = 0.5;

  // Throws InputError("validation.transient.<field>: ...") for a bad value.
  void Validate() const;
};

enum class TransientStatus {
  kPeriodic,     // reached a T-periodic steady state
  kNotPeriodic,  // max_periods reached without it (period_multiple says if kT-periodic)
  kFailed,       // the integrator failed (message says why) or max_seconds passed
  kInterrupted,  // the stop flag was raised (TransientIntegrator::set_stop): ended at a period
};
const char* ToString(TransientStatus status);

// Phase changes of one law over the recorded period: the mode flag at the period's start and
// the times (absolute) at which InPhase() changed, with the new value.
struct LawPhaseLog {
  std::string type;
  std::string phase_name;  // "stick", "contact", or empty for laws without a phase
  bool in_phase_at_start = false;
  std::vector<std::pair<double, bool>> changes;
  // Number of phases (entries into the phase; 1 if in phase throughout) and the share of the
  // period they cover.
  int CountPhases(double t0, double period) const;
  double PhaseFraction(double t0, double period) const;
};

// One period [t0, t0 + T) sampled uniformly at t0 + iT/N, i = 0..N−1.
struct PeriodRecord {
  double t0 = 0.0;
  double period = 0.0;
  Eigen::VectorXd t;
  Eigen::MatrixXd x;  // num_dofs × N
  Eigen::MatrixXd v;  // num_dofs × N
  // Per law: named signals (num laws × signals), each N samples.
  std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> law_signals;
  std::vector<LawPhaseLog> phases;
  // Exact over the period (integrated with the state): mean total energy
  // (1/T)∫(½vᵀMv + ½xᵀKx)dt, input work ∫fᵀv, damping dissipation ∫vᵀCv, work absorbed by
  // the laws ∫f_nlᵀv, and the change of total energy E(t0 + T) − E(t0).
  double mean_energy = 0.0;
  double work_input = 0.0;
  double work_damping = 0.0;
  double work_laws = 0.0;
  double energy_change = 0.0;
};

// Where a run starts: displacements and velocities of every DOF at t = 0 (zero: rest).
struct InitialState {
  Eigen::VectorXd x;
  Eigen::VectorXd v;
  // The laws' own unknowns (TransientModel::laws in order, TimeLaw::NumOwn each), of which a
  // start reads only the differential ones: a law's memory (a Jenkins slider's force). Empty:
  // they start from the momentum rows (a sticking force from the start's displacements). At
  // the end of IntegratePeriods, every own unknown (empty for a scheme without them).
  Eigen::VectorXd own = Eigen::VectorXd();
};

// Work counters of one transient run, summed over the whole run (every re-initialisation of
// the integrator included). IDA fills all of them from SUNDIALS (IDAGetNumSteps,
// IDAGetNumResEvals, IDAGetNumJacEvals, IDAGetNumNonlinSolvIters,
// IDAGetNumNonlinSolvConvFails, IDAGetNumErrTestFails); the explicit central-difference
// scheme has no residual, Jacobian, Newton iteration or error test: it fills steps and events
// and leaves the others 0.
struct TransientStatistics {
  long steps = 0;
  long residual_evaluations = 0;
  long jacobian_evaluations = 0;
  long nonlinear_iterations = 0;
  long nonlinear_convergence_failures = 0;
  long error_test_failures = 0;
  long events = 0;  // mode switches (IDA) or contact openings and closings (explicit scheme)

  TransientStatistics& operator+=(const TransientStatistics& other);
};

struct TransientResult {
  TransientStatus status = TransientStatus::kFailed;
  std::string message;
  std::string method;  // "ida" or "central_difference"
  double omega = 0.0;
  int periods = 0;  // periods integrated
  double t_end = 0.0;
  double wall_seconds = 0.0;  // integration time
  int period_multiple = 0;    // k ≥ 2 if a kT-periodic orbit was found instead, else 0
  // Relative state change at each period boundary (the steady-state measure), per period.
  std::vector<double> period_differences;
  long steps = 0;   // statistics.steps
  long events = 0;  // statistics.events: mode switches
  TransientStatistics statistics;
  PeriodRecord last_period;  // the last period integrated

  bool periodic() const { return status == TransientStatus::kPeriodic; }
};

// One excitation cycle of a chirp run (between successive multiples of 2π of the phase).
struct ChirpCycle {
  double t_start = 0.0;
  double t_end = 0.0;
  double omega = 0.0;        // mean instantaneous ω over the cycle
  Eigen::VectorXd max_abs;   // per DOF, max |x| over the cycle (sampled)
  double mean_energy = 0.0;  // (1/Δt)∫(½vᵀMv + ½xᵀKx)dt over the cycle
};

struct ChirpResult {
  TransientStatus status = TransientStatus::kFailed;  // kPeriodic here means "completed"
  std::string message;
  std::string method;
  double wall_seconds = 0.0;
  long steps = 0;   // statistics.steps
  long events = 0;  // statistics.events
  TransientStatistics statistics;
  std::vector<ChirpCycle> cycles;
};

// A transient integrator of a TransientModel: what callers use (MakeTransientIntegrator). The
// implementations are the one TransientDriver (validation/transient_driver.h) over a stepper.
class TransientIntegrator {
 public:
  virtual ~TransientIntegrator() = default;
  // Raised (a signal handler's flag): a run ends at its next period (or chirp cycle) boundary
  // with kInterrupted, its last whole period recorded. Null: never.
  void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }
  bool stop_requested() const { return stop_ != nullptr && stop_->load(); }
  // Integrates the harmonic excitation at ω from `start` until a T-periodic steady state
  // (T = 2π/ω), max_periods or failure; records the last period.
  virtual TransientResult RunToSteadyState(double omega, const InitialState& start) = 0;
  // Integrates a chirp (excitation.chirp) from rest over its duration, sampling
  // `samples_per_cycle` points per excitation cycle for max |x|.
  virtual ChirpResult RunChirp(const Excitation& chirp, int samples_per_cycle) = 0;
  // The period map iterated: integrates `periods` ≥ 1 periods T = 2π/ω of the harmonic
  // excitation at ω from `start` at t = 0 (excitation phase 0, as RunToSteadyState) without
  // recording or steady-state checks, and puts the state at t = periods·T in `end`. False with
  // `message` set if the integrator failed or max_seconds passed. For the monodromy matrix
  // (validation/monodromy.h).
  virtual bool IntegratePeriods(double omega, const InitialState& start, int periods,
                                InitialState* end, std::string* message) = 0;

 private:
  const std::atomic<bool>* stop_ = nullptr;
};

}  // namespace nfrc
