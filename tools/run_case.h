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

// Traces the branch of `system` from the linear guess at options.lambda_start.
Branch Trace(HarmonicSystem& system, const ContinuationOptions& options,
             ContinuationObserver* observer = nullptr);

// `nfrc run`: traces the case and writes DIR/branch.json and DIR/branch.csv as it goes.
// `stop` (may be null) is polled after every point, so an interrupt keeps what was found.
// Returns the branch; throws InputError for bad input and std::runtime_error for I/O.
Branch RunCase(Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop = nullptr);

}  // namespace nfrc
