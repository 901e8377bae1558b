#include "analysis/bifurcation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/hill_reduction.h"
#include "analysis/trace.h"
#include "continuation/fixed_lambda.h"

namespace nfrc {
namespace {

// A localised crossing whose multipliers are still this far from |μ| = 1 once ω is pinned to
// bifurcation_tolerance (or on both sides of a bracket within jump_tolerance) jumped across
// the circle (a smooth crossing passes through it).
constexpr double kJumpModulus = 0.05;

using Complex = std::complex<double>;

enum class Crossing { kPlusOne, kMinusOne, kComplex };

// |Im μ| up to this fraction of |μ| is a real multiplier: Hill's exponents of a real pencil
// are real or conjugate pairs up to round-off, far below it, while a complex pair that has
// just crossed sits at a finite angle.
constexpr double kRealTolerance = 1e-4;

Crossing TypeOf(Complex mu) {
  if (std::abs(mu.imag()) > kRealTolerance * std::abs(mu)) return Crossing::kComplex;
  return mu.real() > 0.0 ? Crossing::kPlusOne : Crossing::kMinusOne;
}

// The multiplier of a type nearest the unit circle (smallest |log|μ||).
std::optional<Complex> Nearest(const FloquetResult& result, Crossing type) {
  std::optional<Complex> best;
  for (const Complex& mu : result.multipliers) {
    if (TypeOf(mu) != type) continue;
    if (!best || std::abs(std::log(std::abs(mu))) < std::abs(std::log(std::abs(*best)))) best = mu;
  }
  return best;
}

double LogModulus(const FloquetResult& result, Crossing type) {
  const std::optional<Complex> mu = Nearest(result, type);
  return mu ? std::log(std::abs(*mu)) : std::numeric_limits<double>::quiet_NaN();
}

std::vector<Complex> CrossingMultipliers(const FloquetResult& result, Crossing type) {
  const std::optional<Complex> mu = Nearest(result, type);
  if (!mu) return {};
  if (type == Crossing::kComplex) return {*mu, std::conj(*mu)};
  return {*mu};
}

}  // namespace

StabilityMonitor::StabilityMonitor(HarmonicSystem& system, const StabilityOptions& options,
                                   const ContinuationOptions& continuation)
    : system_(system), options_(options), continuation_(continuation) {}

FloquetResult StabilityMonitor::Analyze(const Eigen::VectorXd& y, double omega) {
  return Analyze(y, omega, &krylov_start_);
}

FloquetResult StabilityMonitor::Analyze(const Eigen::VectorXd& y, double omega,
                                        Eigen::VectorXd* warm_start) {
  HillOptions hill;
  hill.unstable_tolerance = options_.unstable_tolerance;
  try {
    if (!hill_) {
      hill_ = std::make_unique<HillAssembler>(
          system_,
          options_.hill_modes >= 0 ? HillReduction(system_, options_.hill_modes) : nullptr);
    }
    return SolveHill(hill_->Assemble(y, omega), hill, warm_start);
  } catch (const std::runtime_error& error) {
    FloquetResult failed;
    failed.method = "hill";
    failed.message = error.what();
    return failed;
  }
}

std::optional<Bifurcation> StabilityMonitor::Between(const BranchPoint& a,
                                                     const FloquetResult& floquet_a,
                                                     const BranchPoint& b,
                                                     const FloquetResult& floquet_b,
                                                     const Fold* fold) {
  if (!floquet_a.computed || !floquet_b.computed ||
      floquet_a.num_unstable == floquet_b.num_unstable) {
    return std::nullopt;
  }
  // The multiplier that crossed: the least unstable one on the more unstable side.
  const FloquetResult& more =
      floquet_b.num_unstable > floquet_a.num_unstable ? floquet_b : floquet_a;
  std::optional<Complex> crossed;
  for (const Complex& mu : more.multipliers) {
    if (std::abs(mu) > 1.0 + options_.unstable_tolerance &&
        (!crossed || std::abs(mu) < std::abs(*crossed))) {
      crossed = mu;
    }
  }
  const Crossing type = TypeOf(*crossed);
  // Each localisation starts Arnoldi cold and warm-starts its own trials from each other: its
  // result depends on its two points only, not on what this monitor analysed before.
  Eigen::VectorXd warm_start;
  Bifurcation bifurcation;
  if (type == Crossing::kPlusOne && fold != nullptr) {
    bifurcation.type = BifurcationType::kFold;
    bifurcation.omega = fold->lambda;
    bifurcation.omega_accuracy = fold->lambda_accuracy;
    bifurcation.converged = fold->converged;
    bifurcation.iterations = fold->iterations;
    bifurcation.y = fold->y;
    bifurcation.crossing_multipliers =
        CrossingMultipliers(Analyze(fold->y, fold->lambda, &warm_start), type);
    return bifurcation;
  }
  bifurcation.type = type == Crossing::kPlusOne    ? BifurcationType::kBranchPoint
                     : type == Crossing::kMinusOne ? BifurcationType::kPeriodDoubling
                                                   : BifurcationType::kNeimarkSacker;

  double wa = a.lambda, wb = b.lambda;
  Eigen::VectorXd ya = a.y, yb = b.y;
  double fa = LogModulus(floquet_a, type), fb = LogModulus(floquet_b, type);
  const int count_a = floquet_a.num_unstable;
  // Until an iterate exists, report the end nearer the crossing.
  const bool b_nearer = std::abs(fb) < std::abs(fa);
  bifurcation.omega = b_nearer ? wb : wa;
  bifurcation.y = b_nearer ? yb : ya;
  bifurcation.crossing_multipliers = CrossingMultipliers(b_nearer ? floquet_b : floquet_a, type);
  bifurcation.omega_accuracy = std::abs(wb - wa);
  int last_side = 0;  // 1: a was replaced last, 2: b (Illinois halves the other end's value)
  // The ends' log-moduli as computed (fa and fb carry Illinois's halvings).
  double log_a = fa, log_b = fb;
  const auto off_circle = [](double log_modulus) {
    return std::isfinite(log_modulus) && std::abs(std::exp(log_modulus) - 1.0) > kJumpModulus;
  };
  const auto jumped = [&] {
    return std::abs(wb - wa) <= options_.jump_tolerance * std::max(std::abs(wa), std::abs(wb)) &&
           off_circle(log_a) && off_circle(log_b);
  };
  for (int iteration = 1; iteration <= options_.max_bifurcation_iterations; ++iteration) {
    if (jumped()) {
      bifurcation.converged = true;
      bifurcation.discontinuous = true;
      return bifurcation;
    }
    double w = 0.5 * (wa + wb);
    if (std::isfinite(fa) && std::isfinite(fb) && (fa < 0.0) != (fb < 0.0)) {
      const double secant = (wa * fb - wb * fa) / (fb - fa);
      if ((secant - wa) * (secant - wb) < 0.0) w = secant;
    }
    const double t = (w - wa) / (wb - wa);
    const Eigen::VectorXd guess = (1.0 - t) * ya + t * yb;
    const FixedLambdaSolution solved = SolveAtFixedLambda(system_, guess, w, yb, continuation_);
    if (!solved.converged) break;
    const FloquetResult at = Analyze(solved.y, w, &warm_start);
    if (!at.computed) break;
    bifurcation.iterations = iteration;
    bifurcation.omega = w;
    bifurcation.y = solved.y;
    bifurcation.crossing_multipliers = CrossingMultipliers(at, type);
    const double f = LogModulus(at, type);
    if (at.num_unstable == count_a) {
      wa = w;
      ya = solved.y;
      fa = f;
      log_a = f;
      if (last_side == 1) fb *= 0.5;
      last_side = 1;
    } else {
      wb = w;
      yb = solved.y;
      fb = f;
      log_b = f;
      if (last_side == 2) fa *= 0.5;
      last_side = 2;
    }
    bifurcation.omega_accuracy = std::abs(wb - wa);
    if (bifurcation.omega_accuracy <= options_.bifurcation_tolerance * std::abs(w)) {
      bifurcation.converged = true;
      break;
    }
  }
  // Pinned to bifurcation_tolerance, a smooth crossing has both ends of its bracket on the
  // circle to within the bracket's width; an end still off it is one side of a jump, whose
  // other side may have landed near the circle (|μ| 1.30 → 0.966 at ω = 0.5819 on NLvib's
  // penalty spring), so the last iterate's multipliers alone do not tell.
  if (bifurcation.converged) bifurcation.discontinuous = off_circle(log_a) || off_circle(log_b);
  return bifurcation;
}

std::vector<QuasiPeriodicWindow> QuasiPeriodicWindows(const std::vector<Bifurcation>& bifurcations,
                                                      const std::vector<TracePoint>& points) {
  std::vector<QuasiPeriodicWindow> windows;
  std::optional<QuasiPeriodicWindow> open;
  auto unstable = [&](int index) {
    return index >= 0 && index < static_cast<int>(points.size())
               ? points[static_cast<size_t>(index)].floquet.num_unstable
               : 0;
  };
  for (const Bifurcation& b : bifurcations) {
    if (b.type != BifurcationType::kNeimarkSacker) continue;
    const bool opens = unstable(b.after_point + 1) > unstable(b.after_point);
    if (opens && !open) {
      open = QuasiPeriodicWindow{b.omega, b.omega, b.after_point + 1, b.after_point + 1, false};
    } else if (!opens && open) {
      open->omega_to = b.omega;
      open->last_point = b.after_point;
      open->closed = true;
      windows.push_back(*open);
      open.reset();
    }
  }
  if (open && !points.empty()) {
    open->omega_to = points.back().point.lambda;
    open->last_point = static_cast<int>(points.size()) - 1;
    windows.push_back(*open);
  }
  return windows;
}

}  // namespace nfrc
