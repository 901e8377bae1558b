#include "tools/reduction_reader.h"

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <string>

#include "models/rod.h"
#include "support/case_error.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// The rigid-obstacle rod (cases/rod/rigid_nh20.json) at 40 elements, reduced onto its end
// (contact, forcing, output) and its middle node (output).
nlohmann::json RodCase() {
  return nlohmann::json::parse(R"({
    "model": {"type": "rod", "elements": 40, "length": 0.13, "area": 15.6e-4, "young": 210e9,
              "density": 7500, "damping": {"modal_ratio": 0.0075},
              "forcing": [{"dof": "end", "cos": 25e3}],
              "reduction": {"type": "craig_bampton", "modes": 38}},
    "nonlinearities": [{"type": "dlft_contact", "dof": "end", "gap": 2e-4}],
    "harmonics": {"max": 5},
    "continuation": {"omega_start": 5e4, "omega_end": 8e4},
    "output": {"dofs": [19, "end"]}})");
}

std::string Error(const nlohmann::json& source) { return testing::CaseError(source); }

Eigen::VectorXd Frequencies(const LinearModel& model) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      Eigen::MatrixXd(model.stiffness), Eigen::MatrixXd(model.mass), Eigen::EigenvaluesOnly);
  return solver.eigenvalues().cwiseSqrt();
}

TEST_CASE("reduction reader: boundary DOFs renumbered, every interior mode keeps the rod") {
  const Case reduced = ParseCase(RodCase(), ".");
  REQUIRE(reduced.reduction.has_value());
  // Boundary order: law DOFs, forcing, outputs → end (39) then 19.
  CHECK(reduced.model.model.num_dofs() == 40);
  CHECK(reduced.model.model.dof_names[0] == "end");
  CHECK(reduced.model.model.dof_names[1] == "node20");
  CHECK(LawDofs(reduced.laws[0]) == std::vector<int>{0});
  CHECK(reduced.model.forcing[0].dof == 0);
  CHECK(reduced.output_dofs == std::vector<int>{1, 0});
  CHECK(reduced.output_names == std::vector<std::string>{"19", "end"});
  CHECK(reduced.reduction->modes == 38);
  // All 38 interior modes: an exact change of basis, so the reduced rod has the full rod's
  // eigenfrequencies (relative 1e-9: round-off of the condition ~10³ of the 40-element K).
  RodParameters rod;
  rod.elements = 40;
  rod.length = 0.13;
  rod.area = 15.6e-4;
  rod.young = 210e9;
  rod.density = 7500;
  const Eigen::VectorXd full = Frequencies(BuildRod(rod));
  const Eigen::VectorXd cb = Frequencies(reduced.model.model);
  for (int j = 0; j < 40; ++j) CHECK(cb(j) == doctest::Approx(full(j)).epsilon(1e-9));
  for (const EigenfrequencyCheck& check : reduced.reduction->eigenfrequencies) {
    CHECK(std::abs(check.relative_error) < 1e-9);
  }
  // Modal damping, deferred to the reduced model: ζ = 0.75 % in its first mode,
  // φᵀCφ = 2ζω for a mass-normalised φ.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(
      Eigen::MatrixXd(reduced.model.model.stiffness), Eigen::MatrixXd(reduced.model.model.mass));
  const Eigen::VectorXd phi = modes.eigenvectors().col(0);
  CHECK(phi.dot(Eigen::MatrixXd(reduced.model.model.damping) * phi) ==
        doctest::Approx(2.0 * 0.0075 * full(0)).epsilon(1e-9));
}

TEST_CASE("reduction reader: a frequency band") {
  nlohmann::json source = RodCase();
  source["model"]["reduction"] = {{"type", "craig_bampton"}, {"max_frequency", 2e5}};
  const Case reduced = ParseCase(source, ".");
  // The fixed-interface problem (end and middle held) is two clamped–clamped rods of 65 mm:
  // ω_j = jπc/L' = j·2.56e5 rad/s (c = √(E/ρ) = 5292 m/s), twice each. Below 2 × 2e5 rad/s:
  // the pair at j = 1 (FE values slightly above the continuum's).
  CHECK(reduced.reduction->modes == 2);
  for (double omega : reduced.reduction->fixed_interface_frequencies) {
    CHECK(omega == doctest::Approx(2.558e5).epsilon(0.01));
  }
  CHECK(reduced.model.model.num_dofs() == 2 + reduced.reduction->modes);
}

TEST_CASE("reduction reader: bad fields are named") {
  auto with = [](const nlohmann::json& reduction) {
    nlohmann::json source = RodCase();
    source["model"]["reduction"] = reduction;
    return Error(source);
  };
  CHECK(with({{"type", "craig_bampton"}, {"modes", -1}}).find("model.reduction.modes") !=
        std::string::npos);
  CHECK(with({{"type", "craig_bampton"}, {"modes", 2}, {"max_frequency", 1.0}})
            .find("model.reduction.modes") != std::string::npos);
  CHECK(with({{"type", "craig_bampton"}}).find("model.reduction.modes") != std::string::npos);
  CHECK(with({{"type", "guyan"}, {"modes", 2}}).find("model.reduction.type") != std::string::npos);
  CHECK(with({{"type", "craig_bampton"}, {"max_frequency", -5}})
            .find("model.reduction.max_frequency") != std::string::npos);
  CHECK(with({{"type", "craig_bampton"}, {"modes", 2}, {"mode", 3}}).find("model.reduction.mode") !=
        std::string::npos);
  CHECK(with({{"type", "craig_bampton"}, {"modes", 39}}).find("model.reduction") !=
        std::string::npos);  // the interior has 38 DOFs
  CHECK(with(3).find("model.reduction") != std::string::npos);
}

}  // namespace
}  // namespace nfrc
