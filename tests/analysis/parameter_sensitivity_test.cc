// ∂R/∂p of case fields: closed forms for the one-harmonic Duffing residual, and the friction
// law's dependence on the product μN only.
#include "analysis/parameter_sensitivity.h"

#include <doctest/doctest.h>

#include <cmath>

#include "analysis/trace.h"
#include "core/errors.h"
#include "tools/case_file.h"

namespace nfrc {
namespace {

// Affine fields: the secant is exact up to rounding of residuals of size ~1.
constexpr double kAffineTolerance = 1e-12;
// Central differences with δ = 1e-5 |p|: truncation ~δ² and rounding ~ε/δ, relative to the
// residual's size.
constexpr double kCentralTolerance = 1e-7;

Case LoadTestCase(const std::string& name) {
  return LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
}

TEST_CASE("parameter sensitivity of the one-harmonic Duffing residual: closed forms") {
  const Case the_case = LoadTestCase("duffing_h1.json");  // x'' + 0.05x' + x + 0.1x³ = P cos ωt
  const Eigen::Vector2d y(1.3, -0.4);                     // x = a cos ωt + b sin ωt
  const double omega = 1.1, a = y(0), b = y(1);

  const CaseParameter forcing("model.forcing[0].cos", the_case);
  ParameterSensitivity by_forcing(the_case, forcing, 0.18);
  CHECK(by_forcing.method() == SensitivityMethod::kAffine);
  Eigen::VectorXd d_residual;
  Eigen::MatrixXd d_jacobian;
  REQUIRE(by_forcing.Evaluate(0.18, y, omega, &d_residual, &d_jacobian));
  // R = (k − ω² + iωc)X + f_nl − P e_cos: ∂R/∂P = −e_cos, and R_y does not depend on P.
  CHECK((d_residual - Eigen::Vector2d(-1.0, 0.0)).norm() < kAffineTolerance);
  CHECK(d_jacobian.norm() < kAffineTolerance);

  const CaseParameter cubic("nonlinearities[0].coefficient", the_case);
  ParameterSensitivity by_cubic(the_case, cubic, 0.1);
  CHECK(by_cubic.method() == SensitivityMethod::kAffine);
  REQUIRE(by_cubic.Evaluate(0.1, y, omega, &d_residual, &d_jacobian));
  // First harmonic of x³: ¾(a² + b²)(a, b); its Jacobian ¾[(3a² + b², 2ab), (2ab, a² + 3b²)].
  const double r2 = a * a + b * b;
  const Eigen::Vector2d expected = 0.75 * r2 * y;
  Eigen::Matrix2d expected_jacobian;
  expected_jacobian << 3 * a * a + b * b, 2 * a * b, 2 * a * b, a * a + 3 * b * b;
  expected_jacobian *= 0.75;
  CHECK((d_residual - expected).norm() < kAffineTolerance * expected.norm());
  CHECK((d_jacobian - expected_jacobian).norm() < kAffineTolerance * expected_jacobian.norm());
}

TEST_CASE("parameter sensitivity of the friction law: N dR/dN = mu dR/dmu on the branch") {
  // The two-DOF oscillator at N_phi = 20: the Coulomb law's force bound is μN, so scaling N or
  // μ by the same factor changes R identically. Two fields, two sets of systems, one result.
  CaseFile file = ReadCaseFile(std::string(NFRC_SOURCE_DIR) + "/cases/friction/frc_n10.json");
  file.source["harmonics"]["max"] = 19;
  file.source["harmonics"]["samples"] = 256;
  file.source["continuation"]["omega_end"] = 0.4;
  Case the_case = ParseCase(file.source, ".");
  the_case.stability.enabled = false;
  TraceOptions options;
  options.solve_signals = false;
  const TraceResult trace = TraceCase(the_case, options);
  REQUIRE(trace.points.size() > 10);
  const CaseParameter load("nonlinearities[0].normal_load", the_case);
  const CaseParameter mu("nonlinearities[0].mu", the_case);
  ParameterSensitivity by_load(the_case, load, 10.0);
  ParameterSensitivity by_mu(the_case, mu, 0.9);
  CHECK(by_load.method() == SensitivityMethod::kCentralDifference);
  double worst = 0.0;
  for (size_t i = 0; i < trace.points.size(); i += trace.points.size() / 8) {
    const BranchPoint& point = trace.points[i].point;
    Eigen::VectorXd d_load, d_mu;
    REQUIRE(by_load.Evaluate(10.0, point.y, point.lambda, &d_load));
    REQUIRE(by_mu.Evaluate(0.9, point.y, point.lambda, &d_mu));
    REQUIRE(d_load.norm() > 0.0);
    worst = std::max(worst, (10.0 * d_load - 0.9 * d_mu).norm() / (10.0 * d_load.norm()));
  }
  CHECK(worst < kCentralTolerance);
  MESSAGE("friction: largest relative |N dR/dN - mu dR/dmu| over 9 branch points " << worst);
}

TEST_CASE("parameter sensitivity: a step the case rejects names the field") {
  const Case the_case = LoadTestCase("friction/frc_n10.json");
  const CaseParameter mu("nonlinearities[0].mu", the_case);
  ParameterSensitivity sensitivity(the_case, mu, 1.0);
  const Eigen::VectorXd y = Eigen::VectorXd::Zero(BuildSystem(the_case)->NumUnknowns());
  Eigen::VectorXd d_residual;
  // μ − δ < 0 at μ = 0.
  CHECK_THROWS_WITH_AS(sensitivity.Evaluate(0.0, y, 0.5, &d_residual), doctest::Contains("mu"),
                       InputError);
}

}  // namespace
}  // namespace nfrc
