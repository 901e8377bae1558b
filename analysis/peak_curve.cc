#include "analysis/peak_curve.h"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>
#include <utility>

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
  double slope = 0.0;
};

// The system at one parameter value and the fixed-ω solves on it.
class PeakSolver {
 public:
  PeakSolver(Case at_parameter, const PeakMeasure& measure)
      : case_(std::move(at_parameter)),
        system_(BuildSystem(case_)),
        analyzer_(*system_, case_.output_dofs),
        measure_(measure) {}

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
    sample->slope =
        (Measure(y + h * sample->dy, omega + h) - Measure(y - h * sample->dy, omega - h)) /
        (2.0 * h);
    if (!std::isfinite(sample->slope) || !sample->dy.allFinite()) {
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

  Case case_;
  std::unique_ptr<HarmonicSystem> system_;
  PointAnalyzer analyzer_;
  const PeakMeasure& measure_;
  int solves_ = 0;
  std::string message_;
};

// The zero of dm/dω between `rising` (slope > 0) and `falling` (slope ≤ 0), a maximum, by
// regula falsi with the Illinois modification (superlinear where the slope is smooth), with a
// bisection whenever two iterations did not halve the bracket (where the slope jumps, as it
// does where a nonsmooth law switches, regula falsi alone crawls).
bool Refine(PeakSolver& solver, Sample rising, Sample falling, Sample* peak, std::string* why) {
  double f_rising = rising.slope, f_falling = falling.slope;
  int kept = 0;  // +1: the rising end was kept last time, −1: the falling end
  double width_before = std::numeric_limits<double>::infinity();  // two iterations ago
  double width_last = width_before;
  for (int iteration = 0; iteration < kMaxRefineIterations; ++iteration) {
    const double width = std::abs(falling.omega - rising.omega);
    const double scale = std::max(std::abs(rising.omega), std::abs(falling.omega));
    if (falling.slope == 0.0 || width <= kOmegaTolerance * scale) {
      *peak = falling.measure >= rising.measure ? falling : rising;
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
    if (next.slope > 0.0) {
      rising = std::move(next);
      f_rising = rising.slope;
      if (kept == +1) f_falling *= 0.5;
      kept = -1;
    } else {
      falling = std::move(next);
      f_falling = falling.slope;
      if (kept == -1) f_rising *= 0.5;
      kept = +1;
    }
  }
  *why = "the bracket from omega=" + Format(rising.omega) + " to " + Format(falling.omega) +
         " did not close in " + std::to_string(kMaxRefineIterations) + " solves";
  return false;
}

// Moves a located maximum to the highest one within the cluster window around it.
bool Polish(PeakSolver& solver, Sample* peak, std::string* why) {
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
    if (highest->slope > 0.0 && j + 1 < probes.size() && probes[j + 1].slope <= 0.0) {
      if (!Refine(solver, probes[j], probes[j + 1], peak, why)) return false;
    } else if (highest->slope <= 0.0 && j > 0 && probes[j - 1].slope > 0.0) {
      if (!Refine(solver, probes[j - 1], probes[j], peak, why)) return false;
    } else {
      *peak = *highest;  // at the window's edge, still rising: the next round goes on from it
    }
  }
  return true;
}

// Refine, then Polish.
bool Locate(PeakSolver& solver, const Sample& rising, const Sample& falling, Sample* peak,
            std::string* why) {
  return Refine(solver, rising, falling, peak, why) && Polish(solver, peak, why);
}

// The maximum nearest ω_pred on `solver`'s system: bracketed by walking uphill from the
// prediction with doubling steps, then refined.
bool Bracket(PeakSolver& solver, double omega_pred, const Eigen::VectorXd& y_pred,
             const PeakCurvePoint& last, Sample* peak, std::string* why) {
  Sample start;
  if (!solver.At(omega_pred, y_pred, last.y, &start)) {
    *why = solver.message();
    return false;
  }
  if (start.slope == 0.0) {
    *peak = start;
    return true;
  }
  const double direction = start.slope > 0.0 ? 1.0 : -1.0;
  const double reach =
      std::max(kReachFactor * std::abs(omega_pred - last.omega), kMinReach * std::abs(last.omega));
  double width = std::max(std::abs(omega_pred - last.omega), kMinBracket * std::abs(last.omega));
  Sample previous = start;
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
    if (next.slope * direction <= 0.0) {
      return direction > 0.0 ? Locate(solver, previous, next, peak, why)
                             : Locate(solver, next, previous, peak, why);
    }
    previous = std::move(next);
    width *= 2.0;
  }
  *why = "no maximum within " + Format(reach) + " of omega=" + Format(omega_pred);
  return false;
}

PeakCurvePoint ToPoint(double parameter, const Sample& sample, int solves) {
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

void FollowPeak(const Case& the_case, const CaseParameter& parameter,
                const PeakCurveOptions& options, double from, int index, StopCheck& check,
                PeakCurve* curve) {
  const double range = std::abs(options.to - from);
  const double sign = options.to > from ? 1.0 : -1.0;
  double step = sign * options.initial_step * range;
  while (curve->points.back().parameter != options.to) {
    if (!check.Continue()) {
      curve->end = PeakCurveEnd::kStopped;
      curve->message = "stopped";
      return;
    }
    if (static_cast<int>(curve->points.size()) >= options.max_points) {
      curve->end = PeakCurveEnd::kMaxPoints;
      curve->message = "max_points reached";
      return;
    }
    const PeakCurvePoint& last = curve->points.back();
    const double p = NextValue(last.parameter, step, options.to, options.stations);
    // Linear extrapolation in the parameter from the last two points.
    double omega_pred = last.omega;
    Eigen::VectorXd y_pred = last.y;
    if (curve->points.size() >= 2) {
      const PeakCurvePoint& before = curve->points[curve->points.size() - 2];
      const double t = (p - last.parameter) / (last.parameter - before.parameter);
      omega_pred += t * (last.omega - before.omega);
      y_pred += t * (last.y - before.y);
    }
    PeakSolver solver(parameter.With(the_case, p), options.measure);
    Sample peak;
    std::string why;
    double largest = 0.0;
    for (const PeakCurvePoint& point : curve->points) largest = std::max(largest, point.measure);
    const bool found = Bracket(solver, omega_pred, y_pred, last, &peak, &why);
    if (found && !(peak.measure > kVanishedMeasure * largest)) {
      curve->solves += solver.solves();
      curve->end = PeakCurveEnd::kVanished;
      curve->message = "the response vanishes at " + parameter.path() + "=" + Format(p) + " (" +
                       options.measure.name + "=" + Format(peak.measure) + ")";
      return;
    }
    if (found) {
      curve->points.push_back(ToPoint(p, peak, solver.solves()));
      curve->solves += solver.solves();
      if (options.progress != nullptr) {
        *options.progress << "nfrc: peak " << index << " point " << curve->points.size() - 1 << " "
                          << parameter.path() << "=" << p << " omega=" << peak.omega << " "
                          << options.measure.name << "=" << peak.measure << " step=" << step
                          << " solves=" << solver.solves() << "\n";
      }
      if (solver.solves() <= kEasySolves) {
        step = sign * std::min(std::abs(step) * kStepGrowth, options.max_step * range);
      }
      continue;
    }
    curve->solves += solver.solves();
    step *= 0.5;
    if (std::abs(step) < options.min_step * range) {
      curve->end = PeakCurveEnd::kVanished;
      curve->message = "no maximum of " + options.measure.name + " followed beyond " +
                       parameter.path() + "=" + Format(last.parameter) +
                       " (omega=" + Format(last.omega) + "): " + why;
      return;
    }
  }
  curve->end = PeakCurveEnd::kReachedTo;
}

// The peak between branch points lo, mid, hi (mid the largest measure), or false with why.
bool LocateOnBranch(PeakSolver& solver, const TracePoint& lo, const TracePoint& mid,
                    const TracePoint& hi, Sample* peak, std::string* why) {
  Sample a, b, c;
  if (!solver.Differentiate(lo.point.lambda, lo.point.y, &a) ||
      !solver.Differentiate(mid.point.lambda, mid.point.y, &b) ||
      !solver.Differentiate(hi.point.lambda, hi.point.y, &c)) {
    *why = solver.message();
    return false;
  }
  if (a.omega > c.omega) std::swap(a, c);  // a below b below c in ω
  if (b.slope > 0.0 && c.slope <= 0.0) return Locate(solver, b, c, peak, why);
  if (b.slope <= 0.0 && a.slope > 0.0) return Locate(solver, a, b, peak, why);
  *why = "dm/domega does not change sign from omega=" + Format(a.omega) + " to " + Format(c.omega);
  return false;
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

const char* ToString(PeakCurveEnd end) {
  switch (end) {
    case PeakCurveEnd::kReachedTo:
      return "reached_to";
    case PeakCurveEnd::kVanished:
      return "vanished";
    case PeakCurveEnd::kMaxPoints:
      return "max_points";
    case PeakCurveEnd::kStopped:
      return "stopped";
    case PeakCurveEnd::kStartFailed:
      return "start_failed";
  }
  return "unknown";
}

void PeakCurveOptions::Validate(double from) const {
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

PeakCurveResult TracePeakCurves(const Case& the_case, const CaseParameter& parameter,
                                const PeakCurveOptions& options) {
  the_case.Validate();
  if (the_case.method != Method::kArclength) {
    throw InputError("continuation.method: peak curves need the arclength method");
  }
  PeakCurveResult result;
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
  branch_case.stability.enabled = false;  // only the measure along the branch is needed
  TraceOptions trace_options;
  trace_options.progress = options.progress;
  trace_options.solve_signals = false;
  StopCheck check(options.stop, options.poll);
  trace_options.observer = &check;
  const TraceResult trace = TraceCase(branch_case, trace_options);

  PeakSolver solver(the_case, options.measure);
  std::vector<double> measures;
  for (const TracePoint& point : trace.points) {
    Sample sample;
    measures.push_back(solver.Differentiate(point.point.lambda, point.point.y, &sample)
                           ? sample.measure
                           : std::numeric_limits<double>::quiet_NaN());
  }
  std::vector<int> peaks;
  for (size_t i = 1; i + 1 < measures.size(); ++i) {
    if (measures[i] > measures[i - 1] && measures[i] >= measures[i + 1]) {
      peaks.push_back(static_cast<int>(i));
    }
  }
  result.branch_peaks = static_cast<int>(peaks.size());
  if (peaks.empty()) {
    result.notes.push_back("the branch has no maximum of " + options.measure.name +
                           " between its ends (" + trace.branch.summary.message + ")");
  }
  if (!std::isnan(options.near) && !peaks.empty()) {
    const auto nearest = std::min_element(peaks.begin(), peaks.end(), [&](int a, int b) {
      return std::abs(trace.points[a].point.lambda - options.near) <
             std::abs(trace.points[b].point.lambda - options.near);
    });
    peaks = {*nearest};
  }
  for (int i : peaks) {
    if (!check.Continue()) break;
    const TracePoint& lo = trace.points[i - 1];
    const TracePoint& mid = trace.points[i];
    const TracePoint& hi = trace.points[i + 1];
    if ((mid.point.lambda - lo.point.lambda) * (hi.point.lambda - mid.point.lambda) <= 0.0) {
      result.notes.push_back("the maximum at point " + std::to_string(i) +
                             " (omega=" + Format(mid.point.lambda) +
                             ") is beside a fold of the branch: follow the fold instead");
      continue;
    }
    const auto started = std::chrono::steady_clock::now();
    PeakCurve curve;
    curve.start_point = i;
    PeakSolver start_solver(the_case, options.measure);
    Sample peak;
    std::string why;
    if (!LocateOnBranch(start_solver, lo, mid, hi, &peak, &why)) {
      curve.message = "the maximum at point " + std::to_string(i) + " was not located: " + why;
    } else {
      curve.start_omega = peak.omega;
      curve.points.push_back(ToPoint(result.from, peak, start_solver.solves()));
      curve.solves = start_solver.solves();
      if (options.progress != nullptr) {
        *options.progress << "nfrc: peak " << result.curves.size() << " at omega=" << peak.omega
                          << ": following " << parameter.path() << " from " << result.from << " to "
                          << options.to << "\n";
      }
      FollowPeak(the_case, parameter, options, result.from, static_cast<int>(result.curves.size()),
                 check, &curve);
    }
    curve.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    result.curves.push_back(std::move(curve));
    if (options.observer != nullptr) options.observer->OnCurve(result.curves.back());
  }
  return result;
}

}  // namespace nfrc
