#pragma once

namespace nfrc::bench {

// What `nfrc run` adds to the trace: each case traced alone (TraceCase) and with its files
// written as it goes (BranchWriter, as RunCase does for the main branch), alternating,
// `repeats` times each, Hill on `threads` threads beside the trace (TraceOptions::threads).
// Prints the fastest and median of each in ms and LU(320) (`lu_unit` s), the writer's share
// and how many times branch.json was written.
void BenchOutputs(int repeats, int threads, double lu_unit);

}  // namespace nfrc::bench
