#pragma once

#include <Eigen/Dense>
#include <Eigen/LU>
#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <utility>

#include "analysis/bifurcation.h"
#include "analysis/case.h"
#include "analysis/event_curve.h"
#include "analysis/point_measures.h"
#include "continuation/fixed_lambda.h"

// The search for an event of a branch at one parameter value (analysis/event_curve.cc's
// inner loop): fixed-ω solves, the event function there, its bracketing and refinement.
namespace nfrc::event_search {

// Relative ω step of the central difference of m along the branch direction (dy/dω, 1): near
// ε^(1/3), where truncation and rounding of a central difference balance.
inline constexpr double kSlopeStep = 1e-6;
// Reciprocal condition number of R_y below which dy/dω is not computed: the point is at a fold.
inline constexpr double kSingular = 1e-13;
// A multiplier is of a complex pair when |Im μ| exceeds this fraction of |μ| (real ones come
// out of Hill's eigenproblem with imaginary parts of rounding size).
inline constexpr double kComplexPart = 1e-6;
// Probes each side of a located maximum when polishing it (see Polish).
inline constexpr int kEventProbes = 4;

enum class EventKind { kPeak, kNeimarkSacker };

inline const char* EventName(EventKind kind) {
  return kind == EventKind::kPeak ? "peak" : "neimark_sacker";
}

// A number as messages print it (8 significant digits).
std::string FormatValue(double value);

// A solution at ω with its derivative along the branch and the measure's slope dm/dω.
struct Sample {
  double omega = 0.0;
  Eigen::VectorXd y;
  Eigen::VectorXd dy;  // dy/dω = −R_y⁻¹R_ω
  double measure = 0.0;
  // The event function: dm/dω for peaks (a maximum where it falls through 0), log|μ| of the
  // largest complex pair of Floquet multipliers for Neimark–Sacker points (0 on the circle).
  double event = 0.0;
};

// The system at one parameter value and the fixed-ω solves on it.
class EventSolver {
 public:
  EventSolver(Case at_parameter, EventKind kind, const PeakMeasure& measure)
      : case_(std::move(at_parameter)),
        kind_(kind),
        system_(BuildSystem(case_)),
        analyzer_(*system_, case_.output_dofs),
        measure_(measure) {}

  EventKind kind() const { return kind_; }

  // Newton at fixed ω from `guess`, then the sample there; false (message()) if it fails.
  bool At(double omega, const Eigen::VectorXd& guess, const Eigen::VectorXd& typical,
          Sample* sample) {
    ++solves_;
    const FixedLambdaSolution solution =
        SolveAtFixedLambda(*system_, guess, omega, typical, case_.continuation);
    if (!solution.converged) {
      message_ = "Newton at omega=" + FormatValue(omega) + ": " + solution.message;
      return false;
    }
    return Differentiate(omega, solution.y, sample);
  }

  // The sample at a solution (y, ω) already converged.
  bool Differentiate(double omega, const Eigen::VectorXd& y, Sample* sample) {
    Eigen::VectorXd residual, r_omega;
    Eigen::MatrixXd r_y;
    if (!system_->Evaluate(y, omega, &residual, &r_y, &r_omega)) {
      message_ = "the system cannot be evaluated at omega=" + FormatValue(omega);
      return false;
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(r_y);
    if (!(lu.rcond() >= kSingular)) {
      message_ = "R_y is singular at omega=" + FormatValue(omega) + " (a fold)";
      return false;
    }
    sample->omega = omega;
    sample->y = y;
    sample->dy = -lu.solve(r_omega);
    const double h = kSlopeStep * std::max(std::abs(omega), 1e-300);
    sample->measure = Measure(y, omega);
    if (kind_ == EventKind::kNeimarkSacker) return NeimarkSacker(omega, y, sample);
    sample->event =
        (Measure(y + h * sample->dy, omega + h) - Measure(y - h * sample->dy, omega - h)) /
        (2.0 * h);
    if (!std::isfinite(sample->event) || !sample->dy.allFinite()) {
      message_ = "dm/domega is not finite at omega=" + FormatValue(omega);
      return false;
    }
    return true;
  }

  // The measure of a solution (y, ω), without the event.
  double Measure(const Eigen::VectorXd& y, double omega) {
    return EvaluatePeakMeasure(measure_, *system_, analyzer_, y, omega);
  }

  int solves() const { return solves_; }
  const std::string& message() const { return message_; }

 private:
  // log|μ| of the largest complex pair of Hill's multipliers.
  bool NeimarkSacker(double omega, const Eigen::VectorXd& y, Sample* sample) {
    if (!monitor_) {
      monitor_ = std::make_unique<StabilityMonitor>(*system_, case_.stability, case_.continuation);
    }
    const FloquetResult floquet = monitor_->Analyze(y, omega);
    if (!floquet.computed) {
      message_ = "Hill's method failed at omega=" + FormatValue(omega) + ": " + floquet.message;
      return false;
    }
    double largest = 0.0;
    for (const std::complex<double>& mu : floquet.multipliers) {
      if (std::abs(mu.imag()) > kComplexPart * std::abs(mu))
        largest = std::max(largest, std::abs(mu));
    }
    if (!(largest > 0.0)) {
      message_ = "no complex pair of multipliers at omega=" + FormatValue(omega);
      return false;
    }
    sample->event = std::log(largest);
    return true;
  }

  Case case_;
  EventKind kind_;
  std::unique_ptr<HarmonicSystem> system_;
  std::unique_ptr<StabilityMonitor> monitor_;  // Neimark–Sacker: made at the first sample
  PointAnalyzer analyzer_;
  const PeakMeasure& measure_;
  int solves_ = 0;
  std::string message_;
};

// The zero of the event between samples of opposite signs (either order); for peaks then
// polished to the highest maximum of its cluster. False with `why` if a solve fails.
bool Locate(EventSolver& solver, const Sample& a, const Sample& b, Sample* found, std::string* why);

// Moves a located maximum to the highest one within a small window around it (on a nonsmooth
// branch the top of a resonance can hold several ~1e-4 apart in ω); a sample that is the
// highest of its window stays as it is. False with `why` if a refinement's solve fails.
bool Polish(EventSolver& solver, Sample* peak, std::string* why);

// The event nearest ω_pred on `solver`'s system, from the prediction (ω_pred, y_pred) after the
// last curve point (last_omega, last_y): bracketed by walking with doubling steps — uphill for
// a peak, towards the smaller |event| for a Neimark–Sacker point — within reach of the
// prediction, then located. False with `why` if none is found.
bool Bracket(EventSolver& solver, double omega_pred, const Eigen::VectorXd& y_pred,
             double last_omega, const Eigen::VectorXd& last_y, Sample* found, std::string* why);

}  // namespace nfrc::event_search
