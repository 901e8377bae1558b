#pragma once

#include <vector>

namespace nfrc {

// Phases (e.g. stick phases) of a periodic signal classified sample by sample on a uniform
// grid over one period.
struct PhaseCount {
  int count = 0;          // number of phases per period (1 if the flag holds throughout)
  double fraction = 0.0;  // fraction of the period they cover
};

// Counts the runs of `flags` (cyclic) after two clean-ups that keep the ripple of a
// truncated Fourier series from inflating the count: runs shorter than min_fraction of the
// period are dropped, then gaps shorter than that between runs are filled. min_fraction
// should be about the period of the highest harmonic over the period (1/H), the shortest
// feature the series resolves.
PhaseCount CountPhases(const std::vector<bool>& flags, double min_fraction);

}  // namespace nfrc
