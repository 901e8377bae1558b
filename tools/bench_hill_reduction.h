#pragma once

namespace nfrc::bench {

// Hill's pencil on a Craig–Bampton reduction (stability.hill_modes) against the pencil on the
// whole model, on the rod against a rigid and a 4 k_rod obstacle (N_h = 20, N_t = 400) and on
// the blade (cases/blade/blade.json with stability on; its matrices generated if missing):
// each traced with stability on, analyses in turn on the tracing thread, with the whole
// pencil and with 4, 8, 12 (and on the rods every interior) mode. Prints the time (ms and
// LU(320), `lu_unit` s), Hill's share, and against the whole pencil: the points whose verdict
// or unstable count differs, the median and largest |Δ max|μ||, and the bifurcations found.
void BenchHillReduction(double lu_unit);

}  // namespace nfrc::bench
