#include "analysis/branch_switching.h"

#include <cmath>
#include <ostream>

#include "continuation/fixed_lambda.h"
#include "core/errors.h"

namespace nfrc {
namespace {

// Beside the period doubling the period-2 amplitude grows like √|ν − ν_pd|; the first try is
// this fraction of ν away, the amplitudes of φ relative to ‖y_pd‖.
constexpr double kSideOffset = 2e-3;
constexpr double kAmplitudes[] = {0.05, 0.15, 0.4};
// A solution with less odd-harmonic content than this has fallen back onto period 1.
constexpr double kMinimumContent = 1e-4;
constexpr int kInverseIterations = 6;
// A solution this far (relative) from the first branch at the same ω is another branch.
constexpr double kMinimumDistance = 1e-3;

// Positions of a set's harmonics, by harmonic number (−1: not in the set).
std::vector<int> PositionOf(const HarmonicSet& set) {
  std::vector<int> position(static_cast<size_t>(set.max_harmonic()) + 1, -1);
  for (int p = 0; p < set.num_harmonics(); ++p) {
    position[static_cast<size_t>(set.harmonics()[static_cast<size_t>(p)])] = p;
  }
  return position;
}

// A unit near-null vector of the Jacobian at (y, λ) by inverse iteration from `start`.
std::optional<Eigen::VectorXd> NearNullVector(HarmonicSystem& system, const Eigen::VectorXd& y,
                                              double lambda, Eigen::VectorXd v) {
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  if (!system.Evaluate(y, lambda, &residual, &jacobian, nullptr)) return std::nullopt;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(jacobian);
  for (int i = 0; i < kInverseIterations; ++i) {
    v = lu.solve(v);
    if (!v.allFinite() || v.norm() == 0.0) return std::nullopt;
    v.normalize();
  }
  return v;
}

// A null vector of the period-2 system's Jacobian in the odd ν-harmonics at (y, ν).
std::optional<Eigen::VectorXd> OddNullVector(HarmonicSystem& system, const Eigen::VectorXd& y,
                                             double nu) {
  const HarmonicSet& set = system.harmonic_set();
  const int nc = set.NumCoefficients();
  // Start from the odd harmonics only; the Jacobian keeps odd and even ν-harmonics apart on
  // a period-1 solution, so inverse iteration stays there.
  Eigen::VectorXd v = Eigen::VectorXd::Zero(y.size());
  for (int p = 0; p < set.num_harmonics(); ++p) {
    if (set.harmonics()[static_cast<size_t>(p)] % 2 == 0) continue;
    for (Eigen::Index block = 0; block + nc <= y.size(); block += nc) {
      v(block + set.CosIndex(p)) = 1.0;
      v(block + set.SinIndex(p)) = 0.5;
    }
  }
  return NearNullVector(system, y, nu, v);
}

// Traces `the_case` from its solution y at λ = lambda towards lambda_end and records the new
// branch in `result` (its start in ω, which is period_multiple·λ).
void TraceSwitched(Case the_case, double lambda, double lambda_end, const Eigen::VectorXd& y,
                   const TraceOptions& options, SwitchedBranch* result) {
  the_case.continuation.lambda_start = lambda;
  the_case.continuation.lambda_end = lambda_end;
  TraceOptions from = options;
  from.start = &y;
  result->trace = TraceCase(the_case, from);
  result->the_case = std::move(the_case);
  result->start_omega = result->the_case.period_multiple * lambda;
  result->started = true;
  result->message = "started at omega = " + std::to_string(result->start_omega);
}

// A switch that found no start: the message, and a start_failed summary that says it.
SwitchedBranch NotStarted(SwitchedBranch result, std::string message) {
  result.message = message;
  result.trace.branch.summary.reason = TerminationReason::kStartFailed;
  result.trace.branch.summary.message = std::move(message);
  return result;
}

// A deterministic start for inverse iteration with a component along every direction.
Eigen::VectorXd SpreadVector(Eigen::Index size) {
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i)
    v(i) = 1.0 + 0.37 * std::sin(1.7 * static_cast<double>(i));
  return v.normalized();
}

}  // namespace

Case SubharmonicCase(const Case& base, int multiple) {
  Case sub = base;
  const double m = multiple;
  sub.harmonics = HarmonicSet(multiple * base.harmonics.max_harmonic(), false,
                              multiple * base.harmonics.num_samples());
  for (ForcingTerm& term : sub.model.forcing) term.harmonic *= multiple;
  ContinuationOptions& c = sub.continuation;
  c.lambda_start /= m;
  c.lambda_end /= m;
  c.lambda_min /= m;  // NaN stays NaN
  c.lambda_max /= m;
  c.lambda_scale /= m;
  // The engine's progress lines then name the parameter for what it is.
  c.lambda_name = "omega/" + std::to_string(base.period_multiple * multiple);
  for (double& omega : sub.signals_at) omega /= m;
  for (double& omega : sub.validation.omegas) omega /= m;
  sub.validation.chirp.omega_start /= m;
  sub.validation.chirp.omega_end /= m;
  sub.title = base.title + " (period " + std::to_string(multiple) + ")";
  sub.period_multiple = base.period_multiple * multiple;
  return sub;
}

Eigen::VectorXd ToSubharmonic(const Eigen::VectorXd& y, const HarmonicSet& from,
                              const HarmonicSet& to, int multiple) {
  const int nc_from = from.NumCoefficients(), nc_to = to.NumCoefficients();
  const std::vector<int> position = PositionOf(to);
  const Eigen::Index blocks = y.size() / nc_from;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(blocks * nc_to);
  for (Eigen::Index b = 0; b < blocks; ++b) {
    for (int p = 0; p < from.num_harmonics(); ++p) {
      const int k = from.harmonics()[static_cast<size_t>(p)];
      const int q = position[static_cast<size_t>(multiple * k)];
      out(b * nc_to + to.CosIndex(q)) = y(b * nc_from + from.CosIndex(p));
      if (k > 0) out(b * nc_to + to.SinIndex(q)) = y(b * nc_from + from.SinIndex(p));
    }
  }
  return out;
}

SwitchedBranch FollowBranchPoint(const Case& base, const Bifurcation& branch_point,
                                 const TraceOptions& options) {
  SwitchedBranch result;
  result.the_case = base;
  std::unique_ptr<HarmonicSystem> system = BuildSystem(base);
  const Eigen::VectorXd& y_bp = branch_point.y;
  const std::optional<Eigen::VectorXd> phi =
      NearNullVector(*system, y_bp, branch_point.omega, SpreadVector(y_bp.size()));
  if (!phi) {
    return NotStarted(std::move(result), "no null vector of the Jacobian at the branch point");
  }
  const double lo = base.continuation.LowerBound(), hi = base.continuation.UpperBound();
  for (const double side : {1.0, -1.0}) {
    const double omega = branch_point.omega * (1.0 + side * kSideOffset);
    if (omega <= lo || omega >= hi) continue;
    const FixedLambdaSolution primary =
        SolveAtFixedLambda(*system, y_bp, omega, y_bp, base.continuation);
    if (!primary.converged) continue;
    for (const double amplitude : kAmplitudes) {
      for (const double sign : {1.0, -1.0}) {
        const Eigen::VectorXd guess = y_bp + sign * amplitude * y_bp.norm() * *phi;
        const FixedLambdaSolution solved =
            SolveAtFixedLambda(*system, guess, omega, y_bp, base.continuation);
        if (!solved.converged) continue;
        const double distance = (solved.y - primary.y).norm() / primary.y.norm();
        if (distance < kMinimumDistance) continue;
        if (options.progress != nullptr) {
          *options.progress << "nfrc: branch from the branch point at omega = "
                            << branch_point.omega << ", starting at omega = " << omega
                            << " (relative distance to the first branch " << distance << ")\n";
        }
        result.subharmonic_content = distance;
        TraceSwitched(base, omega, side > 0 ? hi : lo, solved.y, options, &result);
        return result;
      }
    }
  }
  return NotStarted(std::move(result),
                    "no second solution beside the branch point (tried both sides)");
}

SwitchedBranch FollowBifurcation(const Case& base, const Bifurcation& bifurcation,
                                 const TraceOptions& options) {
  switch (bifurcation.type) {
    case BifurcationType::kPeriodDoubling:
      return FollowPeriodDoubling(base, bifurcation, options);
    case BifurcationType::kBranchPoint:
      return FollowBranchPoint(base, bifurcation, options);
    case BifurcationType::kFold:
    case BifurcationType::kNeimarkSacker:
      break;
  }
  throw InputError(std::string("bifurcation: a ") + ToString(bifurcation.type) +
                   " starts no other branch of periodic solutions (switching needs a "
                   "period_doubling or a branch_point)");
}

double OddHarmonicContent(const Eigen::VectorXd& y, const HarmonicSet& set, int num_signals) {
  const int nc = set.NumCoefficients();
  double odd = 0.0, total = 0.0;
  for (int b = 0; b < num_signals; ++b) {
    const auto block = y.segment(b * nc, nc);
    total += block.squaredNorm();
    for (int p = 0; p < set.num_harmonics(); ++p) {
      if (set.harmonics()[static_cast<size_t>(p)] % 2 == 0) continue;
      odd += std::pow(block(set.CosIndex(p)), 2) + std::pow(block(set.SinIndex(p)), 2);
    }
  }
  return total > 0.0 ? std::sqrt(odd / total) : 0.0;
}

SwitchedBranch FollowPeriodDoubling(const Case& base, const Bifurcation& period_doubling,
                                    const TraceOptions& options) {
  SwitchedBranch result;
  result.the_case = SubharmonicCase(base, 2);
  std::unique_ptr<HarmonicSystem> system = BuildSystem(result.the_case);
  const HarmonicSet& set = system->harmonic_set();
  const double nu_pd = 0.5 * period_doubling.omega;
  // Own unknowns that are samples cannot be re-expressed in other harmonics.
  for (const auto& law : system->laws()) {
    if (law->NumOwnUnknowns(set) > 0 && !law->OwnUnknownsAreCoefficients()) {
      return NotStarted(std::move(result),
                        "a law's own unknowns are time samples: no period-2 start");
    }
  }
  const Eigen::VectorXd y_pd = ToSubharmonic(period_doubling.y, base.harmonics, set, 2);
  const std::optional<Eigen::VectorXd> phi = OddNullVector(*system, y_pd, nu_pd);
  if (!phi) {
    return NotStarted(std::move(result),
                      "no null vector of the period-2 Jacobian at the period doubling");
  }
  const int num_signals = system->num_displacement_unknowns() / set.NumCoefficients();
  const double lo = base.continuation.LowerBound() / 2, hi = base.continuation.UpperBound() / 2;
  for (const double side : {1.0, -1.0}) {
    const double nu = nu_pd * (1.0 + side * kSideOffset);
    if (nu <= lo || nu >= hi) continue;
    for (const double amplitude : kAmplitudes) {
      const Eigen::VectorXd guess = y_pd + amplitude * y_pd.norm() * *phi;
      const FixedLambdaSolution solved =
          SolveAtFixedLambda(*system, guess, nu, y_pd, result.the_case.continuation);
      if (!solved.converged) continue;
      const double content = OddHarmonicContent(solved.y, set, num_signals);
      if (content < kMinimumContent) continue;
      if (options.progress != nullptr) {
        *options.progress << "nfrc: period-2 branch from the period doubling at omega = "
                          << period_doubling.omega << ", starting at omega = " << 2.0 * nu
                          << " (odd nu-harmonic content " << content << ")\n";
      }
      result.subharmonic_content = content;
      TraceSwitched(result.the_case, nu, side > 0 ? hi : lo, solved.y, options, &result);
      return result;
    }
  }
  return NotStarted(std::move(result),
                    "no period-2 solution beside the period doubling (tried both sides)");
}

}  // namespace nfrc
