#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <functional>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include "analysis/case.h"
#include "analysis/case_parameter.h"
#include "analysis/harmonic_system.h"
#include "analysis/point_measures.h"

namespace nfrc {

// The response measure whose maxima along ω a peak curve follows.
struct PeakMeasure {
  enum class Kind { kEnergy, kFirstHarmonic, kMaxAbs };
  Kind kind = Kind::kEnergy;
  int output = 0;               // index among the case's output DOFs (h1, max_abs)
  std::string name = "energy";  // "energy", "h1_<output>", "max_abs_<output>"
};

// "energy", "h1:<output>" or "max_abs:<output>" with <output> the name of one of the case's
// output DOFs; throws InputError naming "measure" otherwise.
PeakMeasure ParsePeakMeasure(const std::string& text, const Case& the_case);

// The measure of solution y at ω (`analyzer` built on `system` with the case's output DOFs).
double EvaluatePeakMeasure(const PeakMeasure& measure, HarmonicSystem& system,
                           PointAnalyzer& analyzer, const Eigen::VectorXd& y, double omega);

struct EventCurve;
struct EventCurvePoint;

// Receives each point of a curve as it is found and each curve as soon as it ends (a writer
// keeps what was found on disk). `curve` numbers the curves from 0 in result order.
class EventCurveObserver {
 public:
  virtual ~EventCurveObserver() = default;
  virtual void OnPoint(int /*curve*/, const EventCurvePoint& /*point*/) {}
  virtual void OnCurve(const EventCurve& curve) = 0;
};

// Events of a case's branch followed in a parameter: resonance peaks (local maxima of a
// measure along ω; where friction removes the folds, the peaks are what a damper is designed
// by) or Neimark–Sacker points.
struct EventCurveOptions {
  double to = 0.0;      // value of the parameter the curves are followed towards
  PeakMeasure measure;  // peaks: whose maxima; both: reported at the points (default energy)
  // Follow only the branch's event nearest this ω (rad per time unit); NaN: every one.
  double near = std::numeric_limits<double>::quiet_NaN();
  // Parameter values strictly between the case's and `to` that every curve lands on exactly
  // (to compare with single runs there).
  std::vector<double> stations;
  // Parameter steps as fractions of |to − from|: the first, the largest, and the smallest
  // before a curve that cannot go on ends (its event vanished or moved out of reach).
  double initial_step = 0.02;
  double max_step = 0.1;
  double min_step = 1e-4;
  int max_points = 1000;  // per curve
  std::ostream* progress = nullptr;
  const std::atomic<bool>* stop = nullptr;  // raised: each curve stops after its point
  // Called after every point of the branch and of the curves; false stops as `stop` does
  // (Python checks its signals here). Empty: not called.
  std::function<bool()> poll;
  EventCurveObserver* observer = nullptr;

  // Sets max_step and lowers initial_step and min_step to it where they exceed it.
  void SetMaxStep(double step) {
    max_step = step;
    initial_step = std::min(initial_step, step);
    min_step = std::min(min_step, initial_step);
  }

  // Throws InputError naming "to", "near", "stations", "initial_step", "max_step", "min_step"
  // or "max_points".
  void Validate(double from) const;
};

// The event (a maximum of the measure along ω, or a Neimark–Sacker point) at one parameter
// value.
struct EventCurvePoint {
  double parameter = 0.0;
  double omega = 0.0;    // rad per time unit
  double measure = 0.0;  // there
  Eigen::VectorXd y;     // the HarmonicSystem's unknowns there
  int solves = 0;        // fixed-ω Newton solves spent on this point
};

enum class EventCurveEnd {
  kReachedTo,  // the curve reached `to`
  kVanished,   // no event near the last one beyond the smallest step: a peak merged with a
               // minimum, Neimark–Sacker points met (or it moved further than a step follows)
  kMaxPoints,
  kStopped,      // the stop flag was raised
  kStartFailed,  // the event could not be located on the branch
};

const char* ToString(EventCurveEnd end);

struct EventCurve {
  int start_point = 0;       // index of the branch point nearest (peak) or before (N–S) it
  double start_omega = 0.0;  // ω of the located event at the case's parameter value
  std::vector<EventCurvePoint> points;  // in order from the case's value towards `to`
  EventCurveEnd end = EventCurveEnd::kStartFailed;
  std::string message;
  int solves = 0;
  double seconds = 0.0;
};

struct EventCurveResult {
  std::string parameter;  // the path
  double from = 0.0;      // its value in the case
  double to = 0.0;
  std::string measure;    // PeakMeasure::name
  int branch_events = 0;  // local maxima among the branch's points, or its N–S points
  std::vector<EventCurve> curves;
  std::vector<std::string> notes;  // events not followed and why
};

// Follows each Neimark–Sacker point of the case's branch (traced with its stability) in the
// parameter: the ω where the largest complex pair of Hill's multipliers has |μ| = 1, bracketed
// and refined on log|μ| over fixed-ω solves exactly as peaks are (no derivatives of the
// multipliers). Needs stability.enabled; `measure` is only reported at the points. Throws
// InputError as TracePeakCurves.
EventCurveResult TraceNeimarkSackerCurves(const Case& the_case, const CaseParameter& parameter,
                                          const EventCurveOptions& options);

// Traces the case's branch, locates each local maximum of the measure between its points as a
// zero of dm/dω = ∇m·(dy/dω, 1) with dy/dω = −R_y⁻¹R_ω (bracketed secant over fixed-ω Newton
// solves: no second derivatives of R, so nonsmooth laws are followed as well as smooth ones),
// then steps the parameter, predicting the peak by extrapolation and bracketing it again.
// Peaks beside a fold of the branch are left to fold curves (noted). Throws InputError for bad
// input (the case, the parameter, the options, a `to` the case rejects).
EventCurveResult TracePeakCurves(const Case& the_case, const CaseParameter& parameter,
                                 const EventCurveOptions& options);

}  // namespace nfrc
