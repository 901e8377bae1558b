#include "validation/transient.h"

#include <cmath>
#include <string>

#include "core/errors.h"

namespace nfrc {
namespace {

[[noreturn]] void Fail(const std::string& field, const std::string& problem) {
  throw InputError("validation.transient." + field + ": " + problem);
}

void RequirePositive(const std::string& field, double value) {
  if (!std::isfinite(value) || value <= 0.0) Fail(field, "must be a finite number > 0");
}

void RequireAtLeast(const std::string& field, int value, int minimum) {
  if (value < minimum) Fail(field, "must be an integer >= " + std::to_string(minimum));
}

}  // namespace

void TransientOptions::Validate() const {
  RequirePositive("relative_tolerance", relative_tolerance);
  if (relative_tolerance >= 1.0) Fail("relative_tolerance", "must be < 1");
  RequirePositive("absolute_scale_factor", absolute_scale_factor);
  RequirePositive("steady_tolerance", steady_tolerance);
  RequireAtLeast("steady_periods", steady_periods, 1);
  RequireAtLeast("min_periods", min_periods, 1);
  RequireAtLeast("max_periods", max_periods, 1);
  if (max_periods < min_periods) Fail("max_periods", "must be >= min_periods");
  RequirePositive("max_seconds", max_seconds);
  RequireAtLeast("samples_per_period", samples_per_period, 2);
  RequireAtLeast("max_period_multiple", max_period_multiple, 1);
  RequirePositive("max_step_fraction", max_step_fraction);
  if (max_step_fraction > 1.0) Fail("max_step_fraction", "must be <= 1");
  RequirePositive("explicit_step_fraction", explicit_step_fraction);
  if (explicit_step_fraction > 1.0) Fail("explicit_step_fraction", "must be <= 1");
}

TransientStatistics& TransientStatistics::operator+=(const TransientStatistics& other) {
  steps += other.steps;
  residual_evaluations += other.residual_evaluations;
  jacobian_evaluations += other.jacobian_evaluations;
  nonlinear_iterations += other.nonlinear_iterations;
  nonlinear_convergence_failures += other.nonlinear_convergence_failures;
  error_test_failures += other.error_test_failures;
  events += other.events;
  return *this;
}

const char* ToString(TransientStatus status) {
  switch (status) {
    case TransientStatus::kPeriodic:
      return "periodic";
    case TransientStatus::kNotPeriodic:
      return "not_periodic";
    case TransientStatus::kFailed:
      return "failed";
    case TransientStatus::kInterrupted:
      return "interrupted";
  }
  return "failed";
}

int LawPhaseLog::CountPhases(double t0, double period) const {
  // Entries false → true around the cycle, the wrap from the period's end back to its start
  // included, so a phase straddling the boundary counts once.
  bool state = in_phase_at_start;
  int entries = 0;
  for (const auto& [time, value] : changes) {
    if (time < t0 || time >= t0 + period || value == state) continue;
    if (value) ++entries;
    state = value;
  }
  if (!state && in_phase_at_start) ++entries;
  if (entries == 0 && in_phase_at_start) return 1;
  return entries;
}

double LawPhaseLog::PhaseFraction(double t0, double period) const {
  if (period <= 0.0) return in_phase_at_start ? 1.0 : 0.0;
  bool state = in_phase_at_start;
  double since = t0;
  double in_phase = 0.0;
  for (const auto& [time, value] : changes) {
    if (time < t0 || time >= t0 + period || value == state) continue;
    if (state) in_phase += time - since;
    state = value;
    since = time;
  }
  if (state) in_phase += t0 + period - since;
  return in_phase / period;
}

}  // namespace nfrc
