#include "tools/lu_calibration.h"

#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

#include "tools/bench_common.h"

namespace nfrc::bench {

double LuUnitSeconds() {
  constexpr int kN = 320;
  std::vector<double> times;
  for (int repeat = 0; repeat < 7; ++repeat) {
    std::vector<double> a(kN * kN);
    // Fixed, well-conditioned and pivot-demanding: a Hilbert-like part plus a shifted diagonal.
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) a[i * kN + j] = 1.0 / (1.0 + i + j) + (i == (j + 7) % kN);
    }
    const auto start = Clock::now();
    for (int k = 0; k < kN; ++k) {
      int pivot = k;
      for (int i = k + 1; i < kN; ++i) {
        if (std::abs(a[i * kN + k]) > std::abs(a[pivot * kN + k])) pivot = i;
      }
      if (pivot != k) {
        for (int j = 0; j < kN; ++j) std::swap(a[k * kN + j], a[pivot * kN + j]);
      }
      for (int i = k + 1; i < kN; ++i) {
        const double factor = a[i * kN + k] / a[k * kN + k];
        a[i * kN + k] = factor;
        for (int j = k + 1; j < kN; ++j) a[i * kN + j] -= factor * a[k * kN + j];
      }
    }
    times.push_back(Seconds(start));
    if (!std::isfinite(a[kN * kN - 1])) std::abort();  // keeps the loop from being elided
  }
  return Median(times);
}

}  // namespace nfrc::bench
