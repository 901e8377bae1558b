#include "tools/epsilon_refinement.h"

#include <cmath>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>

#include "analysis/lcp_hbm.h"
#include "analysis/trace.h"
#include "continuation/fixed_lambda.h"
#include "tools/branch_writer.h"

namespace nfrc {
namespace {

// Records the branch and stops it at the first point at or beyond ω, solving exactly there.
class StopAtOmega : public ContinuationObserver {
 public:
  StopAtOmega(HarmonicSystem& system, const Case& the_case, BranchWriter& writer,
              const ContinuationOptions& options, double omega)
      : system_(system),
        reporter_(system, the_case.output_dofs, the_case.output_names),
        writer_(writer),
        options_(options),
        omega_(omega) {}

  bool OnPoint(const BranchPoint& point, int index) override {
    TracePoint record;
    record.index = index;
    record.point = point;
    record.measures = reporter_.Measure(point.y, point.lambda);
    writer_.OnPoint(record);
    solution_ =
        SolveAtCrossing(system_, previous_ ? &*previous_ : nullptr, point, omega_, options_);
    previous_ = point;
    return !solution_.has_value();
  }
  void OnFold(const Fold& fold) override {
    writer_.OnFold(TraceFold{fold, reporter_.analyzer().Measure(fold.y, fold.lambda)});
  }
  const std::optional<FixedLambdaSolution>& solution() const { return solution_; }

 private:
  HarmonicSystem& system_;
  SolutionReporter reporter_;
  BranchWriter& writer_;
  const ContinuationOptions& options_;
  double omega_;
  std::optional<BranchPoint> previous_;
  std::optional<FixedLambdaSolution> solution_;
};

std::string Format(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// The LCP-HBM solution the refinement tends to: the same case with every dlft_contact
// turned into lcp_contact (same fields), solved by Lemke at ω; its signals and samples go to
// DIR/lcp/. Unknowns have the DLFT system's displacements first, then the forces λ.
struct LcpReference {
  Case twin;
  std::unique_ptr<HarmonicSystem> system;
  LcpHbm::Solution solution;
  nlohmann::json record;
};

std::unique_ptr<LcpReference> SolveLcpReference(const Case& the_case, double omega,
                                                const std::string& out_dir) {
  auto reference = std::make_unique<LcpReference>();
  reference->twin = the_case;
  for (LawSpec& law : reference->twin.laws) {
    const auto* dlft = std::get_if<DlftContactSpec>(&law);
    if (dlft == nullptr) return nullptr;
    law = LcpContactSpec{dlft->contact, 0.0};
  }
  reference->twin.signals_at.clear();
  reference->system = BuildSystem(reference->twin);
  LcpHbm lcp(*reference->system, reference->twin.laws);
  reference->solution = lcp.Solve(omega);
  BranchWriter writer(out_dir + "/lcp", reference->twin, nullptr);
  writer.OnStart(reference->system->NumUnknowns());
  SolutionReporter reporter(*reference->system, reference->twin.output_dofs,
                            reference->twin.output_names);
  SolutionSignals signals = reporter.Signals(reference->solution.y, omega);
  signals.after_point = -1;
  signals.converged = reference->solution.lemke.ok();
  signals.note = "LCP-HBM (Lemke)";
  writer.OnSignals(signals);
  reference->record = writer.document()["signals"].back();
  ContinuationSummary summary;
  summary.reason = TerminationReason::kReachedLambdaBound;
  summary.message = "LCP-HBM at one frequency: Lemke " + ToString(reference->solution.lemke.status);
  writer.Finish(summary);
  return reference;
}

double RelativeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b, bool max_norm) {
  const double scale = max_norm ? b.cwiseAbs().maxCoeff() : b.norm();
  const double distance = max_norm ? (a - b).cwiseAbs().maxCoeff() : (a - b).norm();
  return scale > 0.0 ? distance / scale : distance;
}

// Distances of a DLFT solution y to the LCP-HBM reference on the same samples: raw forces
// (before truncation) and gaps in the max norm, truncated force coefficients and the
// condensed displacements in the 2-norm, each relative to the reference.
nlohmann::json DistanceToLcp(HarmonicSystem& system, const Eigen::VectorXd& y, double omega,
                             const LcpReference& reference) {
  const int nx = system.num_displacement_unknowns();
  const int nt = system.harmonic_set().num_samples();
  Eigen::VectorXd force_raw(nt * system.laws().size());
  Eigen::VectorXd force(nt * system.laws().size());
  Eigen::VectorXd gap(nt * system.laws().size());
  for (size_t i = 0; i < system.laws().size(); ++i) {
    const auto samples =
        system.laws()[i]->RawSamples(system.context(static_cast<int>(i)), y, omega);
    for (const LawSignal& signal : samples) {
      if (signal.name == "gap") gap.segment(i * nt, nt) = signal.samples;
      if (signal.name == "force_raw") force_raw.segment(i * nt, nt) = signal.samples;
      if (signal.name == "force") force.segment(i * nt, nt) = signal.samples;
    }
  }
  const LcpHbm::Solution& lcp = reference.solution;
  const FourierTransform& fourier = system.fourier();
  Eigen::VectorXd lcp_force(force.size());
  for (size_t i = 0; i < system.laws().size(); ++i) {
    lcp_force.segment(i * nt, nt) =
        fourier.ToTime(fourier.ToCoefficients(lcp.lambda.segment(i * nt, nt))).col(0);
  }
  return {{"force_raw", RelativeDistance(force_raw, lcp.lambda, true)},
          {"force", RelativeDistance(force, lcp_force, false)},
          {"gap", RelativeDistance(gap, lcp.gap, true)},
          {"displacement", RelativeDistance(y.head(nx), lcp.y.head(nx), false)}};
}

}  // namespace

void RefinementOptions::Validate(const Case& the_case) const {
  const double lo = std::min(the_case.continuation.lambda_start, the_case.continuation.lambda_end);
  const double hi = std::max(the_case.continuation.lambda_start, the_case.continuation.lambda_end);
  if (!std::isfinite(omega) || omega < lo || omega > hi) {
    throw InputError("omega: must lie in the case's range [" + Format(lo) + ", " + Format(hi) +
                     "], got " + Format(omega));
  }
  if (epsilons.empty()) throw InputError("epsilons: at least one value is needed");
  for (double epsilon : epsilons) {
    if (!(epsilon > 0.0) || !std::isfinite(epsilon)) {
      throw InputError("epsilons: every value must be finite and > 0, got " + Format(epsilon));
    }
  }
}

std::vector<double> GeometricEpsilons(double epsilon0, double factor, int steps) {
  if (!(factor > 1.0) || !std::isfinite(factor)) throw InputError("factor: must be > 1");
  if (steps < 0) throw InputError("steps: must be >= 0");
  std::vector<double> epsilons;
  for (int i = 0; i <= steps; ++i) epsilons.push_back(epsilon0 * std::pow(factor, i));
  return epsilons;
}

nlohmann::json RefineEpsilon(const Case& the_case, const RefinementOptions& options,
                             const std::string& out_dir, std::ostream* progress,
                             const nlohmann::json& source) {
  options.Validate(the_case);
  the_case.Validate();
  bool any_dlft = false;
  for (const LawSpec& law : the_case.laws) any_dlft |= std::holds_alternative<DlftContactSpec>(law);
  if (!any_dlft) throw InputError("nonlinearities: refinement needs a dlft_contact law");
  std::unique_ptr<HarmonicSystem> system = BuildSystem(the_case);

  BranchWriter writer(out_dir, the_case, source);
  writer.OnStart(system->NumUnknowns());
  ContinuationOptions trace_options = the_case.continuation;
  trace_options.progress = progress;
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, progress);
  StopAtOmega observer(*system, the_case, writer, trace_options, options.omega);
  const Branch branch = Trace(*system, trace_options, &observer, &guess);
  writer.Finish(branch.summary);

  nlohmann::json result = {{"omega", options.omega}, {"steps", nlohmann::json::array()}};
  if (!observer.solution() || !observer.solution()->converged) {
    result["message"] = observer.solution()
                            ? "no solution at omega: " + observer.solution()->message
                            : "the branch did not reach omega: " + branch.summary.message;
  } else {
    Eigen::VectorXd y = observer.solution()->y;
    const std::unique_ptr<LcpReference> reference =
        SolveLcpReference(the_case, options.omega, out_dir);
    if (reference) {
      const LcpHbm::Solution& lcp = reference->solution;
      result["lcp"] = {
          {"status", ToString(lcp.lemke.status)},
          {"pivots", lcp.lemke.pivots},
          {"complementarity_gap", lcp.complementarity_gap},
          {"min_gap", lcp.gap.minCoeff()},
          {"max_abs", reference->record["max_abs"]},
          {"h1", reference->record["h1"]},
          {"min_force", reference->record["min_force"]},
          {"signals_file", "lcp/" + reference->record["file"].get<std::string>()},
          {"samples_file", "lcp/" + reference->record.value("samples_file", std::string())}};
    }
    for (double epsilon : options.epsilons) {
      // The same case with this ε on every DLFT contact; the unknowns keep their layout, so
      // the previous solution warm-starts the solve.
      Case refined = the_case;
      for (LawSpec& law : refined.laws) {
        if (auto* dlft = std::get_if<DlftContactSpec>(&law)) dlft->contact.epsilon = epsilon;
      }
      system = BuildSystem(refined);
      const FixedLambdaSolution solved =
          SolveAtFixedLambda(*system, y, options.omega, y, the_case.continuation);
      SolutionReporter reporter(*system, the_case.output_dofs, the_case.output_names);
      SolutionSignals signals = reporter.Signals(solved.y, options.omega);
      signals.after_point = -1;
      signals.converged = solved.converged;
      signals.note = "epsilon=" + Format(epsilon);
      writer.OnSignals(signals);
      const nlohmann::json& record = writer.document()["signals"].back();
      nlohmann::json step = {{"epsilon", epsilon},
                             {"converged", solved.converged},
                             {"newton_iterations", solved.iterations},
                             {"residual_norm", solved.residual_norm},
                             {"message", solved.message},
                             {"max_abs", record["max_abs"]},
                             {"h1", record["h1"]},
                             {"min_gap", record["min_gap"]},
                             {"min_force", record["min_force"]},
                             {"signals_file", record["file"]},
                             {"samples_file", record.value("samples_file", "")},
                             {"laws", record["laws"]}};
      if (reference && reference->solution.lemke.ok()) {
        step["distance_to_lcp"] = DistanceToLcp(*system, solved.y, options.omega, *reference);
      }
      result["steps"].push_back(step);
      if (progress != nullptr) {
        *progress << "refine: epsilon=" << epsilon << "  converged=" << solved.converged
                  << "  newton=" << solved.iterations
                  << "  min_gap=" << record["min_gap"].get<double>()
                  << "  min_force=" << record["min_force"].get<double>() << "\n";
      }
      if (!solved.converged) break;
      y = solved.y;
    }
  }
  const std::string path = out_dir + "/refinement.json";
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out << result.dump(1) << "\n";
  if (!out) throw std::runtime_error(path + ": write failed");
  return result;
}

}  // namespace nfrc
