#include "analysis/event_curve.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>
#include <utility>

#include "analysis/bifurcation.h"
#include "analysis/event_search.h"
#include "analysis/trace.h"
#include "core/errors.h"

namespace nfrc {
namespace {

using event_search::EventKind;
using event_search::EventName;
using event_search::EventSolver;
using event_search::Sample;

// Steps that needed at most this many fixed-ω solves let the parameter step grow by
// kStepGrowth (a start, two brackets, a few secant iterations and the polishing probes).
constexpr int kEasySolves = 2 * event_search::kEventProbes + 10;
constexpr double kStepGrowth = 1.5;
// A step that would leave less than a quarter step to the target goes all the way.
constexpr double kLandingReach = 1.25;
// A maximum below this fraction of the largest one on the curve (or the branch) is of a response
// that has vanished (a friction damper stuck throughout): its ω is rounding; not followed.
constexpr double kVanishedMeasure = 1e-9;

std::string Format(double value) { return event_search::FormatValue(value); }

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
  return kLandingReach * std::abs(step) >= std::abs(target - p) ? target : p + step;
}

void Follow(const Case& the_case, const CaseParameter& parameter, const EventCurveOptions& options,
            EventKind kind, double from, int index, StopCheck& check, EventCurve* curve) {
  const double range = std::abs(options.to - from);
  const double sign = options.to > from ? 1.0 : -1.0;
  double step = sign * options.initial_step * range;
  double largest = curve->points.back().measure;  // on the curve so far
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
    const bool found =
        event_search::Bracket(solver, omega_pred, y_pred, last.omega, last.y, &peak, &why);
    if (found && kind == EventKind::kPeak && !(peak.measure > kVanishedMeasure * largest)) {
      curve->solves += solver.solves();
      curve->end = EventCurveEnd::kVanished;
      curve->message = "the response vanishes at " + parameter.path() + "=" + Format(p) + " (" +
                       options.measure.name + "=" + Format(peak.measure) + ")";
      return;
    }
    if (found) {
      curve->points.push_back(ToPoint(p, peak, solver.solves()));
      if (options.observer != nullptr) options.observer->OnPoint(index, curve->points.back());
      largest = std::max(largest, peak.measure);
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
  if (b.event > 0.0 && c.event <= 0.0) return event_search::Locate(solver, b, c, peak, why);
  if (b.event <= 0.0 && a.event > 0.0) return event_search::Locate(solver, a, b, peak, why);
  if (a.event > 0.0 && c.event <= 0.0) return event_search::Locate(solver, a, c, peak, why);
  // The slopes at the points disagree with their measures (the ripple of a nonsmooth branch
  // between them): the highest point's window is searched instead.
  *peak = b;
  return event_search::Polish(solver, peak, why);
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
  return event_search::Locate(solver, a, b, point, why);
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
  double largest = 0.0;
  for (const TracePoint& point : trace.points) {
    measures.push_back(solver.Measure(point.point.y, point.point.lambda));
    largest = std::max(largest, measures.back());
  }
  std::vector<Start> starts;
  for (size_t i = 1; i + 1 < measures.size(); ++i) {
    if (!(measures[i] > measures[i - 1] && measures[i] >= measures[i + 1])) continue;
    if (!(measures[i] > kVanishedMeasure * largest)) continue;  // rounding of a vanished response
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
  StopCheck check(options.stop, options.poll);
  // Peaks need only the measure along the branch; Neimark-Sacker points its stability.
  const TraceResult trace =
      TraceStudyBranch(the_case, kind == EventKind::kNeimarkSacker, options.progress, &check);

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
      if (options.observer != nullptr) {
        options.observer->OnPoint(static_cast<int>(result.curves.size()), curve.points.back());
      }
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
  CheckStudyTarget(from, to);
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
