#include "continuation/progress.h"

#include <iomanip>
#include <ostream>
#include <sstream>
#include <utility>

namespace nfrc {
namespace {

// Significant digits of λ in progress lines: enough to tell close points apart.
constexpr int kLambdaDigits = 8;
// Significant digits of steps, accuracies and times: orders of magnitude matter there.
constexpr int kShortDigits = 3;

}  // namespace

ProgressReporter::ProgressReporter(std::ostream* out, std::string lambda_name)
    : out_(out), lambda_name_(std::move(lambda_name)) {}

void ProgressReporter::Point(int index, const BranchPoint& point) const {
  if (out_ == nullptr) return;
  std::ostringstream line;
  line << "point " << index << "  " << lambda_name_ << '=' << std::setprecision(kLambdaDigits)
       << point.lambda << "  step=" << std::setprecision(kShortDigits) << point.step
       << "  newton=" << point.newton_iterations << '\n';
  *out_ << line.str() << std::flush;
}

void ProgressReporter::FoldFound(int number, const Fold& fold) const {
  if (out_ == nullptr) return;
  std::ostringstream line;
  line << "fold " << number << "  " << lambda_name_ << '=' << std::setprecision(kLambdaDigits)
       << fold.lambda << "  after point " << fold.after_point
       << "  accuracy=" << std::setprecision(kShortDigits) << fold.lambda_accuracy
       << (fold.corner ? "  (corner)" : "") << (fold.converged ? "" : "  (not converged)") << '\n';
  *out_ << line.str() << std::flush;
}

void ProgressReporter::Finish(const ContinuationSummary& summary) const {
  if (out_ == nullptr) return;
  std::ostringstream line;
  line << "finished: " << ToString(summary.reason) << " (" << summary.message
       << ")  points=" << summary.num_points << "  folds=" << summary.num_folds
       << "  steps=" << summary.num_accepted_steps << " accepted/" << summary.num_rejected_steps
       << " rejected  newton=" << summary.total_newton_iterations
       << "  evaluations=" << summary.num_evaluations
       << "  time=" << std::setprecision(kShortDigits) << summary.wall_time_seconds << " s\n";
  *out_ << line.str() << std::flush;
}

}  // namespace nfrc
