// StopBranchAfter against the engine itself stopped by its observer at the same point.
#include "continuation/branch.h"

#include <doctest/doctest.h>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace nfrc {
namespace {

using testing::CubicProblem;

// Refuses point `last`.
class RefuseAt : public ContinuationObserver {
 public:
  explicit RefuseAt(int last) : last_(last) {}
  bool OnPoint(const BranchPoint& /*point*/, int index) override { return index != last_; }

 private:
  int last_;
};

TEST_CASE("branch: StopBranchAfter leaves what an observer's stop at that point leaves") {
  // The cubic's S-shaped branch from λ = −2 to 2 with its two folds.
  CubicProblem problem;
  ContinuationOptions options;
  options.lambda_start = -2.0;
  options.lambda_end = 2.0;
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(1, 2.0);
  const Branch whole = Continue(problem, start, options);
  REQUIRE(whole.folds.size() == 2);
  // Between the folds, at the point right after the first (whose fold goes), at the last.
  const int first = whole.folds[0].after_point, second = whole.folds[1].after_point;
  REQUIRE(first + 1 < second);
  for (const int last : {first, first + 1, (first + second) / 2, second + 1}) {
    CAPTURE(last);
    RefuseAt observer(last);
    const Branch stopped = Continue(problem, start, options, &observer);
    Branch cut = whole;
    StopBranchAfter(last, options.lambda_name, &cut);
    REQUIRE(cut.points.size() == stopped.points.size());
    for (size_t i = 0; i < cut.points.size(); ++i) {
      CHECK(cut.points[i].lambda == stopped.points[i].lambda);
    }
    REQUIRE(cut.folds.size() == stopped.folds.size());
    for (size_t i = 0; i < cut.folds.size(); ++i) {
      CHECK(cut.folds[i].lambda == stopped.folds[i].lambda);
    }
    CHECK(cut.summary.reason == stopped.summary.reason);
    CHECK(cut.summary.message == stopped.summary.message);
    CHECK(cut.summary.num_points == stopped.summary.num_points);
    CHECK(cut.summary.num_folds == stopped.summary.num_folds);
  }
}

}  // namespace
}  // namespace nfrc
