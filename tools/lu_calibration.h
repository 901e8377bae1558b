#pragma once

namespace nfrc::bench {

// The calibration unit of nfrc_bench: one dense LU with partial pivoting of a fixed
// 320 × 320 matrix, a plain triple loop compiled with the project's flags. Figures divided by
// it survive a shared, noisy machine better than seconds. Median of 7 (s).
//
// Its own file, compiled with loops and functions aligned to 64 bytes: the inner loop's
// placement in the binary otherwise moves with every unrelated change, and its time with it
// (2.2 against 3.2 ms from one build to the next on the same machine, the cases' times
// unchanged).
double LuUnitSeconds();

}  // namespace nfrc::bench
