#pragma once

#include <functional>

namespace nfrc::bench {

// The acceptance cases of the speed issue, each a whole TraceCase with stability on, in a
// child process so that its peak memory (ru_maxrss) is its own: wall time in ms and in
// LU(320) units (`lu_unit()` s, timed again in each child just before its case, so that a
// load that comes and goes on a shared machine shows in both), the budget, points, Newton
// iterations, bifurcations and, with `accuracy`, the curve's accuracy against a reference traced
// with a tenth of the maximum step (see CurveDeviation). Also one friction point at N_φ = 640.
void BenchAcceptance(const std::function<double()>& lu_unit, bool accuracy);

}  // namespace nfrc::bench
