#pragma once

#include <Eigen/Dense>
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

struct PeakCurve;

// Receives each peak curve as soon as it ends (a writer keeps what was found on disk).
class PeakCurveObserver {
 public:
  virtual ~PeakCurveObserver() = default;
  virtual void OnCurve(const PeakCurve& curve) = 0;
};

// Resonance peaks of a case's branch (local maxima of a measure along ω) followed in a
// parameter: where friction removes the folds, the peaks are what a damper is designed by.
struct PeakCurveOptions {
  double to = 0.0;      // value of the parameter the curves are followed towards
  PeakMeasure measure;  // default: the period-mean energy
  // Follow only the branch's peak nearest this ω (rad per time unit); NaN: every peak.
  double near = std::numeric_limits<double>::quiet_NaN();
  // Parameter values strictly between the case's and `to` that every curve lands on exactly
  // (to compare with single runs there).
  std::vector<double> stations;
  // Parameter steps as fractions of |to − from|: the first, the largest, and the smallest
  // before a curve that cannot go on ends (its peak vanished or moved out of reach).
  double initial_step = 0.02;
  double max_step = 0.1;
  double min_step = 1e-4;
  int max_points = 1000;  // per curve
  std::ostream* progress = nullptr;
  const std::atomic<bool>* stop = nullptr;  // raised: each curve stops after its point
  // Called after every point of the branch and of the curves; false stops as `stop` does
  // (Python checks its signals here). Empty: not called.
  std::function<bool()> poll;
  PeakCurveObserver* observer = nullptr;

  // Throws InputError naming "to", "near", "stations", "initial_step", "max_step", "min_step"
  // or "max_points".
  void Validate(double from) const;
};

// The maximum of the measure along ω at one parameter value.
struct PeakCurvePoint {
  double parameter = 0.0;
  double omega = 0.0;    // rad per time unit
  double measure = 0.0;  // at the maximum
  Eigen::VectorXd y;     // the HarmonicSystem's unknowns there
  int solves = 0;        // fixed-ω Newton solves spent on this point
};

enum class PeakCurveEnd {
  kReachedTo,  // the curve reached `to`
  kVanished,   // no maximum near the last one beyond the smallest step: it merged with a
               // minimum (or jumped further than a step can follow)
  kMaxPoints,
  kStopped,      // the stop flag was raised
  kStartFailed,  // the peak could not be located on the branch
};

const char* ToString(PeakCurveEnd end);

struct PeakCurve {
  int start_point = 0;                 // index of the branch point nearest the peak
  double start_omega = 0.0;            // ω of the located peak at the case's parameter value
  std::vector<PeakCurvePoint> points;  // in order from the case's value towards `to`
  PeakCurveEnd end = PeakCurveEnd::kStartFailed;
  std::string message;
  int solves = 0;
  double seconds = 0.0;
};

struct PeakCurveResult {
  std::string parameter;  // the path
  double from = 0.0;      // its value in the case
  double to = 0.0;
  std::string measure;   // PeakMeasure::name
  int branch_peaks = 0;  // local maxima of the measure among the branch's points
  std::vector<PeakCurve> curves;
  std::vector<std::string> notes;  // peaks not followed and why
};

// Traces the case's branch, locates each local maximum of the measure between its points as a
// zero of dm/dω = ∇m·(dy/dω, 1) with dy/dω = −R_y⁻¹R_ω (bracketed secant over fixed-ω Newton
// solves: no second derivatives of R, so nonsmooth laws are followed as well as smooth ones),
// then steps the parameter, predicting the peak by extrapolation and bracketing it again.
// Peaks beside a fold of the branch are left to fold curves (noted). Throws InputError for bad
// input (the case, the parameter, the options, a `to` the case rejects).
PeakCurveResult TracePeakCurves(const Case& the_case, const CaseParameter& parameter,
                                const PeakCurveOptions& options);

}  // namespace nfrc
