#include "nonlinearities/phase_count.h"

#include <doctest/doctest.h>

namespace nfrc {
namespace {

// Flags on n samples: true on [begin, end) (cyclic ranges allowed with begin > end).
std::vector<bool> Flags(int n, std::vector<std::pair<int, int>> ranges) {
  std::vector<bool> flags(n, false);
  for (auto [begin, end] : ranges) {
    for (int i = begin; i != end; i = (i + 1) % n) flags[i] = true;
  }
  return flags;
}

TEST_CASE("phases: counts runs, joins a run across the period boundary") {
  const PhaseCount p = CountPhases(Flags(100, {{10, 30}, {50, 60}, {90, 5}}), 0.02);
  CHECK(p.count == 3);
  CHECK(p.fraction == doctest::Approx(0.45));
}

TEST_CASE("phases: ripple blips and ripple gaps do not change the count") {
  // Two 20-sample phases; a 1-sample blip during slip and a 1-sample gap inside a phase, as
  // the Gibbs ripple of a truncated series produces near a velocity reversal.
  const PhaseCount p = CountPhases(Flags(200, {{10, 20}, {21, 30}, {70, 71}, {100, 120}}), 0.03);
  CHECK(p.count == 2);
  CHECK(p.fraction == doctest::Approx(40.0 / 200.0));
}

TEST_CASE("phases: always on, never on") {
  CHECK(CountPhases(std::vector<bool>(50, true), 0.05).count == 1);
  CHECK(CountPhases(std::vector<bool>(50, true), 0.05).fraction == 1.0);
  CHECK(CountPhases(std::vector<bool>(50, false), 0.05).count == 0);
  // Only blips: nothing survives.
  CHECK(CountPhases(Flags(100, {{3, 4}, {60, 61}}), 0.05).count == 0);
}

}  // namespace
}  // namespace nfrc
