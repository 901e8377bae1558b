#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "analysis/fold_curve.h"

namespace nfrc {

// Writes DIR/fold_curve.json, rewritten (atomically) after each curve and at the end, so an
// interrupted or failing run keeps the curves already followed:
// - "parameter", "from", "to", "branch_folds", "notes", "case" (the case as written);
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
  void OnCurve(const FoldCurve& curve) override;
  // The final document (notes and counts of the finished run).
  void Finish(const FoldCurveResult& result);

 private:
  void Write();

  std::string path_;
  std::vector<std::string> output_names_;
  nlohmann::json document_;
  int curves_ = 0;
};

}  // namespace nfrc
