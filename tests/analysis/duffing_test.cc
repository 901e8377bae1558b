// The foundation's acceptance on the Duffing oscillator ẍ + 0.05ẋ + x + 0.1x³ = 0.18 cos ωt.
#include <doctest/doctest.h>

#include <cmath>

#include "analysis/trace.h"
#include "tools/case_file.h"
#include "tools/run_case.h"

namespace nfrc {
namespace {

constexpr double kC = 0.05, kK3 = 0.1, kF = 0.18;
// The issue asks for folds accurate to 1e-6 in ω against an independent computation.
constexpr double kFoldTolerance = 1e-6;

Branch TraceCaseFile(const std::string& name, std::unique_ptr<HarmonicSystem>* keep = nullptr) {
  Case the_case = LoadCase(std::string(NFRC_SOURCE_DIR) + "/cases/" + name);
  auto system = BuildSystem(the_case);
  Branch branch = Trace(*system, the_case.continuation, nullptr, nullptr, the_case.Plot());
  if (keep != nullptr) *keep = std::move(system);
  return branch;
}

// One-harmonic amplitude equation G(A, ω) = ((1 − ω²) + ¾k₃A²)²A² + (cωA)² − F² = 0 and the
// fold condition ∂G/∂(A²) = 0, solved by Newton in (A², ω): an independent closed form.
double OneHarmonicFold(double omega_guess, double a2_guess) {
  double s = a2_guess, w = omega_guess;
  for (int it = 0; it < 100; ++it) {
    const double d = 1 - w * w + 0.75 * kK3 * s;
    const double g = d * d * s + kC * kC * w * w * s - kF * kF;
    const double h = d * d + 1.5 * kK3 * d * s + kC * kC * w * w;  // ∂G/∂s
    const double g_s = h;
    const double g_w = 2 * d * (-2 * w) * s + 2 * kC * kC * w * s;
    const double h_s = 3.0 * kK3 * d + 1.125 * kK3 * kK3 * s;
    const double h_w = 2 * d * (-2 * w) + 1.5 * kK3 * s * (-2 * w) + 2 * kC * kC * w;
    const double det = g_s * h_w - g_w * h_s;
    const double ds = (-g * h_w + h * g_w) / det;
    const double dw = (-h * g_s + g * h_s) / det;
    s += ds;
    w += dw;
    if (std::abs(ds) + std::abs(dw) < 1e-15) break;
  }
  return w;
}

TEST_CASE("one-harmonic closed form of the folds (reference self-check)") {
  // The issue quotes folds at ω ≈ 1.267537 and 1.115586 for H = 1.
  CHECK(OneHarmonicFold(1.27, 8.0) == doctest::Approx(1.267537).epsilon(1e-6));
  CHECK(OneHarmonicFold(1.11, 0.8) == doctest::Approx(1.115586).epsilon(1e-6));
}

TEST_CASE("Duffing H = 1 traces 0.5 -> 1.6 through both folds, at the closed-form frequencies") {
  const Branch branch = TraceCaseFile("duffing_h1.json");
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.points.back().lambda == doctest::Approx(1.6).epsilon(1e-12));
  REQUIRE(branch.folds.size() == 2);
  CHECK(std::abs(branch.folds[0].lambda - OneHarmonicFold(1.27, 8.0)) < kFoldTolerance);
  CHECK(std::abs(branch.folds[1].lambda - OneHarmonicFold(1.11, 0.8)) < kFoldTolerance);
}

// Fold of the full H = 7 problem by Newton on the extended system
//   R(y, ω) = 0,  R_y(y, ω) φ = 0,  ℓᵀφ = 1
// with its Jacobian by finite differences: independent of the engine's secant localisation.
double ExtendedSystemFold(HarmonicSystem& system, Eigen::VectorXd y, double omega) {
  const int n = system.NumUnknowns();
  Eigen::VectorXd r, dw;
  Eigen::MatrixXd j;
  system.Evaluate(y, omega, &r, &j, &dw);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullV);
  Eigen::VectorXd phi = svd.matrixV().col(n - 1);
  const Eigen::VectorXd ell = phi;
  phi /= ell.dot(phi);
  auto extended = [&](const Eigen::VectorXd& z) {
    Eigen::VectorXd out(2 * n + 1), res, d;
    Eigen::MatrixXd jac;
    system.Evaluate(z.head(n), z(2 * n), &res, &jac, &d);
    out << res, jac * z.segment(n, n), ell.dot(z.segment(n, n)) - 1.0;
    return out;
  };
  Eigen::VectorXd z(2 * n + 1);
  z << y, phi, omega;
  for (int it = 0; it < 30; ++it) {
    const Eigen::VectorXd g = extended(z);
    Eigen::MatrixXd jac(2 * n + 1, 2 * n + 1);
    for (int c = 0; c < 2 * n + 1; ++c) {
      const double h = 1e-7 * std::max(1.0, std::abs(z(c)));
      Eigen::VectorXd zp = z, zm = z;
      zp(c) += h;
      zm(c) -= h;
      jac.col(c) = (extended(zp) - extended(zm)) / (2 * h);
    }
    const Eigen::VectorXd dz = jac.fullPivLu().solve(-g);
    z += dz;
    if (dz.norm() < 1e-12 * z.norm()) break;
  }
  return z(2 * n);
}

TEST_CASE("Duffing H = 7 (the case as given) through both folds, folds vs extended system") {
  std::unique_ptr<HarmonicSystem> system;
  const Branch branch = TraceCaseFile("duffing.json", &system);
  CHECK(branch.summary.reason == TerminationReason::kReachedLambdaBound);
  CHECK(branch.points.front().lambda == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(branch.points.back().lambda == doctest::Approx(1.6).epsilon(1e-12));
  REQUIRE(branch.folds.size() == 2);
  for (const Fold& fold : branch.folds) {
    const double reference = ExtendedSystemFold(*system, fold.y, fold.lambda);
    CHECK(std::abs(fold.lambda - reference) < kFoldTolerance);
  }
  // With higher harmonics the folds move only slightly from the H = 1 values (the response
  // is nearly harmonic); 1e-3 bounds that shift and catches a fold at a wrong place.
  CHECK(std::abs(branch.folds[0].lambda - 1.267537) < 1e-2);
  CHECK(std::abs(branch.folds[1].lambda - 1.115586) < 1e-2);
}

TEST_CASE("the same case in physical units gives the same curve with the same options") {
  std::unique_ptr<HarmonicSystem> unit_system, physical_system;
  const Branch unit = TraceCaseFile("duffing.json", &unit_system);
  const Branch physical = TraceCaseFile("duffing_physical.json", &physical_system);
  CHECK(physical.summary.reason == TerminationReason::kReachedLambdaBound);
  REQUIRE(physical.folds.size() == 2);
  constexpr double kTimeScale = 1e4;  // ω_physical = 1e4 ω
  for (size_t i = 0; i < 2; ++i) {
    CHECK(physical.folds[i].lambda / kTimeScale ==
          doctest::Approx(unit.folds[i].lambda).epsilon(1e-8));
  }
  // Same options, same scaled problem: the point sequences agree (up to round-off growth).
  CHECK(std::abs(static_cast<int>(physical.points.size()) - static_cast<int>(unit.points.size())) <=
        2);
  // Compare the curves by interpolating the physical branch's amplitude at the unit points'
  // frequencies on the first monotone stretch (below the first fold).
  for (const BranchPoint& p : unit.points) {
    if (p.lambda > 1.0) break;
    for (size_t k = 1; k < physical.points.size(); ++k) {
      const double w0 = physical.points[k - 1].lambda / kTimeScale;
      const double w1 = physical.points[k].lambda / kTimeScale;
      if (w0 <= p.lambda && p.lambda <= w1) {
        const double t = (p.lambda - w0) / (w1 - w0);
        const Eigen::VectorXd y = (1 - t) * physical.points[k - 1].y + t * physical.points[k].y;
        CHECK((y - p.y).norm() < 1e-3 * p.y.norm());  // linear interpolation error bound
        break;
      }
    }
  }
}

}  // namespace
}  // namespace nfrc
