#include "analysis/event_curve.h"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
#include <ostream>
#include <sstream>
#include <utility>

#include "analysis/bifurcation.h"
#include "analysis/trace.h"
#include "continuation/fixed_lambda.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// Relative ω step of the central difference of m along the branch direction (dy/dω, 1): near
// ε^(1/3), where truncation and rounding of a central difference balance.
constexpr double kSlopeStep = 1e-6;
// A bracket narrower than this (relative to ω) is the peak: m is stationary there, so the
// measure is exact to second order where m is smooth, to 1e-8 × its slope jump at a kink.
constexpr double kOmegaTolerance = 1e-8;
constexpr int kMaxRefineIterations = 100;
// Bracketing after a parameter step: the first trial is at least kMinBracket (relative to ω)
// from the prediction, and no peak is searched farther from it than kReachFactor times the
// predicted move or kMinReach (relative to ω). A peak farther away is another peak (the one
// followed vanished, or moved faster than the step resolves): the step is cut.
constexpr double kMinBracket = 1e-3;
constexpr double kReachFactor = 1.0;
// Trials of the bracket walk that fail (past a fold) are retried this often, 4× closer.
constexpr int kBracketRetries = 4;
constexpr double kMinReach = 5e-3;
constexpr double kStepGrowth = 1.5;
// Reciprocal condition number of R_y below which dy/dω is not computed: the point is at a fold.
constexpr double kSingular = 1e-13;
// A multiplier is of a complex pair when |Im μ| exceeds this fraction of |μ| (real ones come
// out of Hill's eigenproblem with imaginary parts of rounding size).
constexpr double kComplexPart = 1e-6;
constexpr double kLandingReach = 1.25;
// On a nonsmooth branch the top of a resonance can hold several local maxima ~1e-4 apart in ω
// (the slope jumps where samples switch between stick and slip): kProbes probes each side
// within kClusterWindow (relative to ω) find the highest, in up to kPolishRounds moves.
constexpr double kClusterWindow = 2e-3;
constexpr int kProbes = 4;
constexpr int kPolishRounds = 3;
// Steps that needed at most this many fixed-ω solves let the parameter step grow by
// kStepGrowth (a start, two brackets, a few secant iterations and the polishing probes).
constexpr int kEasySolves = 2 * kProbes + 10;
// A maximum below this fraction of the largest one on the curve is of a response that has
// vanished (a friction damper stuck throughout): its ω is rounding, so the curve ends.
constexpr double kVanishedMeasure = 1e-9;

enum class EventKind { kPeak, kNeimarkSacker };

const char* EventName(EventKind kind) {
  return kind == EventKind::kPeak ? "peak" : "neimark_sacker";
}

std::string Format(double value) {
  std::ostringstream out;
  out.precision(8);
  out << value;
  return out.str();
}

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
      message_ = "Newton at omega=" + Format(omega) + ": " + solution.message;
      return false;
    }
    return Differentiate(omega, solution.y, sample);
  }

  // The sample at a solution (y, ω) already converged.
  bool Differentiate(double omega, const Eigen::VectorXd& y, Sample* sample) {
    Eigen::VectorXd residual, r_omega;
    Eigen::MatrixXd r_y;
    if (!system_->Evaluate(y, omega, &residual, &r_y, &r_omega)) {
      message_ = "the system cannot be evaluated at omega=" + Format(omega);
      return false;
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(r_y);
    if (!(lu.rcond() >= kSingular)) {
      message_ = "R_y is singular at omega=" + Format(omega) + " (a fold)";
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
      message_ = "dm/domega is not finite at omega=" + Format(omega);
      return false;
    }
    return true;
  }

  int solves() const { return solves_; }
  const std::string& message() const { return message_; }

 private:
  double Measure(const Eigen::VectorXd& y, double omega) {
    return EvaluatePeakMeasure(measure_, *system_, analyzer_, y, omega);
  }

  // log|μ| of the largest complex pair of Hill's multipliers.
  bool NeimarkSacker(double omega, const Eigen::VectorXd& y, Sample* sample) {
    if (!monitor_) {
      monitor_ = std::make_unique<StabilityMonitor>(*system_, case_.stability, case_.continuation);
    }
    const FloquetResult floquet = monitor_->Analyze(y, omega);
    if (!floquet.computed) {
      message_ = "Hill's method failed at omega=" + Format(omega) + ": " + floquet.message;
      return false;
    }
    double largest = 0.0;
    for (const std::complex<double>& mu : floquet.multipliers) {
      if (std::abs(mu.imag()) > kComplexPart * std::abs(mu))
        largest = std::max(largest, std::abs(mu));
    }
    if (!(largest > 0.0)) {
      message_ = "no complex pair of multipliers at omega=" + Format(omega);
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

// The zero of the event between `rising` (event > 0) and `falling` (event ≤ 0) — for peaks a
// maximum — by regula falsi with the Illinois modification (superlinear where the event is
// smooth), with a bisection whenever two iterations did not halve the bracket (where it jumps,
// as dm/dω does where a nonsmooth law switches, regula falsi alone crawls).
bool Refine(EventSolver& solver, Sample rising, Sample falling, Sample* peak, std::string* why) {
  double f_rising = rising.event, f_falling = falling.event;
  int kept = 0;  // +1: the rising end was kept last time, −1: the falling end
  double width_before = std::numeric_limits<double>::infinity();  // two iterations ago
  double width_last = width_before;
  for (int iteration = 0; iteration < kMaxRefineIterations; ++iteration) {
    const double width = std::abs(falling.omega - rising.omega);
    const double scale = std::max(std::abs(rising.omega), std::abs(falling.omega));
    if (falling.event == 0.0 || width <= kOmegaTolerance * scale) {
      // A peak: the higher end; a Neimark–Sacker point: the end nearer the unit circle.
      const bool take_falling = solver.kind() == EventKind::kPeak
                                    ? falling.measure >= rising.measure
                                    : std::abs(falling.event) <= std::abs(rising.event);
      *peak = take_falling ? falling : rising;
      return true;
    }
    const double lo = std::min(rising.omega, falling.omega);
    const double hi = std::max(rising.omega, falling.omega);
    double omega = (rising.omega * f_falling - falling.omega * f_rising) / (f_falling - f_rising);
    if (!(omega > lo && omega < hi) || width > 0.5 * width_before) omega = 0.5 * (lo + hi);
    width_before = width_last;
    width_last = width;
    const Sample& near =
        std::abs(omega - rising.omega) < std::abs(omega - falling.omega) ? rising : falling;
    const Eigen::VectorXd guess = near.y + near.dy * (omega - near.omega);
    Sample next;
    if (!solver.At(omega, guess, near.y, &next)) {
      *why = solver.message();
      return false;
    }
    if (next.event > 0.0) {
      rising = std::move(next);
      f_rising = rising.event;
      if (kept == +1) f_falling *= 0.5;
      kept = -1;
    } else {
      falling = std::move(next);
      f_falling = falling.event;
      if (kept == -1) f_rising *= 0.5;
      kept = +1;
    }
  }
  *why = "the bracket from omega=" + Format(rising.omega) + " to " + Format(falling.omega) +
         " did not close in " + std::to_string(kMaxRefineIterations) + " solves";
  return false;
}

// Moves a located maximum to the highest one within the cluster window around it.
bool Polish(EventSolver& solver, Sample* peak, std::string* why) {
  for (int round = 0; round < kPolishRounds; ++round) {
    const double delta = kClusterWindow * std::abs(peak->omega) / kProbes;
    std::vector<Sample> probes = {*peak};  // in increasing ω
    for (double side : {-1.0, 1.0}) {
      const Sample* from = peak;
      Sample probe;
      for (int k = 1; k <= kProbes; ++k) {
        const double omega = peak->omega + side * k * delta;
        // A probe that does not converge (past a fold) ends that side.
        if (!solver.At(omega, from->y + from->dy * (omega - from->omega), from->y, &probe)) break;
        if (side < 0.0) {
          probes.insert(probes.begin(), std::move(probe));
          from = &probes.front();
        } else {
          probes.push_back(std::move(probe));
          from = &probes.back();
        }
      }
    }
    const auto highest =
        std::max_element(probes.begin(), probes.end(),
                         [](const Sample& a, const Sample& b) { return a.measure < b.measure; });
    if (highest->measure <= peak->measure) return true;
    const size_t j = static_cast<size_t>(highest - probes.begin());
    if (highest->event > 0.0 && j + 1 < probes.size() && probes[j + 1].event <= 0.0) {
      if (!Refine(solver, probes[j], probes[j + 1], peak, why)) return false;
    } else if (highest->event <= 0.0 && j > 0 && probes[j - 1].event > 0.0) {
      if (!Refine(solver, probes[j - 1], probes[j], peak, why)) return false;
    } else {
      *peak = *highest;  // at the window's edge, still rising: the next round goes on from it
    }
  }
  return true;
}

// Refine a bracket (ends in either order), then, for peaks, Polish.
bool Locate(EventSolver& solver, const Sample& a, const Sample& b, Sample* peak, std::string* why) {
  const bool a_rises = a.event > 0.0;
  if (!Refine(solver, a_rises ? a : b, a_rises ? b : a, peak, why)) return false;
  return solver.kind() != EventKind::kPeak || Polish(solver, peak, why);
}

// The event nearest ω_pred on `solver`'s system: bracketed by walking from the prediction with
// doubling steps — uphill for a peak, towards the smaller |event| (decided by a first trial
// above the prediction) for a Neimark–Sacker point — then refined.
bool Bracket(EventSolver& solver, double omega_pred, const Eigen::VectorXd& y_pred,
             const EventCurvePoint& last, Sample* peak, std::string* why) {
  Sample start;
  if (!solver.At(omega_pred, y_pred, last.y, &start)) {
    *why = solver.message();
    return false;
  }
  if (start.event == 0.0) {
    *peak = start;
    return true;
  }
  const double reach =
      std::max(kReachFactor * std::abs(omega_pred - last.omega), kMinReach * std::abs(last.omega));
  double width = std::max(std::abs(omega_pred - last.omega), kMinBracket * std::abs(last.omega));
  double direction = start.event > 0.0 ? 1.0 : -1.0;
  Sample previous = start;
  if (solver.kind() == EventKind::kNeimarkSacker) {
    Sample above;
    const double omega = omega_pred + width;
    if (!solver.At(omega, start.y + start.dy * width, start.y, &above)) {
      *why = solver.message();
      return false;
    }
    if (above.event * start.event <= 0.0) return Locate(solver, start, above, peak, why);
    direction = std::abs(above.event) < std::abs(start.event) ? 1.0 : -1.0;
    if (direction > 0.0) previous = std::move(above);
  }
  int failures = 0;
  while (std::abs(previous.omega + direction * width - omega_pred) <= reach) {
    const double omega = previous.omega + direction * width;
    Sample next;
    if (!solver.At(omega, previous.y + previous.dy * (omega - previous.omega), previous.y, &next)) {
      // Past a fold just beyond the peak (lightly damped hardening peaks): a shorter trial.
      if (++failures > kBracketRetries) {
        *why = solver.message();
        return false;
      }
      width *= 0.25;
      continue;
    }
    if (next.event * previous.event <= 0.0) return Locate(solver, previous, next, peak, why);
    previous = std::move(next);
    width *= 2.0;
  }
  *why = std::string(solver.kind() == EventKind::kPeak ? "no maximum" : "no crossing") +
         " within " + Format(reach) + " of omega=" + Format(omega_pred);
  return false;
}

EventCurvePoint ToPoint(double parameter, const Sample& sample, int solves) {
  return {parameter, sample.omega, sample.measure, sample.y, solves};
}

// The next parameter value: a step of `step` from p, landing on the first station or `to`
// it would pass.
double NextValue(double p, double step, double to, const std::vector<double>& stations) {
  double target = to;
  for (double station : stations) {
    if ((station - p) * step > 0.0 && std::abs(station - p) < std::abs(target - p)) {
      target = station;
    }
  }
  // A step that would leave less than a quarter step to the target goes all the way.
  return kLandingReach * std::abs(step) >= std::abs(target - p) ? target : p + step;
}

void Follow(const Case& the_case, const CaseParameter& parameter, const EventCurveOptions& options,
            EventKind kind, double from, int index, StopCheck& check, EventCurve* curve) {
  const double range = std::abs(options.to - from);
  const double sign = options.to > from ? 1.0 : -1.0;
  double step = sign * options.initial_step * range;
  while (curve->points.back().parameter != options.to) {
    if (!check.Continue()) {
      curve->end = EventCurveEnd::kStopped;
      curve->message = "stopped";
      return;
    }
    if (static_cast<int>(curve->points.size()) >= options.max_points) {
      curve->end = EventCurveEnd::kMaxPoints;
      curve->message = "max_points reached";
      return;
    }
    const EventCurvePoint& last = curve->points.back();
    const double p = NextValue(last.parameter, step, options.to, options.stations);
    // Linear extrapolation in the parameter from the last two points.
    double omega_pred = last.omega;
    Eigen::VectorXd y_pred = last.y;
    if (curve->points.size() >= 2) {
      const EventCurvePoint& before = curve->points[curve->points.size() - 2];
      const double t = (p - last.parameter) / (last.parameter - before.parameter);
      omega_pred += t * (last.omega - before.omega);
      y_pred += t * (last.y - before.y);
    }
    EventSolver solver(parameter.With(the_case, p), kind, options.measure);
    Sample peak;
    std::string why;
    double largest = 0.0;
    for (const EventCurvePoint& point : curve->points) largest = std::max(largest, point.measure);
    const bool found = Bracket(solver, omega_pred, y_pred, last, &peak, &why);
    if (found && kind == EventKind::kPeak && !(peak.measure > kVanishedMeasure * largest)) {
      curve->solves += solver.solves();
      curve->end = EventCurveEnd::kVanished;
      curve->message = "the response vanishes at " + parameter.path() + "=" + Format(p) + " (" +
                       options.measure.name + "=" + Format(peak.measure) + ")";
      return;
    }
    if (found) {
      curve->points.push_back(ToPoint(p, peak, solver.solves()));
      curve->solves += solver.solves();
      if (options.progress != nullptr) {
        *options.progress << "nfrc: " << EventName(kind) << " " << index << " point "
                          << curve->points.size() - 1 << " " << parameter.path() << "=" << p
                          << " omega=" << peak.omega << " " << options.measure.name << "="
                          << peak.measure << " step=" << step << " solves=" << solver.solves()
                          << "\n";
      }
      if (solver.solves() <= kEasySolves) {
        step = sign * std::min(std::abs(step) * kStepGrowth, options.max_step * range);
      }
      continue;
    }
    curve->solves += solver.solves();
    step *= 0.5;
    if (std::abs(step) < options.min_step * range) {
      curve->end = EventCurveEnd::kVanished;
      curve->message =
          std::string(kind == EventKind::kPeak ? "no maximum of " + options.measure.name
                                               : std::string("no Neimark-Sacker point")) +
          " followed beyond " + parameter.path() + "=" + Format(last.parameter) +
          " (omega=" + Format(last.omega) + "): " + why;
      return;
    }
  }
  curve->end = EventCurveEnd::kReachedTo;
}

// The peak between branch points lo, mid, hi (mid the largest measure), or false with why.
bool LocateOnBranch(EventSolver& solver, const TracePoint& lo, const TracePoint& mid,
                    const TracePoint& hi, Sample* peak, std::string* why) {
  Sample a, b, c;
  if (!solver.Differentiate(lo.point.lambda, lo.point.y, &a) ||
      !solver.Differentiate(mid.point.lambda, mid.point.y, &b) ||
      !solver.Differentiate(hi.point.lambda, hi.point.y, &c)) {
    *why = solver.message();
    return false;
  }
  if (a.omega > c.omega) std::swap(a, c);  // a below b below c in ω
  if (b.event > 0.0 && c.event <= 0.0) return Locate(solver, b, c, peak, why);
  if (b.event <= 0.0 && a.event > 0.0) return Locate(solver, a, b, peak, why);
  *why = "dm/domega does not change sign from omega=" + Format(a.omega) + " to " + Format(c.omega);
  return false;
}

// The Neimark–Sacker point between the branch points around a localised one.
bool LocateCrossing(EventSolver& solver, const TracePoint& before, const TracePoint& after,
                    Sample* point, std::string* why) {
  Sample a, b;
  if (!solver.Differentiate(before.point.lambda, before.point.y, &a) ||
      !solver.Differentiate(after.point.lambda, after.point.y, &b)) {
    *why = solver.message();
    return false;
  }
  if (a.event * b.event > 0.0) {
    *why = "the complex pair does not cross the unit circle from omega=" + Format(a.omega) +
           " to " + Format(b.omega);
    return false;
  }
  return Locate(solver, a, b, point, why);
}

// Where a curve starts: an event between branch points, to be located.
struct Start {
  int point = 0;  // branch point nearest it (peaks) or before it (Neimark–Sacker)
  double omega = 0.0;
};

std::vector<Start> PeakStarts(const Case& the_case, const TraceResult& trace,
                              const EventCurveOptions& options, EventCurveResult* result) {
  EventSolver solver(the_case, EventKind::kPeak, options.measure);
  std::vector<double> measures;
  for (const TracePoint& point : trace.points) {
    Sample sample;
    measures.push_back(solver.Differentiate(point.point.lambda, point.point.y, &sample)
                           ? sample.measure
                           : std::numeric_limits<double>::quiet_NaN());
  }
  std::vector<Start> starts;
  for (size_t i = 1; i + 1 < measures.size(); ++i) {
    if (!(measures[i] > measures[i - 1] && measures[i] >= measures[i + 1])) continue;
    const double lo = trace.points[i - 1].point.lambda, mid = trace.points[i].point.lambda;
    if ((mid - lo) * (trace.points[i + 1].point.lambda - mid) <= 0.0) {
      result->notes.push_back("the maximum at point " + std::to_string(i) + " (omega=" +
                              Format(mid) + ") is beside a fold of the branch: follow the fold");
      continue;
    }
    starts.push_back({static_cast<int>(i), mid});
  }
  result->branch_events = static_cast<int>(starts.size());
  if (starts.empty()) {
    result->notes.push_back("the branch has no maximum of " + options.measure.name +
                            " between its ends (" + trace.branch.summary.message + ")");
  }
  return starts;
}

std::vector<Start> NeimarkSackerStarts(const TraceResult& trace, EventCurveResult* result) {
  std::vector<Start> starts;
  for (const Bifurcation& bifurcation : trace.bifurcations) {
    if (bifurcation.type != BifurcationType::kNeimarkSacker) continue;
    if (bifurcation.discontinuous) {
      result->notes.push_back("the Neimark-Sacker point at omega=" + Format(bifurcation.omega) +
                              " is a jump of the multipliers (a nonsmooth law switched): no "
                              "smooth crossing to follow");
      continue;
    }
    starts.push_back({bifurcation.after_point, bifurcation.omega});
  }
  result->branch_events = static_cast<int>(starts.size());
  if (starts.empty()) {
    result->notes.push_back("the branch has no Neimark-Sacker point (" +
                            trace.branch.summary.message + ")");
  }
  return starts;
}

EventCurveResult TraceEventCurves(const Case& the_case, const CaseParameter& parameter,
                                  const EventCurveOptions& options, EventKind kind) {
  the_case.Validate();
  if (the_case.method != Method::kArclength) {
    throw InputError(
        "continuation.method: peak and Neimark-Sacker curves need the arclength "
        "method");
  }
  if (kind == EventKind::kNeimarkSacker && !the_case.stability.enabled) {
    throw InputError("stability.enabled: Neimark-Sacker curves need the stability analysis");
  }
  EventCurveResult result;
  result.parameter = parameter.path();
  result.from = parameter.Get(the_case);
  result.to = options.to;
  result.measure = options.measure.name;
  options.Validate(result.from);
  try {
    parameter.With(the_case, options.to);
  } catch (const InputError& error) {
    throw InputError(std::string("to: the case rejects it: ") + error.what());
  }
  Case branch_case = the_case;
  // Peaks need only the measure along the branch; Neimark-Sacker points its stability.
  if (kind == EventKind::kPeak) branch_case.stability.enabled = false;
  TraceOptions trace_options;
  trace_options.progress = options.progress;
  trace_options.solve_signals = false;
  StopCheck check(options.stop, options.poll);
  trace_options.observer = &check;
  const TraceResult trace = TraceCase(branch_case, trace_options);

  std::vector<Start> starts = kind == EventKind::kPeak
                                  ? PeakStarts(the_case, trace, options, &result)
                                  : NeimarkSackerStarts(trace, &result);
  if (!std::isnan(options.near) && !starts.empty()) {
    const auto nearest = std::min_element(starts.begin(), starts.end(), [&](auto& a, auto& b) {
      return std::abs(a.omega - options.near) < std::abs(b.omega - options.near);
    });
    starts = {*nearest};
  }
  const size_t last_point = trace.points.empty() ? 0 : trace.points.size() - 1;
  for (const Start& start : starts) {
    if (!check.Continue()) break;
    const auto started = std::chrono::steady_clock::now();
    EventCurve curve;
    curve.start_point = start.point;
    EventSolver solver(the_case, kind, options.measure);
    Sample located;
    std::string why;
    const size_t i = static_cast<size_t>(start.point);
    const bool found =
        kind == EventKind::kPeak
            ? LocateOnBranch(solver, trace.points[i - 1], trace.points[i], trace.points[i + 1],
                             &located, &why)
            : LocateCrossing(solver, trace.points[i], trace.points[std::min(i + 1, last_point)],
                             &located, &why);
    if (!found) {
      curve.message = std::string("the ") + EventName(kind) + " near omega=" + Format(start.omega) +
                      " was not located: " + why;
    } else {
      curve.start_omega = located.omega;
      curve.points.push_back(ToPoint(result.from, located, solver.solves()));
      curve.solves = solver.solves();
      if (options.progress != nullptr) {
        *options.progress << "nfrc: " << EventName(kind) << " " << result.curves.size()
                          << " at omega=" << located.omega << ": following " << parameter.path()
                          << " from " << result.from << " to " << options.to << "\n";
      }
      Follow(the_case, parameter, options, kind, result.from,
             static_cast<int>(result.curves.size()), check, &curve);
    }
    curve.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    result.curves.push_back(std::move(curve));
    if (options.observer != nullptr) options.observer->OnCurve(result.curves.back());
  }
  return result;
}

}  // namespace

PeakMeasure ParsePeakMeasure(const std::string& text, const Case& the_case) {
  PeakMeasure measure;
  if (text == "energy") return measure;
  const size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  if (colon == std::string::npos || (kind != "h1" && kind != "max_abs")) {
    throw InputError("measure: \"" + text + "\" is not energy, h1:<output> or max_abs:<output>");
  }
  const std::string output = text.substr(colon + 1);
  const auto found = std::find(the_case.output_names.begin(), the_case.output_names.end(), output);
  if (found == the_case.output_names.end()) {
    throw InputError("measure: \"" + output + "\" is not one of the case's output.dofs");
  }
  measure.kind = kind == "h1" ? PeakMeasure::Kind::kFirstHarmonic : PeakMeasure::Kind::kMaxAbs;
  measure.output = static_cast<int>(found - the_case.output_names.begin());
  measure.name = kind + "_" + output;
  return measure;
}

double EvaluatePeakMeasure(const PeakMeasure& measure, HarmonicSystem& system,
                           PointAnalyzer& analyzer, const Eigen::VectorXd& y, double omega) {
  switch (measure.kind) {
    case PeakMeasure::Kind::kEnergy:
      return PeriodEnergy(system, y, omega);
    case PeakMeasure::Kind::kMaxAbs:
      return analyzer.MaxAbs(y, omega, analyzer.output_dofs()[measure.output]);
    case PeakMeasure::Kind::kFirstHarmonic: {
      const int dof = analyzer.output_dofs()[measure.output];
      const Eigen::VectorXd c = system.DofCoefficients(y, omega, dof);
      const HarmonicSet& set = system.harmonic_set();
      for (int p = 0; p < set.num_harmonics(); ++p) {
        if (set.harmonics()[p] == 1) return std::hypot(c(set.CosIndex(p)), c(set.SinIndex(p)));
      }
      return 0.0;
    }
  }
  return 0.0;
}

const char* ToString(EventCurveEnd end) {
  switch (end) {
    case EventCurveEnd::kReachedTo:
      return "reached_to";
    case EventCurveEnd::kVanished:
      return "vanished";
    case EventCurveEnd::kMaxPoints:
      return "max_points";
    case EventCurveEnd::kStopped:
      return "stopped";
    case EventCurveEnd::kStartFailed:
      return "start_failed";
  }
  return "unknown";
}

void EventCurveOptions::Validate(double from) const {
  if (!std::isfinite(to) || to == from) {
    throw InputError("to: must be finite and differ from the parameter's value in the case");
  }
  if (std::isinf(near) || (!std::isnan(near) && !(near > 0.0))) {
    throw InputError("near: must be a positive frequency");
  }
  for (double station : stations) {
    if (!((station - from) * (to - station) > 0.0)) {
      throw InputError("stations: " + Format(station) +
                       " is not strictly between the case's value and to");
    }
  }
  if (!(initial_step > 0.0) || !(initial_step <= 1.0)) {
    throw InputError("initial_step: must be in (0, 1] (a fraction of |to - from|)");
  }
  if (!(max_step >= initial_step) || !(max_step <= 1.0)) {
    throw InputError("max_step: must be in [initial_step, 1]");
  }
  if (!(min_step > 0.0) || !(min_step <= initial_step)) {
    throw InputError("min_step: must be in (0, initial_step]");
  }
  if (max_points < 1) throw InputError("max_points: must be at least 1");
}

EventCurveResult TracePeakCurves(const Case& the_case, const CaseParameter& parameter,
                                 const EventCurveOptions& options) {
  return TraceEventCurves(the_case, parameter, options, EventKind::kPeak);
}

EventCurveResult TraceNeimarkSackerCurves(const Case& the_case, const CaseParameter& parameter,
                                          const EventCurveOptions& options) {
  return TraceEventCurves(the_case, parameter, options, EventKind::kNeimarkSacker);
}

}  // namespace nfrc
