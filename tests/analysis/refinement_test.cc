// DLFT ε-refinement (Vadcard et al. 2022, Sec. 4.1): warm-started solves at one ω tend to the
// LCP-HBM solution as ε grows, and an interrupt ends the refinement with what was done.
#include "analysis/refinement.h"

#include <doctest/doctest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tools/case_file.h"
#include "tools/refinement_writer.h"

namespace nfrc {
namespace {

constexpr double kOmega0 = 63953.9;  // rad/s, first eigenfrequency of the ρ = 7500 rod

// The rod and rigid obstacle (cases/rod/rigid_nh20.json) with DLFT contact, H = 8
// and N_t = 64: small enough for a unit test, the same physics.
Case RodCase() {
  nlohmann::json source =
      ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/rod/rigid_nh20.json").source;
  source["nonlinearities"][0]["type"] = "dlft_contact";
  source["harmonics"] = {{"max", 8}, {"samples", 64}};
  return ParseCase(source, std::string(NFRC_SOURCE_DIR) + "/cases/rod");
}

TEST_CASE("Refinement: DLFT's ε-refinement converges to Lemke's solution") {
  const Case the_case = RodCase();
  RefinementOptions options;
  options.omega = kOmega0;
  options.epsilons = GeometricEpsilons(1e11, 2.0, 8);
  const RefinementResult result = RefineEpsilon(the_case, options);
  REQUIRE(result.lcp.has_value());
  REQUIRE(result.steps.size() == options.epsilons.size());
  std::vector<double> force, displacement, gap;
  for (const RefinementStep& step : result.steps) {
    REQUIRE(step.converged);
    REQUIRE(step.distance_to_lcp.has_value());
    force.push_back(step.distance_to_lcp->force);
    displacement.push_back(step.distance_to_lcp->displacement);
    gap.push_back(step.distance_to_lcp->gap);
  }
  MESSAGE("force " << force.front() << " -> " << force.back() << ", displacement "
                   << displacement.front() << " -> " << displacement.back());
  for (size_t i = 1; i < force.size(); ++i) {
    CHECK(force[i] < force[i - 1]);
    CHECK(displacement[i] < displacement[i - 1]);
  }
  // Doubling ε eight times shrinks the O(1/ε) gap violation 2⁸-fold; ask for 10×.
  CHECK(displacement.back() < displacement.front() / 10.0);
}

TEST_CASE("Refinement: a raised stop flag ends it early and the files say so") {
  const Case the_case = RodCase();
  RefinementOptions options;
  options.omega = kOmega0;
  options.epsilons = {1e11, 2e11};
  const std::atomic<bool> stop{true};
  // Under this build's directory: /tmp is shared with test runs of other checkouts.
  const std::string dir = std::string(NFRC_BINARY_DIR) + "/test_output/refinement_stop";
  std::filesystem::remove_all(dir);
  const RefinementResult result = RunRefinement(the_case, options, dir, nullptr, &stop);
  CHECK(result.interrupted);
  CHECK(result.steps.empty());
  CHECK(result.message.find("interrupted by a signal") != std::string::npos);
  std::ifstream refinement(dir + "/refinement.json");
  const nlohmann::json document = nlohmann::json::parse(refinement);
  CHECK(document["steps"].empty());
  CHECK(document["message"].get<std::string>() == result.message);
  std::ifstream branch(dir + "/branch.json");
  CHECK(nlohmann::json::parse(branch)["summary"]["termination"].get<std::string>() ==
        "stopped_by_observer");
}

TEST_CASE("Refinement: input errors name the field") {
  const Case the_case = RodCase();
  RefinementOptions options;
  options.omega = 1e6;
  options.epsilons = {1e11};
  CHECK_THROWS_WITH_AS(RefineEpsilon(the_case, options), doctest::Contains("omega: must lie"),
                       InputError);
  options.omega = kOmega0;
  options.epsilons = {0.0};
  CHECK_THROWS_WITH_AS(RefineEpsilon(the_case, options), doctest::Contains("epsilons: "),
                       InputError);
  CHECK_THROWS_WITH_AS(GeometricEpsilons(1e11, 1.0, 3), "factor: must be > 1", InputError);
}

}  // namespace
}  // namespace nfrc
