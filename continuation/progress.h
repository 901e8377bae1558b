#pragma once

#include <iosfwd>
#include <string>

#include "continuation/branch.h"

namespace nfrc {

// Writes one line per accepted point and per fold, and a final summary line, on a stream
// (nothing when the stream is null). Lines are formatted apart so the stream's own
// formatting state is left untouched.
class ProgressReporter {
 public:
  ProgressReporter(std::ostream* out, std::string lambda_name);

  // e.g. "point 12  omega=1.2345678  step=0.0123  newton=3"
  void Point(int index, const BranchPoint& point) const;
  // e.g. "fold 1  omega=1.2675370  after point 57  accuracy=3.2e-12"
  void FoldFound(int number, const Fold& fold) const;
  void Finish(const ContinuationSummary& summary) const;

 private:
  std::ostream* out_;
  std::string lambda_name_;
};

}  // namespace nfrc
