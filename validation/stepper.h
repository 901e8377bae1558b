#pragma once

#include <Eigen/Dense>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "validation/excitation.h"
#include "validation/transient.h"

namespace nfrc {

// Where and how a stepper run begins.
struct StepperStart {
  const Excitation* excitation = nullptr;  // outlives the run
  Eigen::VectorXd x;                       // displacements at t = 0 (m), one per DOF
  Eigen::VectorXd v;                       // velocities at t = 0 (m/s)
  // The laws' own unknowns at t = 0, as InitialState::own (empty: from the momentum rows).
  Eigen::VectorXd own;
  // The driver samples the state this many times per excitation cycle; a fixed-step scheme
  // without a stability limit takes it as its resolution.
  int samples_per_cycle = 1;
  // Past it, AdvanceTo gives up with StepOutcome::kOutOfTime.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

enum class StepOutcome {
  kOk,
  kFailed,     // message() says why
  kOutOfTime,  // the start's deadline passed during the call
};

// Integrals over time of the energy and the powers, from the last ResetQuadratures (or the
// start) to the current time: the driver's period and cycle bookkeeping takes differences.
struct StepperQuadratures {
  double energy = 0.0;        // ∫(½vᵀMv + ½xᵀKx) dt (J·s)
  double work_input = 0.0;    // ∫fᵀv dt (J)
  double work_damping = 0.0;  // ∫vᵀCv dt (J)
  double work_laws = 0.0;     // ∫f_nlᵀv dt, rigid contact forces included (J)
};

// Named scalar signals of each law at the current time (TimeLaw::Signals), one list per law.
using LawSignalValues = std::vector<std::vector<std::pair<std::string, double>>>;

// One time integration scheme of a TransientModel under an Excitation, as the driver
// (validation/transient_driver.h) uses it: started at a state, advanced to the times the driver
// asks for. Everything between those times is the stepper's business: its steps, the events
// and mode switches of the laws, re-initialisations, the quadratures of energy and work. It
// holds no notion of steady state, periods or records: those are the driver's, the same for
// every stepper. One stepper object serves successive runs (each Start begins a new one).
class TransientStepper {
 public:
  virtual ~TransientStepper() = default;

  // "ida", "central_difference", ...: TransientResult::method.
  virtual std::string method() const = 0;

  // Begins a run at t = 0 from the start's state under its excitation. False (message())
  // if no run can start there.
  virtual bool Start(const StepperStart& start) = 0;

  // Begins a segment (a period or a chirp cycle) at the current time, ending at t_end: the
  // phase logs restart, and AdvanceTo will not be asked beyond t_end before the next
  // BeginSegment. False (message()) on failure.
  virtual bool BeginSegment(double t_end) = 0;

  // Integrates from the current time to t ≥ t(), handling events on the way.
  virtual StepOutcome AdvanceTo(double t) = 0;

  // Zeroes the quadratures at the current time. False (message()) on failure.
  virtual bool ResetQuadratures() = 0;

  // The state at the current time t() (s): displacements (m) and velocities (m/s).
  virtual double t() const = 0;
  virtual Eigen::Ref<const Eigen::VectorXd> x() const = 0;
  virtual Eigen::Ref<const Eigen::VectorXd> v() const = 0;
  // The laws' own unknowns at t() (InitialState::own's layout); empty for a scheme without.
  virtual Eigen::VectorXd own() const { return {}; }

  virtual LawSignalValues Signals() const = 0;
  // Phase changes of each law (and rigid contact) since the last BeginSegment, at times in
  // [segment start, t_end).
  virtual const std::vector<LawPhaseLog>& PhaseLogs() const = 0;
  virtual StepperQuadratures Quadratures() const = 0;
  // Work done since the last Start (all re-initialisations included).
  virtual TransientStatistics Statistics() const = 0;
  // Why the last call failed.
  virtual const std::string& message() const = 0;
};

}  // namespace nfrc
