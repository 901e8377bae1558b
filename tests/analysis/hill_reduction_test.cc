// Hill's pencil on a Craig–Bampton reduction of the linear model (stability.hill_modes)
// against the pencil on the whole model, along a traced branch of the FE rod against a
// flexible obstacle (20 elements, DLFT in relative coordinates).
#include "analysis/hill_reduction.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// With every interior mode kept the reduction is a change of basis: the largest multiplier is
// the full pencil's up to Arnoldi's 1e-8 on μ, amplified by the conditioning of the
// constraint-mode basis (1.6e-7 seen at worst).
constexpr double kSameModelTolerance = 1e-6;
// With 12 of the 19 fixed-interface modes (up to 1.5e6 rad/s, above the tenth harmonic of the
// resonance, 7e5 rad/s) the median error of max |μ| over the branch is 2.4e-4; 1e-3 is the
// size of a multiplier's change between neighbouring points of the trace.
constexpr double kTwelveModesMedian = 1e-3;

Case ContactRod() {
  Case c = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/rod/flexible_4krod.json");
  // Ten harmonics keep the test fast; the branch still crosses the resonance with the tip in
  // contact on part of the period, and Hill's spectrum has copies up to 7e5 rad/s.
  c.harmonics = HarmonicSet(10, false, 200);
  c.stability.enabled = false;
  return c;
}

double MaxModulus(HillAssembler& assembler, const BranchPoint& point) {
  const FloquetResult result = SolveHill(assembler.Assemble(point.y, point.lambda), HillOptions{});
  REQUIRE(result.computed);
  return result.max_modulus;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

TEST_CASE("hill reduction: max |mu| converges to the whole model's as modes are added") {
  const Case c = ContactRod();
  const TraceResult trace = TraceCase(c);
  REQUIRE(trace.branch.summary.success());
  auto system = BuildSystem(c);
  const int interior = c.model.model.num_dofs() - 1;  // all but the contact DOF
  HillAssembler full(*system);
  const std::vector<int> modes = {2, 4, 8, 12, interior};
  std::vector<std::unique_ptr<HillAssembler>> reduced;
  for (int m : modes) {
    reduced.push_back(std::make_unique<HillAssembler>(*system, HillReduction(*system, m)));
  }
  std::vector<std::vector<double>> errors(modes.size());
  // Every tenth point: 61 solutions from the linear range through the contact resonance.
  for (size_t i = 0; i < trace.points.size(); i += 10) {
    const BranchPoint& point = trace.points[i].point;
    const double reference = MaxModulus(full, point);
    for (size_t k = 0; k < modes.size(); ++k) {
      errors[k].push_back(std::abs(MaxModulus(*reduced[k], point) - reference));
    }
  }
  for (size_t k = 0; k + 1 < modes.size(); ++k) {
    CAPTURE(modes[k]);
    CHECK(Median(errors[k + 1]) < Median(errors[k]));
  }
  CHECK(Median(errors[3]) <= kTwelveModesMedian);
  CHECK(*std::max_element(errors.back().begin(), errors.back().end()) <= kSameModelTolerance);
}

TEST_CASE("hill reduction: impossible reductions name stability.hill_modes") {
  Case c = ContactRod();
  auto system = BuildSystem(c);
  CHECK_THROWS_WITH_AS(HillReduction(*system, c.model.model.num_dofs()),
                       doctest::Contains("stability.hill_modes"), InputError);
  c.stability.hill_modes = c.model.model.num_dofs();
  CHECK_THROWS_WITH_AS(c.Validate(), doctest::Contains("stability.hill_modes"), InputError);
  c.stability.hill_modes = -2;
  CHECK_THROWS_WITH_AS(c.Validate(), doctest::Contains("stability.hill_modes"), InputError);
}

}  // namespace nfrc
