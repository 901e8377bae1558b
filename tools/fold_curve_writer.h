#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/fold_curve.h"
#include "tools/rewrite_schedule.h"

namespace nfrc {

// Writes DIR/fold_curve.json, rewritten (atomically) as points come (on a RewriteSchedule of
// kInterval), after each curve and at the end, so an interrupted, failing or killed run keeps
// the points already found:
// - "parameter", "from", "to", "branch_folds", "notes", "case" (the case as written), "status"
//   ("running" until Finish, then the run's: "complete", "incomplete" or "interrupted");
// - "points": [{"curve", "parameter", "omega", "energy", "max_abs_<output>", "newton"}], each
//   curve's points in order along it, curve after curve;
// - "cusps": [{"curve", "parameter", "omega"}] and "turns" (every turn in the parameter, with
//   "cusp" true or false);
// - "curves": [{"start_fold", "start_omega", "termination", "message", "points", "folds"}].
// It only writes: it never solves.
class FoldCurveWriter : public FoldCurveObserver {
 public:
  // Creates `dir` and writes the document without curves; OutputError if it cannot.
  FoldCurveWriter(std::string dir, const Case& the_case, const std::string& parameter, double from,
                  double to, nlohmann::json source);
  void OnPoint(int curve, const FoldCurvePoint& point) override;
  void OnCurve(const FoldCurve& curve) override;
  // The final document (notes and counts of the finished run, and its status).
  void Finish(const FoldCurveResult& result, const std::string& status);

  static constexpr std::chrono::milliseconds kInterval{1000};

 private:
  void Write();

  RewriteSchedule schedule_{kInterval};
  std::string path_;
  std::vector<std::string> output_names_;
  nlohmann::json document_;
  int curves_ = 0;
};

}  // namespace nfrc
