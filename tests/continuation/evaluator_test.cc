#include "continuation/evaluator.h"

#include <doctest/doctest.h>

#include <limits>

namespace nfrc {
namespace {

// R = y − λ·1 with one Jacobian entry (at `row`, `col`) replaced by `value`.
class PlantedEntryProblem : public ContinuationProblem {
 public:
  PlantedEntryProblem(int n, int row, int col, double value)
      : n_(n), row_(row), col_(col), value_(value) {}
  int NumUnknowns() const override { return n_; }
  bool Evaluate(const Eigen::VectorXd& y, double lambda, Eigen::VectorXd* residual,
                Eigen::MatrixXd* jacobian_y, Eigen::VectorXd* jacobian_lambda) override {
    *residual = y - Eigen::VectorXd::Constant(n_, lambda);
    if (jacobian_y != nullptr) {
      *jacobian_y = Eigen::MatrixXd::Identity(n_, n_);
      (*jacobian_y)(row_, col_) = value_;
    }
    if (jacobian_lambda != nullptr) *jacobian_lambda = -Eigen::VectorXd::Ones(n_);
    return true;
  }

 private:
  int n_, row_, col_;
  double value_;
};

TEST_CASE("evaluator: a single non-finite Jacobian entry fails the evaluation") {
  constexpr int kSize = 37;  // odd: the planted entry also lands outside full SIMD packets
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(kSize + 1, 0.5);
  for (const auto& [row, col] : {std::pair{0, 0}, {17, 23}, {kSize - 1, kSize - 1}}) {
    for (const double bad : {inf, -inf, nan}) {
      PlantedEntryProblem problem(kSize, row, col, bad);
      Evaluator evaluator(problem);
      Linearization linearization;
      CHECK_FALSE(evaluator.Linearize(u, &linearization));
    }
    // Huge but finite entries, whose sum alone could overflow, are fine.
    PlantedEntryProblem problem(kSize, row, col, std::numeric_limits<double>::max());
    Evaluator evaluator(problem);
    Linearization linearization;
    CHECK(evaluator.Linearize(u, &linearization));
  }
}

}  // namespace
}  // namespace nfrc
