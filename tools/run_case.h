#pragma once

#include <atomic>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/case.h"
#include "analysis/trace.h"
#include "continuation/branch.h"

namespace nfrc {

// `nfrc run`: traces the case (TraceCase) and writes DIR/branch.json, DIR/branch.csv and the
// signals as it goes (BranchWriter). `stop` (may be null) is polled after every point, so an
// interrupt keeps what was found. `source` is the case as written, recorded in branch.json.
// Throws InputError for bad input and std::runtime_error for I/O.
// Prints a Craig–Bampton report (sizes, time, eigenfrequency check) as "nfrc: " lines.
void PrintReduction(const ReductionReport& report, std::ostream& out);

// With `trace`, the main branch's whole TraceResult (bifurcations, measures) is kept there.
// `threads`: TraceOptions::threads, for every branch traced.
Branch RunCase(const Case& the_case, const std::string& out_dir, std::ostream* progress,
               const std::atomic<bool>* stop = nullptr, const nlohmann::json& source = nullptr,
               TraceResult* trace = nullptr, int threads = -1);

}  // namespace nfrc
