// LCP-HBM acceptance: Lemke's solution of the rod against the harmonic equations, against
// semismooth Newton on the same equations, and the stepping driver's marking of trivial
// points where a contact solution coexists. DLFT's ε-refinement towards it:
// refinement_test.cc.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/lcp_hbm.h"
#include "analysis/trace.h"
#include "continuation/fixed_lambda.h"
#include "tools/case_file.h"
#include "tools/input_fields.h"
#include "tools/run_case.h"

namespace nfrc {
namespace {

constexpr double kOmega0 = 63953.9;  // rad/s, first eigenfrequency of the ρ = 7500 rod

// The rod and rigid obstacle (cases/rod/rigid_nh20.json) with lcp_contact, H
// harmonics and N_t samples: small enough for a unit test, the same physics.
nlohmann::json RodSource(int max_harmonic, int samples, const std::string& type) {
  nlohmann::json source =
      ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/rod/rigid_nh20.json").source;
  source["nonlinearities"][0]["type"] = type;
  source["harmonics"] = {{"max", max_harmonic}, {"samples", samples}};
  // The file's arclength step settings do not apply to Lemke stepping, which refuses them.
  source["continuation"].erase("plot_tolerance");
  source["continuation"].erase("max_step");
  return source;
}

Case RodCase(const nlohmann::json& source) {
  return ParseCase(source, std::string(NFRC_SOURCE_DIR) + "/cases/rod");
}

// Residual of the harmonic system at y split into the displacement rows and the
// complementarity rows φ(ε g, λ), both in N and relative to the forcing.
struct Residuals {
  double displacement = 0.0;
  double complementarity = 0.0;
};
Residuals SystemResiduals(HarmonicSystem& system, const Eigen::VectorXd& y, double omega) {
  Eigen::VectorXd r;
  REQUIRE(system.Evaluate(y, omega, &r, nullptr, nullptr));
  const int nx = system.num_displacement_unknowns();
  const double forcing = system.LinearForcing(omega).norm();
  return {r.head(nx).norm() / forcing, r.tail(r.size() - nx).cwiseAbs().maxCoeff() / forcing};
}

// Lemke's basis is recomputed by an LU of a ≤ N_t-square matrix whose condition is about
// ‖W‖·‖W_αα⁻¹‖ ≲ 1e6 here, so the equations hold to ~1e-16·1e6; 1e-8 leaves margin while
// any error in W or p (a wrong sign, a missing harmonic) gives O(1).
constexpr double kEquationTolerance = 1e-8;

TEST_CASE("LCP-HBM: Lemke's solution satisfies the harmonic equations and the contact law") {
  for (int samples : {17, 64}) {  // square (N_t = 2H + 1) and oversampled (W singular)
    CAPTURE(samples);
    Case the_case = RodCase(RodSource(8, samples, "lcp_contact"));
    auto system = BuildSystem(the_case);
    LcpHbm lcp(*system, the_case.laws);
    const LcpHbm::Solution s = lcp.Solve(kOmega0);
    REQUIRE(s.lemke.ok());
    CHECK_FALSE(s.lemke.trivial);
    CHECK(s.lambda.minCoeff() >= 0.0);
    // Gap ≥ 0 on every sample up to the LU's round-off on 2e-4 m.
    CHECK(s.gap.minCoeff() > -kEquationTolerance * 2e-4);
    CHECK(s.complementarity_gap < kEquationTolerance * 2e-4);
    const Residuals r = SystemResiduals(*system, s.y, kOmega0);
    CHECK(r.displacement < kEquationTolerance);
    CHECK(r.complementarity < kEquationTolerance);
    if (samples > 17) {
      // Oversampled W has rank ≤ 2H + 1 = 17; a basic solution carries at most that many
      // non-zero forces (the paper's impulses).
      int nonzero = 0;
      for (double f : s.lambda) nonzero += f > 0.0;
      CHECK(nonzero <= 17);
    }
  }
}

// Semismooth Newton converges to the same point to its own tolerance (1e-10 scaled update);
// 1e-7 relative covers the conditioning of the square Fourier matrices.
constexpr double kMethodsTolerance = 1e-7;

TEST_CASE("LCP-HBM: on square Fourier matrices Lemke and semismooth Newton agree") {
  Case the_case = RodCase(RodSource(8, 17, "lcp_contact"));
  auto system = BuildSystem(the_case);
  LcpHbm lcp(*system, the_case.laws);
  for (double omega : {6.3e4, 6.35e4, kOmega0}) {
    CAPTURE(omega);
    const LcpHbm::Solution s = lcp.Solve(omega);
    REQUIRE(s.lemke.ok());
    REQUIRE_FALSE(s.lemke.trivial);
    const Eigen::VectorXd guess = system->InitialGuess(omega);
    const FixedLambdaSolution newton =
        SolveAtFixedLambda(*system, guess, omega, guess, the_case.continuation);
    REQUIRE(newton.converged);
    const int nx = system->num_displacement_unknowns();
    CHECK((newton.y.head(nx) - s.y.head(nx)).norm() / s.y.head(nx).norm() < kMethodsTolerance);
    CHECK((newton.y.tail(17) - s.y.tail(17)).cwiseAbs().maxCoeff() /
              s.y.tail(17).cwiseAbs().maxCoeff() <
          kMethodsTolerance);
  }
}

std::string TempDir(const std::string& name) {
  const std::string dir = (std::filesystem::temp_directory_path() / ("nfrc_lcp_" + name)).string();
  std::filesystem::remove_all(dir);
  return dir;
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST_CASE("LCP-HBM: the arclength branch passes the folds and stepping marks the coexistence") {
  // Square grid H = 8: the smoothed complementarity branch from 5e4 to 8e4 through the
  // turning points (δ = 1e-9 m: g·λ = ε δ² ≈ 2.5e-9 N·m on every sample).
  nlohmann::json arc_source = RodSource(8, 17, "lcp_contact");
  arc_source["nonlinearities"][0]["smoothing"] = 1e-9;
  arc_source["continuation"]["max_step"] = 0.01;
  // Stability is not this test's subject (and costs 40 s on this smoothed square grid).
  arc_source["stability"] = {{"enabled", false}};
  Case arc_case = RodCase(arc_source);
  const std::string arc_dir = TempDir("arc");
  const Branch arc = RunCase(arc_case, arc_dir, nullptr);
  REQUIRE(arc.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(arc.folds.size() >= 2);
  double jump = 0.0;  // rightmost fold: where the contact branch turns back
  for (const Fold& fold : arc.folds) jump = std::max(jump, fold.lambda);

  nlohmann::json source = RodSource(8, 17, "lcp_contact");
  source["continuation"] = {
      {"method", "lemke_stepping"}, {"omega_start", 5e4}, {"omega_end", 8e4}, {"points", 121}};
  Case step_case = RodCase(source);
  const std::string step_dir = TempDir("step");
  const Branch stepped = RunCase(step_case, step_dir, nullptr);
  REQUIRE(stepped.summary.reason == TerminationReason::kReachedLambdaBound);
  const nlohmann::json document = ReadJson(step_dir + "/branch.json");

  // Every coexisting contact solution found by the warm start is an exact LCP solution with
  // contact where the cold solve is trivial, and some lie between the arclength branch's
  // return fold (leftmost fold above the linear resonance) and its jump, where the traced
  // contact branch and the linear solution coexist.
  double return_fold = jump;
  for (const Fold& fold : arc.folds) {
    if (fold.lambda > kOmega0) return_fold = std::min(return_fold, fold.lambda);
  }
  int coexisting = 0;
  int between_folds = 0;
  for (const nlohmann::json& point : document["points"]) {
    const double omega = point["omega"].get<double>();
    const nlohmann::json& info = point["lcp"];
    if (!info["coexisting_contact"].get<bool>()) continue;
    ++coexisting;
    between_folds += omega > return_fold && omega < jump;
    CHECK(info["trivial"].get<bool>());
    CHECK(point["laws"][0]["contact_fraction"].get<double>() == 0.0);
    const nlohmann::json& contact = info["contact_branch"];
    CHECK(contact["laws"][0]["contact_fraction"].get<double>() > 0.0);
    CHECK(contact["lcp"]["status"].get<std::string>() == "solution");
    CHECK(contact["lcp"]["complementarity_gap"].get<double>() < kEquationTolerance * 2e-4);
  }
  MESSAGE("coexisting contact at " << coexisting << " stepping points, " << between_folds
                                   << " between the folds " << return_fold << " and " << jump);
  CHECK(between_folds > 0);
}

TEST_CASE("LCP-HBM: input errors name the field") {
  auto error_of = [](nlohmann::json source) -> std::string {
    try {
      Case the_case = RodCase(source);
      RunCase(the_case, TempDir("errors"), nullptr);
    } catch (const InputError& error) {
      return error.what();
    }
    return "no error";
  };
  nlohmann::json stepping_dlft = RodSource(3, 16, "dlft_contact");
  stepping_dlft["continuation"]["method"] = "lemke_stepping";
  CHECK(error_of(stepping_dlft).rfind("nonlinearities[0]: LCP-HBM needs", 0) == 0);
  nlohmann::json unknown = RodSource(3, 16, "lcp_contact");
  unknown["continuation"]["method"] = "newton";
  CHECK(error_of(unknown).rfind("continuation.method: ", 0) == 0);
  nlohmann::json arclength_field = RodSource(3, 16, "lcp_contact");
  arclength_field["continuation"]["method"] = "lemke_stepping";
  arclength_field["continuation"]["max_step"] = 0.1;
  CHECK(error_of(arclength_field).rfind("continuation.max_step: ", 0) == 0);
  CHECK(error_of(RodSource(3, 16, "lcp_contact")).find("harmonics.samples: ") != std::string::npos);
}

}  // namespace
}  // namespace nfrc
