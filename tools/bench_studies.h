#pragma once

namespace nfrc::bench {

// Parameter studies (issue 15): the fold curve of Duffing (H = 7) in the forcing from 0.18
// down through the cusp to 0.03, the energy peaks of the Fig. 7 oscillator followed in the
// normal load from 8 to 12 (peak curves: points, fixed-ω solves, time per solve), the
// Neimark–Sacker curves of the NES oscillator in the forcing, and a
// 32-branch sweep of the Fig. 7 oscillator (N = 10) in
// the normal load from 6 to 14, with one and two threads: time per branch, the speed-up and
// the parallel efficiency, and whether both sweeps agree. Times also in LU(320) units
// (`lu_unit` s).
void BenchStudies(double lu_unit);

}  // namespace nfrc::bench
