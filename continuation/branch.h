#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace nfrc {

// One converged point of a branch with the normalised tangent there (scaled norm).
struct BranchPoint {
  double lambda = 0.0;
  Eigen::VectorXd y;
  Eigen::VectorXd tangent_y;  // unscaled components of the unit (scaled) tangent
  double tangent_lambda = 0.0;
  double step = 0.0;  // scaled arclength from the previous point (0 for the first)
  int newton_iterations = 0;
  double residual_norm = 0.0;  // ‖R‖ at the point
};

// A turning point in λ, localised between two branch points.
struct Fold {
  double lambda = 0.0;
  Eigen::VectorXd y;
  int after_point = 0;  // index of the branch point preceding the fold
  // Estimated |λ error|: the larger of the λ change between the last two localisation
  // iterates and the quadratic model ½ s_λ τ_λ²/|dτ_λ/ds| (λ is stationary at a fold, so
  // iterates on both sides of it can agree in λ while both are off).
  double lambda_accuracy = 0.0;
  double tangent_lambda = 0.0;  // λ component of the tangent at the reported point
  int iterations = 0;
  bool converged = false;  // accuracy reached within max_fold_iterations
  // λ turns at a kink of the branch (a sampled nonsmooth law switched there), not smoothly:
  // τ_λ kept half its value on each side on both ends of a bracket 64 times shorter than the
  // step. Located to that bracket (lambda_accuracy), not to fold_tolerance.
  bool corner = false;
};

enum class TerminationReason {
  kReachedLambdaBound,  // left [λ_min, λ_max]; the last point lies on the bound
  kClosedCurve,         // came back to the first point: the branch is a closed curve
  kMaxPoints,
  kStalled,            // step below min_step and still failing
  kStartFailed,        // Newton at λ_start did not converge
  kStoppedByObserver,  // the observer asked to stop (e.g. interrupted)
};

const char* ToString(TerminationReason reason);

// One attempted step, accepted or not.
struct StepRecord {
  double step = 0.0;
  int newton_iterations = 0;
  bool accepted = false;
  // A step at fixed λ after a failed arclength corrector (newton_iterations counts both).
  bool fixed_lambda = false;
  std::string note;  // why it was rejected, empty if accepted
};

struct ContinuationSummary {
  TerminationReason reason = TerminationReason::kStartFailed;
  std::string message;
  int num_points = 0;
  int num_folds = 0;
  int num_accepted_steps = 0;
  int num_rejected_steps = 0;
  int total_newton_iterations = 0;
  int num_evaluations = 0;  // calls of ContinuationProblem::Evaluate
  double wall_time_seconds = 0.0;
  std::vector<StepRecord> history;
  // What the engine did beyond its plain algorithm, e.g. an undamped retry of the start.
  std::vector<std::string> notes;

  bool success() const {
    return reason == TerminationReason::kReachedLambdaBound ||
           reason == TerminationReason::kClosedCurve;
  }
};

struct Branch {
  std::vector<BranchPoint> points;
  std::vector<Fold> folds;
  ContinuationSummary summary;
};

// The summary message of a branch its observer stopped at point `index` (λ = `lambda`).
std::string StoppedByObserverMessage(int index, const std::string& lambda_name, double lambda);

// Ends `branch` at point `last` as if its observer had stopped it there: the points after it
// and the folds past it go, and the summary counts what is left (its steps and Newton
// iterations keep the work done). For an observer that hears of points later than the engine
// finds them. `lambda_name` names λ in the message.
void StopBranchAfter(int last, const std::string& lambda_name, Branch* branch);

}  // namespace nfrc
