#include "tools/epsilon_refinement.h"

#include <cmath>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>

#include "continuation/fixed_lambda.h"
#include "core/input_fields.h"
#include "nonlinearities/dlft_contact.h"
#include "tools/branch_writer.h"
#include "tools/run_case.h"

namespace nfrc {
namespace {

// Records the branch and stops it at the first point at or beyond ω, solving exactly there.
class StopAtOmega : public ContinuationObserver {
 public:
  StopAtOmega(HarmonicSystem& system, BranchWriter& writer, const ContinuationOptions& options,
              double omega)
      : system_(system), writer_(writer), options_(options), omega_(omega) {}

  bool OnPoint(const BranchPoint& point, int index) override {
    writer_.OnPoint(point, index);
    solution_ =
        SolveAtCrossing(system_, previous_ ? &*previous_ : nullptr, point, omega_, options_);
    previous_ = point;
    return !solution_.has_value();
  }
  void OnFold(const Fold& fold) override { writer_.OnFold(fold); }
  const std::optional<FixedLambdaSolution>& solution() const { return solution_; }

 private:
  HarmonicSystem& system_;
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

nlohmann::json RefineEpsilon(Case& the_case, const RefinementOptions& options,
                             const std::string& out_dir, std::ostream* progress) {
  options.Validate(the_case);
  std::unique_ptr<HarmonicSystem> system = MakeSystem(the_case);
  std::vector<DlftContact*> dlft;
  for (const auto& law : system->laws()) {
    if (auto* contact = dynamic_cast<DlftContact*>(law.get())) dlft.push_back(contact);
  }
  if (dlft.empty()) throw InputError("nonlinearities: refinement needs a dlft_contact law");

  BranchWriter writer(out_dir, the_case, *system);
  ContinuationOptions trace_options = the_case.continuation;
  trace_options.progress = progress;
  const Eigen::VectorXd guess = StartingGuess(the_case, *system, progress);
  StopAtOmega observer(*system, writer, trace_options, options.omega);
  const Branch branch = Trace(*system, trace_options, &observer, &guess);
  writer.Finish(branch.summary);

  nlohmann::json result = {{"omega", options.omega}, {"steps", nlohmann::json::array()}};
  if (!observer.solution() || !observer.solution()->converged) {
    result["message"] = observer.solution()
                            ? "no solution at omega: " + observer.solution()->message
                            : "the branch did not reach omega: " + branch.summary.message;
  } else {
    Eigen::VectorXd y = observer.solution()->y;
    for (double epsilon : options.epsilons) {
      for (DlftContact* law : dlft) law->set_epsilon(epsilon);
      const FixedLambdaSolution solved =
          SolveAtFixedLambda(*system, y, options.omega, y, the_case.continuation);
      const nlohmann::json& record = writer.WriteSignals(
          options.omega, solved.y, -1, solved.converged, "epsilon=" + Format(epsilon));
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
