#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "validation/stepper.h"
#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// The one transient driver: runs any TransientStepper to a periodic steady state or through a
// chirp, so that TransientOptions mean the same for every integration scheme. It owns what is
// not the scheme's: sampling and recording the last period (PeriodRecord), its energy balance
// from the stepper's quadratures, the steady-state and kT-periodicity rule
// (SteadyStateMonitor), the chirp cycles, the wall-clock limit, input checks and the result's
// statistics. IdaIntegrator and CentralDifferenceIntegrator are this driver over their
// steppers.
class TransientDriver : public TransientIntegrator {
 public:
  // Keeps a reference to `model` (its M and K give the energies); throws InputError for bad
  // options.
  TransientDriver(const TransientModel& model, TransientOptions options,
                  std::unique_ptr<TransientStepper> stepper);
  ~TransientDriver() override;

  TransientResult RunToSteadyState(double omega, const InitialState& start) override;
  ChirpResult RunChirp(const Excitation& chirp, int samples_per_cycle) override;
  bool IntegratePeriods(double omega, const InitialState& start, int periods, InitialState* end,
                        std::string* message) override;

 protected:
  const TransientStepper& stepper() const { return *stepper_; }
  const TransientOptions& options() const { return options_; }

 private:
  // Integrates and records period p, [(p − 1)T, pT] with T = 2π/ω, into `record`;
  // max_i |z_i| over its samples and end goes to `scale`. False with `failure` set if the
  // stepper stopped.
  bool RecordPeriod(int p, double omega, PeriodRecord* record, double* scale, std::string* failure);
  // Advances the stepper to t; on failure or past the wall-clock limit, false with `failure`.
  bool Advance(double t, std::string* failure);
  // The harmonic excitation at ω; InputError for a non-positive or non-finite ω.
  Excitation HarmonicExcitation(double omega) const;
  // A run from `start` at t = 0 under `excitation` (which must outlive it), sampled
  // samples_per_period times a cycle, with the wall-clock limit counted from clock_start
  // (also set as deadline_). InputError names the initial-state field of a wrong size.
  StepperStart StartFrom(const Excitation& excitation, const InitialState& start,
                         std::chrono::steady_clock::time_point clock_start);
  // ½vᵀMv + ½xᵀKx at the stepper's current state (J).
  double Energy() const;

  const TransientModel& model_;
  TransientOptions options_;
  std::unique_ptr<TransientStepper> stepper_;
  std::chrono::steady_clock::time_point deadline_;
};

}  // namespace nfrc
