#pragma once

#include <atomic>
#include <iosfwd>
#include <memory>
#include <string>

#include "continuation/continuation.h"
#include "tools/case_file.h"
#include "tools/harmonic_system.h"

namespace nfrc {

// Builds the harmonic system of a case; the laws move out of `the_case`.
std::unique_ptr<HarmonicSystem> MakeSystem(Case& the_case);

// Traces the branch of `system` from `guess` (default: the linear guess) at
// options.lambda_start.
Branch Trace(HarmonicSystem& system, const ContinuationOptions& options,
             ContinuationObserver* observer = nullptr, const Eigen::VectorXd* guess = nullptr);

// A starting point at lambda_start for a case: Newton from the linear guess or, when that
// fails (nonsmooth laws with many harmonics), the start of the same case with about a third
// of the harmonics (recursively) re-expressed in the full set and corrected. Returns the
// linear guess if every rung fails (the engine then reports the failed start).
Eigen::VectorXd StartingGuess(const Case& the_case, HarmonicSystem& system,
                              std::ostream* progress);

// `nfrc run`: traces the case and writes DIR/branch.json and DIR/branch.csv as it goes.
// `stop` (may be null) is polled after every point, so an interrupt keeps what was found.
// Returns the branch; throws InputError for bad input and std::runtime_error for I/O.
Branch RunCase(Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop = nullptr);

}  // namespace nfrc
