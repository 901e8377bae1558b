#include "analysis/event_search.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <vector>

namespace nfrc::event_search {
namespace {

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
// On a nonsmooth branch the top of a resonance can hold several local maxima ~1e-4 apart in ω
// (the slope jumps where samples switch between stick and slip): kEventProbes probes each side
// within kClusterWindow (relative to ω) find the highest, in up to kPolishRounds moves.
constexpr double kClusterWindow = 2e-3;
constexpr int kPolishRounds = 3;

}  // namespace

std::string FormatValue(double value) {
  std::ostringstream out;
  out.precision(8);
  out << value;
  return out.str();
}

// The zero of the event between `rising` (event > 0) and `falling` (event ≤ 0) — for peaks a
// maximum — by regula falsi with the Illinois modification (superlinear where the event is
// smooth), with a bisection whenever two iterations did not halve the bracket (where it jumps,
// as dm/dω does where a nonsmooth law switches, regula falsi alone crawls).
static bool Refine(EventSolver& solver, Sample rising, Sample falling, Sample* peak,
                   std::string* why) {
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
  *why = "the bracket from omega=" + FormatValue(rising.omega) + " to " +
         FormatValue(falling.omega) + " did not close in " + std::to_string(kMaxRefineIterations) +
         " solves";
  return false;
}

// Moves a located maximum to the highest one within the cluster window around it.
bool Polish(EventSolver& solver, Sample* peak, std::string* why) {
  for (int round = 0; round < kPolishRounds; ++round) {
    const double delta = kClusterWindow * std::abs(peak->omega) / kEventProbes;
    std::vector<Sample> probes = {*peak};  // in increasing ω
    for (double side : {-1.0, 1.0}) {
      const Sample* from = peak;
      Sample probe;
      for (int k = 1; k <= kEventProbes; ++k) {
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
             double last_omega, const Eigen::VectorXd& last_y, Sample* peak, std::string* why) {
  Sample start;
  if (!solver.At(omega_pred, y_pred, last_y, &start)) {
    *why = solver.message();
    return false;
  }
  if (start.event == 0.0) {
    *peak = start;
    return true;
  }
  const double reach =
      std::max(kReachFactor * std::abs(omega_pred - last_omega), kMinReach * std::abs(last_omega));
  double width = std::max(std::abs(omega_pred - last_omega), kMinBracket * std::abs(last_omega));
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
         " within " + FormatValue(reach) + " of omega=" + FormatValue(omega_pred);
  return false;
}

}  // namespace nfrc::event_search
