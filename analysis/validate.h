#pragma once

#include <atomic>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/solution_report.h"
#include "analysis/solve_at.h"
#include "analysis/stability.h"
#include "analysis/trace.h"
#include "analysis/validation_settings.h"
#include "validation/monodromy.h"
#include "validation/period_measures.h"
#include "validation/transient.h"

namespace nfrc {

// How a periodic transient compares with the HBM solution it settled on. Differences are
// relative, |transient − HBM| / |HBM|, per output DOF where they are vectors.
struct TransientComparison {
  int solution = 0;     // index of the matched solution in ValidationPoint::solutions
  std::string label;    // its label ("lower", "only", ...)
  bool stayed = false;  // from rest, or on the HBM solution it started from
  std::vector<double> h1;
  std::vector<double> max_abs;
  double energy = 0.0;
  // RMS of x_HBM − x_transient over the period relative to the RMS of x_HBM.
  std::vector<double> rms;
  bool same_phase_counts = false;  // per law with a phase
  // θ, t, then per output DOF hbm_x_, transient_x_, hbm_v_, transient_v_ <name>, then the
  // laws' HBM signals (hbm_law<i>_<name>) and recorded ones (transient_law<j>_<name>), all on
  // the transient's grid of the recorded period.
  SignalTable overlay;
};

// One transient run at an ω, to a periodic steady state.
struct TransientRun {
  int start_solution = -1;  // index into ValidationPoint::solutions it started from; −1: rest
  std::string start;        // "hbm <label>" or "rest"
  TransientResult result;
  bool recorded = false;    // a last period was recorded (then `measures` are set)
  PeriodMeasures measures;  // of the output DOFs over the recorded period
  std::optional<TransientComparison> comparison;  // periodic and an HBM solution to match
};

// Stability checks of one HBM solution (the same index in ValidationPoint::solutions): one
// field per method, so that others (Hill's multipliers) sit next to it.
struct SolutionStability {
  // The transient monodromy at the HBM state at t = 0 (the state "start hbm" starts from):
  // the orbit may be unstable, so it is not the transient's final state; the HBM truncation
  // error is then the only offset from the orbit (MonodromyResult::closure measures it).
  // Unset when validation.monodromy.enabled is false or a stop came first.
  std::optional<MonodromyResult> monodromy;
  // Hill's multipliers of the same HBM solution (computed = false when stability is off).
  FloquetResult hill;
  // Both computed: the largest distance from a Hill multiplier with |μ| ≥ kCompared to the
  // nearest transient multiplier (the multipliers that decide stability; the smaller ones
  // are strongly damped and the HBM truncation dominates them), and |max|μ|_Hill −
  // max|μ|_transient|.
  static constexpr double kCompared = 0.05;
  std::optional<double> multiplier_difference;
  std::optional<double> max_modulus_difference;
};

// Everything validated at one requested ω.
struct ValidationPoint {
  double omega = 0.0;                        // rad per time unit
  std::vector<CrossingSolution> solutions;   // the converged HBM crossings
  std::vector<TransientRun> transients;      // one per solution (start hbm) or one from rest
  std::vector<SolutionStability> stability;  // one per solution
  // The transient that stands for this ω (the first that stayed where it started, else the
  // first), −1 if none ran; its comparison's solution is the one that stands for the HBM.
  int primary = -1;
};

// One chirp sweep.
struct ChirpRun {
  std::string direction;     // "up" or "down"
  double omega_start = 0.0;  // ω at t = 0 (rad per time unit)
  double omega_end = 0.0;
  double duration = 0.0;    // time units
  double sweep_rate = 0.0;  // (ω_end − ω_start) / duration
  ChirpResult result;
};

// "completed" for a chirp that ran to its end (a chirp has no steady state, so kPeriodic
// only says that), else the transient status's name.
std::string ChirpStatusName(TransientStatus status);

// The outcome of ValidateCase.
struct ValidationResult {
  TraceResult trace;                    // the HBM branch
  std::vector<ValidationPoint> points;  // per requested ω, up to a stop
  std::vector<ChirpRun> chirps;
  // Every point had an HBM solution and no transient or chirp failed (not periodic is no
  // failure), and no stop came: what `nfrc validate` turns into its exit status.
  bool complete = false;
  bool interrupted = false;  // the stop flag ended it early
};

// Receives a validation's results as they are found (a writer). Called on the validating
// thread.
class ValidationObserver {
 public:
  virtual ~ValidationObserver() = default;
  // After the input checks, just before the HBM trace: the observer of its points (null:
  // none). Lets a writer create its files only for a valid input.
  virtual TraceObserver* OnTraceStart() { return nullptr; }
  // The traced branch, before the first ω.
  virtual void OnBranch(const TraceResult& /*trace*/) {}
  // After each transient: `point` holds the HBM solutions and the transients run so far,
  // the new one last.
  virtual void OnTransient(const ValidationPoint& /*point*/) {}
  // After every ω, also one cut short by a stop.
  virtual void OnPoint(const ValidationPoint& /*point*/) {}
  virtual void OnChirp(const ChirpRun& /*chirp*/) {}
  // The whole result, complete or not (a writer records its status).
  virtual void OnEnd(const ValidationResult& /*result*/) {}
};

// Where ValidateCase reports to and what stops it.
struct ValidationOptions {
  std::ostream* progress = nullptr;  // progress lines; null = quiet
  // Polled after every branch point and run, and by the integrators at every period.
  const std::atomic<bool>* stop = nullptr;
  ValidationObserver* observer = nullptr;
};

// `nfrc validate` as a computation: traces the case's branch, solves it at exactly each
// requested ω (every crossing: several inside a fold), integrates the same model in time to
// a periodic steady state (IDA, or the explicit Lagrange-multiplier scheme when the case has
// a rigid obstacle) from each HBM solution or from rest, matches each periodic transient to
// the nearest HBM solution (relative first-harmonic amplitudes and energy) and compares per
// output DOF max |x|, first-harmonic amplitude, mean energy, RMS difference of the signals
// and phase counts. Unless validation.monodromy.enabled is false it computes the transient
// monodromy matrix and Floquet multipliers of every HBM solution (whatever the start; a
// failure there is reported in it and does not make the result incomplete). With a chirp
// configured it also sweeps up and/or down. Throws InputError
// for bad input (a non-arclength method, too few transient samples for the harmonics).
ValidationResult ValidateCase(const Case& the_case, const ValidationSettings& settings,
                              const ValidationOptions& options = {});

}  // namespace nfrc
